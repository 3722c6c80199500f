"""Compatibility module: the document objects before the split of issue 14 lived here.

Documents saved before the split store their proxies as ``metamaterial_wb.objects.structure.SceneProxy``
(and ``NodeShapeProxy``, ``HingeShapeProxy``, ``ItemProxy``, ``ModuleProxy``), both in the pickled
``Proxy`` property and in the hidden ``ProxyClass`` property: FreeCAD imports this module and looks the
class up by that name, so these names must stay. New documents store the new module paths
(``objects/scene.py``, ``shapes.py``, ``item.py``, ``module.py``); saving an old document rewrites its
``Proxy`` entries to the new paths (FreeCAD stores the class's ``__module__``).

The helpers callers use (``make_structure``, ``compose_scene``, ``find_scene_objects``, ``apply_frame`` ...)
are re-exported too; new code imports them from their own module (see ``objects/make.py``).
"""
from metamaterial_wb.objects.display import (apply_frame, display_state, marker_placements, place_markers,  # noqa: F401
                                             restore_display, to_placements)
from metamaterial_wb.objects.item import PROFILE_SHAPES, ItemProxy, item_to_dict  # noqa: F401
from metamaterial_wb.objects.make import (container_of, load_scene_file, make_item, make_module,  # noqa: F401
                                          make_structure)
from metamaterial_wb.objects.module import (JOINT_MODULES, MODULE_ALIASES, MODULE_TYPES, PREFS_PATH,  # noqa: F401
                                            ModuleProxy, build_module_shape, fabrication_overrides,
                                            module_build_key, module_to_dict)
from metamaterial_wb.objects.scene import (SceneProxy, cells_from_rows, compose_scene, find_scene_objects,  # noqa: F401
                                           layout_rows, load_typed_properties, scene_json, scene_object_of,
                                           set_scene_fields, solver_for)
from metamaterial_wb.objects.shapes import HingeShapeProxy, NodeShapeProxy  # noqa: F401

# the proxy classes of documents saved before the split, by their stored name
LEGACY_PROXIES = {"SceneProxy": SceneProxy, "NodeShapeProxy": NodeShapeProxy, "HingeShapeProxy": HingeShapeProxy,
                  "ItemProxy": ItemProxy, "ModuleProxy": ModuleProxy}
