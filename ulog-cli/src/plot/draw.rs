//! Drawing the chart with `plotters`, on any of its backends (SVG, bitmap).

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontTransform;

use ulog_core::read::UtcTime;

use super::markers::{Kind, Marker};
use super::series::Series;

/// The font family every text of the chart names (an SVG viewer picks its own sans-serif;
/// bitmaps and all text layout use the built-in font, see `super::font`).
pub const FONT: &str = "sans-serif";

/// Line colours, in order (the "tab10" palette).
const COLOURS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];
const PARAM_COLOUR: RGBColor = RGBColor(90, 90, 160);
const ERROR_COLOUR: RGBColor = RGBColor(200, 0, 0);

/// Everything on the picture.
pub struct Chart<'a> {
    /// The caption.
    pub title: &'a str,
    /// The lines, already cut to the time range and decimated.
    pub series: &'a [Series],
    /// The markers within the time range.
    pub markers: &'a [Marker],
    /// The time axis, in seconds since log start.
    pub x_range: (f64, f64),
    /// One panel per series instead of all on one.
    pub separate: bool,
    /// The UTC time of the log's start (x = 0), to label the time axis with (`--utc`).
    pub utc_start: Option<UtcTime>,
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// Draws `chart` on `root`.
pub fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart<'_>,
) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let body = root.titled(chart.title, (FONT, 22))?;
    let indexed: Vec<(usize, &Series)> = chart.series.iter().enumerate().collect();
    if chart.separate && indexed.len() > 1 {
        let panels = body.split_evenly((indexed.len(), 1));
        let last = panels.len() - 1;
        for (i, (panel, s)) in panels.iter().zip(&indexed).enumerate() {
            let layout = Panel {
                marker_labels: i == 0,
                x_desc: i == last,
            };
            draw_panel(panel, std::slice::from_ref(s), chart, layout)?;
        }
    } else {
        let layout = Panel {
            marker_labels: true,
            x_desc: true,
        };
        draw_panel(&body, &indexed, chart, layout)?;
    }
    root.present()
}

#[derive(Clone, Copy)]
struct Panel {
    /// Write the markers' labels (only on the first panel, to keep the others clear).
    marker_labels: bool,
    /// Name the time axis (only on the last panel).
    x_desc: bool,
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    series: &[(usize, &Series)],
    chart: &Chart<'_>,
    layout: Panel,
) -> DrawResult<DB> {
    let (x0, x1) = chart.x_range;
    let (y0, y1) = y_range(series.iter().map(|(_, s)| *s));
    let mut ctx = ChartBuilder::on(area)
        .margin(8)
        .margin_right(24)
        .x_label_area_size(if layout.x_desc { 44 } else { 24 })
        .y_label_area_size(76)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    let mut mesh = ctx.configure_mesh();
    let utc_start = chart.utc_start;
    let x_ticks = move |v: &f64| match utc_start {
        Some(t0) => utc_tick(t0, *v, x1 - x0),
        None => tick(*v, x1 - x0),
    };
    let y_ticks = move |v: &f64| tick(*v, y1 - y0);
    mesh.y_desc(y_desc(series.iter().map(|(_, s)| *s)))
        .x_label_formatter(&x_ticks)
        .y_label_formatter(&y_ticks)
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 15))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(205, 205, 205));
    let utc_desc = utc_start.map(|t0| {
        let day = format!("{:.0}", t0);
        format!("UTC time of day (log start: {})", day.replace('T', " "))
    });
    if layout.x_desc {
        mesh.x_desc(utc_desc.as_deref().unwrap_or("time since log start [s]"));
    }
    mesh.draw()?;

    for (kind, colour, what) in [
        (Kind::Param, PARAM_COLOUR, "parameter change"),
        (Kind::Error, ERROR_COLOUR, "error message"),
    ] {
        let marks: Vec<&Marker> = chart.markers.iter().filter(|m| m.kind == kind).collect();
        if marks.is_empty() {
            continue;
        }
        let style = colour.mix(0.7).stroke_width(1);
        let lines = ctx.draw_series(
            marks
                .iter()
                .map(|m| DashedPathElement::new(vec![(m.x, y0), (m.x, y1)], 6, 4, style)),
        )?;
        if layout.marker_labels {
            lines
                .label(format!("{what} ({})", marks.len()))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x + 10, y - 6), (x + 10, y + 6)], style)
                });
        }
    }

    for &(i, s) in series {
        let colour = COLOURS[i % COLOURS.len()];
        let style = colour.stroke_width(2);
        ctx.draw_series(LineSeries::new(s.points.iter().copied(), style))?
            .label(s.legend())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
    }

    let legend_entries: Vec<String> = chart
        .markers
        .iter()
        .filter(|_| layout.marker_labels)
        .map(|m| m.kind)
        .fold(Vec::new(), |mut kinds, k| {
            if !kinds.contains(&k) {
                kinds.push(k);
            }
            kinds
        })
        .into_iter()
        .map(|k| format!("{k:?} marker (00)"))
        .chain(series.iter().map(|(_, s)| s.legend()))
        .collect();
    let legend_font = TextStyle::from((FONT, 14).into_font());
    let (mut legend_w, mut line_h) = (0, 16);
    for e in &legend_entries {
        let (w, h) = area.estimate_text_size(e, &legend_font)?;
        legend_w = legend_w.max(w);
        line_h = line_h.max(h);
    }
    let legend_px = (legend_w + 50, line_h * legend_entries.len() as u32 + 20);
    let corner = legend_corner(
        ctx.plotting_area().dim_in_pixel(),
        legend_px,
        (x0, x1, y0, y1),
        series.iter().map(|(_, s)| *s),
        chart.markers.iter().filter(|_| layout.marker_labels),
    );
    ctx.configure_series_labels()
        .position(corner)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3))
        .label_font((FONT, 14))
        .draw()?;

    if layout.marker_labels {
        // Parameter labels hang from the top, error texts rise from the bottom, so the
        // two kinds do not overprint when they come at the same moment.
        let plot = ctx.plotting_area();
        let room = i32::try_from(plot.dim_in_pixel().1).unwrap_or(i32::MAX) - 12;
        for m in chart.markers {
            let font = (FONT, 12).into_font();
            let plain = TextStyle::from(font.clone());
            let text = fit(&m.label, room, |t| {
                plot.estimate_text_size(t, &plain)
                    .map_or(0, |(w, _)| w as i32)
            });
            let label = match m.kind {
                Kind::Param => {
                    // Anchored at its bottom: turned a quarter clockwise, the text lies
                    // right of the line, as the error texts do.
                    let style = TextStyle::from(font)
                        .color(&PARAM_COLOUR)
                        .transform(FontTransform::Rotate90)
                        .pos(Pos::new(HPos::Left, VPos::Bottom));
                    EmptyElement::at((m.x, y1)) + Text::new(text, (3, 6), style)
                }
                Kind::Error => {
                    let style = TextStyle::from(font)
                        .color(&ERROR_COLOUR)
                        .transform(FontTransform::Rotate270);
                    EmptyElement::at((m.x, y0)) + Text::new(text, (3, -6), style)
                }
            };
            plot.draw(&label)?;
        }
    }
    Ok(())
}

/// The corner of the plot where the legend (`legend` pixels) hides the fewest points,
/// and no marker labels (parameter labels hang from the top, error texts rise from the
/// bottom); on a tie the upper right, then upper left, lower right, lower left.
fn legend_corner<'s>(
    plot: (u32, u32),
    legend: (u32, u32),
    (x0, x1, y0, y1): (f64, f64, f64, f64),
    series: impl Iterator<Item = &'s Series>,
    markers: impl Iterator<Item = &'s Marker>,
) -> SeriesLabelPosition {
    let (w, h) = (f64::from(plot.0), f64::from(plot.1));
    // The box of the legend, with the margin plotters leaves, as fractions of the plot.
    let bw = ((f64::from(legend.0) + 10.0) / w).min(1.0);
    let bh = ((f64::from(legend.1) + 10.0) / h).min(1.0);
    let fx = |x: f64| (x - x0) / (x1 - x0);
    let fy = |y: f64| (y1 - y) / (y1 - y0);
    let in_x = |f: f64, right: bool| if right { f >= 1.0 - bw } else { f <= bw };
    let in_y = |f: f64, lower: bool| if lower { f >= 1.0 - bh } else { f <= bh };
    // (upper right, upper left, lower right, lower left): (right, lower).
    let corners = [(true, false), (false, false), (true, true), (false, true)];
    let mut score = [0usize; 4];
    for s in series {
        for &(x, y) in &s.points {
            let (px, py) = (fx(x), fy(y));
            for (i, &(right, lower)) in corners.iter().enumerate() {
                if in_x(px, right) && in_y(py, lower) {
                    score[i] += 1;
                }
            }
        }
    }
    for m in markers {
        let px = fx(m.x);
        let lower_label = m.kind == Kind::Error;
        for (i, &(right, lower)) in corners.iter().enumerate() {
            if in_x(px, right) && lower == lower_label {
                // A hidden label weighs as much as a stretch of line.
                score[i] += 1000;
            }
        }
    }
    let best = (0..4).min_by_key(|&i| (score[i], i)).unwrap_or(0);
    match best {
        0 => SeriesLabelPosition::UpperRight,
        1 => SeriesLabelPosition::UpperLeft,
        2 => SeriesLabelPosition::LowerRight,
        _ => SeriesLabelPosition::LowerLeft,
    }
}

/// `label`, cut (ending in `…`) to be at most `room` pixels long by `width`.
fn fit(label: &str, room: i32, width: impl Fn(&str) -> i32) -> String {
    if width(label) <= room {
        return label.to_owned();
    }
    let mut chars: Vec<char> = label.chars().collect();
    while !chars.is_empty() {
        chars.pop();
        let t: String = chars.iter().chain(['…'].iter()).collect();
        if width(&t) <= room {
            return t;
        }
    }
    String::new()
}

/// A tick label on an axis spanning `span`: as many decimals as ticks about a tenth of
/// the span apart need, trailing zeros dropped (`10`, `2.5`, `0.125`).
fn tick(v: f64, span: f64) -> String {
    let decimals = if span > 0.0 && span.is_finite() {
        (1.0 - (span / 10.0).log10().floor()).clamp(0.0, 9.0) as usize
    } else {
        3
    };
    let mut s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.truncate(s.trim_end_matches('0').trim_end_matches('.').len());
    }
    if s == "-0" {
        s.remove(0);
    }
    s
}

/// The value axis: every point with a margin of 5 % (a flat line gets a band around it).
fn y_range<'s>(series: impl Iterator<Item = &'s Series>) -> (f64, f64) {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for s in series {
        for &(_, y) in &s.points {
            lo = lo.min(y);
            hi = hi.max(y);
        }
    }
    // No points: lo and hi are still infinite.
    if lo > hi {
        return (-1.0, 1.0);
    }
    let pad = if hi > lo {
        (hi - lo) * 0.05
    } else if lo == 0.0 {
        1.0
    } else {
        lo.abs() * 0.1
    };
    (lo - pad, hi + pad)
}

/// The value axis' name: the units of the series, or `value` when none is known.
fn y_desc<'s>(series: impl Iterator<Item = &'s Series>) -> String {
    let mut units: Vec<&str> = Vec::new();
    for s in series {
        if let Some(u) = s.unit {
            if !units.contains(&u) {
                units.push(u);
            }
        }
    }
    if units.is_empty() {
        "value".to_owned()
    } else {
        units.join(", ")
    }
}

/// A time axis label in UTC: the time of day `seconds` after `start`, with tenths of a
/// second when the axis spans less than 10 s.
fn utc_tick(start: UtcTime, seconds: f64, span: f64) -> String {
    let t = UtcTime(
        start
            .micros()
            .saturating_add((seconds * 1e6).round() as i64),
    );
    let text = if span < 10.0 {
        format!("{t:.1}")
    } else {
        format!("{t:.0}")
    };
    // `2024-02-06T08:25:44.5Z` → `08:25:44.5`.
    match text.split_once('T') {
        Some((_, time)) => time.trim_end_matches('Z').to_owned(),
        None => text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series(unit: Option<&'static str>, ys: &[f64]) -> Series {
        Series {
            label: "t.f".into(),
            unit,
            points: ys.iter().enumerate().map(|(i, &y)| (i as f64, y)).collect(),
        }
    }

    #[test]
    fn value_axis_covers_every_point_with_a_margin() {
        let a = series(None, &[1.0, 3.0]);
        let b = series(None, &[-1.0]);
        let (lo, hi) = y_range([&a, &b].into_iter());
        assert!(lo < -1.0 && hi > 3.0 && hi - lo < 4.5);
        assert_eq!(y_range([&series(None, &[])].into_iter()), (-1.0, 1.0));
        let (lo, hi) = y_range([&series(None, &[5.0, 5.0])].into_iter());
        assert!(lo < 5.0 && hi > 5.0);
    }

    #[test]
    fn labels_are_cut_to_the_room() {
        let width = |t: &str| 7 * t.chars().count() as i32;
        assert_eq!(fit("abcdef", 42, width), "abcdef");
        assert_eq!(fit("abcdef", 41, width), "abcd…");
        assert_eq!(fit("abcdef", 3, width), "");
    }

    #[test]
    fn the_legend_goes_where_it_hides_least() {
        let ranges = (0.0, 10.0, 0.0, 10.0);
        let rising = series(
            None,
            &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0],
        );
        let corner = |s: &[&Series], m: &[Marker]| {
            legend_corner(
                (1000, 1000),
                (300, 100),
                ranges,
                s.iter().copied(),
                m.iter(),
            )
        };
        // A line rising to the upper right leaves the upper left free.
        assert!(matches!(
            corner(&[&rising], &[]),
            SeriesLabelPosition::UpperLeft
        ));
        let falling = series(
            None,
            &[10.0, 9.0, 8.0, 7.0, 6.0, 5.0, 4.0, 3.0, 2.0, 1.0, 0.0],
        );
        assert!(matches!(
            corner(&[&falling], &[]),
            SeriesLabelPosition::UpperRight
        ));
        // A parameter label at the top right pushes the legend to the free lower left.
        let param = Marker {
            x: 9.5,
            kind: Kind::Param,
            label: "A=1".into(),
        };
        assert!(matches!(
            corner(&[&falling], &[param]),
            SeriesLabelPosition::LowerLeft
        ));
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick(10.0, 90.0), "10");
        assert_eq!(tick(2.5, 9.0), "2.5");
        assert_eq!(tick(-0.0001, 9.0), "0");
        assert_eq!(tick(0.125, 0.5), "0.125");
        assert_eq!(tick(1500.0, 4000.0), "1500");
    }

    #[test]
    fn value_axis_names_the_units_once_each() {
        let s = [
            series(Some("m"), &[]),
            series(None, &[]),
            series(Some("m/s"), &[]),
            series(Some("m"), &[]),
        ];
        assert_eq!(y_desc(s.iter()), "m, m/s");
        assert_eq!(y_desc(s[1..2].iter()), "value");
    }
}
