"""The worst-case stack of an export's step, for its header: measured by :func:`checks.stack_usage` on
every target whose compiler is installed (the host's gcc always; the Cortex-M7, and for single precision
the Cortex-M4, with arm-none-eabi-gcc)."""

from __future__ import annotations

import shutil
from pathlib import Path

from rpo.runtime.errors import ModelError
from rpo.runtime.flight.checks import stack_usage
from rpo.runtime.flight.interface import Interface
from rpo.runtime.flight.tools import targets


def header_stack(folder: Path, iface: Interface, precision: str) -> dict[str, int]:
    """Target -> bytes of one ``<prefix>_step`` call (targets without their compiler are left out; a
    bound that cannot be computed is an error: the export has no dynamic frame, recursion or indirect call)."""
    out: dict[str, int] = {}
    for tgt in targets(precision):
        if shutil.which(tgt.cc) is None:
            continue
        res = stack_usage(folder, f"{iface.prefix}_step", tgt)
        if res.bytes is None:
            raise ModelError(f"the stack of {iface.prefix}_step on {tgt.name} cannot be bounded: "
                             + "; ".join(f.text() for f in res.findings[:3]))
        extra = f"; libm frames not counted: {', '.join(res.not_counted)}" if res.not_counted else ""
        out[f"{tgt.name} ({tgt.cc} {' '.join(tgt.flags[1:])}{extra})"] = int(res.bytes)
    return out
