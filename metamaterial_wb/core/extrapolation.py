"""Richardson extrapolation of FE figures over meshes (issue 18): one place for the observed order and the error
estimate every FE table quotes: the hinge and patch studies (:func:`extrapolate`, the meshes' own element sizes),
the sleeve's 2-D and 3-D studies and ``sleeve --fe-check`` (:func:`richardson3`, the same computation per column).

Meshes whose element sizes are not in one ratio are handled by the generalised form of Roache's grid convergence
index method.

With ``f(h) = f0 + C h^p`` at three element sizes ``h1 > h2 > h3`` (ratios ``r21 = h1 / h2``, ``r32 = h2 / h3``),
the observed order ``p`` solves ``(f2 - f1) / (f3 - f2) = r32^p (r21^p - 1) / (r32^p - 1)`` (the right side grows
monotonically in ``p``, from ``ln r21 / ln r32`` at ``p -> 0``; with equal ratios it is ``r^p``), and
``f0 = f3 + (f3 - f2) / (r32^p - 1)``; the error estimate is ``|f0 - f3|``, the correction to the finest mesh.
Celik et al., "Procedure for estimation and reporting of uncertainty due to discretization in CFD applications",
ASME J. Fluids Eng. 130 (2008) 078001, eq. 1-4, without the safety factor.

The sizes must be the meshes' own: :func:`representative_size` (also theirs: ``(dx dy dz)^(1/3)``, the cube root
of the mean brick volume, when the three directions are refined by different ratios). An observed order outside
``p_range`` is clipped to it and flagged (``clipped``); one that cannot be observed (two meshes, or differences that
change sign: oscillating convergence) is taken as 2 and flagged (``assumed``): nothing is clipped silently. Every
sleeve FE table says so under it in :func:`order_note`'s words (the hinge and patch tables per figure).
"""
import math

import numpy as np

P_RANGE = (0.5, 4.0)
P_ASSUMED = 2.0


def representative_size(sizes):
    """The representative element size of a mesh whose bricks measure ``sizes`` (``(dx, dy, dz)`` mm, or a list of
    such for every brick): the cube root of the mean brick volume (Celik et al. 2008, eq. 1)."""
    s = np.atleast_2d(np.asarray(sizes, float))
    return float(np.mean(np.prod(s, axis=1)) ** (1.0 / s.shape[1]))


def _order(h, v, p_range):
    """``(p, observed, clipped, assumed)`` from the last three ``(h, v)``: ``observed`` the solution before
    clipping (NaN when there is none)."""
    (h1, h2, h3), (v1, v2, v3) = h[-3:], v[-3:]
    r21, r32 = h1 / h2, h2 / h3
    e21, e32 = v2 - v1, v3 - v2
    if e21 == 0.0 and e32 == 0.0:
        return P_ASSUMED, math.nan, False, True              # nothing changes: converged, any order
    if e32 == 0.0 or e21 / e32 <= 0.0:
        if e32 == 0.0:                                      # the finest step changed nothing: order "infinite"
            return p_range[1], math.inf, True, False
        return P_ASSUMED, math.nan, False, True             # the differences change sign: oscillating
    q = e21 / e32

    def g(p):                                               # increasing in p
        return p * math.log(r32) + math.log(math.expm1(p * math.log(r21))) - math.log(math.expm1(p * math.log(r32))) \
            - math.log(q)
    observed = math.nan
    lo, hi = 1e-9, 64.0
    if g(lo) < 0.0 < g(hi):
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if g(mid) < 0.0 else (lo, mid)
        observed = 0.5 * (lo + hi)
    elif g(hi) <= 0.0:
        observed = math.inf
    else:
        observed = 0.0                                      # no positive order: convergence does not speed up
    p = min(max(observed, p_range[0]), p_range[1])
    return p, observed, p != observed, False


def extrapolate(h, values, p_range=P_RANGE):
    """Richardson extrapolation of ``values`` (a sequence of arrays, one per mesh, coarse to fine) at the meshes'
    element sizes ``h`` (their own: :func:`representative_size`) to ``h -> 0``, from the last three (two: order 2
    assumed). A dict of arrays of the values' shape: ``value`` (extrapolated), ``error`` (``|value - finest|``),
    ``order`` (the order used), ``order_observed`` (before clipping; NaN where none was observed), ``clipped`` (the
    observed order lay outside ``p_range`` and was clipped to it), ``assumed`` (no order could be observed: 2 used),
    and ``ratios`` (the meshes' size ratios, ``h[i] / h[i + 1]`` over the last three)."""
    V = [np.asarray(x, float) for x in values]
    h = [float(x) for x in h]
    if len(V) != len(h) or not V:
        raise ValueError(f"values: {len(V)} meshes for {len(h)} element sizes; allowed: one value per size")
    if any(not (math.isfinite(x) and x > 0) for x in h) or any(a <= b for a, b in zip(h, h[1:])):
        raise ValueError(f"h: {h!r}; allowed: positive element sizes, coarse to fine (strictly decreasing)")
    shape = V[-1].shape
    flat = np.stack([x.ravel() for x in V])                  # (meshes, components)
    n = flat.shape[1]
    out = {k: np.full(n, np.nan) for k in ("value", "error", "order", "order_observed")}
    out.update(clipped=np.zeros(n, bool), assumed=np.zeros(n, bool))
    if len(V) < 2:
        out["value"] = flat[-1].copy()
    for j in range(n if len(V) >= 2 else 0):
        col = flat[:, j]
        if len(col) >= 3:
            p, observed, clipped, assumed = _order(h, col, p_range)
        else:
            p, observed, clipped, assumed = P_ASSUMED, math.nan, False, True
        r = h[-2] / h[-1]
        value = col[-1] + (col[-1] - col[-2]) / (r ** p - 1.0)
        out["value"][j], out["error"][j], out["order"][j] = value, abs(value - col[-1]), p
        out["order_observed"][j], out["clipped"][j], out["assumed"][j] = observed, clipped, assumed
    res = {k: v.reshape(shape) for k, v in out.items()}
    res["ratios"] = [a / b for a, b in zip(h[-3:], h[-3:][1:])]
    return res


def summary(res):
    """How the orders of :func:`extrapolate`'s result ``res`` came about, in words: ``""`` when every one was
    observed inside the range, else how many were clipped (and to which bound) or assumed."""
    clipped, assumed = np.asarray(res["clipped"]).ravel(), np.asarray(res["assumed"]).ravel()
    order = np.asarray(res["order"]).ravel()
    parts = []
    if clipped.any():
        lo = int(np.sum(clipped & (order <= P_RANGE[0])))
        hi = int(clipped.sum()) - lo
        parts.append(f"{int(clipped.sum())} of {clipped.size} observed orders outside [{P_RANGE[0]:g}, "
                     f"{P_RANGE[1]:g}] and clipped to it ({lo} to {P_RANGE[0]:g}, {hi} to {P_RANGE[1]:g})")
    if assumed.any():
        parts.append(f"{int(assumed.sum())} of {assumed.size} not observable (two meshes, or oscillating "
                     f"differences): order {P_ASSUMED:g} assumed")
    return "; ".join(parts)




def richardson3(h, values):
    """``(extrapolated, error, order)``, lists with one entry per column of ``values`` (rows: meshes, coarse to
    fine, at element sizes ``h``): :func:`extrapolate`'s ``value``, ``error`` and ``order`` (the order's flags:
    :func:`richardson3_flags`). A column with a non-finite value, or fewer than two meshes, is its finest value
    with NaN error and order."""
    res = _columns(h, values)
    return [float(x) for x in res["value"]], [float(x) for x in res["error"]], [float(x) for x in res["order"]]


def richardson3_flags(h, values):
    """:func:`summary` of :func:`richardson3`'s orders for the same input: ``""`` when every order was observed
    inside ``P_RANGE``."""
    return summary(_columns(h, values))


def order_note(figures):
    """The sentence under a table whose figures come from :func:`richardson3`: ``""`` when every order was observed
    inside ``P_RANGE``, else ``"Richardson orders: "`` and :func:`summary`'s words over all the table's figures,
    then the clipped and the assumed ones by name (``"Clipped: <names>. Assumed: <names>."``).

    Parameters
    ----------
    figures : iterable of ``(names, h, values)``
        One entry per extrapolation, ``h`` and ``values`` as :func:`richardson3` takes them (fewer than two meshes:
        left out); ``names`` the table's name of each column (a string for a single column), ``None`` for a column
        the table does not show (left out of the count).

    Returns
    -------
    str
        The sentence, ending with a full stop, or ``""``.
    """
    clipped, assumed, order, names = [], [], [], []
    for cols, h, values in figures:
        if len(h) < 2:
            continue
        res = _columns(h, values)
        cols = [cols] if isinstance(cols, str) or cols is None else list(cols)
        if len(cols) != res["order"].size:
            raise ValueError(f"names: {len(cols)} for {res['order'].size} columns; allowed: one name per column")
        for k, name in enumerate(cols):
            if name is not None:
                clipped.append(bool(res["clipped"][k]))
                assumed.append(bool(res["assumed"][k]))
                order.append(float(res["order"][k]))
                names.append(name)
    words = summary({"clipped": np.array(clipped, bool), "assumed": np.array(assumed, bool), "order": np.array(order)})
    if not words:
        return ""
    which = [f"{kind}: " + "; ".join(n for n, f in zip(names, flags) if f) + "."
             for kind, flags in (("Clipped", clipped), ("Assumed", assumed)) if any(flags)]
    return f"Richardson orders: {words}. " + " ".join(which)


def _columns(h, values):
    V = np.atleast_2d(np.asarray(values, float).T).T          # (meshes, columns)
    good = np.all(np.isfinite(V), axis=0)
    res = extrapolate(h, [np.where(good, row, 0.0) for row in V])
    for k in ("error", "order", "order_observed"):
        res[k] = np.where(good, res[k], np.nan)
    res["value"] = np.where(good, res["value"], V[-1])
    res["clipped"], res["assumed"] = res["clipped"] & good, res["assumed"] & good
    return res


__all__ = ["extrapolate", "representative_size", "summary", "richardson3", "richardson3_flags", "order_note",
           "P_RANGE"]
