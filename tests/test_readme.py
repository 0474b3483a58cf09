"""The README's code blocks work as written.

* ```python blocks run in order in one namespace, in the checkout (as a reader pastes them);
* every ``rpo`` command of the ```sh blocks (``.venv/bin/rpo`` too, each part of a ``&&`` chain,
  ``[...]`` optional parts taken as given) is parsed by the command's own options (a group's by
  its subcommand's); ``rpo run`` also runs, with ``--duration 0.5 --no-plots`` into a temporary
  folder, and must end with its verdict (``rpo run --campaign DIR --case N``: after a small
  campaign of ``scenarios/campaigns/000_III_mc.toml`` made for it); ``rpo validate`` runs;
* a block preceded by the line ``<!-- readme-test: no-run -->`` is not run (the installs);
  its ``rpo`` commands are still parsed and run as above (nothing is installed);
* the verdicts the README quotes (```text blocks starting with ``verdict:``) are what the full runs
  print (slow: about 12 s).
"""

from __future__ import annotations

import re
import shlex
from dataclasses import dataclass
from pathlib import Path

import click
import pytest

from rpo.runtime.cli.main import cli, main

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
NO_RUN = "<!-- readme-test: no-run -->"
#: rpo commands that only parse: they write docs, delete cache files, run minutes or print pages
RUN = {"run", "validate"}


@dataclass
class Block:
    lang: str
    code: str
    line: int        # 1-based line of the opening fence
    run: bool        # False when marked NO_RUN


def blocks(text: str) -> list[Block]:
    out, lines, i = [], text.splitlines(), 0
    while i < len(lines):
        m = re.match(r"^```(\w*)\s*$", lines[i])
        if not m:
            i += 1
            continue
        j = next(k for k in range(i + 1, len(lines)) if lines[k].startswith("```"))
        out.append(Block(m.group(1), "\n".join(lines[i + 1:j]) + "\n", i + 1, not (i and lines[i - 1] == NO_RUN)))
        i = j + 1
    return out


def rpo_commands(block: Block) -> list[list[str]]:
    """The argument lists of the ``rpo`` commands of a shell block."""
    cmds = []
    for line in block.code.splitlines():
        line = re.sub(r"\s+#.*$", "", line).strip()
        for part in line.split("&&"):
            tokens = [tok.strip("[]") for tok in shlex.split(part)]
            tokens = [tok for tok in tokens if tok]
            if tokens and Path(tokens[0]).name == "rpo":
                cmds.append(tokens[1:])
    return cmds


ALL = blocks(README.read_text())
SHELL = [(b.line, cmd) for b in ALL if b.lang == "sh" for cmd in rpo_commands(b)]


def test_readme_starts_with_the_two_commands_and_marks_the_installs():
    first = ALL[0]
    assert first.lang == "sh" and not first.run
    lines = first.code.splitlines()
    assert len(lines) == 2 and all("pip install" in ln for ln in lines)
    assert lines[0].endswith("rpo run scenarios/001_scenario.toml") and lines[1].endswith("python -m pytest")
    assert any(b.lang == "python" for b in ALL) and len(SHELL) >= 8


def test_python_blocks_run_as_written(monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    ns: dict = {"__name__": "readme"}
    code = [b for b in ALL if b.lang == "python" and b.run]
    assert code
    for b in code:
        exec(compile(b.code, f"README.md:{b.line}", "exec"), ns)
    assert ns["res"]["r"].shape[1] == 3 and ns["res"].unit("r") == "m"
    assert "m" in capsys.readouterr().out


@pytest.mark.parametrize("line,args", SHELL, ids=[f"L{ln}-{' '.join(a)[:40]}" for ln, a in SHELL])
def test_rpo_shell_lines_parse_and_run(line, args, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    name, rest = args[0], list(args[1:])
    assert name in cli.commands, f"README.md:{line}: no rpo command {name!r}"
    cmd = cli.commands[name]
    try:
        if isinstance(cmd, click.Group):  # rpo mc run ...: the subcommand's own options
            assert rest and rest[0] in cmd.commands, f"README.md:{line}: no rpo {name} {rest[:1]}"
            cmd.commands[rest[0]].make_context(rest[0], list(rest[1:]))
        else:
            cmd.make_context(name, list(rest))  # parses every option and argument, runs nothing
    except click.ClickException as exc:
        pytest.fail(f"README.md:{line}: rpo {' '.join(args)}: {exc.format_message()}")
    for tok in rest:
        if tok.endswith(".toml"):
            assert (ROOT / tok).is_file(), f"README.md:{line}: {tok} does not exist"
    if name not in RUN:
        return
    if name == "run" and "--campaign" in rest:
        # one case of a campaign: fly a small campaign of the README's file first (enough cases)
        case = int(rest[rest.index("--case") + 1])
        folder = tmp_path / "mc"
        assert main(["mc", "run", "scenarios/campaigns/000_III_mc.toml", "--out", str(folder), "--runs",
                     str(case + 1), "--duration", "0.5", "-q"]) == 0
        rest = ["--campaign", str(folder), "--case", str(case), "--no-plots", "--out", str(tmp_path / "run")]
    elif name == "run":
        drop = {"--out", "--duration"}
        kept, skip = [], False
        for tok in rest:
            if skip:
                skip = False
            elif tok in drop:
                skip = True
            else:
                kept.append(tok)
        rest = [*kept, "--duration", "0.5", "--no-plots", "--out", str(tmp_path / "run")]
    rc = main([name, *rest])
    out = capsys.readouterr()
    assert rc == 0, f"README.md:{line}: rpo {' '.join(args)} exited {rc}: {out.err}"
    if name == "run":
        assert out.out.strip().splitlines()[-1].startswith("verdict: ")


@pytest.mark.slow
def test_the_quoted_verdicts_are_what_the_runs_print(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    quoted = [b.code.strip() for b in ALL if b.lang == "text" and b.code.startswith("verdict:")]
    runs = [cmd for _, cmd in SHELL[:3] if cmd[0] == "run"]  # the first command, then scenario III's
    assert len(quoted) == 2 and len(runs) == 2
    for i, (args, want) in enumerate(zip(runs, quoted, strict=True)):
        assert main([*args, "--no-plots", "--out", str(tmp_path / f"r{i}")]) == 0
        assert capsys.readouterr().out.strip().splitlines()[-1] == want
