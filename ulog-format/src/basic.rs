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
}

impl fmt::Display for BasicType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
