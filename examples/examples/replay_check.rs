//! A replay tool's admission check, compiled against the schema of a reference log:
//! it reads a log, checks each topic the reference subscribes against the binding
//! generated from the reference (`ulog_module!`), and refuses a log whose formats
//! changed, showing every difference and both formats.
//!
//! ```text
//! cargo run -p ulog-examples --example replay_check -- [--exact] [LOG.ulg]
//! ```
//!
//! Without a path it checks the bundled sample log, which has the reference's schema.
//! A topic whose format gained or moved fields is still readable (its fields are
//! found by name) and is accepted with a note, unless `--exact` is given. Exit status:
//! 0 accepted, 1 refused, 2 unreadable.

use std::collections::BTreeSet;
use std::process::ExitCode;

use ulog_core::typed::{BindingVisitor, PlanKind, TypedErrorKind};
use ulog_core::{LogFile, ULog, ULogMessage};

// One struct per format of the reference log, checked when this tool is compiled.
ulog_core::ulog_module!(mod reference = "data/reference.ulg");

/// The reference log itself, for the list of topics it subscribes.
const REFERENCE: &[u8] = include_bytes!("../data/reference.ulg");

/// Checks every binding of the reference against a log, then replays what fits.
struct Admission<'l, 'a> {
    log: &'l ULog<'a>,
    /// The topics the reference log subscribes.
    topics: BTreeSet<String>,
    exact: bool,
    refused: Vec<String>,
    replayed: usize,
}

impl BindingVisitor for Admission<'_, '_> {
    fn visit<T: ULogMessage>(&mut self) {
        // Nested-only formats (`esc_report`) are checked inside their topics.
        if !self.topics.contains(T::NAME) {
            return;
        }
        let instances = self.log.topic_instances(T::NAME);
        if instances.is_empty() {
            println!("  {:<24} not in this log", T::NAME);
        }
        for topic in instances {
            let label = format!("{}/{}", T::NAME, topic.multi_id());
            // One check per subscription; after it, rows decode without lookups.
            let rows = match topic.read::<T>() {
                Ok(rows) => rows,
                Err(e) => {
                    match e.kind() {
                        TypedErrorKind::Mismatch(m) => println!("  {label:<24} REFUSED: {m}"),
                        _ => println!("  {label:<24} REFUSED: {e}"),
                    }
                    self.refused.push(label);
                    continue;
                }
            };
            if rows.plan().kind() == PlanKind::Mapped {
                let theirs = self.log.format(T::NAME).map(|f| f.to_string());
                println!(
                    "  {label:<24} {}: format changed, fields found by name\n    reference: {}\n    log:       {}",
                    if self.exact { "REFUSED (--exact)" } else { "accepted" },
                    T::schema().format_text(),
                    theirs.unwrap_or_default()
                );
                if self.exact {
                    self.refused.push(label);
                    continue;
                }
            } else {
                println!("  {label:<24} same format, {} messages", rows.len());
            }
            let decoded = rows.iter().filter(|r| r.is_ok()).count();
            self.replayed += decoded;
        }
    }
}

fn main() -> ExitCode {
    let mut exact = false;
    let mut path = None;
    for arg in std::env::args_os().skip(1) {
        if arg == "--exact" {
            exact = true;
        } else {
            path = Some(arg);
        }
    }
    let mapped;
    let owned;
    let (name, bytes): (String, &[u8]) = match &path {
        Some(p) => match LogFile::open(p) {
            Ok(m) => {
                mapped = m;
                (p.to_string_lossy().into_owned(), mapped.bytes())
            }
            Err(e) => {
                eprintln!("replay_check: {e}");
                return ExitCode::from(2);
            }
        },
        None => {
            owned = ulog_core::testing::sample_log();
            ("the bundled sample log".to_owned(), &owned)
        }
    };
    let log = match ULog::parse(bytes) {
        Ok(log) => log,
        Err(e) => {
            eprintln!("replay_check: {name}: {e}");
            return ExitCode::from(2);
        }
    };
    let reference = ULog::parse(REFERENCE).expect("the reference log parses");
    let topics = reference.topics().map(|t| t.name().to_owned()).collect();
    println!("replay check of {name} against data/reference.ulg");
    let mut admission = Admission {
        log: &log,
        topics,
        exact,
        refused: Vec::new(),
        replayed: 0,
    };
    reference::visit_bindings(&mut admission);
    if admission.refused.is_empty() {
        println!("accepted: {} messages ready to replay", admission.replayed);
        ExitCode::SUCCESS
    } else {
        println!(
            "refused: {} topic(s) changed: {}",
            admission.refused.len(),
            admission.refused.join(", ")
        );
        ExitCode::FAILURE
    }
}
