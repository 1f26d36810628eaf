"""The peers that come as source rather than from a registry (the peers folder:
$ULOG_PEERS, else ../shared/peers relative to the repository root; each subfolder
names its upstream commit in UPSTREAM_COMMIT):

- ulog_cpp (PX4's C++ reader): bench/cpp/ulog_cpp_peer.cpp compiled with g++ against
  its sources;
- px4-ulog master: bench/px4-master/main.rs (the same workload code as `peers px4-*`)
  in a Cargo package written under the cache, whose `px4-ulog` dependency is the
  snapshot by path;
- flight-review-rs (PX4 Flight Review v2's converter): its `crates/converter` copied
  into the cache, its git dependency on px4-ulog pointed at the snapshot by path, its
  bench and dev-dependencies dropped, `ulog-convert` built in release.

Each is built once into bench/target/peers/<name>/ and rebuilt only when its stamp
(upstream commits, our source's hash, the compiler's version) changes. Nothing here is
copied into the repository: the sources stay in the peers folder.
"""

import hashlib
import os
import shutil
import subprocess
import sys


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def peers_dir(root):
    env = os.environ.get("ULOG_PEERS")
    path = env if env else os.path.join(root, "..", "shared", "peers")
    return os.path.normpath(os.path.abspath(path))


def _read(path):
    with open(path, "rb") as f:
        return f.read()


def _upstream(folder):
    path = os.path.join(folder, "UPSTREAM_COMMIT")
    return _read(path).decode().strip() if os.path.exists(path) else "unknown"


def _version(cmd):
    try:
        return subprocess.run(cmd + ["--version"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return None


def _stamp(*parts):
    h = hashlib.sha256()
    for p in parts:
        h.update(p if isinstance(p, bytes) else str(p).encode())
        h.update(b"\0")
    return h.hexdigest()


def _fresh(cache, stamp, exe):
    path = os.path.join(cache, "stamp")
    return os.path.exists(exe) and os.path.exists(path) and _read(path).decode() == stamp


def _mark(cache, stamp):
    with open(os.path.join(cache, "stamp"), "w") as f:
        f.write(stamp)


def _ulog_cpp(bench, peers, cache):
    src = os.path.join(peers, "ulog_cpp")
    gxx = shutil.which("g++")
    if not os.path.isdir(os.path.join(src, "ulog_cpp")):
        return None, f"ulog_cpp: skipped ({src} is missing)"
    if not gxx:
        return None, "ulog_cpp: skipped (g++ not found)"
    ours = os.path.join(bench, "cpp", "ulog_cpp_peer.cpp")
    lib = sorted(f for f in os.listdir(os.path.join(src, "ulog_cpp")) if f.endswith(".cpp"))
    stamp = _stamp(_upstream(src), _read(ours), _version([gxx]), *lib)
    exe = os.path.join(cache, "ulog_cpp_peer")
    if _fresh(cache, stamp, exe):
        return exe, None
    os.makedirs(cache, exist_ok=True)
    flags = ["-O2", "-std=c++17", "-I", src]
    log(f"== g++ {' '.join(flags)} (ulog_cpp, {len(lib)} files, into {cache})")
    jobs = []
    objects = []
    for name in lib + [ours]:
        path = name if os.path.isabs(name) else os.path.join(src, "ulog_cpp", name)
        obj = os.path.join(cache, os.path.basename(path) + ".o")
        objects.append(obj)
        jobs.append(subprocess.Popen([gxx] + flags + ["-c", path, "-o", obj]))
    if any(j.wait() != 0 for j in jobs):
        return None, "ulog_cpp: skipped (its build failed; see the g++ output above)"
    subprocess.run([gxx] + objects + ["-o", exe], check=True)
    _mark(cache, stamp)
    return exe, None


def _cargo_build(manifest, target, bin_name):
    env = dict(os.environ)
    env["CARGO_TARGET_DIR"] = target
    cmd = ["cargo", "build", "--release", "--bin", bin_name, "--manifest-path", manifest]
    log("== " + " ".join(cmd))
    return subprocess.run(cmd, env=env).returncode == 0


def _px4_master(bench, peers, cache):
    src = os.path.join(peers, "px4-ulog-rs")
    if not os.path.exists(os.path.join(src, "Cargo.toml")):
        return None, f"px4-ulog master: skipped ({src} is missing)"
    main = os.path.join(bench, "px4-master", "main.rs")
    shared = os.path.join(bench, "src", "px4.rs")
    stamp = _stamp(_upstream(src), _read(main), _read(shared), _version(["rustc"]), src)
    target = os.path.join(cache, "target")
    exe = os.path.join(target, "release", "px4-master")
    if _fresh(cache, stamp, exe):
        return exe, None
    os.makedirs(cache, exist_ok=True)
    manifest = os.path.join(cache, "Cargo.toml")
    with open(manifest, "w") as f:
        f.write(
            "# Written by bench/source_peers.py: px4-ulog master, by path.\n"
            "[workspace]\n\n"
            "[package]\n"
            'name = "px4-master-bench"\n'
            'version = "0.0.0"\n'
            'edition = "2021"\n'
            "publish = false\n\n"
            "[[bin]]\n"
            'name = "px4-master"\n'
            f"path = {main!r}\n\n"
            "[dependencies]\n"
            f"px4-ulog = {{ path = {src!r} }}\n\n"
            "[profile.release]\n"
            "debug = 1\n"
        )
    if not _cargo_build(manifest, target, "px4-master"):
        return None, "px4-ulog master: skipped (its build failed; see the cargo output above)"
    _mark(cache, stamp)
    return exe, None


def _copy_tree(src, dst):
    """Copies files without their modes (the peers folder is read-only)."""
    for dirpath, _, files in os.walk(src):
        out = os.path.join(dst, os.path.relpath(dirpath, src))
        os.makedirs(out, exist_ok=True)
        for name in files:
            shutil.copyfile(os.path.join(dirpath, name), os.path.join(out, name))


def _patched_manifest(text, px4_path):
    """flight-review's Cargo.toml with px4-ulog by path and only what `ulog-convert`
    needs: no `[[bench]]`, no `[dev-dependencies]`."""
    out = []
    section = None
    for line in text.splitlines():
        stripped = line.strip()
        if stripped.startswith("["):
            section = stripped
        if section in ("[[bench]]", "[dev-dependencies]"):
            continue
        if section == "[dependencies]" and stripped.startswith("px4-ulog"):
            line = f"px4-ulog = {{ path = {px4_path!r} }}"
        out.append(line)
    out.append("")
    out.append("[workspace]")
    return "\n".join(out) + "\n"


def _flight_review(peers, cache, allow_build):
    src = os.path.join(peers, "flight-review-rs", "crates", "converter")
    px4 = os.path.join(peers, "px4-ulog-rs")
    if not os.path.exists(os.path.join(src, "Cargo.toml")) or not os.path.isdir(px4):
        return None, f"flight-review-rs: skipped ({src} or {px4} is missing)"
    stamp = _stamp(_upstream(os.path.join(peers, "flight-review-rs")), _upstream(px4),
                   _version(["rustc"]), src, px4)
    target = os.path.join(cache, "target")
    exe = os.path.join(target, "release", "ulog-convert")
    if _fresh(cache, stamp, exe):
        return exe, None
    if not allow_build:
        return None, ("flight-review-rs: skipped (not built yet, and its build takes about "
                      "13 minutes on 2 cores: the smoke run does not build it; a full "
                      "`bench/run` builds it once into bench/target/peers)")
    copy = os.path.join(cache, "converter")
    shutil.rmtree(copy, ignore_errors=True)
    _copy_tree(src, copy)
    manifest = os.path.join(copy, "Cargo.toml")
    patched = _patched_manifest(_read(manifest).decode(), px4)
    with open(manifest, "w") as f:
        f.write(patched)
    if not _cargo_build(manifest, target, "ulog-convert"):
        return None, "flight-review-rs: skipped (its build failed; see the cargo output above)"
    _mark(cache, stamp)
    return exe, None


def build(root, bench, cache_root, smoke):
    """Builds what it can: ({"ulog_cpp", "px4_master", "flight_review"} -> program path
    for those built) and the lines saying what was skipped and why."""
    peers = peers_dir(root)
    built = {}
    skipped = []
    for key, make in (
        ("ulog_cpp", lambda c: _ulog_cpp(bench, peers, c)),
        ("px4_master", lambda c: _px4_master(bench, peers, c)),
        ("flight_review", lambda c: _flight_review(peers, c, allow_build=not smoke)),
    ):
        exe, why = make(os.path.join(cache_root, key.replace("_", "-")))
        if exe:
            built[key] = exe
        else:
            log("== " + why)
            skipped.append(why)
    return built, skipped


def flight_review_exe(root):
    """Where `ulog-convert` is built (the tests' build script looks there too)."""
    bench = os.path.join(root, "bench")
    env = os.environ.get("CARGO_TARGET_DIR")
    target = os.path.abspath(env) if env else os.path.join(bench, "target")
    return os.path.join(target, "peers", "flight-review")


if __name__ == "__main__":
    # `python3 bench/source_peers.py flight-review`: builds flight-review-rs's
    # `ulog-convert` (about 13 minutes on 2 cores, once), which the tests of `ulog
    # analyze` compare with; prints its path.
    if sys.argv[1:] != ["flight-review"]:
        sys.exit("usage: source_peers.py flight-review")
    root = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    exe, why = _flight_review(peers_dir(root), flight_review_exe(root), allow_build=True)
    if not exe:
        sys.exit(why)
    print(exe)
