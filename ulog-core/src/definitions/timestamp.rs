//! Timestamps of data messages: `uint64_t` microseconds today; `uint32_t`,
//! `uint16_t` and `uint8_t` (milliseconds) in version 0 logs, which wrap around.

use ulog_format::{BasicType, Layout, LayoutType};

/// Where a topic's timestamp is and what type it has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TimestampField {
    /// Byte offset in the payload.
    pub offset: usize,
    /// `uint64_t`, `uint32_t`, `uint16_t` or `uint8_t`.
    pub ty: BasicType,
}

impl TimestampField {
    /// The top-level `timestamp` field of a layout, if it has a timestamp type.
    pub fn of(layout: &Layout) -> Option<TimestampField> {
        let f = layout.field("timestamp")?;
        match (&f.ty, f.array_len) {
            (
                LayoutType::Basic(
                    ty @ (BasicType::UInt64
                    | BasicType::UInt32
                    | BasicType::UInt16
                    | BasicType::UInt8),
                ),
                None,
            ) => Some(TimestampField {
                offset: f.offset,
                ty: *ty,
            }),
            _ => None,
        }
    }

    /// The raw value in a payload (`None` if the payload is too short).
    pub fn raw(&self, payload: &[u8]) -> Option<u64> {
        let b = payload.get(self.offset..self.offset + self.ty.size())?;
        let mut a = [0u8; 8];
        a[..b.len()].copy_from_slice(b);
        Some(u64::from_le_bytes(a))
    }

    /// Microseconds per raw unit (1000 for `uint8_t`, whose unit is milliseconds).
    pub fn unit_us(&self) -> u64 {
        if self.ty == BasicType::UInt8 {
            1000
        } else {
            1
        }
    }
}

/// Unwraps the narrow timestamps of one series into monotonic microseconds: a raw
/// value smaller than the previous one means the counter wrapped.
#[derive(Debug, Clone, Copy)]
pub struct Unwrapper {
    field: Option<TimestampField>,
    last_raw: Option<u64>,
    wraps: u64,
}

impl Unwrapper {
    /// An unwrapper for a series with this timestamp field (none: every push gives
    /// `None`).
    pub fn new(field: Option<TimestampField>) -> Unwrapper {
        Unwrapper {
            field,
            last_raw: None,
            wraps: 0,
        }
    }

    /// The timestamp field it reads (`None`: the series has none).
    pub fn field(&self) -> Option<TimestampField> {
        self.field
    }

    /// The unwrapped microseconds of the next payload of the series.
    #[inline]
    pub fn push(&mut self, payload: &[u8]) -> Option<u64> {
        let f = self.field?;
        if f.ty == BasicType::UInt64 {
            let b = payload.get(f.offset..f.offset + 8)?;
            return Some(u64::from_le_bytes(b.try_into().ok()?));
        }
        let raw = f.raw(payload)?;
        if let Some(last) = self.last_raw {
            if raw < last {
                self.wraps += 1;
            }
        }
        self.last_raw = Some(raw);
        let modulus = 1u64 << (8 * f.ty.size());
        Some((self.wraps * modulus + raw) * f.unit_us())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn narrow_timestamps_unwrap() {
        let f16 = TimestampField {
            offset: 0,
            ty: BasicType::UInt16,
        };
        let mut u = Unwrapper::new(Some(f16));
        let got: Vec<u64> = [65000u16, 65500, 100, 2000, 1]
            .iter()
            .map(|v| u.push(&v.to_le_bytes()).unwrap())
            .collect();
        assert_eq!(got, [65000, 65500, 65636, 67536, 131073]);
        let f8 = TimestampField {
            offset: 1,
            ty: BasicType::UInt8,
        };
        let mut u = Unwrapper::new(Some(f8));
        assert_eq!(u.push(&[9, 250]), Some(250_000));
        assert_eq!(u.push(&[9, 4]), Some(260_000));
        assert_eq!(u.push(&[9]), None);
    }
}
