//! The page: one HTML file with everything inside (uPlot, the glue script, styles and
//! the data as JSON), so that it opens from disk with no network.
//!
//! The header and the tables are HTML written here (readable without scripts); the
//! plots are drawn by `assets/report/report.js` from the JSON.

use std::fmt::Write as _;

use serde::Serialize;

use super::analysis::{DiagnosticRow, Heatmap, XyPlot};
use super::facts::{InfoRow, Row, Shown};
use super::plots::{Missing, Plot};
use super::timeline::{Mark, ModeBand};
use crate::describe::{bytes_kind, thousands, BINARY};
use crate::markup::{self, data_uri, escape};

const UPLOT_JS: &str = include_str!("../../assets/report/uPlot.iife.min.js");
const UPLOT_CSS: &str = include_str!("../../assets/report/uPlot.min.css");
const UPLOT_LICENSE: &str = include_str!("../../assets/report/LICENSE-uPlot.txt");
const REPORT_JS: &str = include_str!("../../assets/report/report.js");
const REPORT_CSS: &str = include_str!("../../assets/report/report.css");

/// What the script draws.
#[derive(Debug, Serialize)]
pub struct Drawn {
    /// Time zero of the page: microseconds since boot.
    pub origin_us: u64,
    /// The log's duration in seconds (the time axis of every plot).
    pub duration: f64,
    /// What the time axis counts.
    pub x_label: &'static str,
    /// Flight modes, behind every time plot.
    pub modes: Vec<ModeBand>,
    /// Marked instants.
    pub marks: Vec<Mark>,
    /// The time plots.
    pub plots: Vec<Plot>,
    /// The track in local metres (east, north), if any.
    pub track: Option<Vec<[f32; 2]>>,
    /// Spectra and step responses.
    pub analysis: Vec<XyPlot>,
    /// Spectrograms.
    pub heatmaps: Vec<Heatmap>,
}

/// Everything on the page.
pub struct Page {
    /// The log's file name.
    pub title: String,
    /// The header.
    pub header: Vec<Row>,
    /// Standard plots the log lacks data for.
    pub missing: Vec<Missing>,
    /// Notes on the whole report (e.g. a log without PX4's topics).
    pub notes: Vec<String>,
    /// (seconds, level, text).
    pub messages: Vec<(f64, &'static str, String)>,
    /// (name, value, default).
    pub params_vs_defaults: Vec<[String; 3]>,
    /// (seconds, name, value).
    pub params_changed: Vec<(f64, String, String)>,
    /// Information.
    pub info: Vec<InfoRow>,
    /// Multi-information.
    pub multi: Vec<InfoRow>,
    /// The flight analysis's diagnostics.
    pub diagnostics: Vec<DiagnosticRow>,
    /// What the flight analysis could not do, and why.
    pub analysis_notes: Vec<String>,
    /// On a page comparing logs: the parameters that differ across them (the columns'
    /// names, then per parameter its name and each log's value). Such a page has no
    /// messages, parameter or information tables of its own.
    pub params_across: Option<(Vec<String>, Vec<Vec<String>>)>,
    /// The drawn part.
    pub drawn: Drawn,
}

/// `h:mm:ss.mmm` of seconds since the log's start.
fn clock(s: f64) -> String {
    let ms = (s.max(0.0) * 1000.0).round() as u64;
    let sec = ms / 1000;
    format!(
        "{}:{:02}:{:02}.{:03}",
        sec / 3600,
        sec / 60 % 60,
        sec % 60,
        ms % 1000
    )
}

/// The page's HTML.
pub fn render(page: &Page) -> Result<String, serde_json::Error> {
    let data = script_json(&serde_json::to_string(&page.drawn)?);
    let mut h = String::with_capacity(data.len() + UPLOT_JS.len() + 64 * 1024);
    let title = escape(&page.title);
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{title} — flight report</title>\n<style>\n{UPLOT_CSS}\n{REPORT_CSS}\n</style>\n</head>\n<body>\n\
         <header><h1>Flight report: {title}</h1>\n<table id=\"summary\">\n"
    );
    for (k, v) in &page.header {
        let _ = writeln!(h, "<tr><th>{}</th><td>{}</td></tr>", escape(k), escape(v));
    }
    h.push_str("</table>\n");
    h.push_str(
        "<p class=\"help\">Drag across a plot to zoom the time axis of every plot; \
         double-click to zoom out. Click a legend entry to hide or show its line. \
         Coloured bands are flight modes.</p>\n</header>\n",
    );
    h.push_str("<section id=\"notes\">\n");
    for n in &page.notes {
        let _ = writeln!(h, "<p class=\"note\">{}</p>", escape(n));
    }
    if !page.missing.is_empty() {
        h.push_str(
            "<details class=\"missing\"><summary>Plots this log has no data for</summary><ul>\n",
        );
        for m in &page.missing {
            let _ = writeln!(
                h,
                "<li>{}: the log has no data in {}</li>",
                escape(&m.title),
                escape(&m.needs)
            );
        }
        h.push_str("</ul></details>\n");
    }
    diagnostics_table(&mut h, &page.diagnostics);
    h.push_str("</section>\n<div id=\"modes\"></div>\n<main id=\"plots\"></main>\n");
    h.push_str("<section id=\"track-section\"></section>\n");
    h.push_str(
        "<section id=\"analysis-section\"><h2>Spectra and step responses</h2>\n\
         <p class=\"help\">Power spectral densities (Welch, 1 s segments) of the raw IMU and \
         of the controllers' outputs while armed, the IMU's power over time, and the rate \
         controllers' mean response to a unit step of their setpoint.</p>\n",
    );
    for n in &page.analysis_notes {
        let _ = writeln!(h, "<p class=\"note\">{}</p>", escape(n));
    }
    h.push_str("<div id=\"analysis-plots\"></div></section>\n");

    if let Some((columns, rows)) = &page.params_across {
        params_across(&mut h, columns, rows);
        return Ok(finish(h, &data));
    }
    messages_table(&mut h, &page.messages);
    h.push_str("<section><h2>Parameters changed from their defaults</h2>\n");
    if page.params_vs_defaults.is_empty() {
        h.push_str("<p class=\"note\">None, or the log gives no defaults.</p>\n");
    } else {
        h.push_str("<table id=\"params-defaults\" class=\"list\"><thead><tr><th>name</th><th>value</th><th>default</th></tr></thead><tbody>\n");
        for [n, v, d] in &page.params_vs_defaults {
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{}</td></tr>",
                escape(n),
                escape(v),
                escape(d)
            );
        }
        h.push_str("</tbody></table>\n");
    }
    h.push_str("</section>\n<section><h2>Parameters changed during the flight</h2>\n");
    if page.params_changed.is_empty() {
        h.push_str("<p class=\"note\">None.</p>\n");
    } else {
        h.push_str("<table id=\"params-changed\" class=\"list\"><thead><tr><th>time</th><th>name</th><th>value</th></tr></thead><tbody>\n");
        for (t, n, v) in &page.params_changed {
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{}</td></tr>",
                clock(*t),
                escape(n),
                escape(v)
            );
        }
        h.push_str("</tbody></table>\n");
    }
    h.push_str("</section>\n");
    key_values(&mut h, "Information", "info", &page.info);
    key_values(&mut h, "Multi-information", "multi-info", &page.multi);
    Ok(finish(h, &data))
}

/// The footer, the data and the scripts.
fn finish(mut h: String, data: &str) -> String {
    let _ = writeln!(
        h,
        "<footer>Written by <code>ulog report</code>. Plots drawn with uPlot 1.6.32 \
         (MIT licence, below).<details><summary>uPlot's licence</summary><pre>{}</pre></details></footer>",
        escape(UPLOT_LICENSE)
    );
    let _ = write!(
        h,
        "<script id=\"report-data\" type=\"application/json\">{data}</script>\n\
         <script>\n{UPLOT_JS}\n</script>\n<script>\n{REPORT_JS}\n</script>\n</body>\n</html>\n"
    );
    h
}

/// The parameters that differ across the logs of a comparing page.
fn params_across(h: &mut String, columns: &[String], rows: &[Vec<String>]) {
    h.push_str("<section><h2>Parameters that differ across the logs</h2>\n");
    if rows.is_empty() {
        h.push_str("<p class=\"note\">None: every log has the same parameters.</p></section>\n");
        return;
    }
    h.push_str("<table id=\"params-across\" class=\"list\"><thead><tr><th>name</th>");
    for c in columns {
        let _ = write!(h, "<th>{}</th>", escape(c));
    }
    h.push_str("</tr></thead><tbody>\n");
    for r in rows {
        h.push_str("<tr>");
        for cell in r {
            let _ = write!(h, "<td>{}</td>", escape(cell));
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</tbody></table></section>\n");
}

fn diagnostics_table(h: &mut String, rows: &[DiagnosticRow]) {
    h.push_str("<h2>Diagnostics</h2>\n");
    if rows.is_empty() {
        h.push_str(
            "<p class=\"note\" id=\"no-diagnostics\">No battery brownout, EKF failure, GPS \
             interference, motor failure or RC loss found.</p>\n",
        );
        return;
    }
    h.push_str("<table id=\"diagnostics\" class=\"list\"><thead><tr><th>from</th><th>to</th><th>severity</th><th>diagnostic</th><th>summary</th><th>evidence</th></tr></thead><tbody>\n");
    for d in rows {
        let _ = writeln!(
            h,
            "<tr class=\"sev-{}\"><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            d.severity,
            clock(d.t),
            d.end.map_or_else(String::new, clock),
            d.severity,
            d.id,
            escape(&d.summary),
            escape(&d.evidence)
        );
    }
    h.push_str("</tbody></table>\n");
}

fn messages_table(h: &mut String, messages: &[(f64, &'static str, String)]) {
    h.push_str(
        "<section><h2>Logged messages and events</h2>\n\
         <label>Show level <select id=\"level-filter\">\
         <option value=\"7\">DEBUG and above (all)</option>\
         <option value=\"6\">INFO and above</option>\
         <option value=\"5\">NOTICE and above</option>\
         <option value=\"4\">WARNING and above</option>\
         <option value=\"3\">ERROR and above</option>\
         </select></label>\n",
    );
    if messages.is_empty() {
        h.push_str("<p class=\"note\">The log has no logged messages or events.</p>\n");
    }
    h.push_str("<table id=\"messages\" class=\"list\"><thead><tr><th>time</th><th>level</th><th>message</th></tr></thead><tbody>\n");
    for (t, level, text) in messages {
        let _ = writeln!(
            h,
            "<tr class=\"lvl-{}\" data-level=\"{}\"><td>{}</td><td>{}</td><td>{}</td></tr>",
            level.to_ascii_lowercase(),
            severity(level),
            clock(*t),
            level,
            escape(text)
        );
    }
    h.push_str("</tbody></table></section>\n");
}

/// The severity number of a level name (0 EMERGENCY … 7 DEBUG; other names as 7).
pub fn severity(level: &str) -> u8 {
    (0..8)
        .find(|&l| ulog_core::events::level_name(l) == level)
        .unwrap_or(7)
}

/// Texts of more lines than this, or more characters, are folded under their first
/// line.
const FOLD_LINES: usize = 12;
const FOLD_CHARS: usize = 2_000;
/// The characters of a folded text's first line shown.
const SUMMARY_CHARS: usize = 120;
/// Byte values up to this size are also shown in hex.
const HEX_BYTES: usize = 64;
/// Byte values up to this size can be downloaded from the page (a `data:` link, a
/// third larger than the bytes; PX4's `metadata_events` is some 50 KB).
const LINK_BYTES: usize = 256 * 1024;

fn key_values(h: &mut String, title: &str, id: &str, rows: &[InfoRow]) {
    let _ = writeln!(h, "<section><h2>{title}</h2>");
    if rows.is_empty() {
        h.push_str("<p class=\"note\">None.</p></section>\n");
        return;
    }
    let _ = writeln!(
        h,
        "<table id=\"{id}\" class=\"list\"><thead><tr><th>key</th><th>value</th></tr></thead><tbody>"
    );
    for (k, entries) in rows {
        let _ = write!(h, "<tr><td>{}</td><td>", escape(k));
        for (i, v) in entries.iter().enumerate() {
            // A key logged several times (multi-information): each entry on its own.
            let name = match entries.len() {
                1 => k.clone(),
                n => {
                    let _ = write!(h, "<div class=\"entry\">{} of {n}</div>", i + 1);
                    format!("{k}_{}", i + 1)
                }
            };
            value_html(h, &name, v);
        }
        h.push_str("</td></tr>\n");
    }
    h.push_str("</tbody></table></section>\n");
}

/// One value of the information tables: a text (folded under its first line when
/// long), or bytes as their size and what they are (told by their magic number), in
/// hex when short, with a link that downloads them (as `name.<extension>`) unless
/// they are large.
fn value_html(h: &mut String, name: &str, v: &Shown) {
    match v {
        Shown::Text(t) if t.lines().count() > FOLD_LINES || t.chars().count() > FOLD_CHARS => {
            let first = t.lines().find(|l| !l.trim().is_empty()).unwrap_or("");
            let mut shown: String = first.chars().take(SUMMARY_CHARS).collect();
            if shown.len() < first.len() {
                shown.push('…');
            }
            let _ = write!(
                h,
                "<details class=\"long\"><summary><code>{}</code> ({} lines, {} characters)</summary><pre>{}</pre></details>",
                escape(&shown),
                thousands(t.lines().count()),
                thousands(t.chars().count()),
                escape(t)
            );
        }
        Shown::Text(t) => {
            let _ = write!(h, "<pre>{}</pre>", escape(t));
        }
        Shown::Bytes(b) => {
            let kind = bytes_kind(b);
            let _ = write!(
                h,
                "<span class=\"bytes\">{} byte{}, {}</span>",
                thousands(b.len()),
                if b.len() == 1 { "" } else { "s" },
                kind.unwrap_or(BINARY).name
            );
            if b.len() <= HEX_BYTES {
                let hex: Vec<String> = b.iter().map(|x| format!("{x:02x}")).collect();
                let _ = write!(h, " <code class=\"hex\">{}</code>", hex.join(" "));
            }
            if b.is_empty() {
                return;
            }
            if b.len() <= LINK_BYTES {
                let kind = kind.unwrap_or(BINARY);
                let _ = write!(
                    h,
                    " <a class=\"download\" download=\"{}.{}\" href=\"{}\">download</a>",
                    escape(name),
                    kind.extension,
                    data_uri(kind.mime, b)
                );
            } else {
                h.push_str(" (too large to embed)");
            }
        }
    }
}

/// JSON for a `<script>` element: `<` (`</` or `<!--` would end the element early)
/// and the characters HTML cannot hold ([`markup::unfit`]) as `\u` escapes, which JSON
/// reads as the same text. Both only occur inside JSON strings.
fn script_json(json: &str) -> String {
    let mut out = String::with_capacity(json.len());
    for c in json.chars() {
        if c == '<' || markup::unfit(c) {
            let mut units = [0u16; 2];
            for u in c.encode_utf16(&mut units) {
                let _ = write!(out, "\\u{u:04x}");
            }
        } else {
            out.push(c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_escaped_and_times_are_clock_times() {
        assert_eq!(escape("<a & \"b\">"), "&lt;a &amp; &quot;b&quot;&gt;");
        assert_eq!(clock(3723.0456), "1:02:03.046");
        assert_eq!(severity("ERROR"), 3);
        assert_eq!(severity("UNKNOWN"), 7);
    }

    #[test]
    fn script_json_holds_no_markup_and_reads_back_the_same() {
        let text = "</script><!-- \u{1}\u{7f}\u{85}\u{fffe}\u{1fffe} é";
        let json = serde_json::to_string(&text).unwrap();
        let safe = script_json(&json);
        assert!(!safe.contains('<'), "{safe}");
        assert!(!safe.chars().any(markup::unfit), "{safe}");
        let back: String = serde_json::from_str(&safe).unwrap();
        assert_eq!(back, text);
    }
}
