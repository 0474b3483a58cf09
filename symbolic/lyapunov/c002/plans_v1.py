"""002: proof plans of the model, V1 and gain claims (certified domains; see ``symbolic/lyapunov/certify``)."""

from __future__ import annotations

PLANS: dict = {}
