"""Dispersions: the distribution of one scenario value, as a map from uniforms to values.

Every distribution consumes ``dims`` uniforms in (0, 1) per run and turns them into a value by
inverse CDFs (``ppf``), so that pseudo-random, Latin-hypercube and Sobol designs
(:mod:`.sampling`) all feed the same code.  A value is what a scenario file would hold at the
key: a number, an array, a string (a choice), a quaternion ``[x, y, z, w]`` or a 3x3 inertia, in
the key's own unit (``inclination_deg`` in deg, ``relative.position`` in m).

Kinds (``dist = ...`` in ``[dispersions.<key>]``; parameters broadcast over the components of an
array-valued key, each component drawn independently):

``normal``
    ``std`` (>= 0; or ``rel_std``, a fraction of |nominal|), ``mean`` (default: the nominal
    value); optional truncation ``low`` / ``high`` (absolute values, by inverse CDF of the
    truncated normal: never clipped).
``uniform``
    ``low`` and ``high``, or ``half_width`` (or ``rel_half_width``) around the nominal value.
``choice``
    ``values`` (the candidates, each a value of the key), optional ``weights`` (>= 0).
``rotation``
    an attitude (a quaternion key): ``q = q_nominal (x) dq`` with ``dq`` the rotation by the vector
    ``phi`` ~ N(0, sigma^2 I_3), ``sigma_deg`` the 1-sigma angle per body axis (Hamilton product,
    the perturbation in the body axes; docs/conventions.md).  Its column ``<key>.angle_deg`` is
    ``|phi|``.
``inertia``
    a 3x3 inertia key: principal second moments of the mass ``s_i = (tr I)/2 - I_i`` (>= 0 for
    a physical body) scaled by ``exp(moment_std z_i)`` (log-normal: they stay > 0), principal axes
    rotated by ``axes_sigma_deg`` as for ``rotation``; then ``I_i = tr(S) - s_i``.  Every draw is
    symmetric positive definite and obeys the triangle inequality by construction (``I_1 + I_2 =
    I_3 + 2 s_3 >= I_3``).
any ``scipy.stats`` continuous distribution by name (``lognorm``, ``weibull_min``, ...)
    ``shapes = { <name> = value }`` (the distribution's own shape parameters, checked against
    its ``shapes``), ``loc``, ``scale`` (> 0), ``mode = "value"`` (the draw is the value),
    ``"offset"`` (added to the nominal) or ``"scale"`` (multiplies it).  The name is looked up in
    ``scipy.stats``' list of continuous distributions, never evaluated.

A distribution whose parameters are wrong (a negative spread, a truncation holding no
probability, an unknown shape name) is refused when the campaign is read, with one line naming
the key (:class:`DispersionError`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import special, stats

from rpo.runtime.frames import dcm_from_quat, quat_conjugate, quat_multiply, rotation_angle

DEG = math.pi / 180.0
#: Smallest probability a truncation may keep: below it the draws would all sit at a bound to
#: rounding, which is a typo, not a distribution.
MIN_TRUNCATED_MASS = 1e-9
OWN_KINDS = ("normal", "uniform", "choice", "rotation", "inertia")


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


@dataclass
class Dispersion:
    """One dispersed key: its distribution ``dist`` with parameters ``params`` (as written), the
    ``nominal`` value (the scenario's, in the key's unit), ``size`` (components; 1 for a scalar)."""

    key: str
    dist: str
    params: dict[str, Any]
    nominal: Any
    unit: str = ""
    size: int = 1
    _frozen: Any = field(default=None, repr=False)
    _aux: Any = field(default=None, repr=False, compare=False)
    _names: dict[tuple, tuple[str, ...]] = field(default_factory=dict, repr=False, compare=False)

    # -- checks ------------------------------------------------------------------------------

    def __post_init__(self) -> None:
        check = getattr(self, f"_check_{self.dist}", None)
        if check is not None:
            check()
        elif self.dist in continuous_names():
            self._check_scipy()
        else:
            close = [n for n in (*OWN_KINDS, *continuous_names()) if n.startswith(self.dist[:3])][:6]
            raise DispersionError("dist", f"unknown distribution {self.dist!r}; allowed: {', '.join(OWN_KINDS)} or "
                                          f"a scipy.stats continuous distribution by name"
                                          + (f" (close: {', '.join(close)})" if close else ""))

    def _allowed(self, names: set[str]) -> None:
        extra = sorted(set(self.params) - names)
        if extra:
            raise DispersionError(extra[0], f"unknown parameter for dist = {self.dist!r}; allowed: "
                                            f"{', '.join(sorted(names))}")

    def _vector(self, name: str, value: Any, lo: float | None = None, lo_open: bool = False) -> np.ndarray:
        """A parameter broadcast to the key's components, finite, >= lo (or > lo)."""
        items = value if isinstance(value, list) else [value]
        if not items or not all(_number(x) for x in items) or len(items) not in (1, self.size):
            want = "a finite number" + (f" or an array of {self.size}" if self.size > 1 else "")
            raise DispersionError(name, f"must be {want}")
        arr = np.broadcast_to(np.array(items, float), (self.size,)).copy()
        if lo is not None and (np.any(arr <= lo) if lo_open else np.any(arr < lo)):
            raise DispersionError(name, f"must be {'>' if lo_open else '>='} {lo:g}" + (f" {self.unit}" if self.unit
                                                                                           else ""))
        return arr

    def _nominal_array(self) -> np.ndarray:
        items = self.nominal if isinstance(self.nominal, list) else [self.nominal]
        if not all(_number(x) for x in items):
            raise DispersionError("dist", f"dist = {self.dist!r} needs a numeric value at {self.key} "
                                          f"(nominal {self.nominal!r})")
        return np.array(items, float)

    def _check_normal(self) -> None:
        self._allowed({"dist", "mean", "std", "rel_std", "low", "high"})
        if ("std" in self.params) == ("rel_std" in self.params):
            raise DispersionError("std", "give either std or rel_std (a fraction of the nominal)")
        if "mean" in self.params:
            mean = self._vector("mean", self.params["mean"])
        else:
            mean = self._nominal_array() * np.ones(self.size)
        if "std" in self.params:
            std = self._vector("std", self.params["std"], lo=0.0)
        else:
            std = self._vector("rel_std", self.params["rel_std"], lo=0.0) * np.abs(self._nominal_array())
        lo = self._vector("low", self.params["low"]) if "low" in self.params else np.full(self.size, -np.inf)
        hi = self._vector("high", self.params["high"]) if "high" in self.params else np.full(self.size, np.inf)
        for i in range(self.size):
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
        self._frozen = (mean, std, lo, hi)

    def _check_uniform(self) -> None:
        self._allowed({"dist", "low", "high", "half_width", "rel_half_width"})
        given = [k for k in ("half_width", "rel_half_width") if k in self.params]
        if given and ("low" in self.params or "high" in self.params) or len(given) > 1:
            raise DispersionError(given[-1], "give low and high, or one of half_width / rel_half_width")
        if given:
            nom = self._nominal_array() * np.ones(self.size)
            w = self._vector(given[0], self.params[given[0]], lo=0.0)
            w = w * np.abs(nom) if given[0] == "rel_half_width" else w
            lo, hi = nom - w, nom + w
        else:
            if "low" not in self.params or "high" not in self.params:
                raise DispersionError("low", "dist = \"uniform\" needs low and high, or half_width")
            lo, hi = self._vector("low", self.params["low"]), self._vector("high", self.params["high"])
        if np.any(lo > hi):
            i = int(np.argmax(lo > hi))
            raise DispersionError("low", f"low = {lo[i]:g} must be <= high = {hi[i]:g}")
        self._frozen = (lo, hi)

    def _check_choice(self) -> None:
        self._allowed({"dist", "values", "weights"})
        values = self.params.get("values")
        if not isinstance(values, list) or not values:
            raise DispersionError("values", "must be a non-empty array of the candidate values")
        w = self.params.get("weights")
        if w is None:
            weights = np.full(len(values), 1.0 / len(values))
        else:
            if not isinstance(w, list) or len(w) != len(values) or not all(_number(x) and x >= 0 for x in w) \
                    or not sum(w) > 0:
                raise DispersionError("weights", f"must be {len(values)} numbers >= 0 (one per value), not all 0")
            weights = np.array(w, float) / float(sum(w))
        self._frozen = (values, np.cumsum(weights))

    def _check_rotation(self) -> None:
        self._allowed({"dist", "sigma_deg"})
        q = self.nominal
        if not (isinstance(q, list) and len(q) == 4 and all(_number(x) for x in q)):
            raise DispersionError("dist", f"dist = \"rotation\" disperses a quaternion [x, y, z, w]; {self.key} is "
                                          f"{q!r}")
        self.size = 3
        sigma = self._vector("sigma_deg", self.params.get("sigma_deg"), lo=0.0)
        self.size = 4
        q0 = np.array(q, float)
        self._frozen = (q0 / np.linalg.norm(q0), sigma * DEG)

    def _check_inertia(self) -> None:
        self._allowed({"dist", "moment_std", "axes_sigma_deg"})
        I0 = np.array(self.nominal, float)
        if I0.shape != (3, 3):
            raise DispersionError("dist", f"dist = \"inertia\" disperses a 3x3 inertia; {self.key} is {self.nominal!r}")
        self.size = 3
        mstd = self._vector("moment_std", self.params.get("moment_std", 0.0), lo=0.0)
        asig = self._vector("axes_sigma_deg", self.params.get("axes_sigma_deg", 0.0), lo=0.0)
        self.size = 9
        lam, V = np.linalg.eigh(0.5 * (I0 + I0.T))
        s = 0.5 * lam.sum() - lam  # second moments of the mass along the principal axes
        if np.any(s < -1e-9 * lam.max()):
            raise DispersionError("dist", f"the nominal {self.key} is not a physical inertia (triangle inequality)")
        self._frozen = (np.maximum(s, 0.0), V, mstd, asig * DEG)

    def _check_scipy(self) -> None:
        self._allowed({"dist", "shapes", "loc", "scale", "mode"})
        dist = getattr(stats, self.dist)
        names = [n.strip() for n in (dist.shapes or "").split(",") if n.strip()]
        shapes = self.params.get("shapes", {})
        if not isinstance(shapes, dict):
            raise DispersionError("shapes", f"must be a table of the shape parameters ({', '.join(names) or 'none'})")
        extra = sorted(set(shapes) - set(names))
        if extra:
            raise DispersionError(f"shapes.{extra[0]}", f"unknown shape parameter of {self.dist}; its shapes: "
                                                        f"{', '.join(names) or 'none'}")
        missing = [n for n in names if n not in shapes]
        if missing:
            raise DispersionError(f"shapes.{missing[0]}", f"{self.dist} needs its shape parameters "
                                                          f"{', '.join(names)}")
        for n in names:
            if not _number(shapes[n]):
                raise DispersionError(f"shapes.{n}", "must be a finite number")
        loc = self.params.get("loc", 0.0)
        scale = self.params.get("scale", 1.0)
        if not _number(loc):
            raise DispersionError("loc", "must be a finite number")
        if not _number(scale) or not scale > 0:
            raise DispersionError("scale", "must be a finite number > 0")
        mode = self.params.get("mode", "value")
        if mode not in ("value", "offset", "scale"):
            raise DispersionError("mode", "must be \"value\", \"offset\" or \"scale\"")
        frozen = dist(*[float(shapes[n]) for n in names], loc=float(loc), scale=float(scale))
        probe = frozen.ppf(np.array([1e-6, 0.5, 1 - 1e-6]))
        if not np.all(np.isfinite(probe[1:2])) or np.any(np.isnan(probe)):
            raise DispersionError("shapes", f"these parameters are outside the domain of {self.dist} "
                                            f"(its median is {probe[1]})")
        nominal = None if mode == "value" else self._nominal_array() * np.ones(self.size)
        self._frozen = (frozen, mode, nominal)

    # -- sampling ----------------------------------------------------------------------------

    @property
    def dims(self) -> int:
        """Uniforms consumed per draw."""
        if self.dist == "choice":
            return 1
        if self.dist == "rotation":
            return 3
        if self.dist == "inertia":
            return 6
        return self.size

    def value(self, u: np.ndarray) -> Any:
        """The value for one draw's uniforms ``u`` (shape (dims,), in (0, 1)), as a scenario holds it."""
        u = np.asarray(u, float)
        if self.dist == "normal":
            mean, std, lo, hi = self._frozen
            truncated, zero = self._normal_parts()
            z = special.ndtri(u[: self.size])  # the normal ppf, without scipy.stats' overhead
            out = mean + std * z
            for i in truncated:
                if std[i] > 0:
                    x = mean[i] + std[i] * _truncated_normal_ppf(u[i], (lo[i] - mean[i]) / std[i],
                                                                 (hi[i] - mean[i]) / std[i])
                    out[i] = min(max(x, lo[i]), hi[i])  # the last ulp of rounding, not a clip of the draw
            if zero.any():
                out[zero] = mean[zero]
            return self._shape(out)
        if self.dist == "uniform":
            lo, hi = self._frozen
            return self._shape(lo + (hi - lo) * u[: self.size])
        if self.dist == "choice":
            values, cum = self._frozen
            pick = min(int(np.searchsorted(cum, u[0], side="right")), len(values) - 1)
            return values[pick]
        if self.dist == "rotation":
            q0, sigma = self._frozen
            phi = sigma * special.ndtri(u[:3])
            q = quat_multiply(q0, _rotvec_quat(phi))  # = (Rotation(q0) * Rotation.from_rotvec(phi)).as_quat()
            q = q / math.sqrt(float(q @ q))
            if float(np.dot(q, q0)) < 0:  # the same attitude, on the nominal's side (continuous draws)
                q = -q
            return [float(x) for x in q]
        if self.dist == "inertia":
            s, V, mstd, asig = self._frozen
            s_new = s * np.exp(mstd * special.ndtri(u[:3]))
            lam = s_new.sum() - s_new
            R = dcm_from_quat(_rotvec_quat(asig * special.ndtri(u[3:6])))
            W = R @ V
            I = W @ np.diag(lam) @ W.T
            I = 0.5 * (I + I.T)  # symmetric to the last bit
            return [[float(x) for x in row] for row in I]
        frozen, mode, nominal = self._frozen
        x = np.asarray(frozen.ppf(u[: self.size]), float)
        if mode == "offset":
            x = nominal + x
        elif mode == "scale":
            x = nominal * x
        return self._shape(x)

    def _normal_parts(self) -> tuple[list[int], np.ndarray]:
        """A normal's truncated components and its zero-spread mask (made once)."""
        if self._aux is None:
            _mean, std, lo, hi = self._frozen
            self._aux = ([int(i) for i in np.flatnonzero(np.isfinite(lo) | np.isfinite(hi))], std == 0.0)
        return self._aux

    def values(self, us: Sequence[np.ndarray]) -> list[Any]:
        """:meth:`value` of each draw's uniforms in ``us`` (the same values: the element-wise normal
        and uniform maps are applied to all the draws at once, the rest one draw at a time)."""
        if self.dist not in ("normal", "uniform") or len(us) < 2:
            return [self.value(u) for u in us]
        U = np.array([np.asarray(u, float)[: self.size] for u in us])
        if self.dist == "uniform":
            lo, hi = self._frozen
            return [self._shape(row) for row in lo + (hi - lo) * U]
        mean, std, _lo, _hi = self._frozen
        truncated, zero = self._normal_parts()
        if truncated:  # the truncated inverse CDF is scalar code: one draw at a time
            return [self.value(u) for u in us]
        out = mean + std * special.ndtri(U)
        if zero.any():
            out[:, zero] = mean[zero]
        return [self._shape(row) for row in out]

    def _shape(self, arr: np.ndarray) -> Any:
        vals = np.asarray(arr, float).tolist()  # Python floats of the same values
        return vals if isinstance(self.nominal, list) else vals[0]

    # -- summary columns ---------------------------------------------------------------------

    def columns(self, value: Any) -> dict[str, Any]:
        """The summary's columns of one drawn value: ``draw.<key>`` (a scalar or a choice),
        ``draw.<key>[i]`` (components), ``draw.<key>[i][j]`` (an inertia's upper triangle) and, for a
        rotation, ``draw.<key>.angle_deg`` (its angle from the nominal attitude)."""
        if self.dist == "rotation":
            q0 = self._frozen[0]
            q = np.array(value, float)
            ang = math.degrees(float(rotation_angle(quat_multiply(quat_conjugate(q0), q))))
            return dict(zip(self._column_names("rotation", len(value)), [ang, *(float(v) for v in value)],
                            strict=True))
        if self.dist == "inertia":
            return dict(zip(self._column_names("inertia"), [float(value[i][j]) for i in range(3) for j in range(i, 3)],
                            strict=True))
        if isinstance(value, list):
            if value and isinstance(value[0], list):
                return dict(zip(self._column_names("matrix", *(len(row) for row in value)),
                                [float(x) for row in value for x in row], strict=True))
            return dict(zip(self._column_names("vector", len(value)), [_cell(v) for v in value], strict=True))
        return {self._column_names("scalar")[0]: _cell(value)}

    def _column_names(self, form: str, *shape: int) -> tuple[str, ...]:
        """The names of :meth:`columns` for a value of ``form`` and ``shape`` (the length of a
        vector, of each row of a matrix), in its order: made once, a campaign asks for every run."""
        names = self._names.get((form, shape))
        if names is None:
            name = f"draw.{self.key}"
            if form == "rotation":
                names = (f"{name}.angle_deg", *(f"{name}[{i}]" for i in range(shape[0])))
            elif form == "inertia":
                names = tuple(f"{name}[{i}][{j}]" for i in range(3) for j in range(i, 3))
            elif form == "matrix":
                names = tuple(f"{name}[{i}][{j}]" for i, n in enumerate(shape) for j in range(n))
            elif form == "vector":
                names = tuple(f"{name}[{i}]" for i in range(shape[0]))
            else:
                names = (name,)
            self._names[(form, shape)] = names
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
