//! The rotation of the Earth that moves positions, and the units a position is held in.

use ulog_format::BasicType;

/// How a value holds a latitude or longitude.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(super) enum Unit {
    /// `float` or `double` in degrees.
    Degrees,
    /// `float` or `double` in radians.
    Radians,
    /// An integer in 1e-7 degrees.
    E7,
}

impl Unit {
    /// The units a value of this type may hold a position in.
    pub(super) fn of(ty: BasicType) -> &'static [Unit] {
        match ty {
            BasicType::Float | BasicType::Double => &[Unit::Degrees, Unit::Radians],
            BasicType::Int32 | BasicType::Int64 => &[Unit::E7],
            _ => &[],
        }
    }

    /// The unit of a field named as a position: degrees, or 1e-7 degrees in an
    /// `int32_t`.
    pub(super) fn named(ty: BasicType) -> Option<Unit> {
        match ty {
            BasicType::Float | BasicType::Double => Some(Unit::Degrees),
            BasicType::Int32 => Some(Unit::E7),
            _ => None,
        }
    }
}

/// A value of type `ty` in `bytes`, as a number (integers as they are).
pub(super) fn read_raw(bytes: &[u8], ty: BasicType) -> Option<f64> {
    let b = bytes.get(..ty.size())?;
    Some(match ty {
        BasicType::Float => f32::from_le_bytes(b.try_into().ok()?) as f64,
        BasicType::Double => f64::from_le_bytes(b.try_into().ok()?),
        BasicType::Int32 => i32::from_le_bytes(b.try_into().ok()?) as f64,
        BasicType::Int64 => i64::from_le_bytes(b.try_into().ok()?) as f64,
        _ => return None,
    })
}

/// A value of type `ty` in `bytes`, in degrees by `unit`.
pub(super) fn read(bytes: &[u8], ty: BasicType, unit: Unit) -> Option<f64> {
    read_raw(bytes, ty).map(|v| to_degrees(v, unit))
}

/// A number in `unit`, in degrees.
pub(super) fn to_degrees(v: f64, unit: Unit) -> f64 {
    match unit {
        Unit::Degrees => v,
        Unit::Radians => v.to_degrees(),
        Unit::E7 => v * 1e-7,
    }
}

/// Writes `degrees` into `bytes` as a value of type `ty` in `unit`.
pub(super) fn write(bytes: &mut [u8], ty: BasicType, unit: Unit, degrees: f64) {
    let v = match unit {
        Unit::Degrees => degrees,
        Unit::Radians => degrees.to_radians(),
        Unit::E7 => (degrees * 1e7).round(),
    };
    let Some(b) = bytes.get_mut(..ty.size()) else {
        return;
    };
    match ty {
        BasicType::Float => b.copy_from_slice(&(v as f32).to_le_bytes()),
        BasicType::Double => b.copy_from_slice(&v.to_le_bytes()),
        BasicType::Int32 => {
            b.copy_from_slice(&(v.clamp(i32::MIN as f64, i32::MAX as f64) as i32).to_le_bytes())
        }
        BasicType::Int64 => b.copy_from_slice(&(v as i64).to_le_bytes()),
        _ => {}
    }
}

/// A rotation of the sphere: turn about the polar axis to the target's meridian after
/// turning about the east-west axis of the first position's meridian by the change of
/// latitude (so that north stays north along that meridian).
#[derive(Debug, Clone, Copy)]
pub(super) struct Rotation {
    /// Row-major 3×3 matrix on unit vectors (x to 0° N 0° E, z to the north pole).
    m: [[f64; 3]; 3],
}

impl Rotation {
    /// The rotation that takes `from` (latitude, longitude, degrees) to `to`.
    pub(super) fn taking(from: (f64, f64), to: (f64, f64)) -> Rotation {
        let (lat0, lon0) = (from.0.to_radians(), from.1.to_radians());
        let (lat1, lon1) = (to.0.to_radians(), to.1.to_radians());
        // To the first position's meridian at 0° E, tilt by the change of latitude
        // (about the y axis), then to the target's meridian.
        let a = rot_z(-lon0);
        let b = rot_y(-(lat1 - lat0));
        let c = rot_z(lon1);
        Rotation {
            m: mul(&c, &mul(&b, &a)),
        }
    }

    /// The image of a position (degrees).
    pub(super) fn apply(&self, lat: f64, lon: f64) -> (f64, f64) {
        let (la, lo) = (lat.to_radians(), lon.to_radians());
        let v = [la.cos() * lo.cos(), la.cos() * lo.sin(), la.sin()];
        let m = &self.m;
        let w: [f64; 3] =
            core::array::from_fn(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2]);
        let lat = w[2].clamp(-1.0, 1.0).asin().to_degrees();
        let lon = w[1].atan2(w[0]).to_degrees();
        (lat, lon)
    }
}

fn rot_z(a: f64) -> [[f64; 3]; 3] {
    let (s, c) = a.sin_cos();
    [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
}

/// A rotation about the y axis that raises a point on the x axis towards z by `-a`
/// (so `rot_y(-d)` adds `d` to the latitude of points on the 0° meridian).
fn rot_y(a: f64) -> [[f64; 3]; 3] {
    let (s, c) = a.sin_cos();
    [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]
}

fn mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    core::array::from_fn(|i| core::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Great-circle distance in metres.
    fn distance(a: (f64, f64), b: (f64, f64)) -> f64 {
        let (p1, p2) = (a.0.to_radians(), b.0.to_radians());
        let dp = p2 - p1;
        let dl = (b.1 - a.1).to_radians();
        let h = (dp / 2.0).sin().powi(2) + p1.cos() * p2.cos() * (dl / 2.0).sin().powi(2);
        2.0 * 6_371_000.0 * h.sqrt().asin()
    }

    #[test]
    fn the_rotation_takes_the_first_point_to_the_target_and_keeps_distances() {
        let from = (47.397742, 8.545594);
        for to in [(0.0, 0.0), (-33.9, 151.2), (60.0, -120.0)] {
            let r = Rotation::taking(from, to);
            let (lat, lon) = r.apply(from.0, from.1);
            assert!(
                (lat - to.0).abs() < 1e-9 && (lon - to.1).abs() < 1e-9,
                "{lat} {lon}"
            );
            let points = [(47.3978, 8.5457), (47.41, 8.52), (47.2, 8.9), (46.0, 7.0)];
            for p in points {
                for q in points {
                    let (a, b) = (r.apply(p.0, p.1), r.apply(q.0, q.1));
                    assert!((distance(p, q) - distance(a, b)).abs() < 1e-3);
                }
            }
            // North stays north at the first position: a point due north of it is
            // due north of its image.
            let north = r.apply(from.0 + 0.001, from.1);
            assert!((north.1 - to.1).abs() < 1e-9 && north.0 > to.0);
        }
    }

    #[test]
    fn units_read_and_write_degrees() {
        let mut b = [0u8; 8];
        for (ty, unit, degrees) in [
            (BasicType::Int32, Unit::E7, -74.179_300_2),
            (BasicType::Int64, Unit::E7, 151.2),
            (BasicType::Float, Unit::Radians, 47.4),
            (BasicType::Double, Unit::Radians, -33.9),
            (BasicType::Double, Unit::Degrees, 8.545594),
        ] {
            write(&mut b, ty, unit, degrees);
            let back = read(&b, ty, unit).unwrap();
            assert!((back - degrees).abs() < 1e-5, "{ty:?} {unit:?}: {back}");
        }
    }
}
