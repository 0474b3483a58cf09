"""The table of choices made where the papers are silent, read from the scenario files themselves.

Every scenario value carries its source in a comment: ``paper``, ``reading`` (rpo's reading of data
the extracted text lost, ``docs/papers.md``) or ``chosen: <why>``.  :func:`collect` reads each
``key = value`` line with its inline comment and the comment block just above it, and keeps those
whose comment says "chosen" (or "reconstructed"); :func:`render` writes ``docs/scenarios.md``.  The
scenario file stays the single place a choice is written; the table is derived from it and a test
keeps the committed copy current (``rpo choices --check``).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from rpo.runtime.formats import DEFAULT_FIGURE_FORMAT, DEFAULT_FORMATS, FIGURE_FORMATS, OUTPUT_FORMATS

_SECTION = re.compile(r"^\s*\[\[?([^\]]+)\]\]?\s*(#.*)?$")
_ASSIGN = re.compile(r"^\s*([A-Za-z0-9_\-]+)\s*=\s*(.*)$")
_MARKERS = ("chosen", "reconstructed")
#: Tables that hold no scenario value: the report's runs and the papers' published values.
_SKIP = ("reproduction",)


@dataclass(frozen=True)
class Choice:
    scenario: str
    key: str
    value: str
    reason: str


def _split_inline(rest: str) -> tuple[str, str]:
    """Value and inline comment of the text after ``=`` (a ``#`` inside a string is not a comment)."""
    in_str = None
    for i, ch in enumerate(rest):
        if ch in "\"'" and in_str is None:
            in_str = ch
        elif ch == in_str:
            in_str = None
        elif ch == "#" and in_str is None:
            return rest[:i].strip(), rest[i + 1:].strip()
    return rest.strip(), ""


def collect(path: Path) -> list[Choice]:
    """The choices recorded in one scenario file, in file order."""
    out: list[Choice] = []
    section = ""
    block: list[str] = []
    for line in path.read_text().splitlines():
        stripped = line.strip()
        if stripped.startswith("#"):
            block.append(stripped.lstrip("#").strip())
            continue
        m = _SECTION.match(line)
        if m:
            section = m.group(1).strip()
            block = []
            continue
        m = _ASSIGN.match(line)
        if m and section and section.split(".")[0] not in _SKIP:
            value, inline = _split_inline(m.group(2))
            text = " ".join([*block, inline]).strip()
            if any(k in text.lower() for k in _MARKERS):
                out.append(Choice(path.stem, f"{section}.{m.group(1)}", value, " ".join(text.split())))
        block = []
    return out


def _quoted(name: str) -> str:
    return f'`"{name}"`'


#: ``"parquet"`, `"mat"` (MATLAB), ...``: the formats in the [output] table (rpo.runtime.formats).
_FORMATS = ", ".join(_quoted(f.name) + (f" ({f.note})" if f.note else "") for f in OUTPUT_FORMATS.values())
_FIGURE_FORMATS = ", ".join(_quoted(n) for n in list(FIGURE_FORMATS)[:-1]) + " or " * (len(FIGURE_FORMATS) > 1) \
    + _quoted(list(FIGURE_FORMATS)[-1])
#: One row per time-history format: its file and what the file holds.
_FORMAT_ROWS = "\n".join(f"| {_quoted(f.name)} | `{f.file}` | {f.holds} |" for f in OUTPUT_FORMATS.values())
_DEFAULT_FORMATS = "[" + ", ".join(f'"{n}"' for n in DEFAULT_FORMATS) + "]"

#: The reference of the ``[output]`` table and of ``simulation.record_every`` (in docs/scenarios.md);
#: the formats come from :mod:`rpo.runtime.formats`.
OUTPUT_DOC = f"""\
## What a run records and writes: `simulation.record_every` and `[output]`

Two steps, so that the metrics never depend on what is written:

- `simulation.record_every` (integer >= 1, default 1) is the **in-memory record**: every
  `record_every`-th step (and always the final state) is kept while the run simulates. The
  metrics (`metrics.json`, `rpo report`) and the figures are computed from it. Keep 1 (every
  step: PWPF pulses last one step) unless the run is too long to hold in memory
  (`001_scenario.toml`: 5000 s, once per second).
- `[output]` chooses what is **written** from that record (all keys optional):

| key | default | meaning |
| --- | --- | --- |
| `channels` | the default set | array of field names (`"r"`: `r_x`, `r_y`, `r_z`), column labels (`"meas_q_e_w"`), glob patterns (`"ctrl_*"`, `"env_M_gg_?"`) over the layouts `z_<controller>` and `y_<controller>` (`rpo info` lists them), and `"default"` for the default set. An entry that matches nothing is an error naming the close matches. Columns are written in layout order; `t` always |
| `every` | `simulation.record_every` | write the rows whose step is a multiple of `every` (steps of 1 / `simulation.rate`), and the final row; a multiple of `simulation.record_every` |
| `rate_hz` | - | the same as a rate: `every = rate / rate_hz`, which must be a whole number; give `every` or `rate_hz`, not both |
| `formats` | `{_DEFAULT_FORMATS}` | any of {_FORMATS}; `rpo run --format` (comma-separated) replaces it |
| `figures` | `true` | `false` writes no figure (as `rpo run --no-plots`) |
| `figure_format` | {_quoted(DEFAULT_FIGURE_FORMAT)} | {_FIGURE_FORMATS}; `rpo run --figure-format` replaces it |

The default set (`rpo.runtime.scenario.channels.DEFAULT_CHANNELS`) is what the figures and the metrics
read plus the physical state: `q_c`, `w_c`, `h_w`, `q_t`, `w_t`, `r`, `v`, `m_prop`, `meas_q_e`,
`meas_w_e`, `cmd_*`, `wheel_applied`, `thr_duty`, `thr_on`, `env_m_c`, `env_wheel_speed`,
`env_tau_applied`, `env_F_applied`, `env_beta_fov`, `env_beta_ca`, `ctrl_*` (156 of 306 columns
for c000; about 20 MB of Parquet for scenario III's 30001 rows). Left out: the wheel delay line,
the PWPF filter states, the controller's states `xc_*` (logged as `ctrl_*` where they matter),
the other raw measurements and the environment's terms; add them by name or pattern, or write
everything with `channels = ["*"]`.

The time histories' formats (each chosen one is a file of the results folder):

| format | file | holds |
| --- | --- | --- |
{_FORMAT_ROWS}

Example:

```toml
[output]
channels = ["default", "env_M_gg_*", "xc_*"]
rate_hz = 10.0              # 10 rows per second of a 100 Hz run
formats = ["parquet", "mat"]
figure_format = "svg"
```
"""  # noqa: E501 - markdown table rows


#: What a chosen value must respect besides its range (in docs/scenarios.md).
PHYSICAL_DOC = """## What a chosen value must also respect: physically absurd combinations

`rpo validate`, `rpo run` and each draw of a campaign refuse a combination no spacecraft flies,
naming the key, the value and the reason (`runtime/scenario/physical.py`; `docs/parameters.md`
gives the figures): an Earth orbit with its perigee below 100 km (whether it is given by
`orbit.perigee_altitude` or `orbit.semi_major_axis` and `orbit.eccentricity`) or its apogee beyond
the Earth's Hill sphere (1.5e9 m), a chaser starting below that 100 km floor, or at the target's
centre or inside the keep-out sphere `constraints.chaser_radius + constraints.target_radius`.
"""


def render(paths: list[Path]) -> str:
    """Markdown for ``docs/scenarios.md``."""
    lines = [
        "# Scenario choices",
        "",
        "Generated by `rpo choices --write docs/scenarios.md` from the comments in `scenarios/*.toml`;",
        "edit the scenario files, not this page. Each row is a value the paper does not state, states",
        "inconsistently, or lost in the text extraction, with the reason written beside it in the",
        "scenario file. Values marked `paper` or `reading` (rpo's reading of what the extracted text",
        "lost, `docs/papers.md`) there are not repeated here. The reference of the `[output]` table",
        "comes first.",
        "",
        OUTPUT_DOC,
        PHYSICAL_DOC,
    ]
    for path in paths:
        rows = collect(path)
        lines += [f"## {path.name}", ""]
        if not rows:
            lines += ["No choices: every value is the paper's.", ""]
            continue
        lines += ["| key | value | why |", "| --- | --- | --- |"]
        for c in rows:
            value = c.value.replace("|", "\\|")
            reason = c.reason.replace("|", "\\|")
            lines.append(f"| `{c.key}` | `{value}` | {reason} |")
        lines.append("")
    return "\n".join(lines)


def scenario_files(folder: Path) -> list[Path]:
    return sorted(folder.glob("*.toml"))
