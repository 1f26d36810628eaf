//! ROS 2 message definitions (`ros2msg`) from a log's formats, and the plan that
//! copies a payload into CDR by them.

use std::collections::HashSet;

use ulog_format::{BasicType, Layout, LayoutField, LayoutType};

/// The package the message types are named in, as PX4's ROS 2 messages are.
pub(crate) const PACKAGE: &str = "px4_msgs";

/// The line between a message definition and those it uses, in `ros2msg` schemas.
const SEPARATOR: &str =
    "================================================================================";

/// The member a definition without fields gets (ROS 2's IDL needs one), as rosidl
/// adds it: one `uint8`, written as 0.
pub(crate) const EMPTY_MEMBER: &str = "structure_needs_at_least_one_member";

/// A format's ROS 2 type name: `vehicle_gps_position` → `VehicleGpsPosition`,
/// `actuator_controls_0` → `ActuatorControls0`, as `px4_msgs` names PX4's messages.
pub(crate) fn type_name(format: &str) -> String {
    let mut out = String::with_capacity(format.len());
    for word in format.split(|c: char| !c.is_ascii_alphanumeric()) {
        let mut chars = word.chars();
        if let Some(first) = chars.next() {
            out.push(first.to_ascii_uppercase());
            out.extend(chars);
        }
    }
    if !out.starts_with(|c: char| c.is_ascii_alphabetic()) {
        out.insert(0, 'M');
    }
    out
}

/// A field's ROS 2 name: ROS 2 allows lower-case letters, digits and single
/// underscores, starting with a letter and not ending in `_`; others are mapped
/// (lower-cased, runs of other characters to one `_`, `f_` before a leading digit,
/// `_` at the end dropped).
pub(crate) fn field_name(name: &str) -> String {
    let mut out = String::with_capacity(name.len() + 2);
    for c in name.chars() {
        let c = c.to_ascii_lowercase();
        if c.is_ascii_lowercase() || c.is_ascii_digit() {
            out.push(c);
        } else if !out.ends_with('_') && !out.is_empty() {
            out.push('_');
        }
    }
    while out.ends_with('_') {
        out.pop();
    }
    if !out.starts_with(|c: char| c.is_ascii_lowercase()) {
        out.insert_str(0, "f_");
    }
    out
}

/// The ROS 2 name of a basic type; `char` is `uint8`, as PX4's ROS 2 messages
/// declare their `char` arrays.
fn basic_name(ty: BasicType) -> &'static str {
    match ty {
        BasicType::Int8 => "int8",
        BasicType::UInt8 | BasicType::Char => "uint8",
        BasicType::Int16 => "int16",
        BasicType::UInt16 => "uint16",
        BasicType::Int32 => "int32",
        BasicType::UInt32 => "uint32",
        BasicType::Int64 => "int64",
        BasicType::UInt64 => "uint64",
        BasicType::Float => "float32",
        BasicType::Double => "float64",
        BasicType::Bool => "bool",
    }
}

/// The fields of a layout a message has: padding and zero-length arrays left out.
pub(crate) fn members(layout: &Layout) -> impl Iterator<Item = &LayoutField> {
    layout
        .fields()
        .iter()
        .filter(|f| !f.is_padding() && f.array_len != Some(0))
}

/// The `ros2msg` schema of a layout: its definition, then each nested format's once
/// (`MSG: px4_msgs/msg/EscReport` after a line of `=`), in the order first used.
pub(crate) fn ros2msg(layout: &Layout) -> String {
    let mut text = definition(layout);
    let mut seen = HashSet::new();
    let mut nested = Vec::new();
    collect_nested(layout, &mut seen, &mut nested);
    for inner in nested {
        text.push_str(SEPARATOR);
        text.push_str(&format!(
            "\nMSG: {PACKAGE}/msg/{}\n",
            type_name(inner.name())
        ));
        text.push_str(&definition(inner));
    }
    text
}

fn collect_nested<'l>(layout: &'l Layout, seen: &mut HashSet<String>, out: &mut Vec<&'l Layout>) {
    for f in members(layout) {
        if let LayoutType::Nested(inner) = &f.ty {
            if seen.insert(inner.name().to_owned()) {
                out.push(inner);
                collect_nested(inner, seen, out);
            }
        }
    }
}

/// One message definition: a line per member, `type[N] name`.
fn definition(layout: &Layout) -> String {
    let mut text = String::new();
    let mut names = HashSet::new();
    for f in members(layout) {
        let ty = match &f.ty {
            LayoutType::Basic(b) => basic_name(*b).to_owned(),
            LayoutType::Nested(inner) => type_name(inner.name()),
        };
        let mut name = field_name(&f.name);
        // Two fields that map to one name: the later ones numbered.
        let mut n = 1;
        while !names.insert(name.clone()) {
            n += 1;
            name = format!("{}_{n}", field_name(&f.name));
        }
        match f.array_len {
            Some(len) => text.push_str(&format!("{ty}[{len}] {name}\n")),
            None => text.push_str(&format!("{ty} {name}\n")),
        }
    }
    if text.is_empty() {
        text.push_str(&format!("uint8 {EMPTY_MEMBER}\n"));
    }
    text
}

/// One step of copying a payload into CDR.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Step {
    /// `len` bytes from `from` in the payload, after padding the output to `align`.
    Copy {
        from: usize,
        len: usize,
        align: usize,
    },
    /// The one `uint8` member of a definition without fields: a zero.
    Empty,
}

/// The steps that copy a payload of `layout` into CDR: each member in order, aligned
/// to its size; neighbouring values that need no padding between them merged.
pub(crate) fn cdr_plan(layout: &Layout) -> Vec<Step> {
    let mut steps = Vec::new();
    plan_into(layout, 0, &mut steps);
    steps
}

fn plan_into(layout: &Layout, base: usize, steps: &mut Vec<Step>) {
    let mut any = false;
    for f in members(layout) {
        any = true;
        let count = f.array_len.unwrap_or(1);
        match &f.ty {
            LayoutType::Basic(b) => push(
                steps,
                Step::Copy {
                    from: base + f.offset,
                    len: b.size() * count,
                    align: b.size(),
                },
            ),
            LayoutType::Nested(inner) => {
                for i in 0..count {
                    plan_into(inner, base + f.offset + i * inner.size(), steps);
                }
            }
        }
    }
    if !any {
        steps.push(Step::Empty);
    }
}

/// Adds a copy, merged into the last one when it continues it in the payload and no
/// padding can come between them (the next value's alignment divides the bytes so far
/// of a copy that started aligned to at least as much).
fn push(steps: &mut Vec<Step>, step: Step) {
    if let (
        Some(Step::Copy { from, len, align }),
        Step::Copy {
            from: next,
            len: more,
            align: next_align,
        },
    ) = (steps.last_mut(), step)
    {
        if *from + *len == next && *align >= next_align && *len % next_align == 0 {
            *len += more;
            return;
        }
    }
    steps.push(step);
}

/// Encodes `payload` by `plan` at the end of `out` as little-endian CDR with its
/// 4-byte encapsulation header. `None`, and `out` as it was, when the payload is
/// shorter than the plan reads (only trailing padding may be missing).
pub(crate) fn encode(plan: &[Step], payload: &[u8], out: &mut Vec<u8>) -> Option<()> {
    let base = out.len();
    out.extend_from_slice(&[0, 1, 0, 0]);
    for step in plan {
        match *step {
            Step::Copy { from, len, align } => {
                let Some(bytes) = payload.get(from..from + len) else {
                    out.truncate(base);
                    return None;
                };
                let pos = out.len() - base - 4;
                let pad = (align - pos % align) % align;
                out.resize(out.len() + pad, 0);
                out.extend_from_slice(bytes);
            }
            Step::Empty => out.push(0),
        }
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use ulog_format::Format;

    fn layout(formats: &[&str], name: &str) -> Layout {
        let formats: Vec<Format> = formats.iter().map(|f| Format::parse(f).unwrap()).collect();
        Layout::resolve(name, &formats[..]).unwrap()
    }

    #[test]
    fn names_follow_px4_msgs() {
        assert_eq!(type_name("vehicle_gps_position"), "VehicleGpsPosition");
        assert_eq!(type_name("actuator_controls_0"), "ActuatorControls0");
        assert_eq!(field_name("timestamp"), "timestamp");
        assert_eq!(field_name("Accel_X__m_"), "accel_x_m");
        assert_eq!(field_name("2d"), "f_2d");
    }

    #[test]
    fn nested_formats_are_their_own_types_and_padding_is_left_out() {
        let l = layout(
            &[
                "esc_report:uint64_t timestamp;int32_t esc_rpm;char[3] name;uint8_t[1] _padding0;",
                "esc_status:uint64_t timestamp;uint8_t esc_count;uint8_t[7] _padding0;esc_report[2] esc;",
            ],
            "esc_status",
        );
        assert_eq!(
            ros2msg(&l),
            format!(
                "uint64 timestamp\nuint8 esc_count\nEscReport[2] esc\n{SEPARATOR}\n\
                 MSG: px4_msgs/msg/EscReport\nuint64 timestamp\nint32 esc_rpm\nuint8[3] name\n"
            )
        );
        // timestamp, count, then each report aligned to 8 for its timestamp.
        assert_eq!(
            cdr_plan(&l),
            [
                Step::Copy {
                    from: 0,
                    len: 9,
                    align: 8
                },
                Step::Copy {
                    from: 16,
                    len: 15,
                    align: 8
                },
                Step::Copy {
                    from: 32,
                    len: 15,
                    align: 8
                },
            ]
        );
        let payload: Vec<u8> = (0..48).collect();
        let mut out = Vec::new();
        encode(&cdr_plan(&l), &payload, &mut out).unwrap();
        // header, 0..9, pad to 16, 16..24, 24..31, pad to 32, 32..40, 40..47
        let mut expected = vec![0, 1, 0, 0];
        expected.extend(0..9u8);
        expected.extend([0; 7]);
        expected.extend(16..31u8);
        expected.push(0);
        expected.extend(32..47u8);
        assert_eq!(out, expected);
        assert_eq!(encode(&cdr_plan(&l), &payload[..40], &mut out), None);
        assert_eq!(out, expected, "as it was");
    }
}
