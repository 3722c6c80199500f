"""Richardson extrapolation of FE figures over nested meshes (the sleeve's 2-D and 3-D studies, issue 18): one
place for the observed order and the error estimate every FE table quotes."""
import numpy as np


def richardson3(h, values, p_range=(0.5, 4.0)):
    """Richardson extrapolation from the last three of ``values`` at element sizes ``h`` (any ratios): the
    observed order ``p`` solves ``(v2 - v1) / (v3 - v2) = (h1^p - h2^p) / (h2^p - h3^p)`` (bisection, clipped to
    ``p_range``; 2 when the differences do not shrink monotonically), then ``v = v3 + (v3 - v2) h3^p /
    (h2^p - h3^p)``. Error estimate: ``|v - v3|``. With two values, order 2 is assumed."""
    V = np.atleast_2d(np.asarray(values, float).T).T          # (k, m)
    h = np.asarray(h, float)
    ext, err, order = [], [], []
    for col in V.T:
        if len(col) < 2 or not np.all(np.isfinite(col)):
            ext.append(col[-1] if len(col) else np.nan); err.append(np.nan); order.append(np.nan)
            continue
        p = 2.0
        if len(col) >= 3:
            (h1, h2, h3), (v1, v2, v3) = h[-3:], col[-3:]
            q = (v2 - v1) / (v3 - v2) if v3 != v2 else np.inf
            g = lambda pp: (h1 ** pp - h2 ** pp) / (h2 ** pp - h3 ** pp) - q  # noqa: E731
            lo, hi = p_range
            if np.isfinite(q) and q > 0 and g(lo) * g(hi) < 0:
                for _ in range(80):
                    mid = 0.5 * (lo + hi)
                    lo, hi = (mid, hi) if g(lo) * g(mid) > 0 else (lo, mid)
                p = 0.5 * (lo + hi)
            elif np.isfinite(q) and q > 0:
                p = lo if abs(g(lo)) < abs(g(hi)) else hi
        h2, h3 = h[-2], h[-1]
        v = col[-1] + (col[-1] - col[-2]) * h3 ** p / (h2 ** p - h3 ** p)
        ext.append(float(v)); err.append(float(abs(v - col[-1]))); order.append(float(p))
    return ext, err, order
