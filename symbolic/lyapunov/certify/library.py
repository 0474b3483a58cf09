"""The library of proved lemmas: the only lemmas a certificate may use (see :mod:`.lemmas`), gathered from
the core module and the one reviewed module per controller."""

from __future__ import annotations

from . import lemmas_c000, lemmas_c001, lemmas_c002, lemmas_c004
from .lemmas import (
    ABS_PRODUCT,
    CAUCHY_SCHWARZ3,
    COSH_TANH,
    DOT_BALL3,
    LAYER,
    LDL2,
    LEMMA1_002,
    MIN_LE,
    NORM2_LE_NORM1,
    OUTSIDE_002,
    TANH_MONO,
    TRIANGLE3,
    YOUNG,
    Lemma,
)


def _library() -> dict[str, Lemma]:
    lems = (YOUNG, ABS_PRODUCT, CAUCHY_SCHWARZ3, NORM2_LE_NORM1, DOT_BALL3, LDL2, LAYER, LEMMA1_002, COSH_TANH,
            OUTSIDE_002, TRIANGLE3, TANH_MONO, MIN_LE, *lemmas_c000.LEMMAS, *lemmas_c001.LEMMAS,
            *lemmas_c002.LEMMAS, *lemmas_c004.LEMMAS)
    out: dict[str, Lemma] = {}
    for lem in lems:
        if lem.name in out:
            raise ValueError(f"two lemmas named {lem.name}")
        out[lem.name] = lem
    return out


LIBRARY: dict[str, Lemma] = _library()
