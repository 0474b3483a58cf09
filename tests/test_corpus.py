"""The malformed-input corpus (``tests/corpus/cases.toml``, issue 11): every case through ``rpo
validate`` and ``rpo run`` in-process, each with its exit code, one ``error:`` line holding the
expected fragment, no traceback, nothing written; validate and run agree on every case.

Summary for quoting: ``python -m tests.corpus_summary``.
"""

from __future__ import annotations

import pytest
from corpus_summary import Case, expected_code, load_cases, manifest_read_once, outcomes

CASES = load_cases()


@pytest.fixture(scope="module", autouse=True)
def _manifest_once():
    with manifest_read_once():  # ~360 CLI calls in one process: hash the generated files once
        yield


def test_the_corpus_is_large_and_covers_the_issue():
    malformed = [c for c in CASES if c.exit != 0]
    assert len(malformed) >= 100
    specials = {c.special for c in CASES if c.special}
    # the files the issue names: a device, a FIFO, a folder, missing, unreadable, invalid UTF-8, an extends cycle
    assert {"dev_zero", "fifo", "directory", "missing", "unreadable", "latin1", "too_large", "extends_cycle",
            "extends_dev_zero", "extends_fifo"} <= specials
    text = "\n".join(c.toml for c in CASES)
    for needle in ("= nan", "= inf", "= -inf", "1e-320", "1e300", "= -0.1", '= "'):  # non-finite, extreme, sign, type
        assert needle in text, needle
    assert any(c.exit == 0 for c in CASES) and any(c.run_exit == 3 for c in CASES)


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_case(case: Case, tmp_path):
    results = outcomes(case, tmp_path)
    for o in results:
        want = expected_code(case, o.command)
        assert o.code == want, (o.command, o.code, o.stderr)
        assert "Traceback" not in o.stderr + o.stdout, o.stderr
        assert case.fragment in o.stderr, (o.command, case.fragment, o.stderr)
        if want == 2:
            lines = o.stderr.strip().splitlines()
            assert len(lines) == 1 and lines[0].startswith("error: "), o.stderr
            assert o.stdout == ""
            assert "out" not in o.created, o.created  # a refused run writes nothing
        elif o.command == "validate":
            assert o.stdout.splitlines()[0].endswith(": valid"), o.stdout
    if len(results) == 2:  # validate and run agree: both refuse, or validate accepts what run runs
        v, r = results
        assert (v.code == 2) == (r.code == 2), (v.code, r.code)
