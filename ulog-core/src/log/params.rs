//! The parameters of a log as values by name (at its start, at its end, its defaults),
//! and the differences across such sets: between two or more flights, or between a
//! flight and its defaults.
//!
//! "The parameters of a flight" are the values at the end of its log
//! ([`ULog::params_at_end`]): the initial values of the definitions section with every
//! change of the data section applied in file order, as a reader of pyulog gets them
//! from `initial_parameters` and `changed_parameters`. A parameter first set during
//! the flight is one of them too.
//!
//! Values compare as numbers of the log's types ([`same_param_value`]): equal when they
//! have the same type and the same value. A parameter that is an `int32_t` 1 in one log
//! and a `float` 1.0 in the other differs ([`ParamDiff::type_change`] names the
//! types), although Python would call `1 == 1.0` true. Floats compare by value
//! (`0.0` equals `-0.0`), and a NaN equals a NaN, so that an unchanged NaN is not a
//! difference.

use std::collections::BTreeMap;

use crate::log::ulog::ULog;
use crate::value::Value;

/// Which default value of a parameter: the bits of a default parameter message's
/// `default_types`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DefaultKind {
    /// The system-wide default (bit 0).
    System,
    /// The default of the current configuration, e.g. the airframe (bit 1).
    CurrentSetup,
}

impl DefaultKind {
    /// The kind's bit of `default_types` (1 for the system-wide default, 2 for the
    /// current setup's).
    pub fn bit(self) -> u8 {
        match self {
            DefaultKind::System => 1,
            DefaultKind::CurrentSetup => 2,
        }
    }
}

/// The default values a log gives for one parameter, where it gives them. PX4 logs
/// defaults mostly for parameters whose value differs from them.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ParamDefaults<'a> {
    /// The system-wide default (`default_types` bit 0).
    pub system: Option<Value<'a>>,
    /// The default of the current configuration (`default_types` bit 1).
    pub current_setup: Option<Value<'a>>,
}

impl<'a> ParamDefaults<'a> {
    /// The default of `kind`, if the log gives it.
    pub fn get(&self, kind: DefaultKind) -> Option<Value<'a>> {
        match kind {
            DefaultKind::System => self.system,
            DefaultKind::CurrentSetup => self.current_setup,
        }
    }
}

/// A parameter whose value differs between sets of parameters (two or more logs, or a
/// log and its defaults): missing from one of them, or different there
/// ([`same_param_value`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ParamDiff<'a> {
    /// The parameter's name.
    pub name: String,
    /// Its value in each set, in the order given; `None` where a set lacks it.
    pub values: Vec<Option<Value<'a>>>,
}

impl ParamDiff<'_> {
    /// The C type names of the values (`"int32_t"`, `"float"`; `None` where a set
    /// lacks the parameter) when the sets that have it hold values of different
    /// types, else `None`.
    pub fn type_change(&self) -> Option<Vec<Option<&'static str>>> {
        let types: Vec<Option<&'static str>> = self
            .values
            .iter()
            .map(|v| v.as_ref().map(type_name))
            .collect();
        let mut present = types.iter().flatten();
        let first = present.next()?;
        present.any(|t| t != first).then_some(types)
    }
}

/// The C type name of a value, as a parameter's key names it.
fn type_name(v: &Value<'_>) -> &'static str {
    match v {
        Value::I8(_) => "int8_t",
        Value::U8(_) => "uint8_t",
        Value::I16(_) => "int16_t",
        Value::U16(_) => "uint16_t",
        Value::I32(_) => "int32_t",
        Value::U32(_) => "uint32_t",
        Value::I64(_) => "int64_t",
        Value::U64(_) => "uint64_t",
        Value::F32(_) => "float",
        Value::F64(_) => "double",
        Value::Bool(_) => "bool",
        Value::Char(_) => "char",
        Value::Str(_) => "char[]",
        Value::Array(_) => "array",
        _ => "bytes",
    }
}

/// Whether two parameter values are the same: the same type and the same value.
/// Floats compare by value (`0.0` equals `-0.0`) and a NaN equals a NaN; values of
/// different types always differ (an `int32_t` 1 is not a `float` 1.0).
pub fn same_param_value(a: &Value<'_>, b: &Value<'_>) -> bool {
    match (a, b) {
        (Value::F32(x), Value::F32(y)) => x == y || (x.is_nan() && y.is_nan()),
        (Value::F64(x), Value::F64(y)) => x == y || (x.is_nan() && y.is_nan()),
        _ => a == b,
    }
}

/// The parameters that differ across `sets` (two logs, or N), sorted by name: those
/// some set lacks, and those whose values are not all the same ([`same_param_value`]).
pub fn diff_params<'a>(sets: &[&BTreeMap<String, Value<'a>>]) -> Vec<ParamDiff<'a>> {
    let mut names: Vec<&String> = sets.iter().flat_map(|s| s.keys()).collect();
    names.sort_unstable();
    names.dedup();
    names
        .into_iter()
        .filter_map(|name| {
            let values: Vec<Option<Value<'a>>> =
                sets.iter().map(|s| s.get(name).copied()).collect();
            let same = match values.split_first() {
                Some((Some(first), rest)) => rest
                    .iter()
                    .all(|v| v.as_ref().is_some_and(|v| same_param_value(first, v))),
                _ => false,
            };
            (!same).then(|| ParamDiff {
                name: name.clone(),
                values,
            })
        })
        .collect()
}

/// The parameters of `values` that differ from their default of `kind` in
/// `defaults`, sorted by name: the first of [`ParamDiff::values`] is the value
/// (`None` when `values` does not have a parameter the defaults name), the second the
/// default. A parameter without a default of
/// `kind` is left out: a log gives defaults mostly for the parameters that differ from
/// them, so one without is taken to be at its default.
pub fn diff_from_defaults<'a>(
    values: &BTreeMap<String, Value<'a>>,
    defaults: &BTreeMap<String, ParamDefaults<'a>>,
    kind: DefaultKind,
) -> Vec<ParamDiff<'a>> {
    defaults
        .iter()
        .filter_map(|(name, d)| {
            let default = d.get(kind)?;
            let value = values.get(name).copied();
            match &value {
                Some(v) if same_param_value(v, &default) => None,
                _ => Some(ParamDiff {
                    name: name.clone(),
                    values: vec![value, Some(default)],
                }),
            }
        })
        .collect()
}

impl<'a> ULog<'a> {
    /// The parameters when logging started (those of the definitions section), by
    /// name; of a name given twice, the last value.
    pub fn params_at_start(&self) -> BTreeMap<String, Value<'a>> {
        self.initial_params()
            .iter()
            .map(|kv| (kv.name().into_owned(), kv.value()))
            .collect()
    }

    /// The parameters at the end of the log, by name: [`ULog::params_at_start`] with
    /// every [`ULog::param_changes`] applied in file order (a parameter first set
    /// during the log included). These are "the parameters of the flight" that
    /// [`ULog::diff_params`] compares.
    pub fn params_at_end(&self) -> BTreeMap<String, Value<'a>> {
        let mut params = self.params_at_start();
        for c in self.param_changes() {
            params.insert(c.kv.name().into_owned(), c.kv.value());
        }
        params
    }

    /// The default values the log gives (its default parameter messages, in either
    /// section), by name; of a default given twice, the last value. Empty when the log
    /// has none (its flag bits say whether it has them:
    /// [`FlagBits::has_default_parameters`](crate::read::FlagBits::has_default_parameters)).
    pub fn param_defaults(&self) -> BTreeMap<String, ParamDefaults<'a>> {
        let mut defaults: BTreeMap<String, ParamDefaults<'a>> = BTreeMap::new();
        for d in self.default_params() {
            let entry = defaults.entry(d.kv.name().into_owned()).or_default();
            if d.default_types & DefaultKind::System.bit() != 0 {
                entry.system = Some(d.kv.value());
            }
            if d.default_types & DefaultKind::CurrentSetup.bit() != 0 {
                entry.current_setup = Some(d.kv.value());
            }
        }
        defaults
    }

    /// The parameters that differ between this log (A) and `other` (B), sorted by
    /// name: their values at the end of each log ([`ULog::params_at_end`]) compared
    /// by [`diff_params`].
    ///
    /// ```
    /// use ulog_core::testing::LogBuilder;
    /// use ulog_core::{ULog, Value};
    ///
    /// fn flight(params: &[(&str, &[u8])]) -> Vec<u8> {
    ///     let mut b = LogBuilder::new(1, 0);
    ///     for (key, value) in params {
    ///         b.param(key, value);
    ///     }
    ///     b.into_bytes()
    /// }
    /// let a = flight(&[
    ///     ("int32_t MAV_SYS_ID", &1i32.to_le_bytes()),
    ///     ("float MPC_XY_VEL_MAX", &12.0f32.to_le_bytes()),
    ///     ("int32_t SDLOG_MODE", &0i32.to_le_bytes()),
    /// ]);
    /// let b = flight(&[
    ///     ("int32_t MAV_SYS_ID", &1i32.to_le_bytes()),
    ///     ("float MPC_XY_VEL_MAX", &10.0f32.to_le_bytes()),
    ///     ("float SDLOG_MODE", &0.0f32.to_le_bytes()),
    ///     ("int32_t SYS_AUTOSTART", &4001i32.to_le_bytes()),
    /// ]);
    /// let (a, b) = (ULog::parse(&a)?, ULog::parse(&b)?);
    /// let diff = a.diff_params(&b);
    /// let names: Vec<&str> = diff.iter().map(|d| d.name.as_str()).collect();
    /// assert_eq!(names, ["MPC_XY_VEL_MAX", "SDLOG_MODE", "SYS_AUTOSTART"]);
    /// assert_eq!(diff[0].values, [Some(Value::F32(12.0)), Some(Value::F32(10.0))]);
    /// // An int32_t 0 and a float 0.0 differ: their types do.
    /// assert_eq!(diff[1].type_change(), Some(vec![Some("int32_t"), Some("float")]));
    /// // Only B has SYS_AUTOSTART.
    /// assert_eq!(diff[2].values, [None, Some(Value::I32(4001))]);
    /// # Ok::<(), ulog_core::ReadError>(())
    /// ```
    pub fn diff_params<'b>(&self, other: &ULog<'b>) -> Vec<ParamDiff<'b>>
    where
        'a: 'b,
    {
        diff_params(&[&self.params_at_end(), &other.params_at_end()])
    }

    /// The parameters whose value at the end of the log ([`ULog::params_at_end`])
    /// differs from the log's default of `kind`, sorted by name ([`diff_from_defaults`]:
    /// A is the value, B the default; parameters without a default of `kind` are left
    /// out). Empty for a log without defaults.
    ///
    /// ```
    /// use ulog_core::read::DefaultKind;
    /// use ulog_core::testing::LogBuilder;
    /// use ulog_core::{ULog, Value};
    ///
    /// let mut b = LogBuilder::new(1, 0);
    /// b.flag_bits([1, 0, 0, 0, 0, 0, 0, 0], [0; 8], [0; 3]); // DEFAULT_PARAMETERS
    /// b.param("float MPC_XY_VEL_MAX", &12.0f32.to_le_bytes());
    /// b.param("int32_t MAV_TYPE", &13i32.to_le_bytes());
    /// b.default_param(1, "float MPC_XY_VEL_MAX", &10.0f32.to_le_bytes());
    /// b.default_param(1, "int32_t MAV_TYPE", &2i32.to_le_bytes());
    /// b.default_param(2, "int32_t MAV_TYPE", &13i32.to_le_bytes());
    /// let log = ULog::parse(b.bytes())?;
    ///
    /// let system = log.diff_param_defaults(DefaultKind::System);
    /// assert_eq!(system.len(), 2);
    /// assert_eq!(system[0].name, "MAV_TYPE");
    /// assert_eq!(system[0].values, [Some(Value::I32(13)), Some(Value::I32(2))]);
    /// // The airframe's default of MAV_TYPE is its value; MPC_XY_VEL_MAX has none.
    /// assert!(log.diff_param_defaults(DefaultKind::CurrentSetup).is_empty());
    /// # Ok::<(), ulog_core::ReadError>(())
    /// ```
    pub fn diff_param_defaults(&self, kind: DefaultKind) -> Vec<ParamDiff<'a>> {
        diff_from_defaults(&self.params_at_end(), &self.param_defaults(), kind)
    }
}

/// The kind of vehicle a MAVLink `MAV_TYPE` value (PX4's parameter `MAV_TYPE`) names,
/// for the types PX4 flies; `None` for others.
///
/// ```
/// assert_eq!(ulog_core::read::vehicle_type(2), Some("quadrotor"));
/// assert_eq!(ulog_core::read::vehicle_type(99), None);
/// ```
pub fn vehicle_type(mav_type: i128) -> Option<&'static str> {
    Some(match mav_type {
        0 => "generic",
        1 => "fixed wing",
        2 => "quadrotor",
        3 => "coaxial helicopter",
        4 => "helicopter",
        7 => "airship",
        8 => "free balloon",
        10 => "ground rover",
        11 => "surface boat",
        12 => "submarine",
        13 => "hexarotor",
        14 => "octorotor",
        15 => "tricopter",
        19 => "VTOL tailsitter (duo)",
        20 => "VTOL tailsitter (quad)",
        21 => "VTOL tiltrotor",
        22 => "VTOL fixed rotor",
        23 => "VTOL tailsitter",
        24 => "VTOL tiltwing",
        29 => "dodecarotor",
        35 => "decarotor",
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::LogBuilder;

    fn map<'a>(pairs: &[(&str, Value<'a>)]) -> BTreeMap<String, Value<'a>> {
        pairs.iter().map(|(k, v)| ((*k).to_owned(), *v)).collect()
    }

    #[test]
    fn values_compare_by_type_and_number() {
        assert!(same_param_value(&Value::F32(0.0), &Value::F32(-0.0)));
        assert!(same_param_value(
            &Value::F32(f32::NAN),
            &Value::F32(f32::NAN)
        ));
        assert!(!same_param_value(&Value::F32(1.0), &Value::F32(1.5)));
        assert!(!same_param_value(&Value::I32(1), &Value::F32(1.0)));
        assert!(!same_param_value(&Value::I32(1), &Value::I64(1)));
        assert!(same_param_value(&Value::I32(7), &Value::I32(7)));
    }

    #[test]
    fn a_diff_lists_names_of_either_side_that_differ() {
        let a = map(&[
            ("ONLY_A", Value::I32(1)),
            ("SAME", Value::F32(2.5)),
            ("DIFF", Value::F32(1.0)),
            ("TYPE", Value::I32(1)),
        ]);
        let b = map(&[
            ("ONLY_B", Value::F32(3.0)),
            ("SAME", Value::F32(2.5)),
            ("DIFF", Value::F32(2.0)),
            ("TYPE", Value::F32(1.0)),
        ]);
        let d = diff_params(&[&a, &b]);
        let names: Vec<&str> = d.iter().map(|d| d.name.as_str()).collect();
        assert_eq!(names, ["DIFF", "ONLY_A", "ONLY_B", "TYPE"]);
        assert_eq!(d[1].values[1], None);
        assert_eq!(d[2].values[0], None);
        assert_eq!(d[0].type_change(), None);
        assert_eq!(d[1].type_change(), None);
        assert_eq!(
            d[3].type_change(),
            Some(vec![Some("int32_t"), Some("float")])
        );
        assert!(diff_params(&[&a, &a]).is_empty());
        // Three sets: a parameter differs when any of them does, or lacks it.
        let c = map(&[("SAME", Value::F32(2.5)), ("DIFF", Value::F32(1.0))]);
        let names = |sets: &[&BTreeMap<String, Value<'_>>]| -> Vec<String> {
            diff_params(sets).into_iter().map(|d| d.name).collect()
        };
        assert_eq!(names(&[&a, &a, &c]), ["ONLY_A", "TYPE"]);
        assert_eq!(names(&[&c, &c, &c]), Vec::<String>::new());
        let d = diff_params(&[&a, &b, &c]);
        assert_eq!(
            d[0].values,
            [
                Some(Value::F32(1.0)),
                Some(Value::F32(2.0)),
                Some(Value::F32(1.0))
            ]
        );
        assert_eq!(
            d[3].type_change(),
            Some(vec![Some("int32_t"), Some("float"), None])
        );
    }

    #[test]
    fn the_end_values_apply_changes_in_order_and_add_new_names() {
        let mut b = LogBuilder::new(1, 0);
        b.param("int32_t P", &1i32.to_le_bytes());
        b.param("int32_t P", &2i32.to_le_bytes());
        b.format("t:uint64_t timestamp;");
        b.subscribe(0, 0, "t");
        b.param("int32_t P", &3i32.to_le_bytes());
        b.param("float NEW", &1.5f32.to_le_bytes());
        b.param("int32_t P", &4i32.to_le_bytes());
        let log = ULog::parse(b.bytes()).unwrap();
        assert_eq!(log.params_at_start(), map(&[("P", Value::I32(2))]));
        assert_eq!(
            log.params_at_end(),
            map(&[("P", Value::I32(4)), ("NEW", Value::F32(1.5))])
        );
    }

    #[test]
    fn defaults_of_both_kinds_and_a_default_without_a_value() {
        let mut b = LogBuilder::new(1, 0);
        b.param("int32_t A", &1i32.to_le_bytes());
        b.default_param(3, "int32_t A", &0i32.to_le_bytes());
        b.default_param(2, "int32_t GONE", &5i32.to_le_bytes());
        let log = ULog::parse(b.bytes()).unwrap();
        let d = log.param_defaults();
        assert_eq!(d["A"].system, Some(Value::I32(0)));
        assert_eq!(d["A"].current_setup, Some(Value::I32(0)));
        assert_eq!(d["GONE"].system, None);
        let cs = log.diff_param_defaults(DefaultKind::CurrentSetup);
        assert_eq!(cs.len(), 2);
        assert_eq!(cs[1].values, [None, Some(Value::I32(5))]);
        assert_eq!(log.diff_param_defaults(DefaultKind::System).len(), 1);
    }
}
