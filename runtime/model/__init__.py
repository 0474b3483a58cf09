"""Loading the generated model: its manifest, the toolchain, the object cache, the libraries, the functions."""

from rpo.runtime.model.loader import Model, load_model

__all__ = ["Model", "load_model"]
