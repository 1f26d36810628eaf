//! `ulog --help` fits one screen (a short line per command); each command's own
//! `--help` still says everything its documentation says.

mod common;

use std::path::Path;

/// The commands, with the source file whose `Args` doc comment is the command's help.
const COMMANDS: &[(&str, &str)] = &[
    ("info", "info.rs"),
    ("messages", "messages.rs"),
    ("params", "params.rs"),
    ("csv", "csv.rs"),
    ("cut", "cut.rs"),
    ("anonymise", "anonymise.rs"),
    ("check", "check.rs"),
    ("codegen", "codegen.rs"),
    ("dump", "dump.rs"),
    ("parquet", "parquet.rs"),
    ("plot", "plot.rs"),
    ("analyze", "analyze.rs"),
    ("kml", "kml.rs"),
    ("report", "report/mod.rs"),
    ("gps-dump", "gps_dump.rs"),
];

/// The doc comment of `pub struct Args` in `src/<file>`, as one line of words.
fn args_doc(file: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("src").join(file);
    let text = std::fs::read_to_string(&path).expect("command source");
    let lines: Vec<&str> = text.lines().collect();
    let args = lines
        .iter()
        .position(|l| l.starts_with("pub struct Args"))
        .expect("pub struct Args");
    // The doc comment ends at the attributes of the struct.
    let at = lines[..args]
        .iter()
        .rposition(|l| l.starts_with("#[derive("))
        .expect("#[derive] of Args");
    let mut doc: Vec<&str> = lines[..at]
        .iter()
        .rev()
        .map_while(|l| l.strip_prefix("///"))
        .map(str::trim)
        .collect();
    doc.reverse();
    words(&doc.join(" "))
}

fn words(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[test]
fn overview_fits_one_screen_and_each_command_help_keeps_its_detail() {
    let top = common::ulog_ok(["--help"]);
    let lines: Vec<&str> = top.lines().collect();
    // 18 commands and `help`, usage, options and the exit statuses.
    assert!(lines.len() <= 31, "{} lines:\n{top}", lines.len());
    for l in &lines {
        assert!(
            l.chars().count() <= 80,
            "longer than 80 columns: {l}\n{top}"
        );
    }
    for (cmd, file) in COMMANDS {
        assert!(
            lines
                .iter()
                .any(|l| l.trim_start().starts_with(&format!("{cmd} "))),
            "`{cmd}` has a line in the overview:\n{top}"
        );
        let long = common::ulog_ok([*cmd, "--help"]);
        let doc = args_doc(file);
        assert!(doc.len() > 80, "{cmd}: doc comment found: {doc}");
        assert!(
            words(&long).contains(&doc),
            "`ulog {cmd} --help` holds the whole doc comment:\n{doc}\n---\n{long}"
        );
        // The short help (`-h`) is the overview's line, not the detail.
        let short = common::ulog_ok([*cmd, "-h"]);
        assert!(short.len() < long.len(), "{cmd}: -h is shorter than --help");
    }
}
