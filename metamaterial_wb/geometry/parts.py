"""What a build produces: placed parts and the result that holds their unique shapes (no FreeCAD
import here: geometry/build.py makes them, geometry/modules.py adds the modules' parts, the
exporters and document objects read them)."""
from collections import OrderedDict
from dataclasses import dataclass, field


@dataclass
class PlacedPart:
    name: str             # unique, used as the STEP body name and the 3MF object/volume name
    role: str             # "node", "hinge" or "module"
    material: str         # "PLA", "TPU", "ABS", ...
    extruder: int         # 1-based
    key: tuple            # key into BuildResult.shapes
    placement: object     # FreeCAD Placement
    group: str            # output file: "sheet" or a module's name
    info: dict = field(default_factory=dict)


def safe_stem(text):
    """The scene's name as the stem of its file names (``NAME_sheet.step``): letters, digits, ``-_.`` kept."""
    keep = "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in text)
    return keep.strip("._") or "scene"


class BuildResult:
    def __init__(self, scene, params):
        self.scene = scene
        self.params = params
        self.shapes = {}
        self.parts = []
        self.modules = []          # ModuleSpec list (geometry/modules.py)
        self.module_parts = {}     # module shape key -> names of its parts
        self.timings = {}

    def groups(self):
        out = OrderedDict()
        for part in self.parts:
            out.setdefault(part.group, []).append(part)
        return out

    def placed_shape(self, part, copy=False):
        shape = self.shapes[part.key]
        placed = shape.transformed(part.placement.toMatrix())
        return placed.copy() if copy else placed

    def by_name(self, name):
        for part in self.parts:
            if part.name == name:
                return part
        raise KeyError(name)

    def count(self, role=None, group=None):
        return sum(1 for p in self.parts if (role is None or p.role == role) and (group is None or p.group == group))
