"""Where the tests find logs: the repository's own corpus (tests/corpus/files, on
every clone) and the full corpus when there is one ($ULOG_CORPUS, or ../shared/corpus
beside the workspace, as the Rust tests look for it)."""

import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
# CI has everything: a test that would skip for want of something fails there.
REQUIRE_ALL = os.environ.get("ULOG_REQUIRE_ALL_TESTS") == "1"


def missing(reason):
    """Skips the test for want of `reason`, or fails it where CI requires all."""
    (pytest.fail if REQUIRE_ALL else pytest.skip)(reason)
OWN = ROOT / "tests" / "corpus" / "files"


def full_corpus():
    env = os.environ.get("ULOG_CORPUS")
    path = pathlib.Path(env) if env else ROOT.parent / "shared" / "corpus"
    return path if (path / "files").is_dir() else None


def corpus_logs():
    """Every log of both corpora, by file name (the full corpus wins a tie)."""
    logs = {p.name: p for p in OWN.glob("*.ulg")}
    full = full_corpus()
    if full is not None:
        logs.update({p.name: p for p in (full / "files").glob("*.ulg")})
    return [logs[k] for k in sorted(logs)]


def pytest_report_header(config):
    full = full_corpus()
    return "ulog_rs tests: {} logs ({})".format(
        len(corpus_logs()), "full corpus" if full else "the repository's own corpus only"
    )


@pytest.fixture
def sample_log():
    return OWN / "sample_appended_multiple.ulg"
