//! What holds a position in a log: fields and keys named as positions (by name), and
//! fields, parameters and information values whose values lie near those positions
//! (by content).

use std::collections::{HashMap, HashSet};

use ulog_format::{BasicType, Layout, LeafKind, TypeName};

use super::places::{valid, Places};
use super::rotation::{read, read_raw, to_degrees, Unit};
use super::{ARRAY_POSITIONS, POSITION_COMMANDS, POSITION_FIELDS};
use crate::log::message::KeyValue;
use crate::ULog;

/// The topic of other aircraft around the vehicle (ADS-B): their positions are moved
/// too, but the rotation starts from the vehicle's own.
const TRAFFIC: &str = "transponder_report";

/// A leaf of a payload: offset and type.
pub(super) type Leaf = (usize, BasicType);

/// A latitude and a longitude in one payload, and their unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Pair {
    pub lat: Leaf,
    pub lon: Leaf,
    pub unit: Unit,
}

impl Pair {
    /// The position in `payload` (degrees), when it is one.
    pub(super) fn read(&self, payload: &[u8]) -> Option<(f64, f64)> {
        let lat = read(payload.get(self.lat.0..)?, self.lat.1, self.unit)?;
        let lon = read(payload.get(self.lon.0..)?, self.lon.1, self.unit)?;
        valid(lat, lon).then_some((lat, lon))
    }
}

/// Where a `vehicle_command`'s id (`command`) and position (`param5`, `param6`) are.
#[derive(Debug, Clone, Copy)]
pub(super) struct Command {
    pub id: Leaf,
    pub pair: Pair,
}

impl Command {
    /// The position the command in `payload` holds, if its command takes one.
    pub(super) fn read(&self, payload: &[u8]) -> Option<(f64, f64)> {
        let (offset, ty) = self.id;
        let id = match ty {
            BasicType::UInt8 => u32::from(*payload.get(offset)?),
            BasicType::UInt16 => u32::from(u16::from_le_bytes(
                payload.get(offset..offset + 2)?.try_into().ok()?,
            )),
            BasicType::UInt32 => {
                u32::from_le_bytes(payload.get(offset..offset + 4)?.try_into().ok()?)
            }
            _ => return None,
        };
        if POSITION_COMMANDS.contains(&id) {
            self.pair.read(payload)
        } else {
            None
        }
    }
}

/// The scalar leaves of a layout by path.
fn leaves(layout: &Layout) -> HashMap<&str, Leaf> {
    layout
        .columns()
        .filter(|l| l.kind == LeafKind::Scalar)
        .map(|l| (l.path.as_str(), (l.offset, l.ty)))
        .collect()
}

/// The positions a topic's layout names ([`POSITION_FIELDS`] at any depth,
/// [`ARRAY_POSITIONS`]), with their paths.
pub(super) fn named_pairs(topic: &str, layout: &Layout) -> Vec<(Pair, String, String)> {
    let by_path = leaves(layout);
    let mut out = Vec::new();
    for (name, lat, lon) in ARRAY_POSITIONS {
        if topic == *name {
            if let (Some(&a), Some(&b)) = (by_path.get(lat), by_path.get(lon)) {
                if a.1 == BasicType::Double && b.1 == BasicType::Double {
                    let pair = Pair {
                        lat: a,
                        lon: b,
                        unit: Unit::Degrees,
                    };
                    out.push((pair, lat.to_string(), lon.to_string()));
                }
            }
        }
    }
    for leaf in layout.columns().filter(|l| l.kind == LeafKind::Scalar) {
        let (prefix, last) = match leaf.path.rsplit_once('.') {
            Some((p, l)) => (format!("{p}."), l),
            None => (String::new(), leaf.path.as_str()),
        };
        for (lat, lon) in POSITION_FIELDS {
            if last != *lat {
                continue;
            }
            let lon_path = format!("{prefix}{lon}");
            let Some(&other) = by_path.get(lon_path.as_str()) else {
                continue;
            };
            match (Unit::named(leaf.ty), Unit::named(other.1)) {
                (Some(a), Some(b)) if a == b => {
                    let pair = Pair {
                        lat: (leaf.offset, leaf.ty),
                        lon: other,
                        unit: a,
                    };
                    out.push((pair, leaf.path.clone(), lon_path));
                }
                _ => {}
            }
        }
    }
    out
}

/// Where a `vehicle_command` layout holds its id and position parameters.
pub(super) fn command(topic: &str, layout: &Layout) -> Option<Command> {
    if topic != "vehicle_command" {
        return None;
    }
    let by_path = leaves(layout);
    let (&id, &lat, &lon) = (
        by_path.get("command")?,
        by_path.get("param5")?,
        by_path.get("param6")?,
    );
    let unit = Unit::named(lat.1).filter(|&u| Unit::named(lon.1) == Some(u))?;
    Some(Command {
        id,
        pair: Pair { lat, lon, unit },
    })
}

/// A latitude and longitude of a topic found by their values: paths and unit.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub(super) struct PathPair {
    pub lat: String,
    pub lon: String,
    pub unit: Unit,
}

/// What a key (parameter or information) holds: half of a position, the other half
/// in `partner`.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct KeyRole {
    pub partner: String,
    pub latitude: bool,
    pub unit: Unit,
}

/// Everything that holds a position in a log.
#[derive(Debug, Clone)]
pub(super) struct Survey {
    /// The positions of the fields and keys named as positions.
    pub places: Places,
    /// The first of them (in file order; parameters named as positions when no data
    /// is): where the rotation starts.
    pub anchor: Option<(f64, f64)>,
    /// Pairs of fields found by their values, by topic name.
    pub topics: HashMap<String, Vec<PathPair>>,
    /// Parameters that hold a position, by name.
    pub params: HashMap<String, KeyRole>,
    /// Information keys that hold a position (numbers), by name.
    pub info: HashMap<String, KeyRole>,
}

impl Survey {
    /// Surveys `log`: first the named positions, then what lies near them.
    pub(super) fn of(log: &ULog<'_>) -> Survey {
        let mut places = Places::new();
        // The first position of the vehicle; of traffic around it if it has none.
        let mut first: Option<(u64, (f64, f64))> = None;
        let mut first_traffic: Option<(u64, (f64, f64))> = None;
        for topic in log.topics().filter(|t| !t.is_empty()) {
            let Ok(layout) = topic.layout() else {
                continue;
            };
            let pairs: Vec<Pair> = named_pairs(topic.name(), layout)
                .into_iter()
                .map(|(p, _, _)| p)
                .collect();
            let command = command(topic.name(), layout);
            if pairs.is_empty() && command.is_none() {
                continue;
            }
            let offsets = topic.message_offsets();
            for (row, payload) in topic.payloads().enumerate() {
                let mut found: Vec<(f64, f64)> =
                    pairs.iter().filter_map(|p| p.read(payload)).collect();
                found.extend(command.and_then(|c| c.read(payload)));
                for &(lat, lon) in &found {
                    places.add(lat, lon);
                }
                if let (Some(&pos), Some(offset)) = (found.first(), offsets.get(row)) {
                    let first = match topic.name() {
                        TRAFFIC => &mut first_traffic,
                        _ => &mut first,
                    };
                    if first.map_or(true, |(o, _)| offset < o) {
                        *first = Some((offset, pos));
                    }
                }
            }
        }
        let params = key_values(
            log.initial_params()
                .iter()
                .chain(log.param_changes().iter().map(|c| &c.kv))
                .chain(log.default_params().iter().map(|d| &d.kv)),
        );
        let info = key_values(log.info().iter());
        let mut param_roles = named_keys(&params);
        let mut info_roles = named_keys(&info);
        let mut anchor = first.or(first_traffic).map(|(_, pos)| pos);
        for (roles, values) in [(&param_roles, &params), (&info_roles, &info)] {
            let mut names: Vec<&String> = roles.keys().collect();
            names.sort();
            for name in names {
                let role = &roles[name];
                if !role.latitude {
                    continue;
                }
                let lat = to_degrees(values[name].1, role.unit);
                let lon = to_degrees(values[&role.partner].1, role.unit);
                places.add(lat, lon);
                if anchor.is_none() && valid(lat, lon) {
                    anchor = Some((lat, lon));
                }
            }
        }
        let mut survey = Survey {
            places,
            anchor,
            topics: HashMap::new(),
            params: HashMap::new(),
            info: HashMap::new(),
        };
        if !survey.places.is_empty() {
            for topic in log.topics().filter(|t| !t.is_empty()) {
                let found = survey.topic_pairs(&topic);
                if !found.is_empty() {
                    let all = survey.topics.entry(topic.name().to_string()).or_default();
                    for p in found {
                        if !all.contains(&p) {
                            all.push(p);
                        }
                    }
                }
            }
            key_pairs_by_value(&survey.places, &params, &mut param_roles);
            key_pairs_by_value(&survey.places, &info, &mut info_roles);
        }
        survey.params = param_roles;
        survey.info = info_roles;
        survey
    }

    /// The pairs of a topic instance's fields that hold positions near the places, by
    /// their values: a latitude-like and a longitude-like value in one row, in the same
    /// unit, near a place together in at least half of the rows where they are a
    /// position; each field in one pair at most (the pair near in most rows first, then
    /// elements of one index of two arrays, then the closest fields).
    fn topic_pairs(&self, topic: &crate::Topic<'_, '_>) -> Vec<PathPair> {
        let Ok(layout) = topic.layout() else {
            return Vec::new();
        };
        let mut claimed: HashSet<usize> = HashSet::new();
        for (p, _, _) in named_pairs(topic.name(), layout) {
            claimed.extend([p.lat.0, p.lon.0]);
        }
        if let Some(c) = command(topic.name(), layout) {
            claimed.extend([c.pair.lat.0, c.pair.lon.0]);
        }
        // Candidates: every scalar leaf that may hold a position, in each unit.
        let cands: Vec<(Leaf, Unit, &str)> = layout
            .columns()
            .filter(|l| l.kind == LeafKind::Scalar && !claimed.contains(&l.offset))
            .flat_map(|l| {
                Unit::of(l.ty)
                    .iter()
                    .map(move |&u| ((l.offset, l.ty), u, l.path.as_str()))
            })
            .collect();
        if cands.is_empty() {
            return Vec::new();
        }
        let value = |payload: &[u8], c: usize| -> Option<f64> {
            let ((offset, ty), unit, _) = cands[c];
            read(payload.get(offset..)?, ty, unit).filter(|v| v.is_finite())
        };
        // Which candidates ever hold a latitude-like or longitude-like value.
        let (mut lat_like, mut lon_like) = (vec![false; cands.len()], vec![false; cands.len()]);
        for payload in topic.payloads() {
            for c in 0..cands.len() {
                if let Some(v) = value(payload, c) {
                    lat_like[c] |= self.places.lat_like(v);
                    lon_like[c] |= self.places.lon_like(v);
                }
            }
        }
        let mut pairs: Vec<(usize, usize)> = Vec::new();
        for a in (0..cands.len()).filter(|&a| lat_like[a]) {
            for b in (0..cands.len()).filter(|&b| lon_like[b]) {
                if cands[a].0 != cands[b].0 && cands[a].1 == cands[b].1 {
                    pairs.push((a, b));
                }
            }
        }
        if pairs.is_empty() {
            return Vec::new();
        }
        // Rows where each pair is a position, and where it is near a place.
        let mut counts = vec![(0usize, 0usize); pairs.len()];
        for payload in topic.payloads() {
            for (k, &(a, b)) in pairs.iter().enumerate() {
                if let (Some(lat), Some(lon)) = (value(payload, a), value(payload, b)) {
                    if valid(lat, lon) {
                        counts[k].0 += 1;
                        counts[k].1 += usize::from(self.places.near(lat, lon));
                    }
                }
            }
        }
        let mut chosen: Vec<usize> = (0..pairs.len())
            .filter(|&k| counts[k].1 > 0 && counts[k].1 * 2 >= counts[k].0)
            .collect();
        let distance = |k: usize| {
            let (a, b) = pairs[k];
            cands[a].0 .0.abs_diff(cands[b].0 .0)
        };
        // `lat[2]` goes with `lon[2]`, not with the `lon[0]` that follows it closer.
        let index = |c: usize| cands[c].2.rfind('[').map(|i| &cands[c].2[i..]);
        let other_index = |k: usize| index(pairs[k].0) != index(pairs[k].1);
        chosen.sort_by_key(|&k| {
            (
                std::cmp::Reverse(counts[k].1),
                other_index(k),
                distance(k),
                pairs[k],
            )
        });
        let mut used: HashSet<usize> = HashSet::new();
        let mut out = Vec::new();
        for k in chosen {
            let (a, b) = pairs[k];
            let (la, lb) = (cands[a].0 .0, cands[b].0 .0);
            if used.contains(&la) || used.contains(&lb) {
                continue;
            }
            used.extend([la, lb]);
            out.push(PathPair {
                lat: cands[a].2.to_string(),
                lon: cands[b].2.to_string(),
                unit: cands[a].1,
            });
        }
        out
    }
}

/// The numeric scalar keys among `kvs`: name, type and first value.
fn key_values<'a, 'k: 'a>(
    kvs: impl Iterator<Item = &'a KeyValue<'k>>,
) -> HashMap<String, (BasicType, f64)> {
    let mut out = HashMap::new();
    for kv in kvs {
        let Some(field) = &kv.field else {
            continue;
        };
        let (TypeName::Basic(ty), None) = (&field.ty, field.array_len) else {
            continue;
        };
        if let Some(v) = read_raw(kv.raw, *ty) {
            out.entry(field.name.clone()).or_insert((*ty, v));
        }
    }
    out
}

/// The keys named as a position: `NAME_LAT` with `NAME_LON` (`LAT`, `lat`, `_lat`
/// endings, and `latitude` with `longitude`; the case as written), both `float` or
/// `double` (degrees) or both `int32_t` (1e-7 degrees), with values in range.
fn named_keys(values: &HashMap<String, (BasicType, f64)>) -> HashMap<String, KeyRole> {
    let mut roles = HashMap::new();
    for (name, &(ty, v)) in values {
        let Some(partner) = partner_name(name) else {
            continue;
        };
        let Some(&(pty, pv)) = values.get(&partner) else {
            continue;
        };
        let (Some(unit), Some(punit)) = (Unit::named(ty), Unit::named(pty)) else {
            continue;
        };
        let (lat, lon) = (to_degrees(v, unit), to_degrees(pv, punit));
        if unit != punit || !(lat.abs() <= 90.0 && lon.abs() <= 180.0) {
            continue;
        }
        roles.insert(
            partner.clone(),
            KeyRole {
                partner: name.clone(),
                latitude: false,
                unit,
            },
        );
        roles.insert(
            name.clone(),
            KeyRole {
                partner,
                latitude: true,
                unit,
            },
        );
    }
    roles
}

/// The longitude's name for a latitude's name (`LPE_LAT` → `LPE_LON`, `home_lat` →
/// `home_lon`, `latitude` → `longitude`).
fn partner_name(name: &str) -> Option<String> {
    for (lat, lon) in [
        ("latitude", "longitude"),
        ("LATITUDE", "LONGITUDE"),
        ("lat", "lon"),
        ("LAT", "LON"),
    ] {
        if let Some(stem) = name.strip_suffix(lat) {
            if stem.is_empty() || stem.ends_with('_') {
                return Some(format!("{stem}{lon}"));
            }
        }
    }
    None
}

/// Adds the keys that hold a position by their values: a latitude-like and a
/// longitude-like key (numbers in the same unit) whose first values are near a place
/// together; among several such pairs, those whose names share the longest start
/// first, each key in one pair.
fn key_pairs_by_value(
    places: &Places,
    values: &HashMap<String, (BasicType, f64)>,
    roles: &mut HashMap<String, KeyRole>,
) {
    let names: Vec<&String> = values.keys().filter(|n| !roles.contains_key(*n)).collect();
    let degrees = |name: &str, unit: Unit| {
        let (ty, v) = values[name];
        Unit::of(ty).contains(&unit).then(|| to_degrees(v, unit))
    };
    let mut pairs = Vec::new();
    for unit in [Unit::Degrees, Unit::Radians, Unit::E7] {
        for &a in &names {
            let Some(lat) = degrees(a, unit).filter(|&v| places.lat_like(v)) else {
                continue;
            };
            for &b in &names {
                if b != a && degrees(b, unit).is_some_and(|lon| places.near(lat, lon)) {
                    let shared = a.bytes().zip(b.bytes()).take_while(|(x, y)| x == y).count();
                    pairs.push((std::cmp::Reverse(shared), a, b, unit));
                }
            }
        }
    }
    pairs.sort_by(|x, y| (x.0, x.1, x.2).cmp(&(y.0, y.1, y.2)));
    for (_, a, b, unit) in pairs {
        if roles.contains_key(a) || roles.contains_key(b) {
            continue;
        }
        roles.insert(
            a.clone(),
            KeyRole {
                partner: b.clone(),
                latitude: true,
                unit,
            },
        );
        roles.insert(
            b.clone(),
            KeyRole {
                partner: a.clone(),
                latitude: false,
                unit,
            },
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partners_by_name() {
        assert_eq!(partner_name("LPE_LAT").as_deref(), Some("LPE_LON"));
        assert_eq!(partner_name("home_lat").as_deref(), Some("home_lon"));
        assert_eq!(partner_name("latitude").as_deref(), Some("longitude"));
        assert_eq!(partner_name("FLAT"), None);
        assert_eq!(partner_name("MPC_LAT_GAIN"), None);
    }
}
