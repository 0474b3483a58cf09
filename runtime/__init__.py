"""rpo.runtime: load the generated model and simulate it (no SymPy, no code generation here)."""

from rpo.runtime.errors import ModelError, OutputError, RpoError, ScenarioError
from rpo.runtime.model.loader import Model, load_model

__all__ = ["Model", "ModelError", "OutputError", "RpoError", "ScenarioError", "load_model"]
