"""Nodes and joints of a cell layout, with stable indices."""
from metamaterial_wb.core.scene.names import joint_name, parse_joint


class Topology:
    """Nodes and joints of a cell layout, with stable indices (vectorised; fine for 10^6 cells).

    ``nodes``: sorted list of ``(i, j)``; ``node_index[(i, j)]`` its index (``node_id(i, j)`` is the
    fast look-up). ``joints``: sorted list of ``(kind, i, j)`` ("H" block first, then "V");
    ``joint_index[name]`` its index (``joint_id(kind, i, j)`` is the fast look-up);
    ``joint_pairs``: int array (n_joints, 2) of node indices. List and dict views are built lazily.
    """

    def __init__(self, cells):
        import numpy as np

        arr = np.asarray(list(cells) if not hasattr(cells, "shape") else cells, dtype=np.int64).reshape(-1, 2)
        if len(arr):
            w = int(arr[:, 1].max()) + 1
            codes = np.unique(arr[:, 0] * w + arr[:, 1])
            arr = np.column_stack([codes // w, codes % w])
        self.cell_array = arr
        self._W = int(arr[:, 1].max()) + 3 if len(arr) else 3
        W = self._W
        enc = lambda i, j: i * W + j  # noqa: E731
        ci, cj = arr[:, 0], arr[:, 1]
        self._node_codes = np.unique(np.concatenate([enc(ci, cj), enc(ci, cj + 1), enc(ci + 1, cj),
                                                     enc(ci + 1, cj + 1)]))
        self._h_codes = np.unique(np.concatenate([enc(ci, cj), enc(ci + 1, cj)]))
        self._v_codes = np.unique(np.concatenate([enc(ci, cj), enc(ci, cj + 1)]))
        self.n_nodes = int(self._node_codes.size)
        self.n_joints = int(self._h_codes.size + self._v_codes.size)
        hi, hj = self._h_codes // W, self._h_codes % W
        vi, vj = self._v_codes // W, self._v_codes % W
        a = np.concatenate([np.searchsorted(self._node_codes, enc(hi, hj)),
                            np.searchsorted(self._node_codes, enc(vi, vj))])
        b = np.concatenate([np.searchsorted(self._node_codes, enc(hi, hj + 1)),
                            np.searchsorted(self._node_codes, enc(vi + 1, vj))])
        self.joint_pairs = np.column_stack([a, b]).astype(np.int64)
        self._joint_ij = np.column_stack([np.concatenate([hi, vi]), np.concatenate([hj, vj])])
        self.n_h = int(self._h_codes.size)
        self._lazy = {}

    # -- fast look-ups -----------------------------------------------------------------------
    def node_id(self, i, j):
        """Index of node (i, j), or -1."""
        import numpy as np
        code = i * self._W + j
        if j < 0 or j >= self._W or i < 0:
            return -1
        k = int(np.searchsorted(self._node_codes, code))
        return k if k < self.n_nodes and self._node_codes[k] == code else -1

    def joint_id(self, kind, i, j):
        """Index of joint (kind, i, j), or -1."""
        import numpy as np
        if j < 0 or j >= self._W or i < 0:
            return -1
        codes, off = (self._h_codes, 0) if kind == "H" else (self._v_codes, self.n_h)
        code = i * self._W + j
        k = int(np.searchsorted(codes, code))
        return off + k if k < codes.size and codes[k] == code else -1

    def has_joint(self, name):
        kind, i, j = parse_joint(name)
        return self.joint_id(kind, i, j) >= 0

    def node_ij(self):
        import numpy as np
        return np.column_stack([self._node_codes // self._W, self._node_codes % self._W])

    def joint_ij(self):
        """(n_joints, 2) array of the (i, j) of every joint (kinds: first ``n_h`` are H)."""
        return self._joint_ij

    def joint_kinds(self):
        import numpy as np
        return np.array(["H"] * self.n_h + ["V"] * (self.n_joints - self.n_h))

    # -- lazy list / dict views ----------------------------------------------------------------
    def _get(self, key, fn):
        if key not in self._lazy:
            self._lazy[key] = fn()
        return self._lazy[key]

    @property
    def cells(self):
        return self._get("cells", lambda: [tuple(map(int, c)) for c in self.cell_array])

    @property
    def cellset(self):
        return self._get("cellset", lambda: set(self.cells))

    @property
    def nodes(self):
        return self._get("nodes", lambda: [tuple(map(int, n)) for n in self.node_ij()])

    @property
    def node_index(self):
        return self._get("node_index", lambda: {n: k for k, n in enumerate(self.nodes)})

    @property
    def joints(self):
        def build():
            ij = self._joint_ij.tolist()
            return [("H" if k < self.n_h else "V", i, j) for k, (i, j) in enumerate(ij)]
        return self._get("joints", build)

    @property
    def joint_names(self):
        return self._get("joint_names", lambda: [joint_name(*t) for t in self.joints])

    @property
    def joint_index(self):
        return self._get("joint_index", lambda: {name: k for k, name in enumerate(self.joint_names)})

    def joint_cells(self, kind, i, j):
        """The (one or two) cells that a joint borders."""
        if kind == "H":
            cand = [(i - 1, j), (i, j)]
        else:
            cand = [(i, j - 1), (i, j)]
        return [c for c in cand if c in self.cellset]


