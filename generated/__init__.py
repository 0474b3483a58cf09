"""rpo.generated: C sources and manifest written by ``python build.py`` (package marker, not generated)."""
