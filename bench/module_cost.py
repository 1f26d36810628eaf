#!/usr/bin/env python3
"""What `ulog_module!` costs a crate that uses it (see bench/README.md).

    python3 bench/module_cost.py                      # log_61 of the shared corpus
    python3 bench/module_cost.py --log some.ulg --runs 3
    python3 bench/module_cost.py --topics sensor_combined,vehicle_attitude
    python3 bench/module_cost.py --root ../ulog-base       # another checkout (before/after)
    python3 bench/module_cost.py --runs 5 --before ../ulog-base   # both in turn, and the ratios

Writes a small Cargo workspace under the target directory (`target/module-cost/`,
or `$CARGO_TARGET_DIR/module-cost/`) whose library is `ulog_module!` on the log and
a function that reads every instance of every topic through its binding
(`visit_bindings`, `ULog::read_instances`) and visits every field of every row
(`visit_fields`). Then:

1. the generated source: the lines `ulog codegen` writes for the log
   (`ulog_codegen::bindings_for_log`, laid out by prettyplease), per format bound;
2. the library's build alone, debug and release: its dependencies built first, then
   `touch src/lib.rs` and `cargo build --lib` under `/usr/bin/time -v`, `--runs`
   times (wall seconds, user + system seconds, peak RSS of the compiler), with
   `CARGO_INCREMENTAL=0` (every build of the crate compiles all of it: an incremental
   debug rebuild of an untouched file would reuse nearly everything);
3. a run of the decode, so that the figures are those of code that works (rows and
   leaves read, errors).

Nothing is asserted; the figures go to bench/README.md by hand.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
from statistics import median

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_LOG = "log_61_2024-2-6-16-27-02.ulg"


def corpus_dir():
    env = os.environ.get("ULOG_CORPUS")
    return env if env else os.path.join(ROOT, "..", "shared", "corpus")


def target_dir(root):
    env = os.environ.get("CARGO_TARGET_DIR")
    base = env if env else os.path.join(ROOT, "target")
    name = "module-cost" if root == ROOT else "module-cost-" + os.path.basename(root.rstrip("/"))
    return os.path.join(base, name)


MANIFEST = """[workspace]
members = ["lib", "lines"]
resolver = "2"

[workspace.dependencies]
ulog-core = {{ path = "{root}/ulog-core", features = ["derive"] }}
ulog-codegen = {{ path = "{root}/ulog-codegen" }}
"""

LIB_MANIFEST = """[package]
name = "module-cost"
version = "0.0.0"
edition = "2021"
publish = false

[dependencies]
ulog-core.workspace = true
"""

LINES_MANIFEST = """[package]
name = "module-lines"
version = "0.0.0"
edition = "2021"
publish = false

[dependencies]
ulog-codegen.workspace = true
"""

LIB = """//! `ulog_module!` on one log; every topic read through its binding, every field
//! of every row visited. Written by bench/module_cost.py.

ulog_core::ulog_module!(unbound = allow; {topics} pub mod px4 = "../log.ulg");

use ulog_core::typed::BindingVisitor;
use ulog_core::{{ULog, ULogMessage}};

/// What the decode read.
#[derive(Debug, Default)]
pub struct Counts {{
    pub topics: usize,
    pub rows: usize,
    pub leaves: usize,
    pub errors: usize,
    pub sum: f64,
}}

struct Visit<'l, 'a> {{
    log: &'l ULog<'a>,
    counts: Counts,
}}

impl BindingVisitor for Visit<'_, '_> {{
    fn visit<T: ULogMessage>(&mut self) {{
        let Ok(instances) = self.log.read_instances::<T>() else {{
            return;
        }};
        for rows in instances {{
            let Ok(rows) = rows else {{
                self.counts.errors += 1;
                continue;
            }};
            self.counts.topics += 1;
            for row in rows.iter() {{
                let Ok(value) = row else {{
                    self.counts.errors += 1;
                    continue;
                }};
                self.counts.rows += 1;
                let counts = &mut self.counts;
                value.visit_fields(&mut |_, v| {{
                    counts.leaves += 1;
                    counts.sum += v.as_f64().filter(|x| x.is_finite()).unwrap_or(0.0);
                }});
            }}
        }}
    }}
}}

/// Reads every topic of `log` that the module binds.
pub fn decode_all(log: &ULog<'_>) -> Counts {{
    let mut visit = Visit {{
        log,
        counts: Counts::default(),
    }};
    px4::visit_bindings(&mut visit);
    visit.counts
}}
"""

MAIN = """fn main() {
    let bytes = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/../log.ulg")).unwrap();
    let log = ulog_core::ULog::parse(&bytes).unwrap();
    let c = module_cost::decode_all(&log);
    println!(
        "topic instances={} rows={} leaves={} errors={} sum={}",
        c.topics, c.rows, c.leaves, c.errors, c.sum
    );
}
"""

LINES = """fn main() {
    let args: Vec<String> = std::env::args().collect();
    let bytes = std::fs::read(&args[1]).unwrap();
    let topics: Option<Vec<String>> = args
        .get(2)
        .map(|t| t.split(',').map(str::to_owned).collect());
    let options = ulog_codegen::Options {
        topics: topics.as_deref(),
        ..Default::default()
    };
    let g = ulog_codegen::bindings_for_log(&bytes, "log.ulg", &options).unwrap();
    let lines = g.source.lines().count();
    println!(
        "formats={} unbound={} lines={} lines/format={:.1}",
        g.bound.len(),
        g.unbound.len(),
        lines,
        lines as f64 / g.bound.len().max(1) as f64
    );
}
"""


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    old = None
    if os.path.exists(path):
        with open(path) as f:
            old = f.read()
    if old != text:
        with open(path, "w") as f:
            f.write(text)


def older_api(root):
    """Whether `root` is a checkout from before issue 44's module options (`unbound`,
    `topics`, `Generated::bound`): 275b8bb, the code the issue measured."""
    with open(os.path.join(root, "ulog-codegen", "src", "lib.rs")) as f:
        return "pub bound:" not in f.read()


def generate(work, root, log, topics):
    write(os.path.join(work, "Cargo.toml"), MANIFEST.format(root=root))
    write(os.path.join(work, "lib", "Cargo.toml"), LIB_MANIFEST)
    lib, lines = LIB, LINES
    if older_api(root):
        lib = lib.replace("unbound = allow; ", "")
        lines = (
            lines.replace("topics: topics.as_deref(),", "")
            .replace("let topics: Option", "let _topics: Option")
            .replace("g.bound.len().max(1)", "g.formats.max(1)")
            .replace("g.bound.len()", "g.formats")
            .replace("g.unbound.len()", "g.skipped.len()")
        )
    listed = ""
    if topics:
        listed = "topics = [" + ", ".join(f'"{t}"' for t in topics) + "];"
    write(os.path.join(work, "lib", "src", "lib.rs"), lib.format(topics=listed))
    write(os.path.join(work, "lib", "src", "main.rs"), MAIN)
    write(os.path.join(work, "lines", "Cargo.toml"), LINES_MANIFEST)
    write(os.path.join(work, "lines", "src", "main.rs"), lines)
    # The repository's lock: the dependencies at the versions the workspace tests.
    lock = os.path.join(work, "Cargo.lock")
    if not os.path.exists(lock):
        shutil.copyfile(os.path.join(root, "Cargo.lock"), lock)
    dst = os.path.join(work, "log.ulg")
    if not os.path.exists(dst) or open(dst, "rb").read() != open(log, "rb").read():
        shutil.copyfile(log, dst)


def cargo(work, args, timed=False):
    cmd = ["nice", "-n", "10", "cargo"] + args
    env = dict(os.environ, CARGO_TARGET_DIR=os.path.join(work, "target"), CARGO_INCREMENTAL="0")
    if timed:
        cmd = ["/usr/bin/time", "-v"] + cmd
    r = subprocess.run(cmd, cwd=work, env=env, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"module_cost: {' '.join(args)} failed:\n{r.stderr[-4000:]}")
    return r


def timing(stderr):
    def field(name):
        m = re.search(re.escape(name) + r": (.*)", stderr)
        return m.group(1).strip() if m else None

    wall = field("Elapsed (wall clock) time (h:mm:ss or m:ss)")
    parts = [float(p) for p in wall.split(":")]
    seconds = 0.0
    for p in parts:
        seconds = seconds * 60 + p
    cpu = float(field("User time (seconds)")) + float(field("System time (seconds)"))
    rss = int(field("Maximum resident set size (kbytes)")) / 1024
    return seconds, cpu, rss


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--log", help=f"the log (default: {DEFAULT_LOG} of the shared corpus)")
    ap.add_argument("--topics", help="comma-separated topics (`topics = [...]`)")
    ap.add_argument("--runs", type=int, default=2, help="rebuilds per profile (default 2)")
    ap.add_argument("--profiles", default="dev,release", help="default: dev,release")
    ap.add_argument("--root", help="the checkout whose crates to build (default: this one)")
    ap.add_argument(
        "--before",
        help="a second checkout, built in turn with the first (one build of each per run), "
        "and the ratio of the medians",
    )
    args = ap.parse_args()
    log = args.log or os.path.join(corpus_dir(), "files", DEFAULT_LOG)
    if not os.path.exists(log):
        sys.exit(f"module_cost: {log} is missing (give --log or set ULOG_CORPUS)")
    topics = [t for t in (args.topics or "").split(",") if t]
    roots = [os.path.abspath(args.root) if args.root else ROOT]
    if args.before:
        roots.append(os.path.abspath(args.before))
    names = [os.path.basename(r.rstrip("/")) for r in roots]
    if len(set(names)) != len(names) or len(set(target_dir(r) for r in roots)) != len(roots):
        sys.exit(f"module_cost: the checkouts need folders of different names: {roots}")
    if topics and any(older_api(r) for r in roots):
        sys.exit("module_cost: --topics needs checkouts with `ulog_module!`'s topic list")
    works = []
    for root in roots:
        work = target_dir(root)
        generate(work, root, log, topics)
        line_args = ["run", "--quiet", "--release", "-p", "module-lines", "--", log]
        if topics:
            line_args.append(",".join(topics))
        name = os.path.basename(root.rstrip("/"))
        print(f"{name}: generated:", cargo(work, line_args).stdout.strip(), flush=True)
        works.append((name, work))

    for profile in args.profiles.split(","):
        flags = ["--profile", profile]
        results = {name: [] for name, _ in works}
        for _, work in works:
            cargo(work, ["build", "-p", "module-cost", "--lib"] + flags)
        # In turn, so that a slow spell of the machine falls on every checkout.
        for _ in range(args.runs):
            for name, work in works:
                os.utime(os.path.join(work, "lib", "src", "lib.rs"))
                r = cargo(work, ["build", "-p", "module-cost", "--lib"] + flags, timed=True)
                results[name].append(timing(r.stderr))
        for name, work in works:
            rs = results[name]
            walls = ", ".join(f"{w:.1f}" for w, _, _ in rs)
            cpus = ", ".join(f"{c:.1f}" for _, c, _ in rs)
            rss = max(m for _, _, m in rs)
            print(
                f"{name}: {profile}: crate alone wall s [{walls}] (median {median([w for w, _, _ in rs]):.2f})"
                f"  cpu s [{cpus}] (median {median([c for _, c, _ in rs]):.2f})  peak RSS {rss:.0f} MiB",
                flush=True,
            )
            r = cargo(work, ["run", "--quiet", "-p", "module-cost"] + flags)
            print(f"{name}: {profile}: decode: {r.stdout.strip()}", flush=True)
        if len(works) == 2:
            (a, _), (b, _) = works
            wall = median([w for w, _, _ in results[a]]) / median([w for w, _, _ in results[b]])
            cpu = median([c for _, c, _ in results[a]]) / median([c for _, c, _ in results[b]])
            print(f"{profile}: {a} / {b}: wall {wall:.3f}, cpu {cpu:.3f}", flush=True)


if __name__ == "__main__":
    main()
