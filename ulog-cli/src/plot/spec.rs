//! What to plot, as written on the command line: `topic[:instance].field.path`.

use core::fmt;

/// One `topic[:N].field` from the command line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldSpec {
    /// The topic name (`vehicle_local_position`).
    pub topic: String,
    /// The instance (`multi_id`) after `:`, if one was given.
    pub instance: Option<u8>,
    /// The field path inside the topic (`z`, `q[0]`, `esc[2].esc_rpm`).
    pub field: String,
}

impl FieldSpec {
    /// Parses `topic[:N].field.path`: the topic is everything before the first `.`,
    /// optionally ending in `:N` (an instance number, 0–255); the rest is the field path.
    pub fn parse(spec: &str) -> Result<FieldSpec, String> {
        let spec = spec.trim();
        let Some((topic, field)) = spec.split_once('.') else {
            return Err(format!(
                "`{spec}` names no field: write TOPIC.FIELD (e.g. `{}.x`)",
                if spec.is_empty() { "topic" } else { spec }
            ));
        };
        let (topic, instance) = match topic.split_once(':') {
            Some((t, n)) => {
                let n = n.parse::<u8>().map_err(|_| {
                    format!("`{spec}`: the instance after `:` must be a number from 0 to 255")
                })?;
                (t, Some(n))
            }
            None => (topic, None),
        };
        if topic.is_empty() {
            return Err(format!("`{spec}` names no topic before the `.`"));
        }
        if field.is_empty() {
            return Err(format!("`{spec}` names no field after the `.`"));
        }
        Ok(FieldSpec {
            topic: topic.to_owned(),
            instance,
            field: field.to_owned(),
        })
    }
}

impl fmt::Display for FieldSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.topic)?;
        if let Some(n) = self.instance {
            write!(f, ":{n}")?;
        }
        write!(f, ".{}", self.field)
    }
}

#[cfg(test)]
mod tests {
    use super::FieldSpec;

    fn spec(t: &str, i: Option<u8>, f: &str) -> FieldSpec {
        FieldSpec {
            topic: t.into(),
            instance: i,
            field: f.into(),
        }
    }

    #[test]
    fn topic_instance_and_nested_paths() {
        assert_eq!(
            FieldSpec::parse("vehicle_local_position.z"),
            Ok(spec("vehicle_local_position", None, "z"))
        );
        assert_eq!(
            FieldSpec::parse("esc_status:1.esc[2].esc_rpm"),
            Ok(spec("esc_status", Some(1), "esc[2].esc_rpm"))
        );
        assert_eq!(
            FieldSpec::parse(" vehicle_attitude.q[0] "),
            Ok(spec("vehicle_attitude", None, "q[0]"))
        );
        assert_eq!(
            FieldSpec::parse("a:1.b").unwrap().to_string(),
            "a:1.b",
            "shown as written"
        );
    }

    #[test]
    fn malformed_specs_say_what_is_missing() {
        assert!(FieldSpec::parse("vehicle_local_position")
            .unwrap_err()
            .contains("names no field"));
        assert!(FieldSpec::parse("t.")
            .unwrap_err()
            .contains("no field after"));
        assert!(FieldSpec::parse(".x").unwrap_err().contains("no topic"));
        assert!(FieldSpec::parse("t:x.y").unwrap_err().contains("0 to 255"));
        assert!(FieldSpec::parse("t:256.y")
            .unwrap_err()
            .contains("0 to 255"));
    }
}
