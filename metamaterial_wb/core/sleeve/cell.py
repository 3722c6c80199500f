"""Parametric unit cell of the metamaterial sleeve (seed 002, figure 2A), pure geometry.

Two readings of the seed's figure 2A (the figure itself is not in the text; the parameters are).
``layout = "single"`` (default since the seed's supplementary S3.1 was read closely, see
docs/sleeves.md):

* ONE curved beam of thickness ``t`` per cell, cosine centre line of amplitude ``h/2`` and
  wavelength ``L``, highest at the centre: ``y(x) = y0 + h/2 (1 + cos(2 pi x / L))``, its two halves
  being "both beams" that the seed sees "sequentially buckle";
* a *central pillar* of width ``c`` stands on the bottom bar (height ``c/2``) and carries the beam's
  centre; the beam's top leaves a gap ``delta`` under the top bar;
* *edge pillars* of width ``c`` (half in each neighbouring cell) hang from the top bar and carry the
  beam ends, the beams' "lower points" that the seed sees "move outward (away from the structure)"
  when not held by neighbours; they stop a gap ``delta`` above the bottom bar;
* pulling the top bar up lifts the beam ends over the centre: the beam snaps from "bent up" to
  "bent down". The cell is ``W = L + c`` wide and ``H = c + 2 delta + t + h`` high.

``layout = "double"`` (the first reading, kept for comparison):

* two curved beams of thickness ``t`` with a cosine centre line of amplitude ``h/2`` and wavelength
  ``L``: ``y(x) = y0 + h/2 (1 - cos(2 pi x / L))`` for ``x`` in ``[-L/2, L/2]``, lowest at the centre;
  the two beams are parallel (the upper one is the lower one shifted up by ``c + t``), like
  Qiu, Lang & Slocum's double curved beam;
* *edge pillars* of width ``c`` (half of it in each neighbouring cell) carry the beam ends and stand
  on the bottom beam (the bar of height ``c/2``); they stop a gap ``delta`` below the top bar;
* a *central pillar* of width ``c`` joins the centres of both beams and hangs from the top bar of
  height ``c/2``; it stops a gap ``delta`` above the bottom bar;
* pulling the top bar up therefore pulls the beam centres up through their ends: both beams snap
  from "bent down" to "bent up" (bistability), and ``delta`` is a stop in compression;
* out-of-plane thickness ``T`` (radial wall thickness of the sleeve).

The cell is ``W = L + c`` wide (periodic) and ``H = 2c + 2 delta + 2t + h`` high. All lengths in mm
(or in any unit: the mechanics uses ratios to ``L``).
"""
import math
from dataclasses import dataclass, asdict

import numpy as np

from metamaterial_wb.core.errors import check_number


@dataclass(frozen=True)
class CellGeometry:
    L: float = 18.0        # wavelength of the cosine centre line (beam span between edge pillars), mm
    t: float = 1.0         # beam thickness, mm
    h: float = 7.5         # beam undulation height (cosine amplitude h/2), mm
    c: float = 4.0         # pillar width (bars are c/2 high), mm
    delta: float = 0.5     # gap between pillars and bars, mm
    T: float = 1.8         # out-of-plane (radial) thickness, mm
    layout: str = "single"  # "single" (one beam per cell, default) or "double" (the former reading)

    @classmethod
    def checked(cls, field="cell", **kw):
        """Build and validate; errors name ``field`` and the allowed range."""
        g = cls(**kw)
        if g.layout not in ("single", "double"):
            from metamaterial_wb.core.errors import SceneError
            raise SceneError(f"{field}.layout", f"{g.layout!r}; allowed: 'single', 'double'")
        check_number(f"{field}.L_mm", g.L, 0, None, "mm", low_open=True)
        check_number(f"{field}.t_mm", g.t, 0, 0.25 * g.L, "mm", low_open=True)
        check_number(f"{field}.h_mm", g.h, 0, 0.6 * g.L, "mm", low_open=True)
        check_number(f"{field}.c_mm", g.c, 0, 0.6 * g.L, "mm", low_open=True)
        check_number(f"{field}.delta_mm", g.delta, 0, g.L, "mm", low_open=True)
        check_number(f"{field}.T_mm", g.T, 0, 2 * g.L, "mm", low_open=True)
        if g.c >= g.L - 2 * g.t:
            from metamaterial_wb.core.errors import SceneError
            raise SceneError(f"{field}.c_mm", f"{g.c!r} mm leaves no free beam; it must be below L - 2t = {g.L - 2 * g.t:g} mm")
        return g

    def as_dict(self):
        d = {f"{k}_mm": v for k, v in asdict(self).items() if k != "layout"}
        d["layout"] = self.layout
        return d

    # --- derived sizes -------------------------------------------------------------------------
    @property
    def width(self):
        return self.L + self.c

    @property
    def spacing(self):
        """Vertical distance between the centre lines of the two parallel beams."""
        return self.c + self.t

    @property
    def height(self):
        if self.layout == "single":
            return self.c + 2 * self.delta + self.t + self.h
        return 2 * self.c + 2 * self.delta + 2 * self.t + self.h

    @property
    def y_lower(self):
        """Centre-line height of the (lower) beam's lowest point: its ends (single layout) or its
        centre (double layout)."""
        return self.c / 2 + self.delta + self.t / 2

    def centre_line(self, x, which=0):
        """Centre line y(x) of beam ``which`` (0 lower, 1 upper; single layout: one beam) for
        |x| <= L/2. Single layout: highest at the centre (on the central pillar), lowest at the
        ends (on the edge pillars); double layout: lowest at the centre."""
        x = np.asarray(x, dtype=float)
        if self.layout == "single":
            return self.y_lower + 0.5 * self.h * (1 + np.cos(2 * np.pi * x / self.L))
        return self.y_lower + which * self.spacing + 0.5 * self.h * (1 - np.cos(2 * np.pi * x / self.L))

    def slope(self, x):
        sgn = -1.0 if self.layout == "single" else 1.0
        return sgn * 0.5 * self.h * (2 * np.pi / self.L) * np.sin(2 * np.pi * np.asarray(x, float) / self.L)

    def beam_surface(self, x, which=0, side=+1):
        """Points of the beam's upper (side=+1) or lower (side=-1) surface, offset t/2 along the normal."""
        x = np.asarray(x, dtype=float)
        y = self.centre_line(x, which)
        sl = self.slope(x)
        nrm = np.hypot(1.0, sl)
        nx, ny = -sl / nrm, 1.0 / nrm
        return np.stack([x + side * 0.5 * self.t * nx, y + side * 0.5 * self.t * ny], axis=1)

    def normalised(self):
        """The dimensionless ratios that fix the normalised response F/(G L^2) versus d/L."""
        return {"t/L": self.t / self.L, "h/L": self.h / self.L, "c/L": self.c / self.L,
                "delta/L": self.delta / self.L, "T/L": self.T / self.L}

    # --- 2-D outline for the B-rep -------------------------------------------------------------
    def holes(self, samples=24, top=None, left=None):
        """Closed polygons (lists of (x, y), counter-clockwise) of the voids of one cell, in the
        cell frame: x in [-W/2, W/2] (pillar centres at the edges), y in [0, H].

        Returns the voids ``below`` (under the lower beam), ``between_left`` / ``between_right``
        (between the two beams) and ``above`` (over the upper beams). ``above`` spans the edge
        pillar at x = -W/2 (it continues over the pillar top through the gap ``delta`` into the left
        neighbour), so that N copies shifted by W tile a ring without overlap.

        ``top``: height of the top bar's lower face (default ``H - c/2``; a taller value lengthens the
        central pillar and the gap over the edge pillars, used when shorter cell types share a ring
        with taller ones). ``left``: the left neighbour's CellGeometry (default: the same), whose
        upper beam bounds the ``above`` void's left part.
        """
        if self.layout == "single":
            return self._holes_single(samples, top, left)
        L, c, d, t = self.L, self.c, self.delta, self.t
        W, H = self.width, self.height
        xl = np.linspace(-L / 2, -c / 2, samples)
        xr = np.linspace(c / 2, L / 2, samples)
        lo_bot_l = self.beam_surface(xl, 0, -1)
        lo_bot_r = self.beam_surface(xr, 0, -1)
        lo_top_l = self.beam_surface(xl, 0, +1)
        lo_top_r = self.beam_surface(xr, 0, +1)
        up_bot_l = self.beam_surface(xl, 1, -1)
        up_bot_r = self.beam_surface(xr, 1, -1)
        up_top_l = self.beam_surface(xl, 1, +1)
        up_top_r = self.beam_surface(xr, 1, +1)
        ybar = c / 2
        ytop = H - c / 2 if top is None else top
        pillar_top = self.centre_line(L / 2, 1) + t / 2   # top of the edge pillars
        nb = self if left is None else left
        nb_top_r = nb.beam_surface(np.linspace(nb.c / 2, nb.L / 2, samples), 1, +1)
        nb_pillar_top = nb.centre_line(nb.L / 2, 1) + nb.t / 2
        cp_bot = ybar + d                                  # bottom of the central pillar
        # void 0: below the lower beam, above the bottom bar, between the edge pillars; it passes
        # below the central pillar through the gap delta
        v0 = [(-L / 2, ybar), (L / 2, ybar)]
        v0 += [tuple(p) for p in lo_bot_r[::-1]]          # right half, from the end inward
        v0 += [(c / 2, cp_bot), (-c / 2, cp_bot)]
        v0 += [tuple(p) for p in lo_bot_l[::-1]]          # left half, from the centre outward
        # void 1: between the two beams, left and right of the central pillar, closed by the
        # edge pillar on the outside
        mid_r = [tuple(p) for p in lo_top_r] + [tuple(p) for p in up_bot_r[::-1]]
        mid_l = [tuple(p) for p in lo_top_l] + [tuple(p) for p in up_bot_l[::-1]]
        # void 2: above the upper beams, below the top bar; it spans the edge pillar at x = -W/2
        # (right half of the left neighbour, gap delta over the pillar, left half of this cell)
        v2 = [(c / 2 - W, ytop)] + [(p[0] - W, p[1]) for p in nb_top_r]
        v2 += [(L / 2 - W, nb_pillar_top), (-L / 2, pillar_top)]
        v2 += [tuple(p) for p in up_top_l] + [(-c / 2, ytop)]
        polys = {"below": _ccw(v0), "between_left": _ccw(mid_l), "between_right": _ccw(mid_r),
                 "above": _ccw(v2)}
        return polys

    def _holes_single(self, samples, top, left):
        """Voids of a single-layout cell: ``above`` the beam (between the edge pillars, under the
        top bar; it passes over the central pillar, which stops at the beam) and ``below`` it. The
        ``below`` void spans the edge pillar at x = -W/2: it runs from the left neighbour's central
        pillar under its right beam half, through the gap delta under the edge pillar, and under
        this cell's left beam half to this cell's central pillar."""
        L, c, d, t = self.L, self.c, self.delta, self.t
        W = self.width
        ytop = self.height - c / 2 if top is None else top
        nb = self if left is None else left
        ybar = c / 2
        xl = np.linspace(-c / 2, -L / 2, samples)                  # centre -> left end
        lo_l = self.beam_surface(xl, 0, -1)
        xn = np.linspace(nb.L / 2, nb.c / 2, samples)              # neighbour: right end -> centre
        lo_n = nb.beam_surface(xn, 0, -1)
        below = [(-W + nb.c / 2, ybar), (-c / 2, ybar)]
        below += [tuple(p) for p in lo_l]
        below += [(-L / 2, ybar + d), (nb.L / 2 - W, ybar + d)]
        below += [(p[0] - W, p[1]) for p in lo_n]
        xa = np.linspace(-L / 2, L / 2, 2 * samples + 1)
        up = self.beam_surface(xa, 0, +1)
        above = [(L / 2, ytop), (-L / 2, ytop)] + [tuple(p) for p in up]
        return {"below": _ccw(below), "above": _ccw(above)}


def _clean(pts, tol=1e-9):
    out = []
    for p in pts:
        if not out or math.hypot(p[0] - out[-1][0], p[1] - out[-1][1]) > tol:
            out.append((float(p[0]), float(p[1])))
    if len(out) > 1 and math.hypot(out[0][0] - out[-1][0], out[0][1] - out[-1][1]) <= tol:
        out.pop()
    return out


def _ccw(pts):
    pts = _clean(pts)
    a = sum(pts[i][0] * pts[(i + 1) % len(pts)][1] - pts[(i + 1) % len(pts)][0] * pts[i][1]
            for i in range(len(pts)))
    return pts if a > 0 else pts[::-1]


def polygon_area(pts):
    return 0.5 * abs(sum(pts[i][0] * pts[(i + 1) % len(pts)][1] - pts[(i + 1) % len(pts)][0] * pts[i][1]
                         for i in range(len(pts))))


def triangulate_polygon(pts):
    """Ear-clipping triangulation of a simple counter-clockwise polygon: list of index triples."""
    P = [tuple(map(float, p)) for p in pts]
    idx = list(range(len(P)))
    tris = []

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    def inside(p, a, b, c):
        return cross(a, b, p) >= -1e-14 and cross(b, c, p) >= -1e-14 and cross(c, a, p) >= -1e-14

    guard = 0
    while len(idx) > 3 and guard < 10 * len(P) ** 2:
        guard += 1
        n = len(idx)
        for k in range(n):
            i0, i1, i2 = idx[(k - 1) % n], idx[k], idx[(k + 1) % n]
            a, b, c = P[i0], P[i1], P[i2]
            if cross(a, b, c) <= 1e-14:
                continue                      # reflex or degenerate corner
            if any(inside(P[j], a, b, c) for j in idx if j not in (i0, i1, i2)):
                continue
            tris.append((i0, i1, i2))
            idx.pop(k)
            break
        else:
            raise ValueError("polygon could not be triangulated (self-intersecting?)")
    tris.append(tuple(idx))
    return tris
