"""Sleeve spec files (``"format": "metamaterial-sleeve"``), validation with clear errors.

See ``docs/scene-format.md`` section "Sleeve spec" for every field.
"""
import math

from metamaterial_wb.core.errors import SceneError, check_integer, check_number
from metamaterial_wb.core.scene.names import _short
from metamaterial_wb.core.sleeve.cell import CellGeometry
from metamaterial_wb.core.sleeve.model import pillar_tip_coefficient

FORMAT = "metamaterial-sleeve"

# Physical ranges (issue 19). Lower bounds: what an FDM printer resolves in TPU (one 0.4 mm extrusion for a
# wall, a beam, a pillar; a 0.2 mm gap, below which the two sides fuse). Upper bounds: the build volume
# of the bundled printer profile (export/profiles: a 330 x 240 mm bed, 300 mm high; the sleeve prints
# upright, so its outer diameter must fit the bed's short side), the elastic model (a neo-Hookean
# elastomer; stiffer than any printable polymer, G > 5 GPa, is not one) and the beam model's limits.
MIN_FEATURE_MM = 0.4
MIN_GAP_MM = 0.2
BED_MM = 240.0
CAP_RANGE_MM = (0.0, BED_MM)   # actuator.core_diameter_mm, open at 0 (and at most what an end ring holds: _check_cap)
MAX_HEIGHT_MM = 300.0
MAX_G_MPA = 5000.0
# the actuator's cap (the core the inner membrane pushes on), mm: the seed's; a sleeve narrower inside takes the
# widest cap its end rings hold instead. The PLA end pieces (geometry/sleeve.py): the cap sits in the opening of a
# ring glued inside each end of the sleeve, whose wall (the rest of the sleeve's inside) is at least one extrusion,
# and the bottom cap has a hole for the supply tube
DEFAULT_CAP_MM = 24.6
END_RING_MIN_WALL_MM = MIN_FEATURE_MM
TUBE_HOLE_MM = 4.0
MAX_L_MM = 200.0        # a beam span beyond most of the bed's short side (and 2 cells around: 130 mm across)
# The widest static range of each field, (low, high, unit, low_open): the one owner of these numbers (the
# validator below and the GUI's spin boxes read them). c, delta and T are also bounded by L, and a cell
# type's t and h by a fraction of L (CELL_TYPE_RANGES: low, fraction of L, low_open), checked in words.
RANGES = {"L_mm": (2.0, MAX_L_MM, "mm", False),
          "c_mm": (MIN_FEATURE_MM, 0.6 * MAX_L_MM, "mm", False),
          "delta_mm": (MIN_GAP_MM, MAX_L_MM, "mm", False),
          "T_mm": (MIN_FEATURE_MM, 2 * MAX_L_MM, "mm", False),
          "shear_modulus_MPa": (0.0, MAX_G_MPA, "MPa", True)}
CELL_TYPE_RANGES = {"t_mm": (MIN_FEATURE_MM, 0.25, False), "h_mm": (0.0, 0.6, True)}
RINGS_RANGE = (1, 12)


class SleeveSpec:
    def __init__(self, data, source="spec"):
        if not isinstance(data, dict):
            raise SceneError("", f"{source}: expected a JSON object")
        self.raw = data
        fmt = data.get("format")
        if fmt != FORMAT:
            raise SceneError("format", f"{fmt!r}; expected {FORMAT!r}")
        ver = data.get("version", 1)
        if isinstance(ver, bool) or ver != 1:          # True == 1 in Python: a boolean is no version
            raise SceneError("version", f"{ver!r}; supported: 1 (a number)")
        _known(data, "", "")          # after the format: a scene file given here is named as one
        name = data.get("name", "sleeve")
        if not isinstance(name, str) or len(name) > 200:
            raise SceneError("name", f"{str(name)[:40]!r}...; expected a string of at most 200 characters"
                             if isinstance(name, str) else f"{name!r}; expected a string")
        self.name = name
        num = lambda k, d, lo, hi, unit="mm", lo_open=False: check_number(  # noqa: E731
            k, data.get(k, d), lo, hi, unit, low_open=lo_open)
        lo = {k: r[0] for k, r in RANGES.items()}
        self.L = num("L_mm", 18.0, lo["L_mm"], RANGES["L_mm"][1])
        self.c = num("c_mm", 4.0, lo["c_mm"], 0.6 * self.L)
        self.delta = num("delta_mm", 0.5, lo["delta_mm"], self.L)
        self.T = num("T_mm", 1.8, lo["T_mm"], 2 * self.L)
        self.G = num("shear_modulus_MPa", 28.0, lo["shear_modulus_MPa"], RANGES["shear_modulus_MPa"][1], "MPa",
                     lo_open=True)
        self.layout = data.get("layout", "single")
        if self.layout not in ("single", "double"):
            raise SceneError("layout", f"{self.layout!r}; allowed: 'single' (one beam per cell, default), "
                                       "'double' (two parallel beams, the former reading)")
        types = data.get("cell_types")
        if not isinstance(types, list) or not types:
            raise SceneError("cell_types", "expected a non-empty list of {\"t_mm\": ..., \"h_mm\": ...}")
        self.cells = []
        for i, ct in enumerate(types):
            f = f"cell_types[{i}]"
            if not isinstance(ct, dict):
                raise SceneError(f, f"expected an object, got {ct!r}")
            _known(ct, f, "cell_types")
            for k in ("t_mm", "h_mm"):
                if k not in ct:
                    raise SceneError(f"{f}.{k}", "missing")
            (tlo, tfr, topen), (hlo, hfr, hopen) = CELL_TYPE_RANGES["t_mm"], CELL_TYPE_RANGES["h_mm"]
            t = check_number(f"{f}.t_mm", ct["t_mm"], tlo, tfr * self.L, "mm", low_open=topen)
            h = check_number(f"{f}.h_mm", ct["h_mm"], hlo, hfr * self.L, "mm", low_open=hopen)
            self.cells.append(CellGeometry.checked(f, L=self.L, t=t, h=h, c=self.c, delta=self.delta, T=self.T,
                                                   layout=self.layout))
        if "pattern" in data:
            both = [k for k in ("ring", "rings") if k in data]
            if both:
                raise SceneError("pattern", f"with {' / '.join(both)}; give one of them (pattern: every ring's cells; "
                                            f"ring and rings: one ring repeated)")
            pat = data["pattern"]
            if not isinstance(pat, list) or not pat or not all(isinstance(r, list) for r in pat):
                raise SceneError("pattern", "expected a list of rings, each a list of cell type indices")
        else:
            ring = data.get("ring")
            if not isinstance(ring, list):
                raise SceneError("ring", "expected a list of cell type indices around the circumference, e.g. [0, 0, 1, 1]")
            rings = data.get("rings", 1)
            check_integer("rings", rings, *RINGS_RANGE)
            pat = [list(ring) for _ in range(rings)]
        n = len(pat[0])
        for r, row in enumerate(pat):
            f = "ring" if "pattern" not in data else f"pattern[{r}]"
            if len(row) != n:
                raise SceneError(f, f"has {len(row)} cells; every ring needs the same number ({n})")
            if not 2 <= n <= 32:
                raise SceneError(f, f"{n} cells around; allowed range [2, 32]")
            for k, v in enumerate(row):
                check_integer(f"{f}[{k}]", v, 0, len(self.cells) - 1, "a cell type index")
        self.pattern = pat
        m = data.get("model", {})
        if not isinstance(m, dict):
            raise SceneError("model", "expected an object")
        _known(m, "model", "model")
        self.n_el_cell = _integer("model.elements_cell", m.get("elements_cell", 16), 2, 80)
        self.n_el_ring = _integer("model.elements_ring", m.get("elements_ring", 24), 2, 80)
        self.steps = _integer("model.steps", m.get("steps", 160), 20, 2000)
        self.plane = m.get("plane", "strain")
        if self.plane not in ("strain", "stress"):
            raise SceneError("model.plane", f"{self.plane!r}; allowed: 'strain', 'stress'")
        self.imperfection = check_number("model.imperfection", m.get("imperfection", 1e-4), 0, 0.1, "")
        tip = m.get("pillar_tip", "guided")
        coef = pillar_tip_coefficient(tip)             # checks it: "guided", "free" or a number in [3, 12]
        self.pillar_tip = tip if isinstance(tip, str) else coef
        curv = m.get("ring_curvature", True)
        if not isinstance(curv, bool):
            raise SceneError("model.ring_curvature", f"{curv!r}; expected true or false")
        self.ring_curvature = curv
        fnl = m.get("frame_nonlinear", False)
        if not isinstance(fnl, bool):
            raise SceneError("model.frame_nonlinear", f"{fnl!r}; expected true or false")
        if fnl and not (curv and self.layout == "single"):
            raise SceneError("model.frame_nonlinear", "true needs the curved ring of the single layout "
                                                      "(model.ring_curvature true, layout 'single')")
        self.frame_nonlinear = fnl
        self.frame_elements = _integer("model.frame_elements", m.get("frame_elements", 12), 2, 48)
        # root flexibility (units of t): 0 as documented; model.ROOT_EXTENSION_FE (0.63) is the value fitted on CalculiX
        self.root_extension = check_number("model.root_extension", m.get("root_extension", 0.0), 0.0, 2.0, " (units of t)")
        dm = m.get("max_displacement_mm")
        self.d_max_mm = None if dm is None else check_number("model.max_displacement_mm", dm, 0, 10 * self.L, "mm", low_open=True)
        a = data.get("actuator", {})
        if not isinstance(a, dict):
            raise SceneError("actuator", "expected an object")
        _known(a, "actuator", "actuator")
        self.core_diameter = (None if "core_diameter_mm" not in a else      # absent: the default (_check_cap)
                              check_number("actuator.core_diameter_mm", a["core_diameter_mm"], *CAP_RANGE_MM, "mm",
                                           low_open=True))
        self.core_diameter_note = ""          # why the cap is not the one given or the default (set below)
        self.membrane = check_number("actuator.membrane_kPa_per_mL", a.get("membrane_kPa_per_mL", 0.0), 0, 1e4, "kPa/mL")
        dmap = _section(data, "design_map")
        self.design_map = None
        if dmap is not None:
            _known(dmap, "design_map", "design_map")
            if not isinstance(dmap.get("ring", False), bool):
                raise SceneError("design_map.ring", f"{dmap['ring']!r}; expected true or false")
            self.design_map = {
                "t_over_L": _range3("design_map.t_over_L", dmap.get("t_over_L", [0.045, 0.072, 5]), 0, 0.25),
                "h_over_L": _range3("design_map.h_over_L", dmap.get("h_over_L", [0.30, 0.42, 5]), 0, 0.6),
                "ring": dmap.get("ring", False),
                "elements": _integer("design_map.elements", dmap.get("elements", 10), 2, 80)}
        w = _section(data, "walker")
        self.walker = None
        if w is not None:
            _known(w, "walker", "walker")
            self.walker = {
                "foot_length_mm": check_number("walker.foot_length_mm", w.get("foot_length_mm", 20.0), 0, MAX_HEIGHT_MM, "mm"),
                "contact_band_mm": check_number("walker.contact_band_mm", w.get("contact_band_mm", 1.0), 0, 100, "mm",
                                                low_open=True)}
            if "body_length_mm" in w:
                # accepted so that older specs load (examples/walker.json), checked, never used: the walker model
                # (one leg's tip loop and the diagonal gait, core/sleeve/walker.py) has no place for the body;
                # the summary's walker notes say so
                self.walker["body_length_mm"] = check_number("walker.body_length_mm", w["body_length_mm"], 0, 1000,
                                                             "mm", low_open=True)
        self._check_printable()
        self._check_cap()

    def _check_printable(self):
        """The whole sleeve: a tube (wall thinner than its diameter) that fits the printer."""
        height = self.M * max(g.height for g in self.cells)
        if self.T >= 2 * self.radius_mm:
            raise SceneError("T_mm", f"{self.T!r} mm is at least the diameter {2 * self.radius_mm:.4g} mm of a "
                                     f"{self.N}-cell ring; allowed: below it")
        outer = 2 * self.radius_mm + self.T
        if outer > BED_MM:
            raise SceneError("ring", f"{self.N} cells of L + c = {self.L + self.c:g} mm make a sleeve of outer diameter "
                                     f"{outer:.4g} mm; allowed: at most {BED_MM:g} mm (the printer bed's short side)")
        if height > MAX_HEIGHT_MM:
            raise SceneError("rings", f"{self.M} ring(s) of {height / self.M:.4g} mm make a sleeve {height:.4g} mm high; "
                                      f"allowed: at most {MAX_HEIGHT_MM:g} mm (the printer's build height)")

    @property
    def inner_diameter_mm(self):
        """The sleeve's inner diameter, 2 R - T (R: the wall's mid radius): the room for the cap and end pieces."""
        return 2 * self.radius_mm - self.T

    def _inner_words(self):
        return (f"the sleeve's inner diameter N (L + c) / pi - T = {self.N} x {self.L + self.c:g} mm / pi - "
                f"{self.T:g} mm = {self.inner_diameter_mm:.6g} mm (ring, L_mm, c_mm, T_mm)")

    @property
    def cap_max_mm(self):
        """The widest cap an end ring holds: the inner diameter less two ring walls of ``END_RING_MIN_WALL_MM``."""
        return self.inner_diameter_mm - 2 * END_RING_MIN_WALL_MM

    def _ring_words(self):
        return (f"the cap sits in the opening of the PLA end ring, a wall of at least {END_RING_MIN_WALL_MM:g} mm "
                f"inside {self._inner_words()}")

    def _check_cap(self):
        """The cap the membrane pushes on sits in the opening of the end ring glued inside the sleeve (seed SI S1.1,
        ``geometry/sleeve.py``): its diameter at most ``cap_max_mm``. The default (``DEFAULT_CAP_MM``) follows a
        smaller sleeve's widest cap, and ``core_diameter_note`` says so; a value given is never changed."""
        top = self.cap_max_mm
        if top <= 0:
            raise SceneError("ring", f"{self._inner_words()} leaves no room for the actuator's cap inside its end rings "
                                     f"({END_RING_MIN_WALL_MM:g} mm walls); allowed: an inner diameter above "
                                     f"{2 * END_RING_MIN_WALL_MM:g} mm (more cells, larger L_mm or c_mm, a thinner T_mm)")
        if self.core_diameter is None:
            self.core_diameter = DEFAULT_CAP_MM
            if DEFAULT_CAP_MM > top:
                self.core_diameter = top
                self.core_diameter_note = (f"actuator.core_diameter_mm not given: the cap is {top:.4g} mm, the widest "
                                           f"an end ring of {END_RING_MIN_WALL_MM:g} mm wall holds inside the sleeve's "
                                           f"inner diameter {self.inner_diameter_mm:.4g} mm (the default "
                                           f"{DEFAULT_CAP_MM:g} mm does not fit)")
            return
        if self.core_diameter > top:
            raise SceneError("actuator.core_diameter_mm",
                             f"{self.raw['actuator']['core_diameter_mm']!r} mm is outside the allowed range "
                             f"(0, {top:.6g}]: {self._ring_words()}")

    def check_end_pieces(self):
        """The PLA end pieces that ``--step`` / ``--3mf`` / ``--render`` build (``geometry/sleeve.py``) can be made
        for this cap: the bottom cap carries the ``TUBE_HOLE_MM`` supply-tube hole with at least ``MIN_FEATURE_MM``
        of cap around it (the ring around the cap is checked at load, ``_check_cap``). Raises SceneError naming the
        field, the value and the allowed range; checked before any analysis."""
        low = TUBE_HOLE_MM + 2 * MIN_FEATURE_MM
        if self.core_diameter >= low:
            return
        if self.cap_max_mm < low:
            raise SceneError("ring", f"{self._inner_words()} is too small for the end pieces: a cap of at least {low:g} mm "
                                     f"around the {TUBE_HOLE_MM:g} mm supply-tube hole, in a ring of "
                                     f"{END_RING_MIN_WALL_MM:g} mm wall; allowed: an inner diameter of at least "
                                     f"{low + 2 * END_RING_MIN_WALL_MM:g} mm (more cells, larger L_mm or c_mm, a thinner "
                                     f"T_mm), or no --step / --3mf / --render")
        raise SceneError("actuator.core_diameter_mm",
                         f"{self.raw['actuator']['core_diameter_mm']!r} mm is outside the allowed range "
                         f"[{low:g}, {self.cap_max_mm:.6g}] for the end pieces: the bottom cap needs {MIN_FEATURE_MM:g} mm "
                         f"around its {TUBE_HOLE_MM:g} mm supply-tube hole, the end ring a {END_RING_MIN_WALL_MM:g} mm "
                         f"wall around the cap; or no --step / --3mf / --render")

    @classmethod
    def load(cls, path):
        from metamaterial_wb.core.inputfile import read_json

        data = read_json(path, "spec")   # one SceneError line for any unreadable / non-JSON / hostile file
        try:
            return cls(data, str(path))
        except SceneError as exc:
            raise SceneError(exc.field, f"{exc.message} (in {path})") from None

    @property
    def N(self):
        return len(self.pattern[0])

    @property
    def M(self):
        return len(self.pattern)

    @property
    def radius_mm(self):
        """Mid radius of the sleeve wall: the circumference holds N cell widths."""
        return self.N * (self.L + self.c) / (2 * math.pi)


FIELDS = {"": ("format", "version", "name", "L_mm", "c_mm", "delta_mm", "T_mm", "shear_modulus_MPa", "layout",
               "cell_types", "pattern", "ring", "rings", "model", "actuator", "design_map", "walker"),
          "cell_types": ("t_mm", "h_mm"),
          "model": ("elements_cell", "elements_ring", "steps", "plane", "imperfection", "pillar_tip", "ring_curvature",
                    "frame_nonlinear", "frame_elements", "root_extension", "max_displacement_mm"),
          "actuator": ("core_diameter_mm", "membrane_kPa_per_mL"),
          "design_map": ("t_over_L", "h_over_L", "ring", "elements"),
          "walker": ("foot_length_mm", "body_length_mm", "contact_band_mm")}


def _section(data, key):
    """An optional section (``design_map``, ``walker``): absent, null or false -> None (off); true or an object
    -> the object (``{}``: every default). Anything else is refused, never read as off."""
    v = data.get(key)
    if v is None or v is False:
        return None
    if v is True:
        return {}
    if not isinstance(v, dict):
        raise SceneError(key, f"{_short(v, 60)}; expected true, false or an object (an empty object: every "
                              "default)")
    return v


def _known(obj, field, section):
    """Refuse a key of the object ``obj`` (at ``field``) that ``FIELDS[section]`` does not list: a misspelt key
    would otherwise be ignored and its default used."""
    for k in obj:
        if k not in FIELDS[section]:
            raise SceneError(f"{field}.{k}" if field else str(k),
                             f"unknown field; allowed: {', '.join(FIELDS[section])}")


def _integer(field, v, lo, hi):
    """An integer in [lo, hi] (16.0 is 16; 16.5 is refused, never truncated)."""
    x = check_number(field, v, lo, hi, "")
    if x != int(x):
        raise SceneError(field, f"{v!r} is not an integer (allowed: integers in [{lo}, {hi}])")
    return int(x)


def _range3(field, v, lo, hi):
    """``[min, max, count]`` of a design-map axis: count 1 is one value (min = max), a count of 2 to 40 spans
    min to max (min < max); a count that does not fit min and max is refused, never one of them dropped."""
    if not (isinstance(v, list) and len(v) == 3):
        raise SceneError(field, f"{v!r}; expected [min, max, count]")
    a = check_number(f"{field}[0]", v[0], lo, hi, "", low_open=True)
    b = check_number(f"{field}[1]", v[1], a, hi, "")
    n = v[2]
    check_integer(f"{field}[2]", n, 1, 40, "the count")
    if n == 1 and a != b:
        raise SceneError(field, f"{v!r}: count 1 maps one value, but min {a:g} and max {b:g} differ; give "
                                f"[{a:g}, {a:g}, 1] for one value, or a count of 2 to 40 to span {a:g} to {b:g}")
    if n > 1 and a == b:
        raise SceneError(field, f"{v!r}: count {n} spans min to max, but both are {a:g} (the same value {n} "
                                f"times); give [{a:g}, {a:g}, 1] for one value, or a max above {a:g}")
    return (a, b, n)
