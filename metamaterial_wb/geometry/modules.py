"""Snap-fit modules (separate prints, ABS by default) placed on a node or a joint of the scene.

Placeholder: filled in below.
"""
from metamaterial_wb.core.errors import SceneError


def parse_modules(scene, p):
    mods = scene.modules or []
    if mods:
        raise SceneError("modules", "modules are not implemented yet")
    return []


def build_module(res, spec):
    raise NotImplementedError
