"""Reading FD curves: peaks and valleys, snapping events, two-hysteron sequencing, PV curves."""
import numpy as np


def extrema(F, rel_prominence=0.02, floor=0.0):
    """Alternating peaks and valleys of a sampled curve ``F`` (in path order).

    A local maximum counts as a peak (minimum as a valley) only if the curve falls (rises) by more
    than ``rel_prominence`` times the curve's range (up to its lowest point), and by more than ``floor`` (the
    force resolution of the model that traced it, ``model.Path.noise``: a curve of round-off has a range too),
    before the next extremum of the other kind, so that numerical wiggles do not count. Returns lists of indices
    ``(peaks, valleys)``.
    """
    F = np.asarray(F, dtype=float)
    if len(F) < 3:
        return [], []
    # the scale is the curve's range up to its lowest point (first peak to last valley), so that
    # the stiff stretching branch after the last valley does not hide a second peak
    imin = int(np.argmin(F))
    scale = np.ptp(F[:imin + 1]) if imin > 0 else np.ptp(F)
    thr = max(rel_prominence * max(scale, 1e-300), floor)
    peaks, valleys = [], []
    mode = "up"          # looking for a peak
    cand = 0
    for i in range(1, len(F)):
        if mode == "up":
            if F[i] > F[cand]:
                cand = i
            elif F[cand] - F[i] > thr:
                peaks.append(cand)
                mode, cand = "down", i
        else:
            if F[i] < F[cand]:
                cand = i
            elif F[i] - F[cand] > thr:
                valleys.append(cand)
                mode, cand = "up", i
    return peaks, valleys


def peaks_valleys(d, F, rel_prominence=0.02, floor=0.0):
    """``{"peaks": [[d, F], ...], "valleys": [[d, F], ...]}`` of a loading curve (``floor``: :func:`extrema`'s)."""
    p, v = extrema(F, rel_prominence, floor)
    return {"peaks": [[float(d[i]), float(F[i])] for i in p],
            "valleys": [[float(d[i]), float(F[i])] for i in v]}


def zero_crossings(F, resolution=0.0):
    """How often a sampled force changes sign, a force within ``resolution`` of zero counting as zero (neither
    sign): round-off about zero is no crossing."""
    F = np.asarray(F, float)
    s = np.sign(np.where(np.abs(F) > resolution, F, 0.0))
    s = s[s != 0]
    return int(np.sum(s[1:] != s[:-1]))


def has_force_drop(path, rel_prominence=0.02):
    """Whether a traced path (``d``, ``F``, ``jumps``, ``noise`` as ``model.Path``) snaps anywhere: read along
    increasing d (an unloading path reversed), its force has a peak (:func:`extrema`, ``floor`` the path's force
    resolution), or the state jumped (the stable branch ended). A path without either passes every cell through
    its chord continuously, as a spring does: no snap (:func:`snap_order` is not asked)."""
    d, F = np.asarray(path.d, float), np.asarray(path.F, float)
    if len(d) > 1 and d[-1] < d[0]:
        F = F[::-1]
    return bool(path.jumps) or bool(extrema(F, rel_prominence, getattr(path, "noise", 0.0))[0])


def snapped(states, geoms_of_cells):
    """Boolean (n, ncells): cell's top has passed the beams' chord (d > h), i.e. the beams are inverted."""
    h = np.array([g.h / g.L for g in geoms_of_cells])
    return np.asarray(states) > h[None, :]


def units_snapped(rises, snap_height, units):
    """The beam model's snap rule on hysterons of several parts: ``rises`` (k, parts) each part's outer end's rise
    over its inner end's (/ L), ``snap_height`` its h / L (a number or per part), ``units`` (parts,) the hysteron
    of each part (0 .. n - 1). A hysteron has snapped when its parts' mean rise beyond h is positive: (k, n) bool."""
    over = np.atleast_2d(np.asarray(rises, float)) - np.asarray(snap_height, float)
    units = np.asarray(units)
    return np.stack([over[:, units == u].mean(axis=1) > 0 for u in range(int(units.max()) + 1)], axis=1)


def hysteron_types(cell_types, units=None):
    """The cell types of each hysteron: ``units`` (per column of ``cell_types``, as :func:`snap_order`'s; None: one
    hysteron per column) numbered 0 .. n - 1; returns n sorted lists. A hysteron of one type (an edge pillar between
    two cells of that type) can be attributed to it, one of two types (a pillar between them) to neither."""
    if units is None:
        units = list(range(len(cell_types)))
    return [sorted({int(cell_types[j]) for j, u in enumerate(units) if u == uid}) for uid in sorted(set(units))]


def snap_order(path, cell_types, geoms_of_cells, units=None):
    """Order in which cell *types* change state along a path, from the snapped flags.

    ``path.states`` has one column per snapping beam part (``cell_types`` and ``geoms_of_cells``
    per column). ``units`` (optional, per column): the hysteron the part belongs to - in the
    single-beam layout the edge pillar that carries two beam halves, which snap together; a unit
    is snapped when the mean of its parts' rises exceeds their mean h. Types are ordered by the
    first change of a unit made of one type only (:func:`hysteron_types`): a pillar between two types cannot be
    attributed to either, so a type without a pillar of its own, or whose pillars did not change on the path, is
    missing from the order (:func:`sequence_symmetry` says so). A state change is a snap only on a path that has a
    force drop (:func:`has_force_drop`; ``pipeline.simulated_sequence`` asks first): on a monostable path the cells
    pass h continuously.

    Returns (order_of_types, events) where events are (index, d, [units], state_after).
    """
    states = np.asarray(path.states)
    h = np.array([g.h / g.L for g in geoms_of_cells])
    if units is None:
        units = list(range(states.shape[1]))
    ids = sorted(set(units))
    cols = [[j for j, u in enumerate(units) if u == uid] for uid in ids]
    s = np.stack([np.mean(states[:, c] - h[None, c], axis=1) > 0 for c in cols], axis=1)
    utypes = hysteron_types(cell_types, units)
    events = []
    for i in range(1, len(s)):
        changed = np.nonzero(s[i] != s[i - 1])[0]
        if len(changed):
            events.append((i, float(path.d[i]), [int(c) for c in changed], bool(s[i][changed[0]])))
    order = []
    for _, _, us, _ in events:
        for u in us:
            if len(utypes[u]) == 1 and utypes[u][0] not in order:
                order.append(utypes[u][0])
    return order, events


def sequence_symmetry(cell_types, units, paths):
    """Whether unloading reverses loading, from complete orders only: ``(symmetric, note)``.

    ``cell_types``, ``units``: :func:`snap_order`'s; ``paths``: ``[(name, order, events, drops, d_end), ...]``, the
    loading path's first, then the unloading path's (``order`` and ``events`` from :func:`snap_order`, ``drops``
    :func:`has_force_drop`, ``d_end`` the path's last d / L: the stroke on loading, where unloading ends).
    ``symmetric`` is True when the unloading order is the loading order reversed, False when not - only when both
    orders hold every type of the ring. It is None with a ``note`` when nothing snapped on either path ("nothing
    snapped"), or when a type could not be ordered: it has no pillar between two cells of its own type, or a path
    showed no snap of it; the note says which type and why. One-element lists such as [0] | [0] from a two-type
    ring are no evidence of either; ``note`` is "" for a complete order."""
    if not any(p[2] for p in paths):
        return None, (f"nothing snapped within the stroke (to d/L {paths[0][4]:.4g}): no snapping "
                      "sequence, neither symmetric nor asymmetric")
    types = sorted({int(t) for t in cell_types})
    own = {u[0] for u in hysteron_types(cell_types, units) if len(u) == 1}
    why = [f"type {t} has no pillar between two cells of its own type (a pillar between two types cannot be "
           "attributed to either)" for t in types if t not in own]
    for name, order, events, drops, d_end in paths:
        missing = [t for t in types if t in own and t not in order]
        if not missing:
            continue
        which = f"type {missing[0]}" if len(missing) == 1 else f"types {missing}"
        if not drops:
            why.append(f"the {name} path showed no snap (no force drop and no jump on it, analysis.has_force_drop), "
                       f"so {which} could not be ordered on it: a finer path (more model.steps) may resolve one")
        elif name == "loading":
            why.append(f"on the loading path no pillar of {which} changed state (up to d/L {d_end:.4g}): the stroke "
                       "may end before it snaps, or the path is too coarse (more model.steps)")
        else:
            why.append(f"on the {name} path no pillar of {which} changed state (back to d/L {d_end:.4g}): it may "
                       "stay snapped, or the path is too coarse (more model.steps)")
    if why:
        return None, ("snapping order incomplete, symmetry undetermined (neither symmetric nor asymmetric): "
                      + "; ".join(why))
    return bool(paths[0][1][::-1] == paths[1][1]), ""


def symmetry_word(seq):
    """A sequence's verdict in words: ``symmetric`` / ``asymmetric``, or for ``symmetric`` null ``nothing snapped``
    (no snapping events on either path) or ``undetermined`` (events, but an incomplete order:
    :func:`sequence_symmetry`)."""
    if seq.get("symmetric") is None:
        return "undetermined" if seq.get("events_loading") or seq.get("events_unloading") else "nothing snapped"
    return "symmetric" if seq["symmetric"] else "asymmetric"


def two_hysteron_sequence(thresholds):
    """Two-hysteron prediction (seed 002, section 2.3, after Van Raemdonck et al.).

    ``thresholds``: per cell type ``(P1, V2)``: first-peak (forward snapping) and second-valley
    (backward snapping) force of the uniform ring made of that type. On loading the type with the
    lower P1 snaps first; on unloading the type with the higher V2 snaps back first. The sequence
    is *symmetric* when unloading reverses loading (first to snap is last to snap back).
    """
    types = list(range(len(thresholds)))
    loading = sorted(types, key=lambda k: (thresholds[k][0], k))
    unloading = sorted(types, key=lambda k: (-thresholds[k][1], k))
    symmetric = unloading == loading[::-1]
    combination = None
    if len(types) == 2:
        (p1, v1), (p2, v2) = thresholds
        combination = {(True, True): 1, (True, False): 2, (False, False): 3, (False, True): 4}[(p1 > p2, v1 > v2)]
    return {"loading": loading, "unloading": unloading, "symmetric": bool(symmetric),
            "combination": combination}


def lean_direction(tilt):
    """Horizontal direction (unit vector) the top plate's normal leans to for tilt (psi_x, psi_y)."""
    n = np.array([tilt[1], -tilt[0]])
    nn = np.linalg.norm(n)
    return n / nn if nn > 0 else n


# ------------------------------------------------------------------------------------------------
# PV curves
def pv_curve(d_mm, F_N, cap_area_mm2, membrane_kPa_per_mL=0.0):
    """Volume-controlled PV curve from an FD curve: V = A x, p = F / A + k_m V.

    Returns (V_mL, p_kPa). 1 N/mm^2 = 1000 kPa, 1 mL = 1000 mm^3.
    """
    V = np.asarray(d_mm) * cap_area_mm2 / 1000.0
    p = np.asarray(F_N) / cap_area_mm2 * 1000.0 + membrane_kPa_per_mL * V
    return V, p


def pressure_control(V, p, loading=True):
    """Pressure-controlled response derived from a volume-controlled curve ``(V, p)``.

    Under monotonically increasing pressure (``loading``) the state follows the curve while ``p``
    rises; at a local maximum it jumps (at constant pressure) to the first later point where the
    curve exceeds that pressure. Unloading (``loading=False``, curve given from large V to small V):
    mirror image at local minima. Returns (V_path, p_path, jumps) with jumps as
    ``[(p, V_from, V_to), ...]``. Pressures never reached (beyond the curve's end) are cut.
    """
    V = np.asarray(V, float)
    p = np.asarray(p, float)
    sgn = 1.0 if loading else -1.0
    q = sgn * p
    outV, outp, jumps = [V[0]], [p[0]], []
    level = q[0]
    i = 1
    while i < len(V):
        if q[i] >= level:
            level = q[i]
            outV.append(V[i]); outp.append(p[i])
            i += 1
            continue
        # pressure cannot drop: jump to the first later point with q >= level
        later = np.nonzero(q[i:] >= level)[0]
        if len(later) == 0:
            break
        j = i + int(later[0])
        # interpolate the landing point
        if j > 0 and q[j] != q[j - 1]:
            a = (level - q[j - 1]) / (q[j] - q[j - 1])
            Vl = V[j - 1] + a * (V[j] - V[j - 1])
        else:
            Vl = V[j]
        jumps.append((float(sgn * level), float(outV[-1]), float(Vl)))
        outV.append(Vl); outp.append(sgn * level)
        i = j
    return np.array(outV), np.array(outp), jumps
