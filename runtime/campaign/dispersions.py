"""Dispersions: the distribution of one scenario value, as a map from uniforms to values.

Every distribution consumes ``dims`` uniforms in (0, 1) per run and turns them into a value by
inverse CDFs (``ppf``), so that pseudo-random, Latin-hypercube and Sobol designs
(:mod:`.sampling`) all feed the same code.  A value is what a scenario file would hold at the
key: a number, an array, a string (a choice), a quaternion ``[x, y, z, w]`` or a 3x3 inertia, in
the key's own unit (``inclination_deg`` in deg, ``relative.position`` in m).

**The distributions are declared once, here**: :data:`DISTRIBUTIONS` holds rpo's own, each a
:class:`Distribution` object with its name, its parameters (:class:`Param`: name and meaning, with
the unit), the checks of those parameters, the number of uniforms a draw takes and its inverse
CDF; :class:`ScipyDistribution` is the family of every ``scipy.stats`` continuous distribution by name (``lognorm``,
``weibull_min``, ...: the name is looked up in scipy's list, never evaluated).
:func:`distribution` finds the one a ``dist = ...`` names, and :class:`Dispersion` (one dispersed
key) asks it for everything, so nothing else switches on a distribution's name.  The table of
``docs/campaigns.md`` is :func:`reference_table` (``tests/test_vocabularies.py`` keeps it current);
adding a distribution is one class and one entry of :data:`DISTRIBUTIONS`.

Parameters broadcast over the components of an array-valued key, each component drawn
independently.  A distribution whose parameters are wrong (a negative spread, a truncation holding
no probability, an unknown shape name) is refused when the campaign is read, with one line naming
the key (:class:`DispersionError`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import special, stats

from rpo.runtime.frames import dcm_from_quat, quat_conjugate, quat_multiply, rotation_angle

DEG = math.pi / 180.0
#: Smallest probability a truncation may keep: below it the draws would all sit at a bound to
#: rounding, which is a typo, not a distribution.
MIN_TRUNCATED_MASS = 1e-9


class DispersionError(ValueError):
    """A dispersion that cannot be sampled; ``field`` is the parameter at fault (``std``, ``low``)."""

    def __init__(self, field: str, message: str):
        super().__init__(message)
        self.field = field
        self.message = message


def continuous_names() -> list[str]:
    """The names of ``scipy.stats``' continuous distributions (the allowed ``dist`` besides rpo's own)."""
    return sorted(n for n in dir(stats) if isinstance(getattr(stats, n, None), stats.rv_continuous))


def _number(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(float(x))


# --------------------------------------------------------------------------- the distributions


@dataclass(frozen=True)
class Param:
    """A parameter of a distribution (besides ``dist``): its ``name`` in ``[dispersions.<key>]``
    and its ``meaning``, with its unit."""

    name: str
    meaning: str


class Distribution:
    """A kind of dispersion: ``name`` (``dist = ...``), ``params``, ``value_doc`` (what a draw is).

    :meth:`check` validates a :class:`Dispersion`'s parameters (raising :class:`DispersionError`
    with the one-line reason) and returns what :meth:`value` needs, kept as the dispersion's
    ``frozen`` state; :meth:`dims` is the uniforms a draw takes, :meth:`value` the inverse CDF of
    one draw, :meth:`values` of many (the same values), :meth:`columns` the summary's columns of a
    drawn value.
    """

    name: str = ""
    params: tuple[Param, ...] = ()
    value_doc: str = ""

    @property
    def allowed(self) -> set[str]:
        """The keys its table may hold (``dist`` and its parameters)."""
        return {"dist", *(p.name for p in self.params)}

    def check(self, d: Dispersion) -> Any:
        raise NotImplementedError

    def dims(self, d: Dispersion) -> int:
        return d.size

    def value(self, d: Dispersion, u: np.ndarray) -> Any:
        raise NotImplementedError

    def values(self, d: Dispersion, us: Sequence[np.ndarray]) -> list[Any]:
        return [self.value(d, u) for u in us]

    def columns(self, d: Dispersion, value: Any) -> dict[str, Any]:
        """By the value's shape: ``draw.<key>`` (a scalar or a choice), ``draw.<key>[i]``
        (components), ``draw.<key>[i][j]`` (a matrix)."""
        if isinstance(value, list):
            if value and isinstance(value[0], list):
                shape = tuple(len(row) for row in value)
                return dict(zip(d.column_names(("matrix", shape), lambda base: tuple(
                    f"{base}[{i}][{j}]" for i, n in enumerate(shape) for j in range(n))),
                    [float(x) for row in value for x in row], strict=True))
            n = len(value)
            return dict(zip(d.column_names(("vector", n), lambda base: tuple(f"{base}[{i}]" for i in range(n))),
                            [_cell(v) for v in value], strict=True))
        return {d.column_names(("scalar",), lambda base: (base,))[0]: _cell(value)}


class Normal(Distribution):
    name = "normal"
    params = (Param("std", ">= 0, in the key's unit"),
              Param("rel_std", ">= 0, a fraction of the nominal's magnitude, instead of `std`"),
              Param("mean", "the nominal value by default"),
              Param("low", "optional truncation, absolute"),
              Param("high", "optional truncation, absolute"))
    value_doc = ("N(mean, std^2), truncated to [low, high] by the inverse CDF of the truncated normal "
                 "(never clipped)")

    def check(self, d: Dispersion) -> Any:
        p = d.params
        if ("std" in p) == ("rel_std" in p):
            raise DispersionError("std", "give either std or rel_std (a fraction of the nominal)")
        mean = d.vector("mean", p["mean"]) if "mean" in p else d.nominal_array() * np.ones(d.size)
        if "std" in p:
            std = d.vector("std", p["std"], lo=0.0)
        else:
            std = d.vector("rel_std", p["rel_std"], lo=0.0) * np.abs(d.nominal_array())
        lo = d.vector("low", p["low"]) if "low" in p else np.full(d.size, -np.inf)
        hi = d.vector("high", p["high"]) if "high" in p else np.full(d.size, np.inf)
        for i in range(d.size):
            if not lo[i] < hi[i]:
                raise DispersionError("low", f"truncation low = {lo[i]:g} must be < high = {hi[i]:g}")
            if std[i] == 0.0:
                if not lo[i] <= mean[i] <= hi[i]:
                    raise DispersionError("low", f"the truncation [{lo[i]:g}, {hi[i]:g}] excludes the mean "
                                                 f"{mean[i]:g} of a zero-spread component")
                continue
            mass = stats.norm.cdf((hi[i] - mean[i]) / std[i]) - stats.norm.cdf((lo[i] - mean[i]) / std[i])
            if not mass >= MIN_TRUNCATED_MASS:
                raise DispersionError("low", f"the truncation [{lo[i]:g}, {hi[i]:g}] excludes everything: it holds "
                                             f"a probability of {mass:.3g} of N({mean[i]:g}, {std[i]:g}^2) "
                                             f"(at least {MIN_TRUNCATED_MASS:g} needed)")
        # the truncated components and the zero-spread mask, for value()
        truncated = [int(i) for i in np.flatnonzero(np.isfinite(lo) | np.isfinite(hi))]
        return mean, std, lo, hi, truncated, std == 0.0

    def value(self, d: Dispersion, u: np.ndarray) -> Any:
        mean, std, lo, hi, truncated, zero = d.frozen
        z = special.ndtri(np.asarray(u, float)[: d.size])  # the normal ppf, without scipy.stats' overhead
        out = mean + std * z
        for i in truncated:
            if std[i] > 0:
                x = mean[i] + std[i] * _truncated_normal_ppf(u[i], (lo[i] - mean[i]) / std[i],
                                                             (hi[i] - mean[i]) / std[i])
                out[i] = min(max(x, lo[i]), hi[i])  # the last ulp of rounding, not a clip of the draw
        if zero.any():
            out[zero] = mean[zero]
        return d.shape(out)

    def values(self, d: Dispersion, us: Sequence[np.ndarray]) -> list[Any]:
        """The element-wise map applied to all the draws at once (the truncated inverse CDF is
        scalar code: one draw at a time then)."""
        mean, std, _lo, _hi, truncated, zero = d.frozen
        if truncated or len(us) < 2:
            return super().values(d, us)
        out = mean + std * special.ndtri(np.array([np.asarray(u, float)[: d.size] for u in us]))
        if zero.any():
            out[:, zero] = mean[zero]
        return [d.shape(row) for row in out]


class Uniform(Distribution):
    name = "uniform"
    params = (Param("low", "in the key's unit"), Param("high", "in the key's unit"),
              Param("half_width", ">= 0, around the nominal, instead of `low` and `high`"),
              Param("rel_half_width", ">= 0, a fraction of the nominal's magnitude, around it"))
    value_doc = "U(low, high)"

    def check(self, d: Dispersion) -> Any:
        p = d.params
        given = [k for k in ("half_width", "rel_half_width") if k in p]
        if given and ("low" in p or "high" in p) or len(given) > 1:
            raise DispersionError(given[-1], "give low and high, or one of half_width / rel_half_width")
        if given:
            nom = d.nominal_array() * np.ones(d.size)
            w = d.vector(given[0], p[given[0]], lo=0.0)
            w = w * np.abs(nom) if given[0] == "rel_half_width" else w
            lo, hi = nom - w, nom + w
        else:
            if "low" not in p or "high" not in p:
                raise DispersionError("low", f"dist = \"{self.name}\" needs low and high, or half_width")
            lo, hi = d.vector("low", p["low"]), d.vector("high", p["high"])
        if np.any(lo > hi):
            i = int(np.argmax(lo > hi))
            raise DispersionError("low", f"low = {lo[i]:g} must be <= high = {hi[i]:g}")
        return lo, hi

    def value(self, d: Dispersion, u: np.ndarray) -> Any:
        lo, hi = d.frozen
        return d.shape(lo + (hi - lo) * np.asarray(u, float)[: d.size])

    def values(self, d: Dispersion, us: Sequence[np.ndarray]) -> list[Any]:
        if len(us) < 2:
            return super().values(d, us)
        lo, hi = d.frozen
        U = np.array([np.asarray(u, float)[: d.size] for u in us])
        return [d.shape(row) for row in lo + (hi - lo) * U]


class Choice(Distribution):
    name = "choice"
    params = (Param("values", "the candidates, each a value of the key"),
              Param("weights", "optional, >= 0, one per value"))
    value_doc = "one of the values"

    def check(self, d: Dispersion) -> Any:
        values = d.params.get("values")
        if not isinstance(values, list) or not values:
            raise DispersionError("values", "must be a non-empty array of the candidate values")
        w = d.params.get("weights")
        if w is None:
            weights = np.full(len(values), 1.0 / len(values))
        else:
            if not isinstance(w, list) or len(w) != len(values) or not all(_number(x) and x >= 0 for x in w) \
                    or not sum(w) > 0:
                raise DispersionError("weights", f"must be {len(values)} numbers >= 0 (one per value), not all 0")
            weights = np.array(w, float) / float(sum(w))
        return values, np.cumsum(weights)

    def dims(self, d: Dispersion) -> int:
        return 1

    def value(self, d: Dispersion, u: np.ndarray) -> Any:
        values, cum = d.frozen
        pick = min(int(np.searchsorted(cum, u[0], side="right")), len(values) - 1)
        return values[pick]


class Rotation(Distribution):
    name = "rotation"
    params = (Param("sigma_deg", ">= 0 deg, the 1-sigma angle, one or one per body axis"),)
    value_doc = ("`q_nominal (x) dq(phi)`, phi ~ N(0, sigma^2 I), the perturbation in body axes (Hamilton "
                 "product, docs/conventions.md); its column `<key>.angle_deg` is the angle from the nominal "
                 "attitude")

    def check(self, d: Dispersion) -> Any:
        q = d.nominal
        if not (isinstance(q, list) and len(q) == 4 and all(_number(x) for x in q)):
            raise DispersionError("dist", f"dist = \"{self.name}\" disperses a quaternion [x, y, z, w]; {d.key} is "
                                          f"{q!r}")
        sigma = d.vector("sigma_deg", d.params.get("sigma_deg"), lo=0.0, size=3)
        d.size = 4
        q0 = np.array(q, float)
        return q0 / np.linalg.norm(q0), sigma * DEG

    def dims(self, d: Dispersion) -> int:
        return 3

    def value(self, d: Dispersion, u: np.ndarray) -> Any:
        q0, sigma = d.frozen
        phi = sigma * special.ndtri(np.asarray(u, float)[:3])
        q = quat_multiply(q0, _rotvec_quat(phi))  # = (Rotation(q0) * Rotation.from_rotvec(phi)).as_quat()
        q = q / math.sqrt(float(q @ q))
        if float(np.dot(q, q0)) < 0:  # the same attitude, on the nominal's side (continuous draws)
            q = -q
        return [float(x) for x in q]

    def columns(self, d: Dispersion, value: Any) -> dict[str, Any]:
        """``draw.<key>.angle_deg`` (the angle from the nominal attitude), then the components."""
        q0 = d.frozen[0]
        q = np.array(value, float)
        ang = math.degrees(float(rotation_angle(quat_multiply(quat_conjugate(q0), q))))
        n = len(value)
        names = d.column_names((self.name, n), lambda base: (f"{base}.angle_deg", *(f"{base}[{i}]" for i in range(n))))
        return dict(zip(names, [ang, *(float(v) for v in value)], strict=True))


class Inertia(Distribution):
    """Principal second moments of the mass ``s_i = (tr I)/2 - I_i`` (>= 0 for a physical body)
    scaled by ``exp(moment_std z_i)`` (log-normal: they stay > 0), principal axes rotated by
    ``axes_sigma_deg`` as for ``rotation``; then ``I_i = tr(S) - s_i``.  Every draw is symmetric
    positive definite and obeys the triangle inequality by construction (``I_1 + I_2 = I_3 + 2 s_3
    >= I_3``)."""

    name = "inertia"
    params = (Param("moment_std", ">= 0, the log-normal spread of the principal second moments"),
              Param("axes_sigma_deg", ">= 0 deg, the 1-sigma rotation of the principal axes"))
    value_doc = ("principal second moments s_i = tr(I)/2 - I_i scaled by exp(moment_std z_i), principal axes "
                 "rotated: symmetric positive definite and obeying the triangle inequality for every draw")

    def check(self, d: Dispersion) -> Any:
        I0 = np.array(d.nominal, float)
        if I0.shape != (3, 3):
            raise DispersionError("dist", f"dist = \"{self.name}\" disperses a 3x3 inertia; {d.key} is {d.nominal!r}")
        mstd = d.vector("moment_std", d.params.get("moment_std", 0.0), lo=0.0, size=3)
        asig = d.vector("axes_sigma_deg", d.params.get("axes_sigma_deg", 0.0), lo=0.0, size=3)
        d.size = 9
        lam, V = np.linalg.eigh(0.5 * (I0 + I0.T))
        s = 0.5 * lam.sum() - lam  # second moments of the mass along the principal axes
        if np.any(s < -1e-9 * lam.max()):
            raise DispersionError("dist", f"the nominal {d.key} is not a physical inertia (triangle inequality)")
        return np.maximum(s, 0.0), V, mstd, asig * DEG

    def dims(self, d: Dispersion) -> int:
        return 6

    def value(self, d: Dispersion, u: np.ndarray) -> Any:
        s, V, mstd, asig = d.frozen
        u = np.asarray(u, float)
        s_new = s * np.exp(mstd * special.ndtri(u[:3]))
        lam = s_new.sum() - s_new
        R = dcm_from_quat(_rotvec_quat(asig * special.ndtri(u[3:6])))
        W = R @ V
        I = W @ np.diag(lam) @ W.T
        I = 0.5 * (I + I.T)  # symmetric to the last bit
        return [[float(x) for x in row] for row in I]

    def columns(self, d: Dispersion, value: Any) -> dict[str, Any]:
        """The upper triangle, ``draw.<key>[i][j]``."""
        names = d.column_names((self.name,), lambda base: tuple(f"{base}[{i}][{j}]" for i in range(3)
                                                                for j in range(i, 3)))
        return dict(zip(names, [float(value[i][j]) for i in range(3) for j in range(i, 3)], strict=True))


#: What ``mode`` may be for a scipy.stats distribution (the first is the default), and what it does.
SCIPY_MODES = {"value": "the draw is the value; the default", "offset": "added to the nominal",
               "scale": "multiplies the nominal"}


class ScipyDistribution(Distribution):
    """Any ``scipy.stats`` continuous distribution, by ``name`` (one object per name)."""

    params = (Param("shapes", "`{ <name> = value }`, the distribution's own shape parameters, checked against "
                              "its `shapes`"),
              Param("loc", "default 0"), Param("scale", "> 0, default 1"),
              Param("mode", ", ".join(f'`"{m}"` ({what})' for m, what in SCIPY_MODES.items())))
    value_doc = "its inverse CDF; the name is looked up in scipy's list of continuous distributions, never evaluated"
    #: How the reference names the family.
    doc_name = "any `scipy.stats` continuous distribution by name (`lognorm`, `weibull_min`, `truncnorm`, ...)"

    def __init__(self, name: str):
        self.name = name

    def check(self, d: Dispersion) -> Any:
        dist = getattr(stats, self.name)
        names = [n.strip() for n in (dist.shapes or "").split(",") if n.strip()]
        shapes = d.params.get("shapes", {})
        if not isinstance(shapes, dict):
            raise DispersionError("shapes", f"must be a table of the shape parameters ({', '.join(names) or 'none'})")
        extra = sorted(set(shapes) - set(names))
        if extra:
            raise DispersionError(f"shapes.{extra[0]}", f"unknown shape parameter of {self.name}; its shapes: "
                                                        f"{', '.join(names) or 'none'}")
        missing = [n for n in names if n not in shapes]
        if missing:
            raise DispersionError(f"shapes.{missing[0]}", f"{self.name} needs its shape parameters "
                                                          f"{', '.join(names)}")
        for n in names:
            if not _number(shapes[n]):
                raise DispersionError(f"shapes.{n}", "must be a finite number")
        loc = d.params.get("loc", 0.0)
        scale = d.params.get("scale", 1.0)
        if not _number(loc):
            raise DispersionError("loc", "must be a finite number")
        if not _number(scale) or not scale > 0:
            raise DispersionError("scale", "must be a finite number > 0")
        modes = list(SCIPY_MODES)
        mode = d.params.get("mode", modes[0])
        if mode not in modes:
            raise DispersionError("mode", "must be " + ", ".join(f'"{m}"' for m in modes[:-1]) + f' or "{modes[-1]}"')
        frozen = dist(*[float(shapes[n]) for n in names], loc=float(loc), scale=float(scale))
        probe = frozen.ppf(np.array([1e-6, 0.5, 1 - 1e-6]))
        if not np.all(np.isfinite(probe[1:2])) or np.any(np.isnan(probe)):
            raise DispersionError("shapes", f"these parameters are outside the domain of {self.name} "
                                            f"(its median is {probe[1]})")
        nominal = None if mode == modes[0] else d.nominal_array() * np.ones(d.size)
        return frozen, mode, nominal

    def value(self, d: Dispersion, u: np.ndarray) -> Any:
        frozen, mode, nominal = d.frozen
        x = np.asarray(frozen.ppf(np.asarray(u, float)[: d.size]), float)
        if mode == "offset":
            x = nominal + x
        elif mode == "scale":
            x = nominal * x
        return d.shape(x)


#: rpo's own distributions by name, in the order the messages and the docs list them.
DISTRIBUTIONS: dict[str, Distribution] = {k.name: k for k in (Normal(), Uniform(), Choice(), Rotation(), Inertia())}


def distribution(name: str) -> Distribution:
    """The distribution ``dist = name`` names: rpo's own, else a scipy.stats continuous distribution
    (:class:`DispersionError` for any other name, naming the close ones)."""
    own = DISTRIBUTIONS.get(name)
    if own is not None:
        return own
    if name in continuous_names():
        return ScipyDistribution(name)
    close = [n for n in (*DISTRIBUTIONS, *continuous_names()) if n.startswith(name[:3])][:6]
    raise DispersionError("dist", f"unknown distribution {name!r}; allowed: {', '.join(DISTRIBUTIONS)} or "
                                  f"a scipy.stats continuous distribution by name"
                                  + (f" (close: {', '.join(close)})" if close else ""))


def reference_table() -> str:
    """The table of the distributions in ``docs/campaigns.md`` (Markdown)."""
    def row(name: str, k: Distribution) -> str:
        params = "; ".join(f"`{p.name}`: {p.meaning}" for p in k.params)
        return f"| {name} | {params} | {k.value_doc} |"

    return "\n".join(["| `dist` | parameters | value |", "| --- | --- | --- |",
                      *(row(f"`{k.name}`", k) for k in DISTRIBUTIONS.values()),
                      row(ScipyDistribution.doc_name, ScipyDistribution(""))]) + "\n"


# --------------------------------------------------------------------------- one dispersed key


@dataclass
class Dispersion:
    """One dispersed key: its distribution ``dist`` with parameters ``params`` (as written), the
    ``nominal`` value (the scenario's, in the key's unit), ``size`` (components; 1 for a scalar).
    What the distribution does is :attr:`kind`'s (:func:`distribution`)."""

    key: str
    dist: str
    params: dict[str, Any]
    nominal: Any
    unit: str = ""
    size: int = 1
    kind: Distribution = field(init=False, repr=False, compare=False)
    frozen: Any = field(default=None, init=False, repr=False, compare=False)
    _names: dict[tuple, tuple[str, ...]] = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self) -> None:
        self.kind = distribution(self.dist)
        extra = sorted(set(self.params) - self.kind.allowed)
        if extra:
            raise DispersionError(extra[0], f"unknown parameter for dist = {self.dist!r}; allowed: "
                                            f"{', '.join(sorted(self.kind.allowed))}")
        self.frozen = self.kind.check(self)

    # -- what the checks read ----------------------------------------------------------------

    def vector(self, name: str, value: Any, lo: float | None = None, lo_open: bool = False,
               size: int | None = None) -> np.ndarray:
        """A parameter broadcast to ``size`` components (default: the key's), finite, >= lo (or > lo)."""
        n = self.size if size is None else size
        items = value if isinstance(value, list) else [value]
        if not items or not all(_number(x) for x in items) or len(items) not in (1, n):
            want = "a finite number" + (f" or an array of {n}" if n > 1 else "")
            raise DispersionError(name, f"must be {want}")
        arr = np.broadcast_to(np.array(items, float), (n,)).copy()
        if lo is not None and (np.any(arr <= lo) if lo_open else np.any(arr < lo)):
            raise DispersionError(name, f"must be {'>' if lo_open else '>='} {lo:g}" + (f" {self.unit}" if self.unit
                                                                                           else ""))
        return arr

    def nominal_array(self) -> np.ndarray:
        items = self.nominal if isinstance(self.nominal, list) else [self.nominal]
        if not all(_number(x) for x in items):
            raise DispersionError("dist", f"dist = {self.dist!r} needs a numeric value at {self.key} "
                                          f"(nominal {self.nominal!r})")
        return np.array(items, float)

    # -- sampling ----------------------------------------------------------------------------

    @property
    def dims(self) -> int:
        """Uniforms consumed per draw."""
        return self.kind.dims(self)

    def value(self, u: np.ndarray) -> Any:
        """The value for one draw's uniforms ``u`` (shape (dims,), in (0, 1)), as a scenario holds it."""
        return self.kind.value(self, u)

    def values(self, us: Sequence[np.ndarray]) -> list[Any]:
        """:meth:`value` of each draw's uniforms in ``us`` (the same values; some distributions map
        all the draws at once)."""
        return self.kind.values(self, us)

    def shape(self, arr: np.ndarray) -> Any:
        """A drawn array as the key holds it: a list, or a number for a scalar key."""
        vals = np.asarray(arr, float).tolist()  # Python floats of the same values
        return vals if isinstance(self.nominal, list) else vals[0]

    # -- summary columns ---------------------------------------------------------------------

    def columns(self, value: Any) -> dict[str, Any]:
        """The summary's columns of one drawn value: ``draw.<key>`` (a scalar or a choice),
        ``draw.<key>[i]`` (components), ``draw.<key>[i][j]`` (an inertia's upper triangle) and, for a
        rotation, ``draw.<key>.angle_deg`` (its angle from the nominal attitude)."""
        return self.kind.columns(self, value)

    def column_names(self, form: tuple, make: Callable[[str], tuple[str, ...]]) -> tuple[str, ...]:
        """The names of :meth:`columns` for a value of ``form`` (its distribution's tag and shape):
        ``make("draw.<key>")``, made once (a campaign asks for every run)."""
        names = self._names.get(form)
        if names is None:
            names = self._names[form] = make(f"draw.{self.key}")
        return names


def _rotvec_quat(phi: np.ndarray) -> np.ndarray:
    """The unit quaternion [x, y, z, w] of the rotation vector ``phi`` [rad] (angle |phi| about
    phi / |phi|; scipy's Rotation.from_rotvec)."""
    a = math.sqrt(float(phi @ phi))
    s = 0.5 - a * a / 48.0 if a < 1e-4 else math.sin(0.5 * a) / a  # sin(a/2)/a, its series near 0
    return np.append(s * phi, math.cos(0.5 * a))


def _truncated_normal_ppf(u: float, a: float, b: float) -> float:
    """The inverse CDF of the standard normal truncated to [a, b] at ``u``: ``Phi^-1(Phi(a) + u
    (Phi(b) - Phi(a)))``, taken in the lower tail (reflected when a > 0) where Phi keeps its relative
    precision; scipy.stats.truncnorm.ppf gives the same values to ~1e-15 at a hundred times the
    cost (tests/test_campaign.py)."""
    if a > 0:  # both bounds in the upper tail: reflect
        return -_truncated_normal_ppf(1.0 - u, -b, -a)
    pa, pb = float(special.ndtr(a)), float(special.ndtr(b))
    return float(special.ndtri(pa + u * (pb - pa)))


def _cell(v: Any) -> Any:
    if isinstance(v, bool):
        return float(v)
    if isinstance(v, (int, float)):
        return float(v)
    return str(v)
