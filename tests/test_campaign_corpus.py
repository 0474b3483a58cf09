"""The hostile-input corpus of campaign folders (``tests/campaign_corpus/cases.toml``, issue 25): every
case through ``rpo`` in-process on a copy of one tiny real campaign, with its exit code, its message
fragment, no traceback, one ``error:`` line for a refusal, nothing made by a refused ``mc run``, no
summary counting a line that is not a run record, and the uninterrupted campaign's summary bytes
wherever the folder is resumed.  The disk-full, read-only and permission cases monkeypatch the writer
to raise the OSError (tests/campaign_corpus_summary.py, fault): no root and no small disk needed.

Summary for quoting: ``python -m tests.campaign_corpus_summary``.
"""

from __future__ import annotations

import errno
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from campaign_corpus_summary import RUNS, Case, build_reference, check, load_cases, play

from rpo.runtime.campaign import storage
from rpo.runtime.errors import CampaignError

CASES = load_cases()


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> Path:
    """The tiny campaign flown once (per test process): every case starts from a copy of it."""
    return build_reference(tmp_path_factory.mktemp("campaign_corpus"))


def test_the_corpus_is_large_and_covers_the_issue():
    assert len(CASES) >= 60
    groups = {c.group for c in CASES}
    assert {"manifest", "history", "summary", "resolved", "lock", "disk", "campaign", "options"} <= groups
    ids = {c.id for c in CASES}
    # the inputs the issue names
    for needle in ("manifest-object-without-case", "manifest-json-integer", "manifest-case-text", "manifest-case-9999",
                   "manifest-cut-last-line", "manifest-duplicate-line", "history-cut-keeping-its-last-8-bytes",
                   "history-folder-removed-replay", "summary-missing-report", "summary-junk-report",
                   "disk-full-writing-the-manifest", "disk-read-only-model-cache-resume",
                   "lock-held-by-another-command",
                   "options-dask-unreachable", "options-dask-extra-missing"):
        assert needle in ids, needle
    assert {c.exit for c in CASES} == {0, 1, 2}


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_case(case: Case, reference: Path, tmp_path):
    outcome, folder = play(case, reference, tmp_path)
    assert check(case, outcome, folder, reference) == []


# --------------------------------------------------------------------------- the rules, one by one


def test_each_flown_line_records_its_history_sha256(reference):
    import hashlib

    scan = storage.scan_manifest(reference)
    assert scan.problems == [] and scan.unverified == [] and sorted(scan.rows) == list(range(RUNS))
    for c, row in scan.rows.items():
        data = storage.history_path(reference, c, row).read_bytes()
        assert row["history_sha256"] == hashlib.sha256(data).hexdigest()


def test_a_line_replaces_an_earlier_one_only_after_an_error(tmp_path, reference):
    lines = (reference / storage.MANIFEST).read_bytes().splitlines(keepends=True)
    folder = tmp_path / "mc"
    folder.mkdir()
    (folder / storage.RESOLVED).write_bytes((reference / storage.RESOLVED).read_bytes())
    first = json.loads(lines[0])
    error = {**first, "status": "error", "message": "worker lost"}
    again = {**first, "metrics": {**first["metrics"], "pos_err_final_m": 1.0}}
    storage.append_rows(folder, [error, first, again])  # an error flown again, then a second record of it
    scan = storage.scan_manifest(folder)
    assert scan.rows[0] == first
    assert scan.problems == ["line 3: case 0 again (a duplicate: its run is recorded by an earlier line)"]
    storage.append_rows(folder, [error])  # a history found lost: the later error line wins (resume re-flies)
    assert storage.scan_manifest(folder).rows[0]["status"] == "error"


def test_a_failed_atomic_write_leaves_no_temporary(tmp_path, monkeypatch):
    def fsync(fd):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "fsync", fsync)
    with pytest.raises(OSError, match="No space"):
        storage.write_json(tmp_path / "x.json", {"a": 1})
    assert list(tmp_path.iterdir()) == []


def test_history_state_of_an_older_folder_checks_the_footer(reference, tmp_path):
    path = sorted((reference / storage.HISTORIES).glob(storage.HISTORY_GLOB))[0]
    assert storage.history_state(path) == "unverified"  # no sha256 recorded: the Parquet footer parses
    cut = tmp_path / path.name
    data = path.read_bytes()
    cut.write_bytes(data[:100] + data[-8:])  # both magics there, the footer gone
    assert storage.history_state(cut) == "damaged"
    assert storage.history_state(tmp_path / "absent.parquet") == "missing"
    assert storage.history_state(cut, "0" * 64) == "damaged"


def test_the_lock_refuses_a_second_holder_and_is_reentrant(tmp_path):
    from rpo.runtime.campaign.lock import folder_lock

    with folder_lock(tmp_path), folder_lock(tmp_path):  # the same process: re-entrant
        child = subprocess.run([sys.executable, "-c", "import sys; from rpo.runtime.campaign.lock import folder_lock\n"
                                f"with folder_lock({str(tmp_path)!r}): pass"], capture_output=True, text=True)
        assert child.returncode != 0 and f"in use by another `rpo mc run` or `rpo mc resume` (pid {os.getpid()})" \
            in child.stderr, child.stderr
    with folder_lock(tmp_path):  # released: taken again
        pass
    with pytest.raises(CampaignError, match="cannot take the campaign folder's lock"):
        with folder_lock(tmp_path / "absent"):
            pass


def test_two_resumes_at_once_never_fly_the_same_runs(reference, tmp_path):
    """Two ``rpo mc resume`` started together on a folder missing every run: one flies them and the
    other refuses (in use) or finds nothing left; no case is recorded twice, and the summary is the
    uninterrupted campaign's."""
    folder = tmp_path / "mc"
    import shutil
    shutil.copytree(reference, folder)
    (folder / storage.MANIFEST).unlink()
    (folder / storage.SUMMARY).unlink()
    cmd = [sys.executable, "-m", "rpo.runtime.cli.main", "mc", "resume", str(folder), "--workers", "1", "-q"]
    procs = [subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for _ in range(2)]
    results = [(p.wait(timeout=300), p.stderr.read()) for p in procs]
    for p in procs:
        p.stdout.close()
        p.stderr.close()
    codes = sorted(code for code, _ in results)
    assert codes in ([0, 0], [0, 2]), results
    if codes == [0, 2]:
        assert any("in use by another" in err for _, err in results), results
    scan = storage.scan_manifest(folder)
    assert scan.problems == [] and sorted(scan.rows) == list(range(RUNS))
    assert (folder / storage.MANIFEST).read_bytes().count(b"\n") == RUNS  # each run recorded once
    assert (folder / storage.SUMMARY).read_bytes() == (reference / storage.SUMMARY).read_bytes()

