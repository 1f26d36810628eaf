//! Positions and wall-clock times written in text: logged strings, information and
//! multi-information strings, `char[N]` fields.

use super::places::Places;
use super::rotation::Rotation;

/// What text is edited by: the places of the log, the rotation, and whether dates and
/// times go.
#[derive(Debug, Clone)]
pub(super) struct Texts {
    pub places: Places,
    pub rotation: Option<Rotation>,
    pub anchor: Option<(f64, f64)>,
    pub zero_utc: bool,
}

/// Fraction digits a lone number needs to be taken for a coordinate (1 m or finer):
/// coarser numbers near a latitude are as likely a reading of something else.
const LONE_DECIMALS: usize = 5;

/// How a number in text holds a coordinate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// With a decimal point: degrees.
    Decimal,
    /// Seven to ten digits without one: 1e-7 degrees.
    E7,
}

/// A number in text.
#[derive(Debug, Clone, Copy)]
struct Token {
    start: usize,
    end: usize,
    kind: Kind,
    /// Fraction digits.
    decimals: usize,
    /// Degrees.
    degrees: f64,
}

impl Texts {
    /// `text` with its positions moved and, with `zero_utc`, its dates and times made
    /// zeros; `None` when nothing changes. `same_length`: every replacement has the
    /// length of what it replaces (text split over several messages, or held in a
    /// field of fixed size).
    pub(super) fn edit(&self, text: &[u8], same_length: bool) -> Option<Vec<u8>> {
        let mut edits: Vec<(usize, usize, Vec<u8>)> = Vec::new();
        if self.zero_utc {
            for (a, b) in date_time_spans(text) {
                edits.push((a, b, zero_digits(&text[a..b])));
            }
        }
        if let (Some(rotation), false) = (self.rotation, self.places.is_empty()) {
            let tokens: Vec<Token> = numbers(text)
                .into_iter()
                .filter(|t| !edits.iter().any(|&(a, b, _)| t.start < b && a < t.end))
                .collect();
            for (t, degrees) in self.moved(&tokens, &rotation) {
                let original = &text[t.start..t.end];
                edits.push((t.start, t.end, format(degrees, &t, original, same_length)));
            }
        }
        if edits.is_empty() {
            return None;
        }
        edits.sort_by_key(|e| e.0);
        let mut out = Vec::with_capacity(text.len() + 8);
        let mut at = 0;
        for (a, b, with) in edits {
            out.extend_from_slice(&text[at..a]);
            out.extend_from_slice(&with);
            at = b;
        }
        out.extend_from_slice(&text[at..]);
        (out != text).then_some(out)
    }

    /// The numbers of `tokens` that are coordinates, with their new values: a
    /// latitude-like and a longitude-like number of one kind that are near a place
    /// together (the closest such partner in the text), and a lone number with at
    /// least [`LONE_DECIMALS`] decimals near a place's latitude or longitude (moved
    /// with the first position's other coordinate).
    fn moved(&self, tokens: &[Token], rotation: &Rotation) -> Vec<(Token, f64)> {
        let places = &self.places;
        let lat_like: Vec<bool> = tokens.iter().map(|t| places.lat_like(t.degrees)).collect();
        let lon_like: Vec<bool> = tokens.iter().map(|t| places.lon_like(t.degrees)).collect();
        let mut used = vec![false; tokens.len()];
        let mut out = Vec::new();
        for a in 0..tokens.len() {
            if !lat_like[a] || used[a] {
                continue;
            }
            let partner = (0..tokens.len())
                .filter(|&b| b != a && !used[b] && lon_like[b] && tokens[b].kind == tokens[a].kind)
                .filter(|&b| places.near(tokens[a].degrees, tokens[b].degrees))
                .min_by_key(|&b| (a.abs_diff(b), b < a));
            if let Some(b) = partner {
                used[a] = true;
                used[b] = true;
                let (lat, lon) = rotation.apply(tokens[a].degrees, tokens[b].degrees);
                out.push((tokens[a], lat));
                out.push((tokens[b], lon));
            }
        }
        if let Some((lat0, lon0)) = self.anchor {
            for (k, t) in tokens.iter().enumerate() {
                if used[k] || t.kind != Kind::Decimal || t.decimals < LONE_DECIMALS {
                    continue;
                }
                if lat_like[k] {
                    out.push((*t, rotation.apply(t.degrees, lon0).0));
                } else if lon_like[k] {
                    out.push((*t, rotation.apply(lat0, t.degrees).1));
                }
            }
        }
        out
    }
}

/// The numbers of a text that may be coordinates: a decimal number (`-33.9`,
/// `8.545594`) or an integer of seven to ten digits, not part of a word (`v1.14`,
/// `x47`) or of a dotted version (`1.14.0`).
fn numbers(text: &[u8]) -> Vec<Token> {
    let n = text.len();
    let digit = |i: usize| i < n && text[i].is_ascii_digit();
    let mut out = Vec::new();
    let mut i = 0;
    while i < n {
        let word_before =
            i > 0 && (text[i - 1].is_ascii_alphanumeric() || matches!(text[i - 1], b'_' | b'.'));
        let sign = text[i] == b'-' && digit(i + 1) && !word_before;
        if digit(i) && word_before {
            // A word's digits are the word's (and so is a fraction after them).
            while digit(i) || (i < n && text[i] == b'.' && digit(i + 1)) {
                i += 1;
            }
            continue;
        }
        if !(digit(i) || sign) {
            i += 1;
            continue;
        }
        let start = i;
        let mut j = i + usize::from(sign);
        while digit(j) {
            j += 1;
        }
        let int_digits = j - start - usize::from(sign);
        let mut decimals = 0;
        if j + 1 < n && text[j] == b'.' && digit(j + 1) {
            j += 1;
            while digit(j) {
                j += 1;
                decimals += 1;
            }
        }
        let dotted = j + 1 < n && text[j] == b'.' && digit(j + 1);
        if dotted {
            // A version or an address: skip all of it.
            while j < n && (text[j] == b'.' || text[j].is_ascii_digit()) {
                j += 1;
            }
            i = j;
            continue;
        }
        i = j;
        let kind = if decimals > 0 {
            Kind::Decimal
        } else if (7..=10).contains(&int_digits) {
            Kind::E7
        } else {
            continue;
        };
        let Some(v) = std::str::from_utf8(&text[start..j])
            .ok()
            .and_then(|s| s.parse::<f64>().ok())
        else {
            continue;
        };
        let degrees = match kind {
            Kind::Decimal => v,
            Kind::E7 => v * 1e-7,
        };
        out.push(Token {
            start,
            end: j,
            kind,
            decimals,
            degrees,
        });
    }
    out
}

/// A coordinate written as the number it replaces was: as many decimals (an integer
/// in 1e-7 degrees for one), and with `same_length` exactly as long (decimals dropped
/// or added; the original's digits made zeros when it cannot be).
fn format(degrees: f64, t: &Token, original: &[u8], same_length: bool) -> Vec<u8> {
    let text = match t.kind {
        Kind::Decimal => format!("{degrees:.*}", t.decimals),
        Kind::E7 => format!("{}", (degrees * 1e7).round() as i64),
    };
    if !same_length || text.len() == original.len() {
        return text.into_bytes();
    }
    let n = original.len();
    match t.kind {
        Kind::Decimal => {
            for d in 0..=15 {
                let s = format!("{degrees:.d$}");
                if s.len() == n {
                    return s.into_bytes();
                }
                if d == 0 && s.len() + 1 == n {
                    return format!("{s}.").into_bytes();
                }
            }
        }
        Kind::E7 if text.len() < n => {
            let (sign, digits) = match text.strip_prefix('-') {
                Some(d) => ("-", d),
                None => ("", text.as_str()),
            };
            let zeros = "0".repeat(n - text.len());
            return format!("{sign}{zeros}{digits}").into_bytes();
        }
        Kind::E7 => {}
    }
    zero_digits(original)
}

/// The bytes with every ASCII digit made `0`.
fn zero_digits(bytes: &[u8]) -> Vec<u8> {
    bytes
        .iter()
        .map(|&b| if b.is_ascii_digit() { b'0' } else { b })
        .collect()
}

/// A number of 1 to `max` digits at `i`: its value and end.
fn number_at(text: &[u8], i: usize, max: usize) -> Option<(u32, usize)> {
    let mut j = i;
    while j < text.len() && text[j].is_ascii_digit() && j - i < max {
        j += 1;
    }
    if j == i || text.get(j).is_some_and(|b| b.is_ascii_digit()) {
        return None;
    }
    let v = std::str::from_utf8(&text[i..j]).ok()?.parse().ok()?;
    Some((v, j))
}

/// A time of day at `i` (`14:47:02`, `14-47-02`, `6_5_17`, with `seps`), with an
/// optional fraction of a second: its end.
fn time_at(text: &[u8], i: usize, seps: &[u8]) -> Option<usize> {
    let (h, j) = number_at(text, i, 2)?;
    let sep = *text.get(j)?;
    if !seps.contains(&sep) {
        return None;
    }
    let (m, k) = number_at(text, j + 1, 2)?;
    if text.get(k) != Some(&sep) {
        return None;
    }
    let (s, mut end) = number_at(text, k + 1, 2)?;
    if h > 23 || m > 59 || s > 60 {
        return None;
    }
    if text.get(end) == Some(&b'.') && text.get(end + 1).is_some_and(u8::is_ascii_digit) {
        end += 1;
        while text.get(end).is_some_and(u8::is_ascii_digit) {
            end += 1;
        }
    }
    Some(end)
}

/// The dates and times of day written in a text: a date `YYYY-M-D` (or with `/`;
/// years 1970 to 2100) with the time that follows it (`2024-03-01T06:46:06`,
/// `2021-05-22/19_41_57`, `2024-3-1-14-47-02`, `2000-01-01-00:00:36`), a time of day
/// `H:MM:SS` alone, and a log file's name `H_M_S.ulg`.
pub(super) fn date_time_spans(text: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < text.len() {
        let starts = text[i].is_ascii_digit() && (i == 0 || !text[i - 1].is_ascii_alphanumeric());
        if !starts {
            i += 1;
            continue;
        }
        if let Some(end) = date_at(text, i) {
            let mut end = end;
            if let Some(&sep) = text.get(end) {
                if b"-_T /".contains(&sep) {
                    if let Some(t) = time_at(text, end + 1, b":_-") {
                        end = t;
                    }
                }
            }
            out.push((i, end));
            i = end;
            continue;
        }
        if let Some(end) = time_at(text, i, b":") {
            out.push((i, end));
            i = end;
            continue;
        }
        if let Some(end) = time_at(text, i, b"_").filter(|&e| text[e..].starts_with(b".ulg")) {
            out.push((i, end));
            i = end;
            continue;
        }
        while i < text.len() && text[i].is_ascii_digit() {
            i += 1;
        }
    }
    out
}

/// A date `YYYY-M-D` or `YYYY/M/D` at `i`: its end.
fn date_at(text: &[u8], i: usize) -> Option<usize> {
    let (y, j) = number_at(text, i, 4)?;
    if j - i != 4 || !(1970..=2100).contains(&y) {
        return None;
    }
    let sep = *text.get(j)?;
    if sep != b'-' && sep != b'/' {
        return None;
    }
    let (m, k) = number_at(text, j + 1, 2)?;
    if text.get(k) != Some(&sep) || !(1..=12).contains(&m) {
        return None;
    }
    let (d, end) = number_at(text, k + 1, 2)?;
    (1..=31).contains(&d).then_some(end)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(zero_utc: bool) -> Texts {
        let mut places = Places::new();
        places.add(47.397742, 8.545594);
        Texts {
            places,
            rotation: Some(Rotation::taking((47.397742, 8.545594), (-33.9, 151.2))),
            anchor: Some((47.397742, 8.545594)),
            zero_utc,
        }
    }

    fn edit(t: &Texts, s: &str, same_length: bool) -> String {
        String::from_utf8(
            t.edit(s.as_bytes(), same_length)
                .unwrap_or(s.as_bytes().to_vec()),
        )
        .unwrap()
    }

    #[test]
    fn dates_and_times_become_zeros() {
        let t = texts(true);
        for (from, to) in [
            (
                "[logger] Opened full log file: /fs/microsd/log/2021-05-22/19_41_57.ulg",
                "[logger] Opened full log file: /fs/microsd/log/0000-00-00/00_00_00.ulg",
            ),
            (
                "opening log file 2026-8-20/6_5_17.ulg",
                "opening log file 0000-0-00/0_0_00.ulg",
            ),
            (
                "log_123_2024-3-1-14-47-02.ulg",
                "log_123_0000-0-0-00-00-00.ulg",
            ),
            (
                "-- 2000-01-01-00:00:36 Begin",
                "-- 0000-00-00-00:00:00 Begin",
            ),
            ("at 06:46:06.25 UTC", "at 00:00:00.00 UTC"),
            ("file 19_41_57.ulg", "file 00_00_00.ulg"),
        ] {
            assert_eq!(edit(&t, from, true), to);
        }
        // Not dates or times: versions, counters, ids, a ratio.
        for same in [
            "v1.14.0-2024",
            "imu_1_2_3 ok",
            "12:30",
            "1234-56-78",
            "ESC 2024-13-01",
            "sess100/log100.ulg",
        ] {
            assert_eq!(edit(&t, same, true), same);
        }
        assert_eq!(
            edit(&texts(false), "2021-05-22/19_41_57.ulg", true),
            "2021-05-22/19_41_57.ulg"
        );
    }

    #[test]
    fn positions_in_text_move_and_other_numbers_stay() {
        let t = texts(false);
        assert_eq!(
            edit(&t, "home: 47.397742, 8.545594 alt 488.1", false),
            "home: -33.900000, 151.200000 alt 488.1"
        );
        assert_eq!(
            edit(&t, "lat 473977420 lon 85455940", false),
            "lat -339000000 lon 1512000000"
        );
        // Same length: fewer decimals where the sign or the degrees take room.
        assert_eq!(
            edit(&t, "home: 47.397742, 8.545594", true),
            "home: -33.90000, 151.2000"
        );
        // A lone coordinate with 5 decimals or more moves, a coarser one stays.
        assert_eq!(edit(&t, "lat=47.39774", false), "lat=-33.90000");
        assert_eq!(edit(&t, "load 47.39%", false), "load 47.39%");
        for same in [
            "v47.397742",
            "1.14.0",
            "battery 8.54 V",
            "t 1234567 us",
            "x47.3977",
        ] {
            assert_eq!(edit(&t, same, false), same);
        }
    }
}
