"""The report of a Monte Carlo campaign folder: ``report.md`` and ``figures/*.png``.

Reads what the campaign runner writes (pyarrow and NumPy only; no pandas):

* ``resolved.json``      the campaign as run (name, runs requested, scenario, controller, command);
* ``summary.parquet``    one row per finished case: ``case``, ``seed``, ``status`` (``ok``,
  ``diverged``, ``invalid``, ``error``), ``message``, the ``draw.*`` columns, the outcome flags
  (bool, nullable) and the metrics (float, NaN = unavailable); units in the schema metadata
  ``rpo.units``;
* ``histories/batch_*.parquet``  the time histories of the flown cases, one file a batch (``case``,
  ``t`` [s], ``err_att_rad``, ``err_pos_m``, ``h_w_norm``...), each case's file named by its line
  in ``manifest.jsonl`` (folders of older versions: ``histories/case_NNNNNN.parquet``).

:func:`write_report` writes the report; :func:`summary_table` and :func:`case_history` give the
columns as NumPy arrays.  Conventions of the report (also in ``docs/campaigns.md``):

* **flown** runs are those with status ``ok`` or ``diverged``; rates (failed, not settled,
  diverged, constraint violated) are over the flown runs, invalid draws and worker errors over
  the done cases;
* the metric table is over the runs flown to the end (``ok``): a diverged run's metrics describe a
  truncated flight;
* the Wilks tolerance bounds are over the flown runs, with a diverged run counted as beyond any
  bound (+inf, or -inf for a bound from below) and a run that never settled as a settling time of
  +inf: the bound is a statement on all flown runs, not only on the good ones;
* the sensitivity table ranks Spearman's rho of each metric (over ``ok`` runs) and of ``failed``
  (over flown runs, 0/1) against every numeric draw; string draws are skipped;
* ``constraint violated`` counts the runs whose verdict names a violated constraint (the verdict's
  rule, :func:`rpo.runtime.outputs.verdict.violated_constraints`); ``failed`` counts a violated
  constraint only where the scenario declares it (``[constraints]``); the report says both rules;
* units: SI as in the summary, except angles in deg, angular rates in deg/s and wheel speeds in rpm
  (:func:`rpo.runtime.outputs.jsonunits.shown`; a column's SI suffix becomes the shown one:
  ``att_err_final_rad`` is shown as ``att_err_final_deg``), so no table shows rad beside deg;
* everything is deterministic: the bootstrap seed is fixed, no date is written, and the files of
  the figures carry no timestamp.
"""

from __future__ import annotations

from pathlib import Path

from rpo.runtime.campaign.folder import (  # noqa: F401  (summary_table, case_history: the module's API)
    case_history,
    read_folder,
    summary_table,
)
from rpo.runtime.campaign.qualification import requirement_lines, sobol_lines
from rpo.runtime.campaign.sections import (
    ReportContext,
    failure_rate_lines,
    figure_lines,
    header_lines,
    metric_lines,
    sensitivity_lines,
    status_lines,
    wilks_lines,
    worst_case_lines,
)
from rpo.runtime.formats import DEFAULT_FIGURE_FORMAT, FIGURE_FORMATS, unknown_figure_format


def write_report(campaign_dir: str | Path, out: str | Path | None = None, coverage: float = 0.95,
                 confidence: float = 0.95, n_boot: int = 2000, seed: int = 0, figures: bool = True,
                 top: int = 15, worst: int = 5, fmt: str = DEFAULT_FIGURE_FORMAT) -> Path:
    """Write ``report.md`` (and ``figures/*.<fmt>``) of a finished or partly finished campaign into
    ``out`` (default: the campaign folder); returns the path of ``report.md``.

    ``coverage`` and ``confidence`` (fractions) set the Wilks tolerance bounds and the confidence
    of every interval; ``n_boot`` and ``seed`` the bootstrap of the percentiles (the same folder
    gives the same bytes); ``top`` the rows of the sensitivity table, ``worst`` the rows per
    worst-case list.  The report's conventions are in the module docstring.
    """
    if fmt not in FIGURE_FORMATS:
        raise ValueError(unknown_figure_format(fmt))
    c = read_folder(campaign_dir)
    out_dir = Path(out) if out is not None else c.path
    out_dir.mkdir(parents=True, exist_ok=True)
    x = ReportContext(c, c.path.resolve(), coverage, confidence, n_boot, seed, top, worst)
    L = [f"# Monte Carlo campaign: {c.name}", ""]
    L += header_lines(x) + status_lines(x) + requirement_lines(x) + failure_rate_lines(x) + wilks_lines(x)
    L += metric_lines(x)
    sensitivity, by_pair = sensitivity_lines(x)
    L += sensitivity + sobol_lines(x) + worst_case_lines(x)
    if figures:
        L += figure_lines(x, out_dir, by_pair, fmt)
    text = "\n".join(L).rstrip("\n") + "\n"
    path = out_dir / "report.md"
    path.write_text(text)
    return path
