//! Numbers as numpy and Python print them (and so pyulog's CSV and scripts): the
//! shortest digits that read back to the same value, ties to the even digit, positional
//! or scientific by numpy's bounds.
//!
//! The `format_*` functions write into a fixed `[u8; NUM_LEN]` window and return the
//! length, so that a caller filling a large buffer can hand out a window of it and never
//! grow a `Vec` per value; the `write_*` functions append to a `Vec`.

/// The size of the window the `format_*` functions write into: more than the longest
/// text they write (`-1.2345678901234567e-308`, 24 bytes; `-9223372036854775808`, 20).
pub const NUM_LEN: usize = 32;

/// Writes `v` as numpy prints a `float32` scalar at the start of `out` and returns its
/// length: the shortest digits that read back as the same `f32` (ties between two
/// shortest candidates go to the even digit, as numpy's Dragon4 does), positional when
/// `1e-4 <= |v| < 1e6` (numpy's bounds for `float32`, compared as doubles), scientific
/// otherwise (`1e-05`, `1.5e+07`).
pub fn format_numpy_f32(v: f32, out: &mut [u8; NUM_LEN]) -> usize {
    if !v.is_finite() || v == 0.0 {
        return special(out, v.is_nan(), v == 0.0, v.is_sign_negative());
    }
    // Ryu gives the shortest digits that read back as `v`, the closest to it among
    // those, an exact tie to the even digit: numpy's digits. Its positional form for
    // numpy's positional range is numpy's (`100.0`, `0.00012`, `-2.5`).
    let n = ryu_f32(v, out);
    if (1e-4..1e6).contains(&f64::from(v.abs())) {
        n
    } else {
        let text = *out;
        scientific(out, &text[..n])
    }
}

/// Writes `v` as numpy prints a `float64` scalar, and Python a float: the same rules
/// as [`format_numpy_f32`] with the bounds `1e-4 <= |v| < 1e16`.
pub fn format_numpy_f64(v: f64, out: &mut [u8; NUM_LEN]) -> usize {
    if !v.is_finite() || v == 0.0 {
        return special(out, v.is_nan(), v == 0.0, v.is_sign_negative());
    }
    let n = ryu_f64(v, out);
    if (1e-4..1e16).contains(&v.abs()) {
        n
    } else {
        let text = *out;
        scientific(out, &text[..n])
    }
}

/// Writes Ryu's text of a finite `v` at the start of `out`; returns its length.
#[inline]
#[allow(unsafe_code)]
fn ryu_f32(v: f32, out: &mut [u8; NUM_LEN]) -> usize {
    const { assert!(NUM_LEN >= 16) };
    // Straight into `out`: through Ryu's own buffer, the copy out of it waited on
    // the stores that had just filled it, a tenth of a CSV export (bench/README.md).
    // SAFETY: `v` is finite (the callers handle the others), and `out` has room
    // for the 16 bytes `format32` writes at most (asserted above).
    unsafe { ryu::raw::format32(v, out.as_mut_ptr()) }
}

/// Writes Ryu's text of a finite `v` at the start of `out`; returns its length.
#[inline]
#[allow(unsafe_code)]
fn ryu_f64(v: f64, out: &mut [u8; NUM_LEN]) -> usize {
    const { assert!(NUM_LEN >= 24) };
    // Straight into `out`: through Ryu's own buffer, the copy out of it waited on
    // the stores that had just filled it, a tenth of a CSV export (bench/README.md).
    // SAFETY: `v` is finite (the callers handle the others), and `out` has room
    // for the 24 bytes `format64` writes at most (asserted above).
    unsafe { ryu::raw::format64(v, out.as_mut_ptr()) }
}

/// Writes an unsigned integer in decimal at the start of `out`; returns its length.
pub fn format_u64(v: u64, out: &mut [u8; NUM_LEN]) -> usize {
    put_u64(out, 0, v)
}

/// Writes a signed integer in decimal at the start of `out`; returns its length.
pub fn format_i64(v: i64, out: &mut [u8; NUM_LEN]) -> usize {
    let at = usize::from(v < 0);
    out[0] = b'-';
    put_u64(out, at, v.unsigned_abs())
}

/// Appends `v` as numpy prints a `float32` scalar (see [`format_numpy_f32`]).
pub fn write_numpy_f32(out: &mut Vec<u8>, v: f32) {
    let mut text = [0u8; NUM_LEN];
    let n = format_numpy_f32(v, &mut text);
    out.extend_from_slice(&text[..n]);
}

/// Appends `v` as numpy prints a `float64` scalar and Python a float (see
/// [`format_numpy_f64`]).
pub fn write_numpy_f64(out: &mut Vec<u8>, v: f64) {
    let mut text = [0u8; NUM_LEN];
    let n = format_numpy_f64(v, &mut text);
    out.extend_from_slice(&text[..n]);
}

fn special(out: &mut [u8; NUM_LEN], nan: bool, zero: bool, neg: bool) -> usize {
    let text: &[u8] = match (nan, zero, neg) {
        (true, ..) => b"nan",
        (_, true, true) => b"-0.0",
        (_, true, false) => b"0.0",
        (_, false, true) => b"-inf",
        (_, false, false) => b"inf",
    };
    out[..text.len()].copy_from_slice(text);
    text.len()
}

/// Rewrites Ryu's text of a finite nonzero number (`-1.2345e-7`, `1e30`, `0.00005`,
/// `123.0`) in numpy's scientific form: the significant digits as `d.ddd`, then `e`, the
/// exponent's sign and at least two exponent digits (`-1.2345e-07`, `1e+30`, `5e-05`,
/// `1.23e+02`).
fn scientific(out: &mut [u8; NUM_LEN], text: &[u8]) -> usize {
    let (neg, text) = match text.split_first() {
        Some((b'-', rest)) => (true, rest),
        _ => (false, text),
    };
    let (mantissa, exp) = match text.iter().position(|&c| c == b'e') {
        Some(i) => (&text[..i], parse_exponent(&text[i + 1..])),
        None => (text, 0),
    };
    // The mantissa's digits without the point, and how many came before it.
    let mut digits = [b'0'; NUM_LEN];
    let mut n = 0;
    let mut int_len = None;
    for &c in mantissa {
        if c == b'.' {
            int_len = Some(n);
        } else if n < NUM_LEN {
            digits[n] = c;
            n += 1;
        }
    }
    let int_len = int_len.unwrap_or(n);
    let lead = digits[..n]
        .iter()
        .take_while(|&&d| d == b'0')
        .count()
        .min(n.saturating_sub(1));
    let mut end = n.max(1);
    while end > lead + 1 && digits[end - 1] == b'0' {
        end -= 1;
    }
    let sig = &digits[lead..end];
    let e10 = exp + int_len as i32 - 1 - lead as i32;

    let mut i = usize::from(neg);
    out[0] = b'-';
    out[i] = sig[0];
    i += 1;
    if sig.len() > 1 {
        out[i] = b'.';
        out[i + 1..i + sig.len()].copy_from_slice(&sig[1..]);
        i += sig.len();
    }
    out[i] = b'e';
    out[i + 1] = if e10 < 0 { b'-' } else { b'+' };
    i += 2;
    let e = e10.unsigned_abs();
    if e < 10 {
        out[i] = b'0';
        i += 1;
    }
    put_u64(out, i, u64::from(e))
}

/// The value of Ryu's exponent text (`-7`, `30`).
fn parse_exponent(text: &[u8]) -> i32 {
    let (neg, digits) = match text.split_first() {
        Some((b'-', rest)) => (true, rest),
        _ => (false, text),
    };
    let e = digits
        .iter()
        .fold(0i32, |a, &d| a * 10 + i32::from(d.wrapping_sub(b'0')));
    if neg {
        -e
    } else {
        e
    }
}

/// Two decimal digits for each number below 100.
const PAIRS: &[u8; 200] = b"\
0001020304050607080910111213141516171819\
2021222324252627282930313233343536373839\
4041424344454647484950515253545556575859\
6061626364656667686970717273747576777879\
8081828384858687888990919293949596979899";

/// Writes `v` in decimal at `out[at..]`; returns the end of its text.
#[inline]
fn put_u64(out: &mut [u8; NUM_LEN], at: usize, v: u64) -> usize {
    let len = v.checked_ilog10().unwrap_or(0) as usize + 1;
    let end = at + len;
    let mut i = end;
    let mut x = v;
    while x >= 100 {
        let r = (x % 100) as usize * 2;
        x /= 100;
        i -= 2;
        out[i..i + 2].copy_from_slice(&PAIRS[r..r + 2]);
    }
    if x >= 10 {
        let r = x as usize * 2;
        out[at..at + 2].copy_from_slice(&PAIRS[r..r + 2]);
    } else {
        out[at] = b'0' + x as u8;
    }
    end
}

#[cfg(test)]
mod oracle;

#[cfg(test)]
mod tests {
    use super::*;
    use ulog_core::testing::Rng;

    fn f32s(v: f32) -> String {
        let mut out = Vec::new();
        write_numpy_f32(&mut out, v);
        String::from_utf8(out).unwrap()
    }

    fn f64s(v: f64) -> String {
        let mut out = Vec::new();
        write_numpy_f64(&mut out, v);
        String::from_utf8(out).unwrap()
    }

    /// Expected texts are numpy 2.4's `str(np.float32(v))` and Python's `repr(v)`.
    #[test]
    fn floats_print_like_numpy() {
        let cases: &[(f32, &str)] = &[
            (0.1, "0.1"),
            (1.0, "1.0"),
            (100.0, "100.0"),
            (-2.5, "-2.5"),
            (1e-5, "1e-05"),
            (1.5e-7, "1.5e-07"),
            // f32 0.0001 is just below 1e-4: numpy prints it in scientific form.
            (0.0001, "1e-04"),
            (0.00012345, "0.00012345"),
            (3.4028235e38, "3.4028235e+38"),
            (1e16, "1e+16"),
            // numpy's float32 switches to scientific form at 1e6, not 1e16.
            (123456790.0, "1.2345679e+08"),
            (4e6, "4e+06"),
            (999999.94, "999999.94"),
            // Exact midpoints between two shortest candidates go to the even digit.
            (f32::from_bits(0x43f4_0200), "488.01562"),
            (-0.047851563, "-0.047851562"),
            (f32::NAN, "nan"),
            (f32::NEG_INFINITY, "-inf"),
            (-0.0, "-0.0"),
        ];
        for &(v, s) in cases {
            assert_eq!(f32s(v), s, "{v:e}");
        }
        assert_eq!(f64s(f64::from(0.1f32)), "0.10000000149011612");
        assert_eq!(f64s(1e15), "1000000000000000.0");
        assert_eq!(f64s(1e16), "1e+16");
        assert_eq!(f64s(2f64.powi(60)), "1.152921504606847e+18");
        assert_eq!(f64s(0.5 + 2f64.powi(-53)), "0.5000000000000001");
        assert_eq!(f64s(-1.25e-100), "-1.25e-100");
        assert_eq!(f64s(5e-324), "5e-324");
        assert_eq!(f64s(-f64::MAX), "-1.7976931348623157e+308");
        assert_eq!(f64s(f64::INFINITY), "inf");
    }

    #[test]
    fn integers_print_in_decimal() {
        let mut cases: Vec<u64> = vec![0, 9, 10, 99, 100, 101, u64::MAX, u64::MAX - 1];
        for k in 0..20 {
            let p = 10u64.pow(k);
            cases.extend([p - 1, p, p + 1, p.saturating_mul(3).saturating_sub(7)]);
        }
        let mut out = [0u8; NUM_LEN];
        for v in cases {
            let n = format_u64(v, &mut out);
            assert_eq!(&out[..n], v.to_string().as_bytes());
            for s in [v as i64, (v as i64).wrapping_neg(), i64::MIN, i64::MAX] {
                let n = format_i64(s, &mut out);
                assert_eq!(&out[..n], s.to_string().as_bytes());
            }
        }
    }

    /// The significant digits of a number's text (`"-0.00120e+05"` → `"12"`).
    fn significant(text: &str) -> String {
        let mantissa = text.split('e').next().unwrap_or_default();
        let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
        digits.trim_matches('0').to_owned()
    }

    /// Checks that the new and the old formatter agree on `v`; returns whether this
    /// was a tie that the old one had to move to the even digit (Rust's shortest
    /// digits differ from numpy's).
    fn same_f32(v: f32) -> bool {
        let mut new = Vec::new();
        write_numpy_f32(&mut new, v);
        let mut old = Vec::new();
        oracle::write_numpy_f32(&mut old, &mut String::new(), v);
        let new = String::from_utf8(new).unwrap();
        assert_eq!(
            new,
            String::from_utf8(old).unwrap(),
            "f32 bits {:#010x}",
            v.to_bits()
        );
        v.is_finite() && significant(&new) != significant(&format!("{v:e}"))
    }

    fn same_f64(v: f64) -> bool {
        let mut new = Vec::new();
        write_numpy_f64(&mut new, v);
        let mut old = Vec::new();
        oracle::write_numpy_f64(&mut old, &mut String::new(), v);
        let new = String::from_utf8(new).unwrap();
        assert_eq!(
            new,
            String::from_utf8(old).unwrap(),
            "f64 bits {:#018x}",
            v.to_bits()
        );
        v.is_finite() && significant(&new) != significant(&format!("{v:e}"))
    }

    /// Values of the form `n * 2^-j` are exact decimals ending in 5: many of them lie
    /// exactly halfway between two shortest candidates, where numpy takes the even one.
    #[test]
    fn f32_agrees_with_the_old_formatter() {
        let mut rng = Rng::new(0x9e37_79b9_7f4a_7c15);
        for _ in 0..400_000 {
            same_f32(f32::from_bits(rng.next_u64() as u32));
        }
        let mut ties = 0;
        for _ in 0..200_000 {
            let r = rng.next_u64();
            let n = (r >> 40) as u32 & 0xff_ffff;
            let j = (r % 60) as i32 - 20;
            ties += usize::from(same_f32(n as f32 * 2f32.powi(-j)));
            ties += usize::from(same_f32(-(n as f32) * 2f32.powi(-j)));
        }
        assert!(ties > 100, "only {ties} ties were checked");
        // Around numpy's bounds, the extremes and subnormals.
        for edge in [1e-4f32, 1e6, 1e16, f32::MAX, f32::MIN_POSITIVE, 1.0, 0.1] {
            let b = edge.to_bits();
            for bits in b.saturating_sub(2000)..b.saturating_add(2000).min(0x7f7f_ffff) {
                same_f32(f32::from_bits(bits));
            }
        }
        for bits in 1..20_000 {
            same_f32(f32::from_bits(bits));
        }
    }

    #[test]
    fn f64_agrees_with_the_old_formatter() {
        let mut rng = Rng::new(0x2545_f491_4f6c_dd1d);
        let mut ties = 0;
        for _ in 0..200_000 {
            same_f64(f64::from_bits(rng.next_u64()));
        }
        for _ in 0..100_000 {
            let r = rng.next_u64();
            let n = r >> 11;
            let j = (rng.next_u64() % 140) as i32 - 40;
            ties += usize::from(same_f64(n as f64 * 2f64.powi(-j)));
            // Short decimals, as sensors and parameters hold them.
            let short = (r % 1_000_000) as f64 * 10f64.powi(j % 20);
            same_f64(short);
            same_f64(f64::from(short as f32));
        }
        assert!(ties > 100, "only {ties} ties were checked");
        for edge in [1e-4f64, 1e16, f64::MAX, f64::MIN_POSITIVE, 1.0] {
            let b = edge.to_bits();
            for bits in b - 2000..(b + 2000).min(0x7fef_ffff_ffff_ffff) {
                same_f64(f64::from_bits(bits));
            }
        }
        for bits in 1..20_000 {
            same_f64(f64::from_bits(bits));
        }
    }

    /// Every 16th `f32` bit pattern (268 million values); slow, run with
    /// `cargo test --release -p ulog-cli -- --ignored`.
    #[test]
    #[ignore = "slow (268 million values): cargo test --release -p ulog-cli -- --ignored"]
    fn f32_agrees_with_the_old_formatter_on_every_16th_pattern() {
        std::thread::scope(|s| {
            for t in 0..4u32 {
                s.spawn(move || {
                    let mut new = Vec::new();
                    let mut old = Vec::new();
                    let mut scratch = String::new();
                    let mut bits = t * 16;
                    loop {
                        let v = f32::from_bits(bits);
                        new.clear();
                        old.clear();
                        write_numpy_f32(&mut new, v);
                        oracle::write_numpy_f32(&mut old, &mut scratch, v);
                        assert_eq!(new, old, "f32 bits {bits:#010x}");
                        match bits.checked_add(64) {
                            Some(b) => bits = b,
                            None => break,
                        }
                    }
                });
            }
        });
    }
}
