//! An event's message template filled in, by the rules of PX4's events library:
//!
//! - `\x` stands for `x` itself (`\{`, `\<`);
//! - tags: `<profile name="[!]NAME">…</profile>` keeps its content only for that
//!   profile (or all others, with `!`); `<a [href="URL"]>…</a>` and
//!   `<param>NAME</param>` keep their content as it is; an unknown tag is left out
//!   with its content; text that is not a well-formed tag stays as it is;
//! - arguments: `{N}` (1-based), `{N:.D}` with D decimals, and a unit after it:
//!   `m`, `m_v` (shown `m`), `m/s`, `m^2`, `C`, shown after a space;
//! - integers in decimal, floats as the shortest decimal that reads back as the
//!   same value (as Python prints them), enums by their entry's description (an
//!   unknown value as `(unknown: V)`), bitfields as the descriptions of their set
//!   bits joined by the enum's separator (`|` unless it says);
//! - the result is trimmed of white space.

use crate::events::metadata::EnumDef;

/// A decoded argument.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ArgValue {
    /// An unsigned integer (`uint8_t` … `uint64_t`).
    Unsigned(u64),
    /// A signed integer (`int8_t` … `int64_t`).
    Signed(i64),
    /// A `float`.
    Float(f32),
}

impl ArgValue {
    fn as_f64(self) -> f64 {
        match self {
            ArgValue::Unsigned(v) => v as f64,
            ArgValue::Signed(v) => v as f64,
            ArgValue::Float(v) => f64::from(v),
        }
    }

    fn as_u64(self) -> u64 {
        match self {
            ArgValue::Unsigned(v) => v,
            ArgValue::Signed(v) => v as u64,
            ArgValue::Float(v) => v as u64,
        }
    }
}

impl std::fmt::Display for ArgValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ArgValue::Unsigned(v) => write!(f, "{v}"),
            ArgValue::Signed(v) => write!(f, "{v}"),
            ArgValue::Float(v) => f.write_str(&shortest(f64::from(*v))),
        }
    }
}

/// The size in bytes of a basic type's value, and how to read it.
pub(crate) fn read_basic(ty: &str, bytes: &[u8]) -> Option<(ArgValue, usize)> {
    let take = |n: usize| bytes.get(..n);
    Some(match ty {
        "uint8_t" => (ArgValue::Unsigned(u64::from(take(1)?[0])), 1),
        "int8_t" => (ArgValue::Signed(i64::from(take(1)?[0] as i8)), 1),
        "uint16_t" => (
            ArgValue::Unsigned(u64::from(u16::from_le_bytes(take(2)?.try_into().ok()?))),
            2,
        ),
        "int16_t" => (
            ArgValue::Signed(i64::from(i16::from_le_bytes(take(2)?.try_into().ok()?))),
            2,
        ),
        "uint32_t" => (
            ArgValue::Unsigned(u64::from(u32::from_le_bytes(take(4)?.try_into().ok()?))),
            4,
        ),
        "int32_t" => (
            ArgValue::Signed(i64::from(i32::from_le_bytes(take(4)?.try_into().ok()?))),
            4,
        ),
        "uint64_t" => (
            ArgValue::Unsigned(u64::from_le_bytes(take(8)?.try_into().ok()?)),
            8,
        ),
        "int64_t" => (
            ArgValue::Signed(i64::from_le_bytes(take(8)?.try_into().ok()?)),
            8,
        ),
        "float" => (
            ArgValue::Float(f32::from_le_bytes(take(4)?.try_into().ok()?)),
            4,
        ),
        _ => return None,
    })
}

/// The size of a basic type (`None`: not one).
pub(crate) fn basic_size(ty: &str) -> Option<usize> {
    Some(match ty {
        "uint8_t" | "int8_t" => 1,
        "uint16_t" | "int16_t" => 2,
        "uint32_t" | "int32_t" | "float" => 4,
        "uint64_t" | "int64_t" => 8,
        _ => return None,
    })
}

/// An argument as the template shows it: its value, or its enum's words.
pub(crate) fn display(value: ArgValue, en: Option<&EnumDef>) -> Shown {
    let Some(en) = en else {
        return Shown::Value(value);
    };
    let v = value.as_u64();
    if en.is_bitfield {
        let bits = basic_size(&en.ty).unwrap_or(8) * 8;
        let mut out = String::new();
        let mut had = false;
        for i in 0..bits.min(64) {
            let bit = 1u64 << i;
            if v & bit == 0 {
                continue;
            }
            if had {
                out.push_str(&en.separator);
            }
            match en.entries.iter().find(|(e, _)| *e == bit) {
                Some((_, d)) => out.push_str(d),
                None => out.push_str(&format!("(unknown: {value})")),
            }
            had = true;
        }
        return Shown::Text(out);
    }
    match en.entries.iter().find(|(e, _)| *e == v) {
        Some((_, d)) => Shown::Text(d.clone()),
        None => Shown::Text(format!("(unknown: {value})")),
    }
}

/// An argument ready to be put in the text.
#[derive(Debug, Clone)]
pub(crate) enum Shown {
    Value(ArgValue),
    Text(String),
}

impl Shown {
    fn render(&self, decimals: Option<usize>) -> String {
        match (self, decimals) {
            (Shown::Value(v), None) => v.to_string(),
            (Shown::Value(v), Some(d)) => fixed(v.as_f64(), d),
            (Shown::Text(t), _) => t.clone(),
        }
    }
}

/// `template` filled in with `args` for `profile`.
pub(crate) fn fill(template: &str, args: &[Shown], profile: &str) -> String {
    let mut msg: Vec<char> = template.chars().collect();
    let mut i = 0;
    while i < msg.len() {
        match msg[i] {
            '\\' => {
                // The next character is itself.
                msg.remove(i);
                i += 1;
            }
            '<' => match tag_at(&msg, i) {
                None => i += 1,
                Some(tag) => {
                    let content: Vec<char> = msg[tag.content.clone()].to_vec();
                    let (replace, skip) = match tag.name.as_str() {
                        "profile" => {
                            let wanted = tag.value.unwrap_or_default();
                            let keep = match wanted.strip_prefix('!') {
                                Some(not) => profile != not,
                                None => profile == wanted,
                            };
                            // Kept content is read on (it may hold arguments).
                            (if keep { content } else { Vec::new() }, 0)
                        }
                        "a" | "param" => {
                            let n = content.len();
                            (content, n)
                        }
                        _ => (Vec::new(), 0),
                    };
                    msg.splice(i..tag.end, replace);
                    i += skip;
                }
            },
            '{' => match argument_at(&msg, i, args) {
                None => i += 1,
                Some((end, text)) => {
                    let text: Vec<char> = text.chars().collect();
                    let n = text.len();
                    msg.splice(i..end, text);
                    i += n;
                }
            },
            _ => i += 1,
        }
    }
    let s: String = msg.into_iter().collect();
    s.trim().to_owned()
}

/// A tag at `msg[i]` (`<`): its name, its one attribute's value, where its content
/// is, and where its end tag ends.
struct Tag {
    name: String,
    value: Option<String>,
    content: std::ops::Range<usize>,
    end: usize,
}

fn tag_at(msg: &[char], i: usize) -> Option<Tag> {
    let mut j = i + 1;
    let lower = |c: char| c.is_ascii_lowercase();
    let start = j;
    while j < msg.len() && lower(msg[j]) {
        j += 1;
    }
    if j == start {
        return None;
    }
    let name: String = msg[start..j].iter().collect();
    let mut value = None;
    if msg.get(j) == Some(&' ') {
        // ` attr="value"`
        let a = j + 1;
        let mut k = a;
        while k < msg.len() && lower(msg[k]) {
            k += 1;
        }
        if k == a || msg.get(k) != Some(&'=') || msg.get(k + 1) != Some(&'"') {
            return None;
        }
        let v = k + 2;
        let close = v + msg[v..].iter().position(|&c| c == '"')?;
        value = Some(msg[v..close].iter().collect());
        j = close + 1;
    }
    if msg.get(j) != Some(&'>') {
        return None;
    }
    let content_start = j + 1;
    // At least one character of content.
    if content_start >= msg.len() {
        return None;
    }
    let closing: Vec<char> = format!("</{name}>").chars().collect();
    let end_tag = (content_start..=msg.len().saturating_sub(closing.len()))
        .find(|&p| msg[p..].starts_with(&closing))?;
    Some(Tag {
        name,
        value,
        content: content_start..end_tag,
        end: end_tag + closing.len(),
    })
}

/// An argument at `msg[i]` (`{`): where it ends, and its text.
fn argument_at(msg: &[char], i: usize, args: &[Shown]) -> Option<(usize, String)> {
    let close = i + msg[i..].iter().position(|&c| c == '}')?;
    let spec: String = msg[i + 1..close].iter().collect();
    let digits = spec.chars().take_while(char::is_ascii_digit).count();
    if digits == 0 {
        return None;
    }
    let index: usize = spec[..digits].parse().ok()?;
    let mut rest = &spec[digits..];
    let mut decimals = None;
    if let Some(r) = rest.strip_prefix(':') {
        rest = r;
        if let Some(r) = rest.strip_prefix('.') {
            let n = r.chars().take_while(char::is_ascii_digit).count();
            if n == 0 {
                return None;
            }
            decimals = Some(r[..n].parse().ok()?);
            rest = &r[n..];
        }
    }
    let unit = match rest {
        "" => None,
        "m" | "m_v" => Some("m"),
        "m/s" => Some("m/s"),
        "m^2" => Some("m^2"),
        "C" => Some("C"),
        _ => return None,
    };
    let arg = args.get(index.checked_sub(1)?)?;
    let mut text = arg.render(decimals);
    if let Some(u) = unit {
        text.push(' ');
        text.push_str(u);
    }
    Some((close + 1, text))
}

/// `x` with `d` decimals (`nan`, `inf` as Python writes them).
fn fixed(x: f64, d: usize) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.into();
    }
    format!("{x:.d$}")
}

/// The shortest decimal that reads back as `x`, written as Python's `repr` writes
/// it: positional from 1e-4 up to below 1e16 (with `.0` for whole numbers),
/// scientific with a signed exponent of at least two digits otherwise.
pub(crate) fn shortest(x: f64) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.into();
    }
    // Rust's `{:e}` gives the shortest round-trip digits: `d.ddde-N`.
    let e = format!("{:e}", x.abs());
    let (mantissa, exp) = e.split_once('e').unwrap_or((&e, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    let sign = if x.is_sign_negative() { "-" } else { "" };
    if (-4..16).contains(&exp) {
        let n = digits.len() as i32;
        let body = if exp >= 0 {
            let int_len = (exp + 1) as usize;
            if digits.len() <= int_len {
                format!("{digits}{}.0", "0".repeat(int_len - digits.len()))
            } else {
                format!("{}.{}", &digits[..int_len], &digits[int_len..])
            }
        } else {
            let _ = n;
            format!("0.{}{digits}", "0".repeat((-exp - 1) as usize))
        };
        return format!("{sign}{body}");
    }
    let m = if digits.len() > 1 {
        format!("{}.{}", &digits[..1], &digits[1..])
    } else {
        digits
    };
    let es = if exp < 0 { '-' } else { '+' };
    format!("{sign}{m}e{es}{:02}", exp.abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_print_as_python_prints_them() {
        let cases: &[(f64, &str)] = &[
            (1.0, "1.0"),
            (0.1, "0.1"),
            (f64::from(0.1f32), "0.10000000149011612"),
            (1e-5, "1e-05"),
            (1.5e-4, "0.00015"),
            (123456.0, "123456.0"),
            (1e16, "1e+16"),
            (1.2345e16, "1.2345e+16"),
            (9999999999999998.0, "9999999999999998.0"),
            (-2.5, "-2.5"),
            (-0.0, "-0.0"),
            (0.0, "0.0"),
            (f64::NAN, "nan"),
            (f64::NEG_INFINITY, "-inf"),
        ];
        for (x, want) in cases {
            assert_eq!(shortest(*x), *want, "{x:e}");
        }
        assert_eq!(fixed(2.345, 1), "2.3");
        assert_eq!(fixed(5.0, 2), "5.00");
    }

    fn en(bitfield: bool) -> EnumDef {
        EnumDef {
            ty: "uint8_t".into(),
            is_bitfield: bitfield,
            separator: if bitfield { ", ".into() } else { "|".into() },
            entries: vec![(1, "one".into()), (2, "two".into()), (8, "eight".into())],
        }
    }

    #[test]
    fn templates_fill_by_the_events_library_rules() {
        let args = [
            Shown::Value(ArgValue::Float(2.5)),
            Shown::Value(ArgValue::Unsigned(7)),
            display(ArgValue::Unsigned(2), Some(&en(false))),
            display(ArgValue::Unsigned(11), Some(&en(true))),
            display(ArgValue::Unsigned(5), Some(&en(false))),
            Shown::Value(ArgValue::Signed(-3)),
        ];
        let f = |t: &str| fill(t, &args, "normal");
        assert_eq!(f("alt {1:.1m_v}, speed {1m/s}"), "alt 2.5 m, speed 2.5 m/s");
        assert_eq!(f("{2} sats, {2:.2} {6}"), "7 sats, 7.00 -3");
        assert_eq!(
            f("mode {3}, bits {4}, {5}"),
            "mode two, bits one, two, eight, (unknown: 5)"
        );
        assert_eq!(f("set <param>COM_ARM</param> {2}"), "set COM_ARM 7");
        assert_eq!(f("<a href=\"https://x\">docs</a>"), "docs");
        assert_eq!(
            f("<profile name=\"dev\">dev {2}</profile><profile name=\"!dev\">user {2}</profile>"),
            "user 7"
        );
        assert_eq!(
            fill("<profile name=\"dev\">dev {2}</profile>", &args, "dev"),
            "dev 7"
        );
        assert_eq!(f("\\{1\\} and \\<b> {1}"), "{1} and <b> 2.5");
        // What is not an argument or tag stays; an unknown tag goes with its content.
        assert_eq!(f("{0} {9} {x} {1:q} a < b"), "{0} {9} {x} {1:q} a < b");
        assert_eq!(f("x <b>bold</b> y"), "x  y");
        assert_eq!(f("  padded {2}\t"), "padded 7");
    }
}
