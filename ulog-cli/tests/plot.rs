//! `ulog plot`: pictures of real logs (SVG and PNG), checked for what they must show,
//! and one clear line with a distinct exit status for each kind of bad input.

mod common;

use std::path::Path;
use std::process::Output;

/// The text of every `<text>` element of an SVG, whitespace-trimmed.
fn svg_texts(svg: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = svg;
    while let Some(i) = rest.find("<text") {
        rest = &rest[i..];
        let Some(open_end) = rest.find('>') else {
            break;
        };
        let Some(close) = rest.find("</text>") else {
            break;
        };
        out.push(unescape(rest[open_end + 1..close].trim()));
        rest = &rest[close..];
    }
    out
}

fn unescape(s: &str) -> String {
    s.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&apos;", "'")
        .replace("&#39;", "'")
        .replace("&amp;", "&")
}

/// `(stroke colour, number of points)` of every `<polyline>` of an SVG.
fn polylines(svg: &str) -> Vec<(String, usize)> {
    svg.split("<polyline")
        .skip(1)
        .map(|p| {
            let tag = &p[..p.find("/>").unwrap_or(p.len())];
            let attr = |name: &str| {
                let key = format!("{name}=\"");
                tag.find(&key).map(|i| {
                    let v = &tag[i + key.len()..];
                    v[..v.find('"').unwrap()].to_owned()
                })
            };
            let points = attr("points").unwrap_or_default();
            (
                attr("stroke").unwrap_or_default(),
                points.split_whitespace().count(),
            )
        })
        .collect()
}

/// The polylines that draw data (more than a legend swatch or a dash has).
fn data_lines(svg: &str) -> Vec<(String, usize)> {
    polylines(svg)
        .into_iter()
        .filter(|(_, n)| *n > 10)
        .collect()
}

fn plot(args: &[&str]) -> Output {
    common::ulog(args)
}

fn assert_ok(out: &Output) -> String {
    assert!(
        out.status.success(),
        "ulog plot failed ({:?}): {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout.clone()).unwrap()
}

/// One line on stderr starting with `ulog: `, containing each of `expect`, with exit
/// status `status`, nothing on stdout.
fn assert_fails(out: &Output, status: i32, expect: &[&str]) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        out.status.code(),
        Some(status),
        "exit status; stderr: {err}"
    );
    assert!(out.stdout.is_empty(), "stdout: {:?}", out.stdout);
    assert_eq!(err.lines().count(), 1, "one line expected: {err}");
    assert!(err.starts_with("ulog: "), "{err}");
    for e in expect {
        assert!(err.contains(e), "`{e}` expected in: {err}");
    }
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

#[test]
#[cfg_attr(
    not(full_corpus),
    ignore = "needs the full corpus: ../shared/corpus beside the workspace, or $ULOG_CORPUS"
)]
fn svg_of_a_real_log_shows_each_series_and_the_markers() {
    let corpus = common::corpus();
    let log = corpus.join("files/sample.ulg");
    let summary = common::summary(&corpus, "sample");
    let svg_path = common::scratch("plot_svg").join("pos.svg");
    assert_ok(&plot(&[
        "plot",
        s(&log),
        "vehicle_local_position.z,vehicle_local_position.vz",
        "sensor_combined.gyro_rad[2]",
        "-o",
        s(&svg_path),
    ]));
    let svg = std::fs::read_to_string(&svg_path).expect("SVG written");
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert!(
        svg.len() > 10_000,
        "a non-trivial picture: {} bytes",
        svg.len()
    );
    let texts = svg_texts(&svg);

    // One legend entry per series, with its unit; one line of data per series, each in
    // its own colour.
    for label in [
        "vehicle_local_position.z [m]",
        "vehicle_local_position.vz [m/s]",
        "sensor_combined.gyro_rad[2] [rad/s]",
    ] {
        assert!(
            texts.iter().any(|t| t == label),
            "legend `{label}` in {texts:?}"
        );
    }
    let lines = data_lines(&svg);
    assert_eq!(lines.len(), 3, "one polyline per series: {lines:?}");
    let mut colours: Vec<&str> = lines.iter().map(|(c, _)| c.as_str()).collect();
    colours.dedup();
    assert_eq!(colours.len(), 3, "distinct colours: {lines:?}");
    // The axes are named, the value axis with the units.
    assert!(texts.iter().any(|t| t.contains("time since log start")));
    assert!(texts.iter().any(|t| t == "m, m/s, rad/s"), "{texts:?}");

    // Every parameter changed during the flight is marked (pyulog's list).
    let changed = summary["changed_parameters"].as_array().unwrap();
    assert!(!changed.is_empty());
    for c in changed {
        let name = c[1].as_str().unwrap();
        assert!(
            texts.iter().any(|t| t.contains(&format!("{name}="))),
            "parameter change of {name} marked"
        );
    }
    // Every logged message of level ERROR or worse is marked with (the start of) its text.
    let errors: Vec<&str> = summary["logged_messages"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m[0].as_u64().unwrap() <= u64::from(b'3'))
        .map(|m| m[2].as_str().unwrap())
        .collect();
    assert!(!errors.is_empty());
    for e in errors {
        let start: String = e.chars().take(20).collect();
        assert!(
            texts.iter().any(|t| t.starts_with(&start)),
            "message `{e}` marked"
        );
    }

    // Without markers, neither kind is drawn.
    let bare = common::scratch("plot_svg_bare").join("bare.svg");
    assert_ok(&plot(&[
        "plot",
        s(&log),
        "vehicle_local_position.z",
        "--no-params",
        "--no-messages",
        "-o",
        s(&bare),
    ]));
    let texts = svg_texts(&std::fs::read_to_string(&bare).unwrap());
    assert!(
        !texts.iter().any(|t| t.contains("COM_AUTOS_PAR")),
        "{texts:?}"
    );
    assert!(!texts.iter().any(|t| t.contains("barometer")), "{texts:?}");
}

#[test]
#[cfg_attr(
    not(full_corpus),
    ignore = "needs the full corpus: ../shared/corpus beside the workspace, or $ULOG_CORPUS"
)]
fn long_series_are_thinned_per_pixel_column() {
    let corpus = common::corpus();
    let log = corpus.join("files/sample.ulg");
    let rows = common::summary(&corpus, "sample")["topics"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["name"] == "sensor_combined")
        .unwrap()["rows"]
        .as_u64()
        .unwrap() as usize;
    let out = common::scratch("plot_thin").join("gyro.svg");
    assert_ok(&plot(&[
        "plot",
        s(&log),
        "sensor_combined.gyro_rad[0]",
        "--size",
        "400x300",
        "-o",
        s(&out),
    ]));
    let svg = std::fs::read_to_string(&out).unwrap();
    assert!(svg.contains(r#"width="400" height="300""#));
    let lines = data_lines(&svg);
    assert_eq!(lines.len(), 1);
    let drawn = lines[0].1;
    assert!(rows > 4 * 400, "the topic is long: {rows} rows");
    assert!(
        drawn <= 4 * 400,
        "at most 4 points per pixel column: {drawn}"
    );
    assert!(drawn >= 400, "every column keeps points: {drawn}");
}

#[test]
#[cfg_attr(
    not(full_corpus),
    ignore = "needs the full corpus: ../shared/corpus beside the workspace, or $ULOG_CORPUS"
)]
fn png_has_the_asked_size() {
    let corpus = common::corpus();
    let log = corpus.join("files/log_61_2024-2-6-16-27-02.ulg");
    let out = common::scratch("plot_png").join("flight.png");
    assert_ok(&plot(&[
        "plot",
        s(&log),
        "vehicle_local_position.z,battery_status.voltage_v",
        "--size",
        "900x500",
        "--separate",
        "--title",
        "A flight",
        "-o",
        s(&out),
    ]));
    let png = std::fs::read(&out).expect("PNG written");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&png[12..16], b"IHDR");
    let be = |b: &[u8]| u32::from_be_bytes(b.try_into().unwrap());
    assert_eq!((be(&png[16..20]), be(&png[20..24])), (900, 500));
    assert!(
        png.len() > 10_000,
        "a non-trivial picture: {} bytes",
        png.len()
    );

    // Decoded: text is drawn (dark pixels in the caption's band at the top, with no font
    // installed on the system), and so are coloured lines.
    let mut reader = png::Decoder::new(std::io::Cursor::new(&png))
        .read_info()
        .unwrap();
    let mut rgb = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut rgb).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    let pixel = |x: usize, y: usize| {
        let i = (y * 900 + x) * 3;
        (rgb[i], rgb[i + 1], rgb[i + 2])
    };
    let caption_ink = (0..25)
        .flat_map(|y| (0..900).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let (r, g, b) = pixel(x, y);
            r < 100 && g < 100 && b < 100
        })
        .count();
    assert!(caption_ink > 30, "caption drawn: {caption_ink} dark pixels");
    let coloured = (0..500)
        .flat_map(|y| (0..900).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let (r, g, b) = pixel(x, y);
            r.max(g).max(b) - r.min(g).min(b) > 80
        })
        .count();
    assert!(coloured > 1000, "lines drawn: {coloured} coloured pixels");
}

#[test]
fn whole_arrays_instances_and_the_default_output_name() {
    let file = common::sample_file("plot_default");
    let out = assert_ok(&plot(&[
        "plot",
        s(&file),
        "vehicle_attitude.q,battery_status:1.voltage_v,esc_status.esc[1].esc_rpm",
    ]));
    let expected = file.with_file_name("sample_plot.svg");
    assert!(out.contains(s(&expected)), "names what it wrote: {out}");
    let svg = std::fs::read_to_string(&expected).expect("default output next to FILE");
    let texts = svg_texts(&svg);
    for label in [
        "vehicle_attitude.q[0]",
        "vehicle_attitude.q[3]",
        "battery_status:1.voltage_v [V]",
        "esc_status.esc[1].esc_rpm [rpm]",
    ] {
        assert!(texts.iter().any(|t| t == label), "`{label}` in {texts:?}");
    }
    assert_eq!(data_lines(&svg).len(), 6, "q[0..4], voltage, rpm");
    // The parameter set in flight is marked; warnings are not errors.
    assert!(texts.iter().any(|t| t == "MPC_XY_VEL_MAX=8.0"), "{texts:?}");
    assert!(!texts.iter().any(|t| t.contains("battery at 70%")));
}

#[test]
fn unknown_topic_names_the_closest() {
    let file = common::sample_file("plot_unknown_topic");
    let out = plot(&["plot", s(&file), "vehicle_local_positon.z"]);
    assert_fails(
        &out,
        5,
        &[
            "no topic `vehicle_local_positon`",
            "`vehicle_local_position`",
        ],
    );
    let out = plot(&["plot", s(&file), "battery_status:4.voltage_v"]);
    assert_fails(
        &out,
        5,
        &["topic `battery_status` has no instance 4 (its instances: 0, 1)"],
    );
    assert!(!file.with_file_name("sample_plot.svg").exists());
}

#[test]
fn unknown_field_names_the_closest() {
    let file = common::sample_file("plot_unknown_field");
    let out = plot(&["plot", s(&file), "vehicle_local_position.zz"]);
    assert_fails(&out, 5, &["no field `zz`", "did you mean `z`"]);
    let out = plot(&["plot", s(&file), "esc_status.esc"]);
    assert_fails(&out, 5, &["`esc` is a group of fields", "esc[0]."]);
    // Nothing close (pyulog users ask for `roll`; PX4 logs a quaternion): the fields
    // the topic has, read from the log.
    let out = plot(&["plot", s(&file), "vehicle_attitude.roll"]);
    let bytes = std::fs::read(&file).unwrap();
    let log = ulog_core::ULog::parse(&bytes).unwrap();
    let layout = log.topic("vehicle_attitude", 0).unwrap().layout().unwrap();
    let listed: Vec<String> = layout
        .fields()
        .iter()
        .filter(|f| !f.is_padding())
        .map(|f| match f.array_len {
            Some(n) => format!("`{}[{n}]`", f.name),
            None => format!("`{}`", f.name),
        })
        .collect();
    let listed = format!("(its fields: {})", listed.join(", "));
    assert_fails(&out, 5, &["has no field `roll`", &listed]);
    assert!(!file.with_file_name("sample_plot.svg").exists());
}

#[test]
fn missing_and_refused_files() {
    let dir = common::scratch("plot_files");
    let missing = dir.join("nope.ulg");
    assert_fails(
        &plot(&["plot", s(&missing), "a.b"]),
        3,
        &["nope.ulg: no such file"],
    );
    let junk = dir.join("junk.ulg");
    std::fs::write(&junk, b"%PDF-1.4 this is not a flight log at all").unwrap();
    assert_fails(&plot(&["plot", s(&junk), "a.b"]), 4, &["not a ULog file"]);
    // An output that cannot be written is an I/O failure too.
    let file = common::sample_file("plot_files_out");
    let out = dir.join("no_such_dir").join("x.svg");
    assert_fails(
        &plot(&["plot", s(&file), "vehicle_local_position.z", "-o", s(&out)]),
        3,
        &["x.svg"],
    );
}

#[test]
fn bad_options_are_usage_errors_or_say_why() {
    let file = common::sample_file("plot_usage");
    for args in [
        vec!["vehicle_local_position"],
        vec!["vehicle_local_position.z", "-o", "x.pdf"],
        vec!["vehicle_local_position.z", "--size", "big"],
        vec![],
    ] {
        let mut all = vec!["plot", s(&file)];
        all.extend(args.iter().copied());
        let out = plot(&all);
        assert_eq!(out.status.code(), Some(2), "{args:?}: usage error");
    }
    let out = plot(&[
        "plot",
        s(&file),
        "vehicle_local_position.z",
        "--start",
        "8",
        "--end",
        "2",
    ]);
    assert_fails(&out, 6, &["empty time range"]);
    let out = plot(&["plot", s(&file), "vehicle_local_position.xy_valid"]);
    assert_ok(&out);
}

#[test]
fn help_names_every_option() {
    let top = common::ulog_ok(["--help"]);
    assert!(top.contains("plot"), "{top}");
    let help = common::ulog_ok(["plot", "--help"]);
    for opt in [
        "TOPIC.FIELD",
        "--output",
        "--size",
        "--title",
        "--start",
        "--end",
        "--no-params",
        "--no-messages",
        "--separate",
        "--quiet",
    ] {
        assert!(help.contains(opt), "`{opt}` in plot --help:\n{help}");
    }
}

/// `--start`/`--end` are seconds since the log's start, as `90`, `1:30` or `1:30.5`;
/// `--time-start`/`--time-end` (boot-time seconds in `csv`) are not plot's.
#[test]
fn time_range_is_start_and_end_since_log_start() {
    let file = common::sample_file("plot_start_end");
    let field = "vehicle_local_position.z";
    // An empty range says how the values were read.
    let out = plot(&["plot", s(&file), field, "--start", "1:30", "--end", "1:00"]);
    assert_fails(&out, 6, &["empty time range: 90 s to 60 s since log start"]);
    let out = plot(&["plot", s(&file), field, "--start", "1:30.5", "--end", "90"]);
    assert_fails(
        &out,
        6,
        &["empty time range: 90.5 s to 90 s since log start"],
    );

    let svg = file.with_file_name("range.svg");
    let drawn = |range: &[&str]| {
        let mut args = vec!["plot", s(&file), field, "-o", s(&svg)];
        args.extend_from_slice(range);
        let stdout = assert_ok(&plot(&args));
        let points = stdout.split(" line(s), ").nth(1).expect("points drawn");
        points.split(' ').next().unwrap().parse::<usize>().unwrap()
    };
    let all = drawn(&[]);
    let part = drawn(&["--start", "2", "--end", "4.5"]);
    assert!(0 < part && part < all, "{part} of {all} points");
    assert_eq!(drawn(&["--start", "0:02", "--end", "0:04.5"]), part);
    assert_eq!(drawn(&["--start=0:0:02", "--end=4.50"]), part);

    for bad in [
        vec!["--time-start", "2"],
        vec!["--time-end", "4"],
        vec!["--start", "1:75"],
        vec!["--end", "abc"],
        vec!["--start", "1:2:3:4"],
    ] {
        let mut args = vec!["plot", s(&file), field];
        args.extend(bad.iter().copied());
        let out = plot(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{bad:?}: usage error: {err}");
        assert!(
            err.contains("--start") || err.contains("--end"),
            "{bad:?}: {err}"
        );
    }
}
