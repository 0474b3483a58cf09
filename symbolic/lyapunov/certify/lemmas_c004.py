"""Lemmas written for the plans of controller c004 (reviewed like the rest of :mod:`.lemmas`).

Each is a small, general fact: its proof re-checks identities symbolically, its text names the textbook
step; a claim-sized lemma does not belong here.
"""

from __future__ import annotations

LEMMAS: tuple = ()
