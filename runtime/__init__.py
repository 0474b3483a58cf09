"""rpo.runtime: load the generated model and simulate it (no SymPy, no code generation here)."""

from .compiled import Model, load_model
from .errors import ModelError, OutputError, RpoError, ScenarioError

__all__ = ["Model", "ModelError", "OutputError", "RpoError", "ScenarioError", "load_model"]
