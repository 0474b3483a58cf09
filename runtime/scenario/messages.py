"""Error text of scenario files: every error is ONE line naming the file, the dotted key, the
offending value and what is allowed, e.g.
``scenario.toml: orbit.eccentricity = 1.2: must be in [0, 1)``."""

from __future__ import annotations

import difflib
import json
import typing
from collections.abc import Sequence
from typing import Any

from pydantic import BaseModel
from pydantic_core import ErrorDetails, PydanticCustomError


def field_error(field_name: str, value: Any, message: str) -> PydanticCustomError:
    """An error on ``field_name`` (dotted, relative to the model raising it) with its value."""
    return PydanticCustomError("scenario", message, {"field": field_name, "value": value})


def show(v: Any, limit: int = 70) -> str:
    """A value as it would be typed in TOML, shortened."""
    if isinstance(v, bool):
        s = "true" if v else "false"
    elif isinstance(v, str):
        s = json.dumps(v)
    elif isinstance(v, float):
        s = repr(v)
    elif isinstance(v, (list, tuple)):
        s = "[" + ", ".join(show(x, limit) for x in v) + "]"
    elif isinstance(v, dict):
        s = "{ " + ", ".join(f"{k} = {show(x, limit)}" for k, x in v.items()) + " }"
    else:
        s = str(v)
    return s if len(s) <= limit else s[: limit - 3] + "..."


def dotted(loc: Sequence[int | str], index: str = "[{}]") -> str:
    """``orbit.eccentricity``, ``chaser.inertia[1]`` (``index``: how a list position is written)."""
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += index.format(part)
        else:
            out += ("." if out else "") + str(part)
    return out


def unknown_key(key: str, allowed: list[str]) -> str:
    close = difflib.get_close_matches(key, allowed, n=1)
    hint = f"did you mean {close[0]!r}? " if close else ""
    return f"unknown key ({hint}allowed: {', '.join(allowed)})"


def section_class(loc: Sequence[int | str], root: type[BaseModel]) -> type[BaseModel] | None:
    """The model class of the table at ``loc`` below ``root`` (for listing the allowed keys)."""
    cls: Any = root
    for part in loc:
        if isinstance(part, int):  # an entry of an array of tables ([[faults]]): the entry's class
            continue
        if not (isinstance(cls, type) and issubclass(cls, BaseModel)) or part not in cls.model_fields:
            return None
        ann = cls.model_fields[str(part)].annotation
        cands = [ann, *typing.get_args(ann)]
        cls = next((c for c in cands if isinstance(c, type) and issubclass(c, BaseModel)), None)
    return cls


_SIMPLE = {
    "float_type": "must be a number", "float_parsing": "must be a number",
    "int_type": "must be an integer", "int_from_float": "must be an integer",
    "bool_type": "must be true or false", "string_type": "must be a string",
    "list_type": "must be an array", "model_type": "must be a table", "model_attributes_type": "must be a table",
    "dict_type": "must be a table", "finite_number": "must be a finite number",
    "missing": "required key is missing",
}


def _message(err: ErrorDetails, root: type[BaseModel]) -> str:
    t, ctx = err["type"], err.get("ctx") or {}
    inp = err.get("input")
    if t in _SIMPLE:
        return _SIMPLE[t]
    if t == "literal_error":
        return f"must be one of {ctx.get('expected', '')}"
    if t in ("too_short", "too_long"):
        n = ctx.get("min_length", ctx.get("max_length"))
        got = len(inp) if isinstance(inp, (list, tuple)) else ctx.get("actual_length")
        return f"must have {n} values, got {got}"
    if t == "extra_forbidden":
        cls = section_class(err["loc"][:-1], root)
        return unknown_key(str(err["loc"][-1]), list(cls.model_fields) if cls else [])
    msg = err["msg"]
    return msg[0].lower() + msg[1:] if msg else t


def format_error(err: ErrorDetails, source: str, root: type[BaseModel], prefix: tuple[str, ...] = (),
                 index: str = "[{}]") -> str:
    """One line: ``source: dotted.key = value: message``.  ``root`` is the model validated (for
    the allowed keys of a table); ``prefix`` is where it sits in the file (e.g. ``("reproduction",)``);
    ``index`` writes a position in an array of tables (``".{}"``: ``run.0.plant``)."""
    ctx = err.get("ctx") or {}
    loc = tuple(err["loc"])
    value = err.get("input")
    if "field" in ctx:
        loc = loc + tuple(str(ctx["field"]).split("."))
        value = ctx.get("value")
    path = dotted(prefix + loc, index) or "(top level)"
    msg = _message(err, root) if "field" not in ctx else err["msg"]
    msg = " ".join(msg.split())  # never more than one line
    if err["type"] == "missing":
        what = "table" if section_class(loc, root) is not None else "key"
        return f"{source}: {path}: required {what} is missing"
    if value is None:
        return f"{source}: {path}: {msg}"
    return f"{source}: {path} = {show(value)}: {msg}"


def first_error(errors: list[ErrorDetails], source: str, root: type[BaseModel], prefix: tuple[str, ...] = (),
                index: str = "[{}]") -> str:
    """The first error as one line, with the count of the others."""
    more = f" (and {len(errors) - 1} more error{'s' if len(errors) > 2 else ''})" if len(errors) > 1 else ""
    return format_error(errors[0], source, root, prefix, index) + more
