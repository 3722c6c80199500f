"""The ``layout`` section: cells from grid / chain / cells / rows, the size budget and the seed's rules.

Size budget (issue 19), checked before anything is allocated: at most :data:`MAX_CELLS` cells, cell
indices below :data:`MAX_INDEX`, and a bounding box of at most :data:`MAX_BOX` places (the layout
rules label an image of the bounding box). Each limit is given in its error.
"""
import re

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene.names import _short

MAX_CELLS = 1_000_000          # documented maximum; solve of 1000 x 1000 measured (docs/scene-format.md)
MAX_INDEX = 4_000_000          # a cell row / column index
MAX_BOX = 16_000_000           # places in the bounding box of the cells (bool image + int32 labels: 80 MB)
_ROW_RE = re.compile(r"[#Xx1. 0\-]*")


def _too_many(field_name, n, what="cells"):
    raise SceneError(field_name, f"{n} {what}; at most {MAX_CELLS} cells are allowed (the size budget)")


def _is_int(x):
    return isinstance(x, int) and not isinstance(x, bool)


def cells_from_layout(layout, field_name="layout"):
    """Expand the ``layout`` object to an (n, 2) int array or a list of cells (not yet validated)."""
    import numpy as np

    if not isinstance(layout, dict):
        raise SceneError(field_name, f"expected an object with \"grid\", \"chain\" or \"cells\", got {_short(layout)}")
    for k in layout:
        if k not in ("grid", "chain", "cells", "rows"):
            raise SceneError(f"{field_name}.{k}", "unknown field; allowed: grid, chain, cells, rows (one of them)")
    keys = [k for k in ("grid", "chain", "cells", "rows") if k in layout]
    if len(keys) != 1:
        raise SceneError(field_name, f"give exactly one of \"grid\": [rows, columns], \"chain\": n, \"cells\": "
                                     f"[[i, j], ...] or \"rows\": [\"##.\", ...]; got keys {sorted(layout)[:8]}")
    key = keys[0]
    val = layout[key]
    if key == "grid":
        if not isinstance(val, (list, tuple)) or len(val) != 2 or not all(_is_int(x) for x in val):
            raise SceneError(f"{field_name}.grid", f"expected [rows, columns] (cell counts), got {_short(val)}")
        r, c = val
        if r < 1 or c < 1:
            raise SceneError(f"{field_name}.grid", f"{list(val)!r}: both cell counts must be >= 1")
        if r * c > MAX_CELLS or max(r, c) > MAX_INDEX:
            raise SceneError(f"{field_name}.grid", f"{list(val)!r} has {r * c} cells; at most {MAX_CELLS} are "
                                                   f"allowed (the size budget)")
        ii, jj = np.meshgrid(np.arange(r), np.arange(c), indexing="ij")
        return np.column_stack([ii.ravel(), jj.ravel()])
    if key == "chain":
        if not _is_int(val) or val < 1:
            raise SceneError(f"{field_name}.chain", f"expected a cell count >= 1, got {_short(val)}")
        if val > MAX_CELLS:
            _too_many(f"{field_name}.chain", val)
        return np.column_stack([np.zeros(val, dtype=np.int64), np.arange(val)])
    if key == "rows":
        if not isinstance(val, list) or not all(isinstance(s, str) for s in val):
            raise SceneError(f"{field_name}.rows", "expected a list of strings, '#' for a cell and '.' for none")
        width = max((len(s) for s in val), default=0)
        if len(val) > MAX_INDEX or width > MAX_INDEX or len(val) * width > MAX_BOX:
            raise SceneError(f"{field_name}.rows", f"{len(val)} rows of up to {width} characters: more than the "
                                                   f"{MAX_BOX} places the size budget allows")
        parts = []
        for i, s in enumerate(val):
            if not _ROW_RE.fullmatch(s):
                j = next(k for k, ch in enumerate(s) if ch not in "#Xx1. 0-")
                raise SceneError(f"{field_name}.rows[{i}]", f"character {s[j]!r} at column {j}; use '#' for a "
                                                           f"cell and '.' for an empty place (also X, x, 1 for a "
                                                           f"cell and a space, 0, - for an empty place)")
            b = np.frombuffer(s.encode("ascii"), dtype=np.uint8)
            js = np.flatnonzero((b == 35) | (b == 88) | (b == 120) | (b == 49))
            if js.size:
                parts.append(np.column_stack([np.full(js.size, i, dtype=np.int64), js]))
        cells = np.concatenate(parts) if parts else np.zeros((0, 2), dtype=np.int64)
        if len(cells) > MAX_CELLS:
            _too_many(f"{field_name}.rows", len(cells))
        return cells
    if not isinstance(val, list):
        raise SceneError(f"{field_name}.cells", f"expected a list of [row, column] pairs, got {_short(val)}")
    if len(val) > MAX_CELLS:
        _too_many(f"{field_name}.cells", len(val))
    return val


def _int_pairs(cells):
    """Fast check: every item is a pair of plain ints in [0, MAX_INDEX) (then no per-item loop)."""
    import itertools

    import numpy as np
    try:
        if {len(c) for c in cells} != {2} or set(map(type, itertools.chain.from_iterable(cells))) != {int}:
            return False
        arr = np.asarray(cells, dtype=np.int64)
    except (TypeError, ValueError, OverflowError):
        return False
    return bool(arr.size) and int(arr.min()) >= 0 and int(arr.max()) < MAX_INDEX


def validate_layout(cells, field_name="layout"):
    """The size budget and the seed's layout rules (section 4.1), each with its own error.

    * at least one cell, no duplicates, integer positions in [0, MAX_INDEX);
    * the bounding box holds at most MAX_BOX places;
    * every cell shares an edge with another one (when there are several);
    * the cells form one connected structure;
    * no closed contour of cells encloses a hole (the empty cells all reach the outside; a contour
      closed through a shared corner node counts as closed).
    """
    import numpy as np
    from scipy import ndimage

    if cells is None or len(cells) == 0:
        raise SceneError(field_name, "the layout has no cells; give at least one cell")
    if len(cells) > MAX_CELLS:
        _too_many(field_name, len(cells))
    if not hasattr(cells, "shape") and not _int_pairs(cells):
        for k, c in enumerate(cells):
            if not isinstance(c, (list, tuple)) or len(c) != 2 or not all(_is_int(x) for x in c):
                raise SceneError(f"{field_name}.cells[{k}]", f"expected [row, column] integers, got {_short(c)}")
            if not (0 <= c[0] < MAX_INDEX and 0 <= c[1] < MAX_INDEX):
                if c[0] < 0 or c[1] < 0:
                    raise SceneError(f"{field_name}.cells[{k}]", f"{list(c)!r} has a negative index; rows and "
                                                                 f"columns start at 0")
                raise SceneError(f"{field_name}.cells[{k}]", f"{_short(list(c))}: cell indices must be below "
                                                             f"{MAX_INDEX} (the size budget)")
    arr = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
    neg = np.flatnonzero((arr < 0).any(axis=1))
    if neg.size:
        k = int(neg[0])
        raise SceneError(f"{field_name}.cells[{k}]", f"{arr[k].tolist()!r} has a negative index; rows and "
                                                     f"columns start at 0")
    r0, c0 = arr.min(axis=0) - 1
    r1, c1 = arr.max(axis=0) + 1
    box = int(r1 - r0 + 1) * int(c1 - c0 + 1)
    if box > MAX_BOX:
        raise SceneError(field_name, f"the cells span rows {r0 + 1}..{r1 - 1} and columns {c0 + 1}..{c1 - 1}: "
                                     f"a bounding box of {box} places, more than the {MAX_BOX} the size budget "
                                     f"allows")
    w = int(arr[:, 1].max()) + 1
    uniq, counts = np.unique(arr[:, 0] * w + arr[:, 1], return_counts=True)
    if (counts > 1).any():
        code = uniq[counts > 1][0]
        dup = np.array([code // w, code % w])
        k = int(np.flatnonzero((arr == dup).all(axis=1))[1])
        raise SceneError(f"{field_name}.cells[{k}]", f"cell {dup.tolist()!r} is listed twice")
    if len(arr) == 1:
        return
    img = np.zeros((r1 - r0 + 1, c1 - c0 + 1), dtype=bool)
    img[arr[:, 0] - r0, arr[:, 1] - c0] = True
    nb = np.zeros_like(img)
    nb[1:, :] |= img[:-1, :]
    nb[:-1, :] |= img[1:, :]
    nb[:, 1:] |= img[:, :-1]
    nb[:, :-1] |= img[:, 1:]
    lonely = np.argwhere(img & ~nb)
    if len(lonely):
        c = (lonely[0] + (r0, c0)).tolist()
        raise SceneError(field_name, f"cell {c} shares no edge with another cell; every cell must have at least "
                                     f"one edge neighbour ({len(lonely)} such cell(s))")
    four = ndimage.generate_binary_structure(2, 1)
    labels, n = ndimage.label(img, structure=four)
    if n > 1:
        start = arr[np.lexsort((arr[:, 1], arr[:, 0]))[0]]
        lab0 = labels[start[0] - r0, start[1] - c0]
        other = np.argwhere(img & (labels != lab0))
        other = other[np.lexsort((other[:, 1], other[:, 0]))][0] + (r0, c0)
        raise SceneError(field_name, f"the layout is not connected: cell {other.tolist()} cannot be reached from "
                                     f"cell {start.tolist()} through shared edges")
    del labels
    elabels, en = ndimage.label(~img, structure=four)
    outside = elabels[0, 0]
    holes = np.argwhere((~img) & (elabels != outside))
    if len(holes):
        h = (holes[0] + (r0, c0)).tolist()
        raise SceneError(field_name, f"the cells form a closed contour around the empty cell {h}; a layout may not "
                                     f"enclose a hole ({len(holes)} enclosed empty cell(s))")
