//! `ulog params --diff B.ulg` and `--diff-defaults [KIND]`: on pairs and triples of
//! corpus logs and on the corpus logs with default parameters, the `--format json` output equals the
//! diff computed with pyulog (its `initial_parameters` with `changed_parameters`
//! applied in order; `get_default_parameters(0)`/`(1)`); on logs built here, every
//! kind of difference in each format, and the errors' exit statuses.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value as Json;
use ulog_core::testing::LogBuilder;

/// pyulog's side: for each pair of logs (`diff`, `initial`) and each log with defaults
/// (`defaults`), the parameters that differ as `[{"name", "a", "b"}]`. Values compare
/// with their Python types (an int 1 is not a float 1.0); non-finite floats are given
/// as Python's `str()` of them, as `ulog` writes them.
const PYULOG_DIFF: &str = r#"
import json, math, sys
from pyulog import ULog

def at_end(u):
    p = dict(u.initial_parameters)
    for _, name, value in u.changed_parameters:
        p[name] = value
    return p

def same(x, y):
    if type(x) is not type(y):
        return False
    if isinstance(x, float) and math.isnan(x) and math.isnan(y):
        return True
    return x == y

def js(v):
    if isinstance(v, float) and not math.isfinite(v):
        return str(v)
    return v

def diff(a, b, names):
    return diff_all([a, b], names)

def diff_all(sets, names):
    out = []
    for n in sorted(names):
        values = [s.get(n) for s in sets]
        first = values[0]
        if first is not None and all(v is not None and same(first, v) for v in values[1:]):
            continue
        row = {'name': n}
        for i, v in enumerate(values):
            row['abcdefghijklmnopqrstuvwxyz'[i]] = js(v)
        out.append(row)
    return out

files = sys.argv[1:]
logs = {f: ULog(f, []) for f in files}
result = {'diff': {}, 'initial': {}, 'defaults': {}, 'triples': {}}
for i in range(len(files) - 2):
    trio = files[i:i + 3]
    ends = [at_end(logs[f]) for f in trio]
    result['triples']['|'.join(trio)] = diff_all(ends, set().union(*ends))
for i, fa in enumerate(files):
    for fb in files[i + 1:]:
        a, b = logs[fa], logs[fb]
        key = fa + '|' + fb
        ea, eb = at_end(a), at_end(b)
        result['diff'][key] = diff(ea, eb, set(ea) | set(eb))
        ia, ib = a.initial_parameters, b.initial_parameters
        result['initial'][key] = diff(ia, ib, set(ia) | set(ib))
for f, u in logs.items():
    if u.has_default_parameters:
        for kind, name in ((0, 'system'), (1, 'current_setup')):
            d = u.get_default_parameters(kind)
            result['defaults'][f + '|' + name] = diff(at_end(u), d, set(d))
print('RESULT ' + json.dumps(result))
"#;

/// Whether two JSON parameter values are the same: both null, both integers of the
/// same value, or both floats of the same value (a float is never an integer).
fn same_value(ours: &Json, theirs: &Json) -> bool {
    match (ours, theirs) {
        (Json::Number(x), Json::Number(y)) => match (x.is_f64(), y.is_f64()) {
            (true, true) => x.as_f64() == y.as_f64(),
            (false, false) => x == y,
            _ => false,
        },
        _ => ours == theirs,
    }
}

/// Asserts that our diff (`--format json`) equals pyulog's, parameter by parameter.
fn assert_same_diff(what: &str, ours: &Json, theirs: &Json) {
    let (o, t) = (ours.as_array().unwrap(), theirs.as_array().unwrap());
    let names = |v: &[Json]| -> Vec<String> {
        v.iter()
            .map(|d| d["name"].as_str().unwrap().to_owned())
            .collect()
    };
    assert_eq!(names(o), names(t), "{what}: the names that differ");
    for (x, y) in o.iter().zip(t) {
        let sides: Vec<&String> = y
            .as_object()
            .unwrap()
            .keys()
            .filter(|k| *k != "name")
            .collect();
        assert_eq!(x.as_object().unwrap().len(), sides.len() + 1, "{what}: {x}");
        for side in sides {
            assert!(
                same_value(&x[side.as_str()], &y[side.as_str()]),
                "{what}: {} {side}: ours {} pyulog {}",
                x["name"],
                x[side.as_str()],
                y[side.as_str()]
            );
        }
    }
}

fn json_of(args: &[&std::ffi::OsStr]) -> Json {
    let out = common::ulog_ok(args);
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"))
}

#[test]
#[cfg_attr(
    not(all(pyulog, full_corpus)),
    ignore = "needs pyulog (pip install pyulog==1.3.0) and the full corpus (../shared/corpus): pairs of its logs, and its logs with default parameters"
)]
fn diffs_equal_pyulogs_on_pairs_of_corpus_logs_and_defaults() {
    let corpus = common::corpus();
    let logs: Vec<PathBuf> = common::corpus_logs(&corpus)
        .into_iter()
        .map(|(_, p)| p)
        .collect();
    let py = Command::new("python3")
        .args(["-c", PYULOG_DIFF])
        .args(&logs)
        .output()
        .expect("run python3");
    assert!(
        py.status.success(),
        "{}",
        String::from_utf8_lossy(&py.stderr)
    );
    // pyulog prints its parse warnings on stdout; the result is its own line.
    let stdout = String::from_utf8(py.stdout).unwrap();
    let line = stdout
        .lines()
        .find_map(|l| l.strip_prefix("RESULT "))
        .expect("pyulog's result");
    let expected: Json = serde_json::from_str(line).unwrap();
    let key = |a: &Path, b: &str| format!("{}|{b}", a.display());

    let (mut pairs, mut differing) = (0, 0);
    for (i, a) in logs.iter().enumerate() {
        for b in &logs[i + 1..] {
            let k = key(a, &b.display().to_string());
            let ours = json_of(&[
                "params".as_ref(),
                a.as_os_str(),
                "--diff".as_ref(),
                b.as_os_str(),
                "--format".as_ref(),
                "json".as_ref(),
            ]);
            assert_same_diff(&k, &ours, &expected["diff"][&k]);
            let initial = json_of(&[
                "params".as_ref(),
                a.as_os_str(),
                "--diff".as_ref(),
                b.as_os_str(),
                "--initial".as_ref(),
                "-f".as_ref(),
                "json".as_ref(),
            ]);
            assert_same_diff(
                &format!("{k} (initial)"),
                &initial,
                &expected["initial"][&k],
            );
            pairs += 1;
            differing += usize::from(!ours.as_array().unwrap().is_empty());
        }
    }
    assert!(pairs >= 100, "{pairs} pairs compared");
    assert!(differing >= 100, "{differing} pairs differ");

    // N-way: every three consecutive logs, `--diff B --diff C`.
    let mut triples = 0;
    for trio in logs.windows(3) {
        let k = trio
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join("|");
        let ours = json_of(&[
            "params".as_ref(),
            trio[0].as_os_str(),
            "--diff".as_ref(),
            trio[1].as_os_str(),
            "--diff".as_ref(),
            trio[2].as_os_str(),
            "-f".as_ref(),
            "json".as_ref(),
        ]);
        assert_same_diff(
            &format!("{k} (three logs)"),
            &ours,
            &expected["triples"][&k],
        );
        triples += 1;
    }
    assert!(triples >= 15, "{triples} triples compared");

    let mut with_defaults = 0;
    for log in &logs {
        for kind in ["system", "current_setup"] {
            let k = key(log, kind);
            let Some(theirs) = expected["defaults"].get(&k) else {
                continue;
            };
            let ours = json_of(&[
                "params".as_ref(),
                log.as_os_str(),
                format!("--diff-defaults={kind}").as_ref(),
                "-f".as_ref(),
                "json".as_ref(),
            ]);
            assert!(!ours.as_array().unwrap().is_empty(), "{k}: no differences");
            assert_same_diff(&k, &ours, theirs);
            with_defaults += 1;
        }
    }
    assert!(
        with_defaults >= 2 * 5,
        "{with_defaults} logs and kinds with defaults compared"
    );
    assert!(expected["defaults"]
        .as_object()
        .unwrap()
        .keys()
        .any(|k| k.contains("sample_logging_tagged_and_default_params")));
}

fn int(v: i32) -> [u8; 4] {
    v.to_le_bytes()
}

fn float(v: f32) -> [u8; 4] {
    v.to_le_bytes()
}

/// Two flights: a parameter only in A, one only in B, one that differs, one the same,
/// one an int32 in A and a float in B, one changed during A's flight back to B's
/// value, one changed during B's flight.
fn two_flights(dir: &Path) -> (PathBuf, PathBuf) {
    let mut a = LogBuilder::new(1, 0);
    a.param("int32_t ONLY_A", &int(7));
    a.param("float DIFF", &float(0.1));
    a.param("int32_t SAME", &int(3));
    a.param("int32_t TYPE", &int(1));
    a.param("int32_t BACK", &int(5));
    a.param("float LATER", &float(2.5));
    a.format("t:uint64_t timestamp;");
    a.subscribe(0, 0, "t");
    a.data(0, &1_000u64.to_le_bytes());
    a.param("int32_t BACK", &int(6));

    let mut b = LogBuilder::new(1, 0);
    b.param("float DIFF", &float(0.25));
    b.param("int32_t SAME", &int(3));
    b.param("float TYPE", &float(1.0));
    b.param("int32_t BACK", &int(6));
    b.param("float LATER", &float(2.5));
    b.param("float ONLY_B", &float(-1.5));
    b.format("t:uint64_t timestamp;");
    b.subscribe(0, 0, "t");
    b.data(0, &1_000u64.to_le_bytes());
    b.param("float LATER", &float(3.0));

    let (pa, pb) = (dir.join("first.ulg"), dir.join("second.ulg"));
    std::fs::write(&pa, a.bytes()).unwrap();
    std::fs::write(&pb, b.bytes()).unwrap();
    (pa, pb)
}

#[test]
fn each_kind_of_difference_in_each_format() {
    let dir = common::scratch("params_diff_kinds");
    let (a, b) = two_flights(&dir);
    let run = |extra: &[&str]| {
        let mut args = vec![
            "params".as_ref(),
            a.as_os_str(),
            "--diff".as_ref(),
            b.as_os_str(),
        ];
        args.extend(extra.iter().map(|s| std::ffi::OsStr::new(*s)));
        common::ulog_ok(args)
    };

    assert_eq!(
        run(&[]),
        "\
name    first                second
DIFF    0.10000000149011612  0.25
LATER   2.5                  3.0
ONLY_A  7                    -
ONLY_B  -                    -1.5
TYPE    1                    1.0     (types differ: int32_t, float)
"
    );
    assert_eq!(
        run(&["--format", "csv"]),
        "\
name,first,second
DIFF,0.10000000149011612,0.25
LATER,2.5,3.0
ONLY_A,7,
ONLY_B,,-1.5
TYPE,1,1.0
"
    );
    assert_eq!(
        run(&["--format", "csv", "-l", ";"]),
        "name;first;second\nDIFF;0.10000000149011612;0.25\nLATER;2.5;3.0\nONLY_A;7;\n\
         ONLY_B;;-1.5\nTYPE;1;1.0\n"
    );
    let json = run(&["--format", "json"]);
    assert_eq!(
        json,
        r#"[
  {"name":"DIFF","a":0.10000000149011612,"b":0.25},
  {"name":"LATER","a":2.5,"b":3.0},
  {"name":"ONLY_A","a":7,"b":null},
  {"name":"ONLY_B","a":null,"b":-1.5},
  {"name":"TYPE","a":1,"b":1.0}
]
"#
    );
    let parsed: Json = serde_json::from_str(&json).unwrap();
    assert!(parsed[4]["a"].is_i64() && parsed[4]["b"].is_f64());
    // The initial values: BACK differed then, LATER did not.
    let names = |text: &str| -> Vec<String> {
        text.lines()
            .skip(1)
            .map(|l| l.split(',').next().unwrap().to_owned())
            .collect()
    };
    assert_eq!(
        names(&run(&["--initial", "-f", "csv"])),
        ["BACK", "DIFF", "ONLY_A", "ONLY_B", "TYPE"]
    );
    // A log against itself: nothing differs, still exit status 0.
    let same = common::ulog_ok([
        "params".as_ref(),
        a.as_os_str(),
        "--diff".as_ref(),
        a.as_os_str(),
        "-f".as_ref(),
        "json".as_ref(),
    ]);
    assert_eq!(same, "[]\n");
    // The output file, the positional after FILE, works as for the parameters.
    let out = dir.join("diff.csv");
    common::ulog_ok([
        "params".as_ref(),
        a.as_os_str(),
        out.as_os_str(),
        "--diff".as_ref(),
        b.as_os_str(),
        "-f".as_ref(),
        "csv".as_ref(),
    ]);
    assert_eq!(
        std::fs::read_to_string(&out).unwrap(),
        run(&["--format", "csv"])
    );
    // Two logs of the same name: the header names their paths.
    let other = common::scratch("params_diff_kinds_other").join("first.ulg");
    std::fs::copy(&b, &other).unwrap();
    let header = common::ulog_ok([
        "params".as_ref(),
        a.as_os_str(),
        "--diff".as_ref(),
        other.as_os_str(),
        "-f".as_ref(),
        "csv".as_ref(),
    ]);
    assert_eq!(
        header.lines().next().unwrap(),
        format!("name,{},{}", a.display(), other.display())
    );
}

/// A log with defaults: MAV_TYPE differs from its system default but not from the
/// airframe's, MPC_XY_VEL_MAX from both, SYS_AUTOSTART has no default, and a default
/// names a parameter the log does not have.
fn log_with_defaults(path: &Path) {
    let mut b = LogBuilder::new(1, 0);
    b.flag_bits([1, 0, 0, 0, 0, 0, 0, 0], [0; 8], [0; 3]);
    b.param("int32_t MAV_TYPE", &int(13));
    b.param("float MPC_XY_VEL_MAX", &float(12.0));
    b.param("int32_t SYS_AUTOSTART", &int(4001));
    b.default_param(1, "int32_t MAV_TYPE", &int(2));
    b.default_param(2, "int32_t MAV_TYPE", &int(13));
    b.default_param(3, "float MPC_XY_VEL_MAX", &float(10.0));
    b.default_param(2, "int32_t NOT_LOGGED", &int(1));
    std::fs::write(path, b.bytes()).unwrap();
}

#[test]
fn differences_from_defaults_of_each_kind() {
    let dir = common::scratch("params_diff_defaults");
    let log = dir.join("tuned.ulg");
    log_with_defaults(&log);
    let run = |extra: &[&str]| {
        let mut args = vec!["params".as_ref(), log.as_os_str()];
        args.extend(extra.iter().map(|s| std::ffi::OsStr::new(*s)));
        common::ulog_ok(args)
    };
    let system = "\
name            tuned  system_default
MAV_TYPE        13     2
MPC_XY_VEL_MAX  12.0   10.0
";
    assert_eq!(run(&["--diff-defaults"]), system);
    assert_eq!(run(&["--diff-defaults=system"]), system);
    assert_eq!(
        run(&["--diff-defaults=current_setup", "-f", "csv"]),
        "name,tuned,current_setup_default\nMPC_XY_VEL_MAX,12.0,10.0\nNOT_LOGGED,,1\n"
    );
    assert_eq!(
        run(&["--diff-defaults=current_setup", "-f", "json"]),
        "[\n  {\"name\":\"MPC_XY_VEL_MAX\",\"a\":12.0,\"b\":10.0},\n  \
         {\"name\":\"NOT_LOGGED\",\"a\":null,\"b\":1}\n]\n"
    );
}

#[test]
fn errors_have_the_statuses_of_their_kind() {
    let dir = common::scratch("params_diff_errors");
    let (a, b) = two_flights(&dir);
    let missing = dir.join("missing.ulg");
    let not_ulog = dir.join("not.ulg");
    std::fs::write(&not_ulog, b"not a log").unwrap();
    let status = |args: &[&std::ffi::OsStr]| {
        let out = common::ulog(args);
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let p = |s: &'static str| std::ffi::OsStr::new(s);

    // A missing A or B: 3, naming the file.
    for (x, y) in [(&missing, &b), (&a, &missing)] {
        let (code, err) = status(&[p("params"), x.as_os_str(), p("--diff"), y.as_os_str()]);
        assert_eq!(code, Some(3), "{err}");
        assert!(err.contains(&missing.display().to_string()), "{err}");
    }
    // Not a ULog log: 4.
    let (code, err) = status(&[
        p("params"),
        a.as_os_str(),
        p("--diff"),
        not_ulog.as_os_str(),
    ]);
    assert_eq!(code, Some(4), "{err}");
    // A log without defaults: 7 (the log lacks what the option needs), one line
    // naming the log and the option, as `ulog params -d` says it.
    let lacking = |option: &str| {
        format!(
            "ulog: {}: {option}: the log has no default parameters to compare with (compat \
             flag DEFAULT_PARAMETERS is not set; `--diff B.ulg` compares with another log)",
            a.display()
        )
    };
    let (code, err) = status(&[p("params"), a.as_os_str(), p("--diff-defaults")]);
    assert_eq!(code, Some(7), "{err}");
    assert_eq!(err.trim_end(), lacking("--diff-defaults"));
    let (code, dash_d) = status(&[p("params"), a.as_os_str(), p("-d"), p("system")]);
    assert_eq!(code, Some(7), "{dash_d}");
    assert_eq!(dash_d.trim_end(), lacking("--default"));
    // Usage errors: 2.
    for args in [
        vec![p("params"), a.as_os_str(), p("-f"), p("json")],
        vec![p("params"), a.as_os_str(), p("-f"), p("text")],
        vec![
            p("params"),
            a.as_os_str(),
            p("--diff"),
            b.as_os_str(),
            p("-f"),
            p("qgc"),
        ],
        vec![
            p("params"),
            a.as_os_str(),
            p("--diff"),
            b.as_os_str(),
            p("-f"),
            p("octave"),
        ],
        vec![
            p("params"),
            a.as_os_str(),
            p("--diff"),
            b.as_os_str(),
            p("-t"),
        ],
        vec![
            p("params"),
            a.as_os_str(),
            p("--diff"),
            b.as_os_str(),
            p("--diff-defaults"),
        ],
        vec![
            p("params"),
            a.as_os_str(),
            p("--diff-defaults"),
            p("-d"),
            p("system"),
        ],
        vec![p("params"), a.as_os_str(), p("--diff-defaults=airframe")],
    ] {
        let (code, err) = status(&args);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(err.starts_with("error: "), "{args:?}: {err}");
    }
}

#[test]
fn three_flights_give_a_column_each_in_every_format() {
    let dir = common::scratch("params_diff_three");
    let (a, b) = two_flights(&dir);
    let c = dir.join("c.ulg");
    std::fs::copy(&a, &c).unwrap();
    let run = |format: &str| {
        common::ulog_ok([
            "params".as_ref(),
            a.as_os_str(),
            "--diff".as_ref(),
            b.as_os_str(),
            "--diff".as_ref(),
            c.as_os_str(),
            "-f".as_ref(),
            std::ffi::OsStr::new(format),
        ])
    };
    // C is A: what differs is what differs between A and B, with A's values twice.
    let two = common::ulog_ok([
        "params".as_ref(),
        a.as_os_str(),
        "--diff".as_ref(),
        b.as_os_str(),
        "-f".as_ref(),
        "csv".as_ref(),
    ]);
    let csv = run("csv");
    let (head2, head3) = (two.lines().next().unwrap(), csv.lines().next().unwrap());
    assert_eq!(head3, format!("{head2},c"), "a column per log");
    for (row2, row3) in two.lines().zip(csv.lines()).skip(1) {
        let a_value = row2.split(',').nth(1).unwrap();
        assert_eq!(row3, format!("{row2},{a_value}"), "C's value is A's");
    }
    assert_eq!(two.lines().count(), csv.lines().count());
    let text = run("text");
    let header: Vec<&str> = text.lines().next().unwrap().split_whitespace().collect();
    assert_eq!(header, ["name", "first", "second", "c"]);
    assert!(
        text.contains("(types differ: int32_t, float, int32_t)"),
        "{text}"
    );
    let json: Json = serde_json::from_str(&run("json")).unwrap();
    for row in json.as_array().unwrap() {
        assert_eq!(row["a"], row["c"], "{row}");
    }
    // The same log twice differs in nothing.
    let same = common::ulog_ok([
        "params".as_ref(),
        a.as_os_str(),
        "--diff".as_ref(),
        c.as_os_str(),
        "--diff".as_ref(),
        a.as_os_str(),
        "-f".as_ref(),
        "json".as_ref(),
    ]);
    assert_eq!(same, "[]\n");
}
