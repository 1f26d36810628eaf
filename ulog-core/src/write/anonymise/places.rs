//! Where a log was: the positions its fields named as positions hold (the references),
//! and whether a value or a pair of values is near them.

use std::collections::HashSet;

/// How near a value must be to a reference to count as the same place, in degrees
/// of latitude and of longitude (0.05°: 5.5 km north-south).
pub(super) const NEAR: f64 = 0.05;

/// The grid the references are kept on (degrees).
const CELL: f64 = 0.01;

/// Cells around a reference that are near it.
const REACH: i32 = (NEAR / CELL + 0.5) as i32;

/// The places of a log: every cell of the grid within [`REACH`] cells of a reference,
/// so that a pair within [`NEAR`] of a reference in both coordinates is near (and none
/// farther than `NEAR + CELL`), and a single value near a reference's latitude or
/// longitude likewise.
#[derive(Debug, Clone, Default)]
pub(super) struct Places {
    /// Reference cells already added (each is dilated once).
    seen: HashSet<(i32, i32)>,
    cells: HashSet<(i32, i32)>,
    lats: Cells,
    lons: Cells,
    /// The span of the latitudes and longitudes near a reference: a quick test before
    /// the sets.
    lat_span: (f64, f64),
    lon_span: (f64, f64),
}

fn cell(v: f64) -> i32 {
    (v / CELL).floor() as i32
}

/// A set of cells of one coordinate (-180° to 180°), as bits: a value is looked up
/// for every number of every row, so without hashing.
#[derive(Debug, Clone, Default)]
struct Cells(Vec<u64>);

impl Cells {
    /// Cells from -180° (index 0) to 180°.
    const SPAN: i32 = (360.0 / CELL + 0.5) as i32 + 2 * REACH + 2;

    fn index(c: i32) -> Option<usize> {
        usize::try_from(c + (180.0 / CELL + 0.5) as i32 + REACH + 1)
            .ok()
            .filter(|&i| i < Self::SPAN as usize)
    }

    fn insert(&mut self, c: i32) {
        if self.0.is_empty() {
            self.0 = vec![0; Self::SPAN as usize / 64 + 1];
        }
        if let Some(i) = Self::index(c) {
            self.0[i / 64] |= 1 << (i % 64);
        }
    }

    fn contains(&self, c: i32) -> bool {
        Self::index(c).is_some_and(|i| self.0.get(i / 64).is_some_and(|w| w & (1 << (i % 64)) != 0))
    }
}

impl Places {
    pub(super) fn new() -> Places {
        Places {
            lat_span: (f64::INFINITY, f64::NEG_INFINITY),
            lon_span: (f64::INFINITY, f64::NEG_INFINITY),
            ..Places::default()
        }
    }

    /// Adds a reference position (degrees); (0, 0), values that are not numbers and
    /// values out of range are not positions.
    pub(super) fn add(&mut self, lat: f64, lon: f64) {
        if !valid(lat, lon) {
            return;
        }
        let c = (cell(lat), cell(lon));
        if !self.seen.insert(c) {
            return;
        }
        for dy in -REACH..=REACH {
            self.lats.insert(c.0 + dy);
            self.lons.insert(c.1 + dy);
            for dx in -REACH..=REACH {
                self.cells.insert((c.0 + dy, c.1 + dx));
            }
        }
        let reach = f64::from(REACH + 1) * CELL;
        self.lat_span = (
            self.lat_span.0.min(lat - reach),
            self.lat_span.1.max(lat + reach),
        );
        self.lon_span = (
            self.lon_span.0.min(lon - reach),
            self.lon_span.1.max(lon + reach),
        );
    }

    /// Whether there is no reference.
    pub(super) fn is_empty(&self) -> bool {
        self.seen.is_empty()
    }

    /// Whether `v` (degrees) is near the latitude of a reference.
    #[inline]
    pub(super) fn lat_like(&self, v: f64) -> bool {
        v >= self.lat_span.0 && v <= self.lat_span.1 && self.lats.contains(cell(v))
    }

    /// Whether `v` (degrees) is near the longitude of a reference.
    #[inline]
    pub(super) fn lon_like(&self, v: f64) -> bool {
        v >= self.lon_span.0 && v <= self.lon_span.1 && self.lons.contains(cell(v))
    }

    /// Whether a position (degrees) is near a reference.
    pub(super) fn near(&self, lat: f64, lon: f64) -> bool {
        self.lat_like(lat) && self.lon_like(lon) && self.cells.contains(&(cell(lat), cell(lon)))
    }
}

/// Whether a latitude and longitude (degrees) are a position: numbers, in range, and
/// not 0, 0 (what a receiver without a fix reports).
pub(super) fn valid(lat: f64, lon: f64) -> bool {
    lat.is_finite()
        && lon.is_finite()
        && lat.abs() <= 90.0
        && lon.abs() <= 180.0
        && !(lat == 0.0 && lon == 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn near_means_within_the_reach_in_both_coordinates() {
        let mut p = Places::new();
        assert!(p.is_empty());
        p.add(47.397742, 8.545594);
        p.add(0.0, 0.0);
        p.add(f64::NAN, 1.0);
        assert!(!p.is_empty());
        assert!(p.near(47.397742, 8.545594));
        assert!(p.near(47.397742 + NEAR, 8.545594 - NEAR));
        assert!(!p.near(47.397742 + NEAR + 2.0 * CELL, 8.545594));
        assert!(
            !p.near(8.545594, 47.397742),
            "the coordinates in their order"
        );
        assert!(!p.near(0.0, 0.0));
        assert!(p.lat_like(47.35) && !p.lat_like(47.5) && !p.lat_like(8.5));
        assert!(p.lon_like(8.5) && !p.lon_like(47.4));
    }
}
