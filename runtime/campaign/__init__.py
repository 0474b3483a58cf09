"""Monte Carlo campaigns: a scenario with dispersions, flown many times, stored so nothing is lost.

* :mod:`.spec`: the campaign file (``[campaign]``, ``[dispersions]``), :func:`load_campaign`;
* :mod:`.dispersions`: the distributions; :mod:`.sampling`: seeds and designs;
* :mod:`.execute`: flying the runs (this process, a process pool, Dask), resuming;
* :mod:`.requirements`: ``[requirements]`` and their verdicts; :mod:`.sequential`: stopping once decided;
* :mod:`.sobol`: Sobol indices of a Saltelli design (``sampling = "sobol-indices"``);
* :mod:`.storage`: the campaign folder (manifest.jsonl, summary.parquet, histories);
* :mod:`.stats`, :mod:`.report`, :mod:`.figures`: statistics and ``report.md``.

From Python::

    from rpo.runtime.campaign import load_summary, load_history
    df = load_summary("runs/mc")            # one row per run (pandas)
    h = load_history("runs/mc", 17)          # one run's time history (pandas)

docs/campaigns.md describes the file, the folder and the statistics.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from rpo.runtime.campaign.execute import CampaignOutcome, check_resume, start_folder
from rpo.runtime.campaign.sequential import run_campaign  # execute's, in looks for a sequential campaign
from rpo.runtime.campaign.spec import Campaign, load_campaign, loads_campaign
from rpo.runtime.campaign.storage import read_history, read_rows
from rpo.runtime.errors import CampaignError

__all__ = ["Campaign", "CampaignError", "CampaignOutcome", "check_resume", "load_campaign", "load_history",
           "load_summary", "loads_campaign", "read_history", "read_rows", "run_campaign", "start_folder"]


def _pandas() -> Any:
    try:
        import pandas as pd
    except ImportError:
        raise CampaignError("this needs pandas: pip install pandas") from None
    return pd


def load_summary(folder: str | Path) -> Any:
    """``summary.parquet`` as a pandas DataFrame (one row per run; units in ``df.attrs["units"]``)."""
    import json

    import pyarrow.parquet as pq
    path = Path(folder) / "summary.parquet"
    if not path.exists():
        raise CampaignError(f"{path}: no summary (the campaign has not finished a `rpo mc run` or `resume`)")
    table = pq.read_table(path)
    df = table.to_pandas()
    df.attrs["units"] = json.loads((table.schema.metadata or {}).get(b"rpo.units", b"{}"))
    return _pandas().DataFrame(df) if not hasattr(df, "attrs") else df


def load_history(folder: str | Path, case: int) -> Any:
    """One run's decimated time history as a pandas DataFrame (``t`` [s] and the channels)."""
    cols, units, meta = read_history(Path(folder), int(case))
    df = _pandas().DataFrame(cols)
    df.attrs["units"], df.attrs["case"] = units, meta
    return df
