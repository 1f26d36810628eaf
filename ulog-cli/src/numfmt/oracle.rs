//! The formatter this module had before it used Ryu, kept as the tests' oracle: Rust's
//! shortest `{:e}` text, re-laid out in numpy's form, with an exact tie between two
//! shortest candidates moved to the even digit after checking the value exactly.

use core::fmt::Write as _;

/// Appends `v` as numpy prints a `float32` scalar: the shortest digits that read back
/// as the same `f32` (ties between two shortest candidates go to the even digit, as
/// numpy's Dragon4 does), positional when `1e-4 <= |v| < 1e6` (numpy's bounds for
/// `float32`, compared as doubles), scientific otherwise. `scratch` is reused between
/// calls so that no value allocates.
pub fn write_numpy_f32(out: &mut Vec<u8>, scratch: &mut String, v: f32) {
    if let Some(special) = special(v.is_nan(), v.is_infinite(), v == 0.0, v.is_sign_negative()) {
        out.extend_from_slice(special);
        return;
    }
    scratch.clear();
    let _ = write!(scratch, "{v:e}");
    let bits = v.to_bits();
    let (exp_bits, frac) = ((bits >> 23) & 0xff, u64::from(bits & 0x7f_ffff));
    let (m, q) = if exp_bits == 0 {
        (frac, -149)
    } else {
        (frac | 1 << 23, exp_bits as i32 - 150)
    };
    let abs = f64::from(v.abs());
    let positional = (1e-4..1e6).contains(&abs);
    let tie_ok = |s: &str| s.parse::<f32>().ok() == Some(v.abs());
    layout_numpy(out, scratch, m, q, positional, tie_ok);
}

/// Appends `v` as numpy prints a `float64` scalar, and Python a float: the same rules
/// with bounds `1e-4 <= |v| < 1e16`.
pub fn write_numpy_f64(out: &mut Vec<u8>, scratch: &mut String, v: f64) {
    if let Some(special) = special(v.is_nan(), v.is_infinite(), v == 0.0, v.is_sign_negative()) {
        out.extend_from_slice(special);
        return;
    }
    scratch.clear();
    let _ = write!(scratch, "{v:e}");
    let bits = v.to_bits();
    let (exp_bits, frac) = ((bits >> 52) & 0x7ff, bits & ((1 << 52) - 1));
    let (m, q) = if exp_bits == 0 {
        (frac, -1074)
    } else {
        (frac | 1 << 52, exp_bits as i32 - 1075)
    };
    let positional = (1e-4..1e16).contains(&v.abs());
    let tie_ok = |s: &str| s.parse::<f64>().ok() == Some(v.abs());
    layout_numpy(out, scratch, m, q, positional, tie_ok);
}

fn special(nan: bool, inf: bool, zero: bool, neg: bool) -> Option<&'static [u8]> {
    match (nan, inf, zero, neg) {
        (true, ..) => Some(b"nan"),
        (_, true, _, true) => Some(b"-inf"),
        (_, true, _, false) => Some(b"inf"),
        (_, _, true, true) => Some(b"-0.0"),
        (_, _, true, false) => Some(b"0.0"),
        _ => None,
    }
}

/// Whether `m * 2^q` lies exactly halfway between the decimals `lo * 10^k'` and
/// `(lo + 1) * 10^k'`, i.e. equals `(10 * lo + 5) * 10^k` with `k = k' - 1`.
fn is_midpoint(m: u64, q: i32, lo: u64, k: i32) -> bool {
    if m == 0 {
        return false;
    }
    // Both sides as odd * 2^e: compare the powers of two, then the odd parts.
    let t = m.trailing_zeros();
    let (m_odd, q2) = (u128::from(m >> t), q + t as i32);
    if q2 != k {
        return false;
    }
    let Some(mid) = lo.checked_mul(10).and_then(|x| x.checked_add(5)) else {
        return false;
    };
    let mid = u128::from(mid);
    let pow5 = |e: u32| 5u128.checked_pow(e);
    if k >= 0 {
        pow5(k as u32).and_then(|p| mid.checked_mul(p)) == Some(m_odd)
    } else {
        pow5(k.unsigned_abs()).and_then(|p| m_odd.checked_mul(p)) == Some(mid)
    }
}

/// Lays out Rust's shortest `{:e}` text of `m * 2^q` (`-1.2345e-7`) as numpy does:
/// positional with at least one fractional digit, or scientific with a signed
/// two-digit exponent (`1.2345e-07`). Rust breaks a tie between two shortest
/// candidates upwards; numpy (and Python) take the even one, so an odd last digit at
/// an exact midpoint is lowered (when the lower candidate reads back the same).
fn layout_numpy(
    out: &mut Vec<u8>,
    sci: &str,
    m: u64,
    q: i32,
    positional: bool,
    reads_back: impl Fn(&str) -> bool,
) {
    let (mantissa, exp) = sci.split_once('e').unwrap_or((sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let mantissa = match mantissa.strip_prefix('-') {
        Some(m) => {
            out.push(b'-');
            m
        }
        None => mantissa,
    };
    let mut digits = [0u8; 40];
    let mut n = 0;
    for &c in mantissa.as_bytes().iter().filter(|c| c.is_ascii_digit()) {
        if n < digits.len() {
            digits[n] = c;
            n += 1;
        }
    }
    let last = digits[n - 1] - b'0';
    if last % 2 == 1 && !(n == 1 && last == 1) && n <= 19 {
        let value: u64 = digits[..n]
            .iter()
            .fold(0, |a, &d| a * 10 + u64::from(d - b'0'));
        let k = exp - n as i32;
        if is_midpoint(m, q, value - 1, k) {
            // Rare (exact midpoints only), so this one allocation does not matter.
            let scaled = format!("{}e{}", value - 1, exp - n as i32 + 1);
            if reads_back(&scaled) {
                digits[n - 1] -= 1;
            }
        }
    }
    let digits = &digits[..n];
    if positional {
        if exp >= 0 {
            let int_len = exp as usize + 1;
            out.extend_from_slice(&digits[..n.min(int_len)]);
            out.extend(core::iter::repeat(b'0').take(int_len.saturating_sub(n)));
            out.push(b'.');
            if n <= int_len {
                out.push(b'0');
            } else {
                out.extend_from_slice(&digits[int_len..]);
            }
        } else {
            out.extend_from_slice(b"0.");
            for _ in 0..(-exp - 1) {
                out.push(b'0');
            }
            out.extend_from_slice(digits);
        }
    } else {
        out.push(digits[0]);
        if n > 1 {
            out.push(b'.');
            out.extend_from_slice(&digits[1..]);
        }
        out.push(b'e');
        out.push(if exp < 0 { b'-' } else { b'+' });
        let e = exp.unsigned_abs();
        if e < 10 {
            out.push(b'0');
        }
        write_u64(out, u64::from(e));
    }
}

/// Appends an unsigned integer in decimal.
pub fn write_u64(out: &mut Vec<u8>, mut v: u64) -> usize {
    let mut buf = [0u8; 20];
    let mut i = buf.len();
    loop {
        i -= 1;
        buf[i] = b'0' + (v % 10) as u8;
        v /= 10;
        if v == 0 {
            break;
        }
    }
    out.extend_from_slice(&buf[i..]);
    buf.len() - i
}
