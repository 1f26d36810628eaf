//! The twelve basic ULog types.

use core::fmt;

/// One of the basic binary types of ULog (all little endian, unaligned).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BasicType {
    /// `int8_t`
    Int8,
    /// `uint8_t`
    UInt8,
    /// `int16_t`
    Int16,
    /// `uint16_t`
    UInt16,
    /// `int32_t`
    Int32,
    /// `uint32_t`
    UInt32,
    /// `int64_t`
    Int64,
    /// `uint64_t`
    UInt64,
    /// `float` (IEEE 754 binary32)
    Float,
    /// `double` (IEEE 754 binary64)
    Double,
    /// `bool` (one byte, non-zero is true)
    Bool,
    /// `char` (one byte; arrays of it are strings without a terminating NUL)
    Char,
}

impl BasicType {
    /// Every basic type, in the order of the spec's table.
    pub const ALL: [BasicType; 12] = [
        BasicType::Int8,
        BasicType::UInt8,
        BasicType::Int16,
        BasicType::UInt16,
        BasicType::Int32,
        BasicType::UInt32,
        BasicType::Int64,
        BasicType::UInt64,
        BasicType::Float,
        BasicType::Double,
        BasicType::Bool,
        BasicType::Char,
    ];

    /// Size in bytes of one value.
    #[inline]
    pub const fn size(self) -> usize {
        match self {
            BasicType::Int8 | BasicType::UInt8 | BasicType::Bool | BasicType::Char => 1,
            BasicType::Int16 | BasicType::UInt16 => 2,
            BasicType::Int32 | BasicType::UInt32 | BasicType::Float => 4,
            BasicType::Int64 | BasicType::UInt64 | BasicType::Double => 8,
        }
    }

    /// The name used in format strings, e.g. `uint16_t`.
    pub const fn name(self) -> &'static str {
        match self {
            BasicType::Int8 => "int8_t",
            BasicType::UInt8 => "uint8_t",
            BasicType::Int16 => "int16_t",
            BasicType::UInt16 => "uint16_t",
            BasicType::Int32 => "int32_t",
            BasicType::UInt32 => "uint32_t",
            BasicType::Int64 => "int64_t",
            BasicType::UInt64 => "uint64_t",
            BasicType::Float => "float",
            BasicType::Double => "double",
            BasicType::Bool => "bool",
            BasicType::Char => "char",
        }
    }

    /// The basic type of a format-string type name, if it is one.
    ///
    /// ```
    /// use ulog_format::BasicType;
    /// assert_eq!(BasicType::from_name("uint64_t"), Some(BasicType::UInt64));
    /// assert_eq!(BasicType::from_name("vehicle_status"), None);
    /// ```
    pub fn from_name(name: &str) -> Option<BasicType> {
        BasicType::ALL.into_iter().find(|t| t.name() == name)
    }

    /// Whether the type is a signed or unsigned integer (not bool or char).
    pub const fn is_integer(self) -> bool {
        !matches!(
            self,
            BasicType::Float | BasicType::Double | BasicType::Bool | BasicType::Char
        )
    }

    /// Whether the type is `float` or `double`.
    pub const fn is_float(self) -> bool {
        matches!(self, BasicType::Float | BasicType::Double)
    }

    /// Whether every value of `self` is a value of `to`, exactly: the conversions
    /// Rust's `From` has between the Rust types of the two (`u8` → `i32`, `u32` →
    /// `f64`, `f32` → `f64`, `bool` → any number). A typed binding of type `to` reads
    /// a log field of type `self` when this holds. Not `u32` → `f32` (24 bits of
    /// mantissa), not `i64` → `f64`, not signed → unsigned, never into `bool` or
    /// `char`. Every type widens to itself.
    ///
    /// ```
    /// use ulog_format::BasicType::*;
    /// assert!(UInt8.widens_to(Int32) && Float.widens_to(Double) && UInt32.widens_to(Int64));
    /// assert!(!Int32.widens_to(UInt8) && !UInt32.widens_to(Float) && !Int8.widens_to(UInt16));
    /// ```
    pub const fn widens_to(self, to: BasicType) -> bool {
        use BasicType::*;
        if self as u8 == to as u8 {
            return true;
        }
        match self {
            UInt8 => matches!(
                to,
                UInt16 | UInt32 | UInt64 | Int16 | Int32 | Int64 | Float | Double
            ),
            UInt16 => matches!(to, UInt32 | UInt64 | Int32 | Int64 | Float | Double),
            UInt32 => matches!(to, UInt64 | Int64 | Double),
            Int8 => matches!(to, Int16 | Int32 | Int64 | Float | Double),
            Int16 => matches!(to, Int32 | Int64 | Float | Double),
            Int32 => matches!(to, Int64 | Double),
            Float => matches!(to, Double),
            Bool => !matches!(to, Char),
            Int64 | UInt64 | Double | Char => false,
        }
    }

    /// The index of the type in [`BasicType::ALL`].
    pub const fn index(self) -> usize {
        self as usize
    }
}

impl fmt::Display for BasicType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every widening holds every value of its source exactly, checked on each
    /// type's extremes and a value that needs every bit (as Rust's `From` would).
    #[test]
    fn widenings_are_exact() {
        use BasicType::*;
        let samples: &[(BasicType, &[f64])] = &[
            (Int8, &[-128.0, 127.0]),
            (UInt8, &[0.0, 255.0]),
            (Int16, &[-32768.0, 32767.0]),
            (UInt16, &[65535.0]),
            (Int32, &[-2147483648.0, 2147483647.0]),
            (UInt32, &[4294967295.0]),
            (Float, &[16777217.0f32 as f64, 1e38]),
            (Bool, &[0.0, 1.0]),
        ];
        let range = |t: BasicType| -> (f64, f64) {
            match t {
                Int8 => (-128.0, 127.0),
                UInt8 => (0.0, 255.0),
                Int16 => (-32768.0, 32767.0),
                UInt16 => (0.0, 65535.0),
                Int32 => (-2147483648.0, 2147483647.0),
                UInt32 => (0.0, 4294967295.0),
                Int64 => (-9.3e18, 9.3e18),
                UInt64 => (0.0, 1.8e19),
                Float => (-3.4e38, 3.4e38),
                Double => (f64::MIN, f64::MAX),
                Bool | Char => (0.0, 0.0),
            }
        };
        for &(from, values) in samples {
            for to in BasicType::ALL {
                if !from.widens_to(to) || from == to {
                    continue;
                }
                let (lo, hi) = range(to);
                for &v in values {
                    assert!(lo <= v && v <= hi, "{from} -> {to}: {v} out of range");
                    if to == Float {
                        assert_eq!(v as f32 as f64, v, "{from} -> float: {v} rounds");
                    }
                }
            }
        }
        assert!(!UInt32.widens_to(Float), "2^24 + 1 does not fit a float");
        assert!(!Int64.widens_to(Double) && !UInt64.widens_to(Double));
        assert!(BasicType::ALL.iter().all(|t| t.widens_to(*t)));
        assert!(BasicType::ALL
            .iter()
            .all(|t| *t == Bool || !t.widens_to(Bool)));
    }

    #[test]
    fn names_round_trip_and_sizes_match_the_spec() {
        let sizes = [1, 1, 2, 2, 4, 4, 8, 8, 4, 8, 1, 1];
        for (t, size) in BasicType::ALL.into_iter().zip(sizes) {
            assert_eq!(BasicType::from_name(t.name()), Some(t));
            assert_eq!(t.size(), size, "{t}");
        }
        assert_eq!(BasicType::from_name("uint8"), None);
    }
}
