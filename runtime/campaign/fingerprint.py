"""What a campaign's runs depend on in the generated model, recorded when the campaign starts: the sha256
of every generated C file its runs can reach (the controller's step and its callees, every plant copy,
and what the pre-flight calls) and of the layouts those functions pack.

A re-fly (``rpo run --campaign DIR --case N``) or a resume compares these rather than the hash of the
whole manifest, so rebuilding for an unrelated controller does not orphan a campaign, and a change
that does matter is refused naming the file.  Folders of an older rpo, without the record, keep the
whole-manifest rule.
"""

from __future__ import annotations

import hashlib
from typing import Any

#: the functions a run calls besides its controller's (runtime/scenario/initial_state.py prepares them)
PREFLIGHT = ("target_orbit", "env_outputs", "measure")


def fingerprint(model: Any, controller: str) -> dict[str, Any]:
    """{"files": {C file: sha256}, "layouts": {layout: sha256}} of what ``controller``'s runs can reach."""
    man = model.manifest
    ctrl = man.controller(controller)
    names = [n for n in (*PREFLIGHT, ctrl.step, ctrl.xc0 or "") if n and n in man.functions]
    reach = model.needs(names)  # every specialised copy: a draw may select any of them
    files = {man.functions[f].source: man.files[man.functions[f].source] for f in sorted(reach)}
    layouts = sorted({port.layout for f in reach for port in (*man.functions[f].inputs, *man.functions[f].outputs)
                      if port.layout is not None} | {ctrl.gains})
    return {"files": files,
            "layouts": {n: hashlib.sha256(repr(man.layouts[n]).encode()).hexdigest() for n in layouts
                        if n in man.layouts}}


def changes(recorded: dict[str, Any], model: Any, controller: str) -> list[str]:
    """What differs between the ``recorded`` fingerprint and this model's (empty: the same code)."""
    now = fingerprint(model, controller)
    out = []
    for kind in ("files", "layouts"):
        then_, now_ = recorded.get(kind, {}), now[kind]
        for name in sorted(set(then_) | set(now_)):
            if then_.get(name) != now_.get(name):
                what = "generated/" + name if kind == "files" else f"layout {name}"
                state = "added" if name not in then_ else "removed" if name not in now_ else "changed"
                out.append(f"{what} {state}")
    return out


def model_changes(resolved: dict[str, Any], model: Any) -> str:
    """Why ``model`` cannot fly the campaign ``resolved`` (a folder's resolved.json) as it flew: the files
    and layouts of its fingerprint that changed, or (a folder without one) the manifest's hash; "" if
    nothing that its runs reach changed."""
    recorded = resolved.get("model_fingerprint")
    if isinstance(recorded, dict):
        diff = changes(recorded, model, resolved.get("controller", "baseline"))
        return "; ".join(diff[:4]) + (f" and {len(diff) - 4} more" if len(diff) > 4 else "")
    then = resolved.get("model_hash")
    if then != model.manifest.manifest_hash:
        return (f"generated/manifest.json hash {str(then)[:12]} then, {model.manifest.manifest_hash[:12]} now; "
                "this folder records no per-file fingerprint")
    return ""
