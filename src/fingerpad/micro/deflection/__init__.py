"""Compliant asperities under sliding: a finite-element deflection model and directional friction.

See :mod:`.gain` for the API (placeholder docstring, completed below)."""
