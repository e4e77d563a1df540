"""The one version source of fingerpad (pyproject.toml reads it)."""

__version__ = "0.2.0"
