//! `ulog report A.ulg B.ulg …`: one page comparing flights. Each log is read as for its
//! own report ([`super::draw`]: the standard plots and the flight analysis), its time
//! axis moved so that 0 is its first takeoff (or its start where it never takes off),
//! its lines drawn in one colour per log; the plots of the same id overlaid; the
//! parameters that differ across the logs (the N-way form of `ulog params --diff`)
//! and every log's diagnostics in tables.

use std::path::{Path, PathBuf};

use ulog_core::read::TimeSpan;

use super::analysis::{diagnostics, DiagnosticRow};
use super::plots::Plot;
use super::timeline::Mark;
use super::{draw, html, pass, write_page, Args, Drawing};
use crate::failure::{Failure, Status};
use crate::input;
use crate::pyfmt::py_str;

/// One colour per log, with its name for the header.
const LOG_COLORS: [(&str, &str); 8] = [
    ("#1f77b4", "blue"),
    ("#d62728", "red"),
    ("#2ca02c", "green"),
    ("#ff7f0e", "orange"),
    ("#9467bd", "purple"),
    ("#8c564b", "brown"),
    ("#e377c2", "pink"),
    ("#17becf", "cyan"),
];

/// Time 0 of a log on the page, µs: its first takeoff within its span, else its start.
fn zero_of(d: &Drawing, span: &TimeSpan) -> (u64, bool) {
    match d
        .flight
        .timeline
        .takeoff_us()
        .filter(|t| (span.start()..=span.end()).contains(t))
    {
        Some(t) => (t, true),
        None => (span.start(), false),
    }
}

/// The page comparing the logs of `args` (two or more).
pub fn run(args: &Args) -> Result<(), Failure> {
    let files: Vec<&Path> = args.files.iter().map(PathBuf::as_path).collect();
    let names = input::column_names(&files);
    let mut read = Vec::new();
    for file in &files {
        let name = file.display().to_string();
        let input = crate::input::Input::open(file)?;
        let survey = pass::survey(&input, &name)?;
        read.push((name, input, survey));
    }
    let mut logs = Vec::new();
    for (name, _, survey) in &read {
        let log = survey
            .metadata
            .log()
            .map_err(|e| Failure::new(Status::Refused, name, input::error_text(&e)))?;
        logs.push(log);
    }
    let mut plots: Vec<Plot> = Vec::new();
    let mut header = Vec::new();
    let mut rows: Vec<DiagnosticRow> = Vec::new();
    let mut marks = Vec::new();
    let mut duration: f64 = 0.0;
    for (i, ((name, input, survey), log)) in read.iter().zip(&logs).enumerate() {
        let drawing = draw(input, name, survey, log)?;
        let span = log.span();
        let (zero, took_off) = zero_of(&drawing, span);
        let offset = span.seconds(zero);
        duration = duration.max(span.duration_s());
        let (color, color_name) = LOG_COLORS[i % LOG_COLORS.len()];
        let who = &names[i];
        header.push((
            format!("Log {}", i + 1),
            format!(
                "{name} ({color_name}): {}, {:.1} s long{}",
                if took_off {
                    format!("time 0 at its takeoff, {offset:.1} s after its start")
                } else {
                    "never takes off: time 0 at its start".to_owned()
                },
                span.duration_s(),
                match drawing.flight.diagnostics.len() {
                    0 => String::new(),
                    n => format!(", {n} diagnostic(s)"),
                }
            ),
        ));
        for mut p in drawing.plots {
            for t in &mut p.tables {
                t.x.iter_mut().for_each(|x| *x -= offset);
                t.color = Some(color);
                t.labels = t.labels.iter().map(|l| format!("{who}: {l}")).collect();
            }
            let sources: Vec<String> = p.sources.iter().map(|s| format!("{who}: {s}")).collect();
            match plots.iter_mut().find(|m| m.id == p.id) {
                Some(m) => {
                    m.sources.extend(sources);
                    m.tables.extend(p.tables);
                }
                None => {
                    p.sources = sources;
                    plots.push(p);
                }
            }
        }
        let (mut diag, _) = diagnostics(&drawing.flight, span);
        for d in &mut diag {
            d.t -= offset;
            d.end = d.end.map(|e| e - offset);
            d.summary = format!("{who}: {}", d.summary);
        }
        rows.extend(diag);
        if took_off && marks.is_empty() {
            marks.push(Mark {
                t: 0.0,
                kind: "takeoff",
                text: "takeoff".into(),
            });
        }
    }
    rows.sort_by(|a, b| a.t.total_cmp(&b.t));
    // The parameters at the end of each log, compared as `ulog params --diff` does.
    let sets: Vec<_> = logs.iter().map(|l| l.params_at_end()).collect();
    let sets: Vec<&_> = sets.iter().collect();
    let params: Vec<Vec<String>> = ulog_core::read::diff_params(&sets)
        .into_iter()
        .map(|d| {
            let mut row = vec![d.name];
            row.extend(
                d.values
                    .iter()
                    .map(|v| v.as_ref().map_or_else(|| "—".to_owned(), py_str)),
            );
            row
        })
        .collect();
    let title = names.join(" vs ");
    let page = html::Page {
        title: title.clone(),
        header,
        missing: Vec::new(),
        notes: vec![format!(
            "{} logs overlaid, one colour per log (the lines of one log differ by dashes). \
             Each log's time 0 is its first takeoff (vehicle_land_detected), or its start \
             where it never takes off. Drag to zoom, as on a single log's page.",
            files.len()
        )],
        params_vs_defaults: Vec::new(),
        params_changed: Vec::new(),
        messages: Vec::new(),
        info: Vec::new(),
        multi: Vec::new(),
        diagnostics: rows,
        analysis_notes: Vec::new(),
        params_across: Some((names.clone(), params)),
        drawn: html::Drawn {
            origin_us: 0,
            duration,
            x_label: "seconds since takeoff (or the log's start)",
            modes: Vec::new(),
            marks,
            plots,
            track: None,
            analysis: Vec::new(),
            heatmaps: Vec::new(),
        },
    };
    let out = args
        .output
        .clone()
        .unwrap_or_else(|| default_output(files[0]));
    write_page(args, &page, &title, &out)
}

/// `<first FILE's stem>_compare.html`, next to it.
fn default_output(first: &Path) -> PathBuf {
    first.with_file_name(format!("{}_compare.html", input::stem(first)))
}
