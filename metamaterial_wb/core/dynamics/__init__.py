"""Soft-robot dynamics: planar rigid nodes + elastic hinges + floor contact (see docs/dynamics.md)."""
from .system import DynamicsError, PlanarSystem  # noqa: F401
from .integrators import Simulator  # noqa: F401
