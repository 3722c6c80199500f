"""Pictures without a GUI: the sheet in 3D as a PNG (matplotlib, Agg backend).

Plates are drawn as squares (side ``cell_size - hinge length``) at their 3D poses, coloured by D
(blue = -1, white = 0, red = +1); hinges as line segments between the plate corners they join
(green where tilted, i.e. bending cells, grey elsewhere); actuators as red dots on their joints,
angular constraints as black crosses. Equal scale on all three axes.
"""
import io
import re
import unicodedata
import warnings

import numpy as np

from metamaterial_wb.core import kinematics as kin


def plate_corners(scene, pos, R):
    """(n, 4, 3) corners of every plate (mm)."""
    a = 0.5 * kin.plate_side_mm(scene)
    local = np.array([[-a, -a, 0.0], [a, -a, 0.0], [a, a, 0.0], [-a, a, 0.0]])
    return pos[:, None, :] + np.einsum("nij,cj->nci", R, local)


def hinge_segments(scene, pos, R):
    """(m, 2, 3) end points of every hinge (mm)."""
    a, b, ra, rb, _d0 = kin._hinge_geometry(scene)
    pa = pos[a] + np.einsum("mij,mj->mi", R[a], ra)
    pb = pos[b] + np.einsum("mij,mj->mi", R[b], rb)
    return np.stack([pa, pb], axis=1)


def render_png(scene, pos, R, D, path=None, title=None, elev=28.0, azim=-62.0, size_px=(1200, 800), dpi=150,
               tilts_deg=None, title_tail="", title_field=None, notes=None):
    """Draw the sheet; write a PNG to ``path`` atomically (or return the PNG bytes when path is None).

    The title is ``title + title_tail`` drawn literally (no ``$...$`` math), ``\\n`` starting a new line. With
    ``title_field`` (the option the user typed it in, e.g. ``"--title"``) a title that does not fit the picture
    is refused naming that option (:func:`fit_title`); without it ``title`` (e.g. the scene name) is shortened to
    fit and that is said in ``notes``. Characters the font cannot draw and any other drawing problem are said
    in ``notes`` (a list of one-line warnings), never as raw library warnings."""
    import matplotlib
    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    from metamaterial_wb.core.fileio import write_atomic
    from metamaterial_wb.core.scene import parse_joint

    pos = np.asarray(pos, dtype=float)
    R = np.asarray(R, dtype=float)
    D = np.asarray(D, dtype=float)
    topo = scene.topology
    notes = [] if notes is None else notes
    fig = plt.figure(figsize=(size_px[0] / dpi, size_px[1] / dpi), dpi=dpi)
    with warnings.catch_warnings(record=True) as caught:     # said as one-line notes below, not raw
        warnings.simplefilter("always")
        try:
            text = fit_title(fig, title or "", title_tail if title else "", field=title_field, notes=notes)
            ax = fig.add_subplot(111, projection="3d")
            corners = plate_corners(scene, pos, R)
            cmap = plt.get_cmap("coolwarm")
            colours = cmap(0.5 + 0.4 * np.clip(D, -1, 1))
            lw = 0.6 if topo.n_nodes <= 400 else 0.15
            poly = Poly3DCollection(corners, facecolors=colours, edgecolors=(0.2, 0.2, 0.25, 1.0), linewidths=lw,
                                    alpha=0.95)
            ax.add_collection3d(poly)
            seg = hinge_segments(scene, pos, R)
            tilts = np.asarray(tilts_deg) if tilts_deg is not None else None
            if tilts is None:
                from metamaterial_wb.core.design import effective_tilts_deg
                tilts = effective_tilts_deg(scene)
            tilted = np.abs(tilts) > 1e-9
            hw = 1.6 if topo.n_joints <= 800 else 0.4
            if np.any(~tilted):
                ax.add_collection3d(Line3DCollection(seg[~tilted], colors=(0.35, 0.35, 0.35, 1), linewidths=hw))
            if np.any(tilted):
                ax.add_collection3d(Line3DCollection(seg[tilted], colors=(0.1, 0.65, 0.2, 1), linewidths=hw * 1.6))
            # actuators and constraints at the middle of their hinge
            for kind, item in scene.fixed_items():
                k = topo.joint_id(*parse_joint(item.joint))
                mid = seg[k].mean(axis=0)
                if kind == "actuator":
                    ax.scatter([mid[0]], [mid[1]], [mid[2]], s=70, c="red", edgecolors="darkred", depthshade=False,
                               zorder=10)
                else:
                    ax.scatter([mid[0]], [mid[1]], [mid[2]], s=50, c="black", marker="x", depthshade=False, zorder=10)
            pts = corners.reshape(-1, 3)
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            span = hi - lo
            big = float(span.max()) or 1.0
            span = np.maximum(span, 0.12 * big)
            mid = 0.5 * (lo + hi)
            for setter, c, s in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), mid, span):
                setter(c - 0.5 * s, c + 0.5 * s)
            ax.set_box_aspect(tuple(span))
            ax.view_init(elev=elev, azim=azim)
            ax.set_xlabel("x (mm)")
            ax.set_ylabel("y (mm)")
            ax.set_zlabel("z (mm)")
            ax.tick_params(labelsize=6)
            if text:
                fig.suptitle(text, fontsize=TITLE_PT, parse_math=False)
            fig.tight_layout()
            buf = io.BytesIO()
            fig.savefig(buf, format="png", dpi=dpi)
        finally:
            plt.close(fig)
    notes.extend(drawing_notes(caught, size_px, text))
    data = buf.getvalue()
    if path is None:
        return data
    write_atomic(path, data, mode="wb")
    return path


def state_title_parts(scene, g=None, values=None, extra=""):
    """The default title as ``(scene name, the state after it)``: only the name may be shortened to fit."""
    name = scene.name or "scene"
    if g is not None:
        s = f": global deformation g = {g:g}"
    elif values:
        s = ": " + ", ".join(f"{k} = {v:g}" for k, v in values.items())
    else:
        s = ""
    return name, s + (f" {extra}" if extra else "")


def state_title(scene, g=None, values=None, extra=""):
    return "".join(state_title_parts(scene, g, values, extra))


# ---- titles: a user-given text drawn so that it fits the picture, or refused, and said ----------------------------
#
# The rule (the same for every picture that draws a user-given name): the title is drawn literally (no $...$
# math), a newline starts a new line; it may be at most the picture's width less a 2 % margin on each side wide
# and a quarter of the picture's height high. A title the user typed (--title) that does not fit is refused
# naming the option, its length and how much of it fits; a title made from the scene name (whose format allows
# 100 000 characters) is shortened -- the name part only, ending in '...' -- and that is said once as a warning.

TITLE_PT = 9
ELLIPSIS = "\u2026"


def title_room(fig):
    """``(width, height)`` in px the title may take in ``fig``."""
    w, h = (float(v) for v in fig.get_size_inches() * fig.dpi)
    return w - 2 * max(4.0, 0.02 * w), 0.25 * h


def _title_measure(fig, fontsize):
    """A function ``fits(text) -> bool`` for ``fig``, and the most lines a title may have."""
    from matplotlib.backends.backend_agg import RendererAgg
    from matplotlib.text import Text

    w, h = (float(v) for v in fig.get_size_inches() * fig.dpi)
    renderer = RendererAgg(int(round(w)), int(round(h)), fig.dpi)
    room_w, room_h = title_room(fig)
    probe = Text(0, 0, "", fontsize=fontsize, parse_math=False)
    probe.set_figure(fig)

    def extent(text):
        probe.set_text(text)
        bb = probe.get_window_extent(renderer)
        return bb.width, bb.height

    h1 = extent("Ag")[1]
    step = extent("Ag\nAg")[1] - h1
    max_lines = 0 if h1 > room_h else 1 + int((room_h - h1) // max(step, 1e-9))
    cap = int(room_w) * max(max_lines, 1)      # a glyph is at least 1 px wide: a longer text never fits

    def fits(text):
        if text.count("\n") >= max_lines or len(text) > cap:
            return False
        tw, th = extent(text)
        return tw <= room_w and th <= room_h

    return fits, max_lines


def _longest(n_max, ok):
    """The largest n in [0, n_max] with ok(n) (ok monotone, ok(0) assumed), by bisection."""
    lo, hi = 0, n_max
    while lo < hi:
        m = (lo + hi + 1) // 2
        if ok(m):
            lo = m
        else:
            hi = m - 1
    return lo


def _lines(text):
    """``", 3 lines"`` for a text of several lines, ``""`` for one."""
    k = text.count("\n") + 1
    return f", {k} lines" if k > 1 else ""


def fit_title(fig, head, tail="", field=None, notes=None, fontsize=TITLE_PT, what="the scene name",
              advice="give --title to choose the title, or a larger --size"):
    """The title ``head + tail`` as it will be drawn in ``fig``.

    ``field`` given (the option the user typed ``head`` in): a title that does not fit raises
    :class:`SceneError` naming ``field``, the title's length and how many of its first characters fit.
    ``field`` None: ``head`` (``what``, e.g. the scene name) is shortened to fit, ending in '...', and a
    one-line warning saying so is appended to ``notes``."""
    from metamaterial_wb.core.errors import SceneError

    full = head + tail
    if not full:
        return ""
    fits, max_lines = _title_measure(fig, fontsize)
    if fits(full):
        return full
    w, h = (int(round(float(v))) for v in fig.get_size_inches() * fig.dpi)
    room_w, _room_h = title_room(fig)
    room = (f"at {fontsize:g} pt a title may be at most {room_w:.0f} px wide and {max_lines} "
            f"line{'s' if max_lines != 1 else ''} high in a {w} x {h} px picture")
    if field is not None:
        n = _longest(len(full), lambda m: fits(full[:m]))
        raise SceneError(field, f"the title ({len(full)} characters{_lines(full)}) does not fit: {room}; "
                                f"the first {n} characters of it fit. Give a shorter {field} or a larger --size")
    whole = f"the title ({what}{' and what follows it' if tail else ''}, {len(full)} characters{_lines(full)})"
    if fits(ELLIPSIS + tail):
        n = _longest(len(head), lambda m: fits(head[:m].rstrip() + ELLIPSIS + tail))
        kept = head[:n].rstrip()
        text = kept + ELLIPSIS + tail
        said = (f"{what} ({len(head)} characters{_lines(head)}) is shortened to its first {len(kept)} characters "
                f"and '{ELLIPSIS}' in the title")
    elif fits(ELLIPSIS):
        n = _longest(len(full), lambda m: fits(full[:m].rstrip() + ELLIPSIS))
        kept = full[:n].rstrip()
        text = kept + ELLIPSIS
        said = f"{whole} is shortened to its first {len(kept)} characters and '{ELLIPSIS}'"
    else:
        text, said = "", f"{whole} is left out: not even '{ELLIPSIS}' fits"
    if notes is not None:
        notes.append(f"{said}: {room}; {advice}")
    return text


def check_title(text, size_px, dpi=150, field="--title", fontsize=TITLE_PT):
    """Refuse (SceneError naming ``field``) a user-given title that does not fit a ``size_px`` picture, before
    any work is done."""
    from matplotlib.figure import Figure

    if text:
        with warnings.catch_warnings():    # e.g. a glyph the font lacks: said once when the picture is drawn
            warnings.simplefilter("ignore")
            fit_title(Figure(figsize=(size_px[0] / dpi, size_px[1] / dpi), dpi=dpi), text, field=field,
                      fontsize=fontsize)


_GLYPH = re.compile(r"Glyph (\d+) .*missing from")      # "... current font." (3.6), "... font(s) X." (3.8+)


def _char(cp):
    c = chr(cp)
    name = unicodedata.name(c, "")
    shown = repr(c) if not c.isprintable() else f"'{c}'"
    return f"{shown} (U+{cp:04X}{' ' + name if name else ''})"


def drawing_notes(caught, size_px, text="", field_size="--size"):
    """One-line warnings for what matplotlib warned while drawing ``caught`` (``warnings.WarningMessage``s): the
    title's characters the font has no glyph for, named once; a picture too small to lay out; anything else as
    one line each (never the raw multi-line library warning)."""
    out, missing, other = [], [], []
    for wm in caught:
        msg = str(wm.message)
        m = _GLYPH.search(msg)
        if m:
            cp = int(m.group(1))
            if cp not in missing and chr(cp) in text:      # not glyphs of a part cut off while fitting
                missing.append(cp)
        elif "Tight layout not applied" in msg:
            line = (f"the picture ({size_px[0]} x {size_px[1]} px) is too small to lay out the axes, their labels "
                    f"and the title: they may overlap or be cut; give a larger {field_size}")
            if line not in other:
                other.append(line)
        elif not m:
            line = "while drawing: " + (msg.strip().splitlines() or [""])[0]
            if line not in other:
                other.append(line)
    if missing:
        try:
            from matplotlib.font_manager import FontProperties
            font = f" ({FontProperties(size=TITLE_PT).get_name()})"
        except Exception:        # noqa: BLE001 -- the name is only a courtesy
            font = ""
        more = f" and {len(missing) - 12} more" if len(missing) > 12 else ""
        out.append(f"the title has {len(missing)} character{'s' if len(missing) != 1 else ''} the font{font} "
                   f"cannot draw, drawn as empty boxes: " + ", ".join(_char(c) for c in missing[:12]) + more)
    return out + other


def view_angles(text):
    """``"ELEV,AZIM"`` -> (elev, azim) degrees, with a clear error."""
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.numbers import parse_float

    items = text.split(",") if isinstance(text, str) else []
    if len(items) != 2:
        raise SceneError("--view", f"{text!r}: expected ELEV,AZIM in degrees, e.g. 28,-62")
    # strict: no '1_0', no non-ASCII digits, no inf/nan (float() would take them all)
    e, a = (parse_float(f"--view {what}", x) for what, x in zip(("elevation", "azimuth"), items))
    for what, v, lim in (("elevation", e, 90), ("azimuth", a, 360)):
        if not -lim <= v <= lim:
            raise SceneError("--view", f"{text!r}: {what} {v:g} is outside the allowed range [-{lim}, {lim}] deg")
    return e, a
