"""Shared fixtures: the compiled model and the SymPy sources it was generated from."""

from __future__ import annotations

import functools
import os
from pathlib import Path

import numpy as np
import pytest

# the certificates are data of the checkout (docs/), not of the package: an installed copy finds them here
os.environ.setdefault("RPO_CERTIFICATES", str(Path(__file__).resolve().parents[1] / "docs" / "certificates"))

from rpo.runtime import load_model
from rpo.runtime.scenario import paper_data

DEG = np.pi / 180
#: 000 scenario III, read from its scenario file (the one place a paper's data is typed)
SCENARIO_III = paper_data("000_scenario_III")
#: the initial chaser and target quaternions of scenario III, used as generic attitudes
Q_C0_III = np.array(SCENARIO_III["chaser"]["quaternion"], float)
Q_T0_III = np.array(SCENARIO_III["target"]["quaternion"], float)


@pytest.fixture(scope="session")
def model():
    return load_model()


@functools.cache
def _sources():
    from rpo.symbolic.codegen import functions

    return functions.sources()


@pytest.fixture(scope="session")
def sources():
    """(pieces, ctx): SymPy pieces by generated-function name; ctx has the plant and controllers."""
    return _sources()


@functools.cache
def _lambdified(name):
    from rpo.symbolic.codegen.numpy_reference import lambdified

    return lambdified(_sources()[0][name])


@pytest.fixture(scope="session")
def numpy_piece():
    """numpy_piece(name) -> NumPy callable of the SymPy source of generated function ``name``."""
    return _lambdified


def unit(q):
    q = np.asarray(q, float)
    return q / np.linalg.norm(q)


def quiet_params(**over):
    """Plant parameters with every disturbance off (for the independent-reference checks)."""
    base = dict(gg_on=0, mag_on=0, j2_on=0, drag_on=0, mass_profile_on=0, chaser_rand_std=0, target_rand_std=0)
    base.update(over)
    return base


ZERO_GAINS = dict(kp_att=0, kd_att=0, kp_pos=0, kd_pos=0)


def target_state(model, p=None) -> dict:
    """r_T, v_T [m, m/s, ECI]: the target's state on the Keplerian orbit of the parameters ``p``
    (a packed vector, a dict of overrides, or None for the defaults) at t = 0: the plant's
    propagated-orbit states, for tests that pack a plant state by hand."""
    pv = model.vector("p", p or {}) if p is None or isinstance(p, dict) else np.asarray(p, float)
    o = model.functions["target_orbit"](0.0, pv)
    return {"r_T": np.ravel(o[5]).copy(), "v_T": np.ravel(o[6]).copy()}
