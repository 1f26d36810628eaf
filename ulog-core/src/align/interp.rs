//! Linear interpolation of a payload between two rows of one format: `float` and
//! `double` leaves interpolated, quaternions (`q[4]` of `float`s) by slerp, every
//! other leaf (integers, booleans, enums, strings) the earlier row's.

use ulog_format::{BasicType, Layout, LeafKind};

/// Where the interpolated leaves of a format are: `float`/`double` scalars, and
/// quaternions (the offsets of `q[0]`, four `float`s in a row).
#[derive(Debug, Clone, Default)]
pub(crate) struct Lerp {
    floats: Vec<(usize, BasicType)>,
    quaternions: Vec<usize>,
}

impl Lerp {
    /// The interpolated leaves of `layout`.
    pub(crate) fn new(layout: &Layout) -> Lerp {
        let leaves: Vec<_> = layout.columns().collect();
        let mut out = Lerp::default();
        let mut i = 0;
        while i < leaves.len() {
            let l = leaves[i];
            let quaternion = l.ty == BasicType::Float
                && (l.path == "q[0]" || l.path.ends_with(".q[0]"))
                && leaves.get(i + 3).is_some_and(|last| {
                    let base = &l.path[..l.path.len() - 3];
                    (1..4).all(|k| {
                        leaves[i + k].path == format!("{base}[{k}]")
                            && leaves[i + k].offset == l.offset + 4 * k
                    }) && last.ty == BasicType::Float
                });
            if quaternion {
                out.quaternions.push(l.offset);
                i += 4;
                continue;
            }
            if l.kind == LeafKind::Scalar && l.ty.is_float() {
                out.floats.push((l.offset, l.ty));
            }
            i += 1;
        }
        out
    }

    /// Whether the format has nothing to interpolate.
    pub(crate) fn is_empty(&self) -> bool {
        self.floats.is_empty() && self.quaternions.is_empty()
    }

    /// The payload at fraction `w` (0..1) from `a` to `b`, into `out`: `a`'s bytes,
    /// its floats and quaternions replaced. `a` and `b` must be of the same format.
    pub(crate) fn between(&self, a: &[u8], b: &[u8], w: f64, out: &mut Vec<u8>) {
        out.clear();
        out.extend_from_slice(a);
        for &(at, ty) in &self.floats {
            match ty {
                BasicType::Float => {
                    let (Some(x), Some(y)) = (f32_at(a, at), f32_at(b, at)) else {
                        continue;
                    };
                    let v = lerp(f64::from(x), f64::from(y), w) as f32;
                    out[at..at + 4].copy_from_slice(&v.to_le_bytes());
                }
                _ => {
                    let (Some(x), Some(y)) = (f64_at(a, at), f64_at(b, at)) else {
                        continue;
                    };
                    out[at..at + 8].copy_from_slice(&lerp(x, y, w).to_le_bytes());
                }
            }
        }
        for &at in &self.quaternions {
            let read = |p: &[u8]| -> Option<[f64; 4]> {
                let mut q = [0.0; 4];
                for (k, v) in q.iter_mut().enumerate() {
                    *v = f64::from(f32_at(p, at + 4 * k)?);
                }
                Some(q)
            };
            let (Some(x), Some(y)) = (read(a), read(b)) else {
                continue;
            };
            for (k, v) in slerp(x, y, w).iter().enumerate() {
                let o = at + 4 * k;
                out[o..o + 4].copy_from_slice(&(*v as f32).to_le_bytes());
            }
        }
    }
}

/// `x + w (y - x)`, as `numpy.interp` computes it: the end values exactly at `w` 0
/// and 1.
pub(crate) fn lerp(x: f64, y: f64, w: f64) -> f64 {
    if w == 0.0 {
        x
    } else if w == 1.0 {
        y
    } else {
        x + w * (y - x)
    }
}

fn f32_at(p: &[u8], at: usize) -> Option<f32> {
    p.get(at..at + 4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

fn f64_at(p: &[u8], at: usize) -> Option<f64> {
    let b: [u8; 8] = p.get(at..at + 8)?.try_into().ok()?;
    Some(f64::from_le_bytes(b))
}

/// Spherical linear interpolation of unit quaternions along the shorter arc (`q` and
/// `-q` are one rotation), normalised; `x` itself when either is not a rotation (all
/// zeros, NaN).
pub(crate) fn slerp(x: [f64; 4], y: [f64; 4], w: f64) -> [f64; 4] {
    let norm = |q: [f64; 4]| q.iter().map(|v| v * v).sum::<f64>().sqrt();
    let (nx, ny) = (norm(x), norm(y));
    if !(nx > 0.0 && ny > 0.0 && nx.is_finite() && ny.is_finite()) {
        return x;
    }
    let x = x.map(|v| v / nx);
    let mut y = y.map(|v| v / ny);
    let mut dot: f64 = x.iter().zip(&y).map(|(a, b)| a * b).sum();
    if dot < 0.0 {
        y = y.map(|v| -v);
        dot = -dot;
    }
    let (a, b) = if dot > 0.9995 {
        // Nearly the same rotation: linear, then normalised.
        (1.0 - w, w)
    } else {
        let theta = dot.min(1.0).acos();
        let s = theta.sin();
        (((1.0 - w) * theta).sin() / s, (w * theta).sin() / s)
    };
    let q: [f64; 4] = core::array::from_fn(|k| a * x[k] + b * y[k]);
    let n = norm(q);
    q.map(|v| v / n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slerp_halves_a_rotation_about_one_axis() {
        // 0 and 90 degrees about z: halfway is 45 degrees.
        let h = std::f64::consts::FRAC_PI_4;
        let q = slerp([1.0, 0.0, 0.0, 0.0], [h.cos(), 0.0, 0.0, h.sin()], 0.5);
        let e = std::f64::consts::FRAC_PI_8;
        for (a, b) in q.iter().zip([e.cos(), 0.0, 0.0, e.sin()]) {
            assert!((a - b).abs() < 1e-12, "{q:?}");
        }
        // The shorter arc: -q is the same rotation as q.
        let q = slerp([1.0, 0.0, 0.0, 0.0], [-h.cos(), 0.0, 0.0, -h.sin()], 0.5);
        assert!((q[3] - e.sin()).abs() < 1e-12, "{q:?}");
        assert_eq!(slerp([0.0; 4], [1.0, 0.0, 0.0, 0.0], 0.5), [0.0; 4]);
    }

    #[test]
    fn floats_interpolate_and_the_rest_stays_the_earlier_rows() {
        let format = ulog_format::Format::parse(
            "m:uint64_t timestamp;float x;double y;int32_t n;bool b;float[4] q;",
        )
        .unwrap();
        let layout = Layout::resolve("m", &[format][..]).unwrap();
        let lerp = Lerp::new(&layout);
        let row = |t: u64, x: f32, y: f64, n: i32, b: u8, q: [f32; 4]| {
            let mut p = t.to_le_bytes().to_vec();
            p.extend_from_slice(&x.to_le_bytes());
            p.extend_from_slice(&y.to_le_bytes());
            p.extend_from_slice(&n.to_le_bytes());
            p.push(b);
            for v in q {
                p.extend_from_slice(&v.to_le_bytes());
            }
            p
        };
        let a = row(10, 1.0, 10.0, 7, 0, [1.0, 0.0, 0.0, 0.0]);
        let b = row(20, 3.0, 30.0, 9, 1, [0.0, 0.0, 0.0, 1.0]);
        let mut out = Vec::new();
        lerp.between(&a, &b, 0.25, &mut out);
        assert_eq!(
            &out[..8],
            &10u64.to_le_bytes(),
            "the earlier row's timestamp"
        );
        assert_eq!(f32_at(&out, 8), Some(1.5));
        assert_eq!(f64_at(&out, 12), Some(15.0));
        assert_eq!(
            &out[20..25],
            &[7, 0, 0, 0, 0],
            "integers and booleans: previous"
        );
        let q: Vec<f32> = (0..4).map(|k| f32_at(&out, 25 + 4 * k).unwrap()).collect();
        let e = std::f64::consts::FRAC_PI_8;
        assert!((f64::from(q[0]) - e.cos()).abs() < 1e-6, "{q:?}");
        assert!((f64::from(q[3]) - e.sin()).abs() < 1e-6, "{q:?}");
    }
}
