//! `.ulog` logs are logs as `.ulg` ones are (either extension, any case): a directory
//! given to `parquet` includes them, and output names drop the extension alike.

mod common;

use std::collections::BTreeSet;
use std::path::Path;

fn names(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .expect("read dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn parquet_takes_ulog_files_from_a_directory_and_names_them_as_ulg() {
    let root = common::scratch("names_parquet");
    let logs = root.join("logs");
    std::fs::create_dir_all(&logs).unwrap();
    let sample = ulog_core::testing::sample_log();
    for name in ["a.ulg", "b.ulog", "c.ULOG", "d.Ulg"] {
        std::fs::write(logs.join(name), &sample).unwrap();
    }
    std::fs::write(logs.join("notes.txt"), b"not a log").unwrap();

    let out = root.join("out");
    common::ulog_ok([
        "parquet".as_ref(),
        "--per-log".as_ref(),
        logs.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    assert_eq!(names(&out), ["a", "b", "c", "d"].map(String::from).into());
    let first = names(&out.join("a"));
    assert!(first.contains("metadata.json"), "{first:?}");
    for stem in ["b", "c", "d"] {
        assert_eq!(names(&out.join(stem)), first, "{stem}");
    }

    // Beside the log, without `-o`: the same folder name as for a `.ulg`.
    let single = root.join("single");
    std::fs::create_dir_all(&single).unwrap();
    for name in ["x.ulg", "y.ulog"] {
        std::fs::write(single.join(name), &sample).unwrap();
        common::ulog_ok([
            "parquet".as_ref(),
            "--per-log".as_ref(),
            single.join(name).as_os_str(),
        ]);
    }
    assert_eq!(
        names(&single),
        ["x", "x.ulg", "y", "y.ulog"].map(String::from).into()
    );
    assert_eq!(names(&single.join("y")), names(&single.join("x")));
}

#[test]
fn csv_and_plot_name_their_files_alike_for_ulg_and_ulog() {
    let dir = common::scratch("names_csv");
    let sample = ulog_core::testing::sample_log();
    for name in ["x.ulg", "y.ulog", "z.ULOG"] {
        let path = dir.join(name);
        std::fs::write(&path, &sample).unwrap();
        common::ulog_ok(["csv".as_ref(), path.as_os_str()]);
        common::ulog_ok([
            "plot".as_ref(),
            path.as_os_str(),
            "vehicle_local_position.z".as_ref(),
        ]);
    }
    let all = names(&dir);
    let of = |stem: &str| -> BTreeSet<String> {
        all.iter()
            .filter_map(|n| n.strip_prefix(&format!("{stem}_")))
            .map(str::to_owned)
            .collect()
    };
    let x = of("x");
    assert!(x.contains("vehicle_attitude_0.csv"), "{all:?}");
    assert!(x.contains("plot.svg"), "{all:?}");
    assert_eq!(of("y"), x, "{all:?}");
    assert_eq!(of("z"), x, "{all:?}");
    assert_eq!(all.len(), 3 * (x.len() + 1), "{all:?}");
}
