"""Live solving for the 3D view: factor once, then D -> node and hinge poses per slider move or frame.

Pure numpy (core layer): no FreeCAD, no Qt. The document glue (``FreeCAD.Placement`` lists) is
``objects/display.py:to_placements``, with the rest of placing a frame in a document.
The heavy work of a frame is numpy: one product with the solver's stored response matrix (or one
back-substitution), one kinematics solve (factored once per topology) and the hinge frames.

``LiveSolver(scene)`` keeps

* the factored quadratic model (``core.solver.model_for_scene``), reused for every ``solve``;
* the kinematics object (``core.kinematics.PlanarKinematics`` or its 3D successor), reused;
* the hinge corner offsets, so that hinge poses follow their two nodes.

Other simulation models (``core.models``) are run per frame through ``run_model`` (slower: they
solve a nonlinear problem each time); the quadratic model is the live default.
"""
import math
import time

import numpy as np

from metamaterial_wb.core import design, kinematics
from metamaterial_wb.core.errors import SceneError, check_number
from metamaterial_wb.core.motion import scene_values_at
from metamaterial_wb.core.scene import joint_nodes, parse_joint
from metamaterial_wb.core.solver import model_for_scene, scene_values


def matrices_to_quaternions(R):
    """(n, 3, 3) rotation matrices -> (n, 4) unit quaternions (x, y, z, w), w >= 0.

    Parameters
    ----------
    R : array_like
        (n, 3, 3) rotation matrices.

    Returns
    -------
    numpy.ndarray
        (n, 4) quaternions ``(x, y, z, w)``.
    """
    R = np.asarray(R, dtype=float).reshape(-1, 3, 3)
    n = R.shape[0]
    q = np.empty((n, 4))
    tr = R[:, 0, 0] + R[:, 1, 1] + R[:, 2, 2]
    # four candidate formulas; take the numerically best per row
    cand = np.stack([tr, R[:, 0, 0], R[:, 1, 1], R[:, 2, 2]], axis=1)
    k = np.argmax(cand, axis=1)
    for case in range(4):
        m = k == case
        if not np.any(m):
            continue
        r = R[m]
        if case == 0:
            s = np.sqrt(np.maximum(1.0 + tr[m], 1e-300)) * 2.0
            q[m, 3] = 0.25 * s
            q[m, 0] = (r[:, 2, 1] - r[:, 1, 2]) / s
            q[m, 1] = (r[:, 0, 2] - r[:, 2, 0]) / s
            q[m, 2] = (r[:, 1, 0] - r[:, 0, 1]) / s
        elif case == 1:
            s = np.sqrt(np.maximum(1.0 + r[:, 0, 0] - r[:, 1, 1] - r[:, 2, 2], 1e-300)) * 2.0
            q[m, 3] = (r[:, 2, 1] - r[:, 1, 2]) / s
            q[m, 0] = 0.25 * s
            q[m, 1] = (r[:, 0, 1] + r[:, 1, 0]) / s
            q[m, 2] = (r[:, 0, 2] + r[:, 2, 0]) / s
        elif case == 2:
            s = np.sqrt(np.maximum(1.0 + r[:, 1, 1] - r[:, 0, 0] - r[:, 2, 2], 1e-300)) * 2.0
            q[m, 3] = (r[:, 0, 2] - r[:, 2, 0]) / s
            q[m, 0] = (r[:, 0, 1] + r[:, 1, 0]) / s
            q[m, 1] = 0.25 * s
            q[m, 2] = (r[:, 1, 2] + r[:, 2, 1]) / s
        else:
            s = np.sqrt(np.maximum(1.0 + r[:, 2, 2] - r[:, 0, 0] - r[:, 1, 1], 1e-300)) * 2.0
            q[m, 3] = (r[:, 1, 0] - r[:, 0, 1]) / s
            q[m, 0] = (r[:, 0, 2] + r[:, 2, 0]) / s
            q[m, 1] = (r[:, 1, 2] + r[:, 2, 1]) / s
            q[m, 2] = 0.25 * s
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    q[q[:, 3] < 0] *= -1.0
    return q


def quaternions_to_matrices(q):
    """(n, 4) unit quaternions (x, y, z, w) -> (n, 3, 3) rotation matrices.

    Parameters
    ----------
    q : array_like
        (n, 4) unit quaternions ``(x, y, z, w)``.

    Returns
    -------
    numpy.ndarray
        (n, 3, 3).
    """
    q = np.asarray(q, dtype=float).reshape(-1, 4)
    x, y, z, w = q.T
    R = np.empty((q.shape[0], 3, 3))
    R[:, 0, 0] = 1 - 2 * (y * y + z * z)
    R[:, 0, 1] = 2 * (x * y - z * w)
    R[:, 0, 2] = 2 * (x * z + y * w)
    R[:, 1, 0] = 2 * (x * y + z * w)
    R[:, 1, 1] = 1 - 2 * (x * x + z * z)
    R[:, 1, 2] = 2 * (y * z - x * w)
    R[:, 2, 0] = 2 * (x * z - y * w)
    R[:, 2, 1] = 2 * (y * z + x * w)
    R[:, 2, 2] = 1 - 2 * (x * x + y * y)
    return R


def hinge_corner_offsets(scene):
    """Per joint ``(ra, rb)`` (n_joints, 3): the hinge ends in the frames of its two nodes (mm).

    Same checkerboard rule as ``core.kinematics``: ``H(i,j)`` uses the top corners when i+j is even,
    the bottom ones when odd; ``V(i,j)`` the right corners when even, the left ones when odd.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    tuple of numpy.ndarray
        ``(ra, rb)``, each (n_joints, 3).
    """
    topo = scene.topology
    a = 0.5 * kinematics.plate_side_mm(scene)
    ra = np.zeros((topo.n_joints, 3))
    rb = np.zeros((topo.n_joints, 3))
    for k, (kind, i, j) in enumerate(topo.joints):
        even = (i + j) % 2 == 0
        if kind == "H":
            y = a if even else -a
            ra[k, :2] = (a, y)
            rb[k, :2] = (-a, y)
        else:
            x = a if even else -a
            ra[k, :2] = (x, -a)
            rb[k, :2] = (x, a)
    return ra, rb


class Frame:
    """One solved state: ``D`` per node, node ``positions`` (n, 3) mm and ``rotations`` (n, 3, 3),
    hinge ``hinge_positions`` (m, 3) and ``hinge_quaternions`` (m, 4), node ``quaternions`` (n, 4); the model's
    ``warnings`` for this state (a list; the lattice models warn per state, e.g. a hinge past its limits) and
    whether its solve ``converged``."""

    __slots__ = ("D", "positions", "rotations", "quaternions", "hinge_positions", "hinge_quaternions",
                 "timings", "warnings", "converged")

    def __init__(self, **kw):
        for k in self.__slots__:
            setattr(self, k, kw.get(k))
        self.warnings = list(self.warnings or ())
        self.converged = True if self.converged is None else bool(self.converged)


class LiveSolver:
    """Factor a scene once; ``frame(values=..., global_deformation=...)`` per slider move."""

    def __init__(self, scene, model="quadratic", backend="auto"):
        t0 = time.perf_counter()
        self.scene = scene
        self.model_name = model or "quadratic"
        topo = scene.topology
        self.topo = topo
        self.item_names = [it.name for _, it in scene.fixed_items()]
        self.actuator_names = [a.name for a in scene.actuators]
        self.base_values = scene_values(scene)
        self.qmodel = None
        if self.model_name == "quadratic" and self.item_names:
            self.qmodel = model_for_scene(scene, backend=backend)
        elif self.model_name != "quadratic":
            from metamaterial_wb.core.models import model_names
            if self.model_name not in model_names():
                raise SceneError("model", f"{self.model_name!r}; allowed: {', '.join(model_names())}")
        self.kin = self._make_kinematics()
        self.ra, self.rb = hinge_corner_offsets(scene)
        self.ja = topo.joint_pairs[:, 0]
        self.jb = topo.joint_pairs[:, 1]
        # a hinge box is modelled along x; V joints are turned by -90 deg about z
        self.is_v = np.array([kind == "V" for kind, _, _ in topo.joints], dtype=bool)
        self.warnings = list(self.qmodel.warnings) if self.qmodel is not None else []
        if not self.item_names:
            self.warnings.append("the structure has no motor or constraint: every D = 0 unless the global "
                                 "deformation is used")
        self._last = None           # (D, pos, R, q, hinge_pos, hinge_q) of the last frame
        self.pose_evaluations = 0   # how often poses were really computed (tests, diagnostics)
        self.prepare_s = time.perf_counter() - t0

    def _make_kinematics(self):
        for cls_name in ("Kinematics", "Kinematics3D", "PlanarKinematics"):
            cls = getattr(kinematics, cls_name, None)
            if cls is not None:
                try:
                    return cls(self.scene, design.joint_tilts_rad(self.scene))
                except TypeError:
                    continue
        return None

    # -- values ----------------------------------------------------------------------------
    def values_with(self, overrides=None):
        """The scene's item values with some replaced.

        Parameters
        ----------
        overrides : dict, optional
            ``{item name: value}``.

        Returns
        -------
        dict
            ``{item name: value}`` of every actuator and constraint.

        Raises
        ------
        SceneError
            If an override names no item of the scene.
        """
        vals = dict(self.base_values)
        if overrides:
            for k, v in overrides.items():
                if k not in vals:
                    raise SceneError(f"values.{k}", f"unknown actuator/constraint; known: {self.item_names}")
                vals[k] = float(v)
        return vals

    def values_at(self, t):
        """Item values at time ``t`` s from the actuators' motion profiles (constraints keep theirs).

        Parameters
        ----------
        t : float
            Time (s).

        Returns
        -------
        dict
            ``{item name: value}``.
        """
        vals = dict(self.base_values)
        vals.update(scene_values_at(self.scene, t))
        return vals

    # -- solving ---------------------------------------------------------------------------
    def solve(self, values=None, global_deformation=None):
        """D per node. ``global_deformation`` g: every D = g (the seed's global slider).

        Parameters
        ----------
        values : dict, optional
            Overrides of item values (see :meth:`values_with`).
        global_deformation : float, optional
            If given, D = g everywhere (no solve); a number in [-1, 1].

        Returns
        -------
        numpy.ndarray
            (n_nodes,) D.

        Raises
        ------
        SceneError
            If ``global_deformation`` is not a finite number in [-1, 1] (named ``global_deformation``).
        """
        n = self.topo.n_nodes
        if global_deformation is not None:
            g = global_deformation.item() if isinstance(global_deformation, np.generic) else global_deformation
            return np.full(n, check_number("global_deformation", g, -1.0, 1.0))
        if self.model_name != "quadratic":
            return self._run_other(values, None).D
        if self.qmodel is None:
            return np.zeros(n)
        return self.qmodel.solve(self.values_with(values))

    def _run_other(self, values, g):
        from metamaterial_wb.core.models import run_model
        sc = self.scene.copy()
        for k, v in self.values_with(values).items():
            sc.set_value(k, v)
        return run_model(self.model_name, sc, global_deformation=g)

    def poses(self, D):
        """Node poses for a D field (the scene's kinematics).

        Parameters
        ----------
        D : numpy.ndarray
            (n_nodes,) deformation per node.

        Returns
        -------
        tuple of numpy.ndarray
            Positions (n, 3) mm and rotation matrices (n, 3, 3).
        """
        out = kinematics.node_poses(self.scene, D, kin=self.kin) if self.kin is not None else \
            kinematics.node_poses(self.scene, D)
        return np.asarray(out[0], dtype=float), np.asarray(out[1], dtype=float)

    def frame(self, values=None, global_deformation=None):
        """A solved :class:`Frame`: D, node poses and hinge frames (the last one is reused when unchanged).

        Parameters
        ----------
        values : dict, optional
            Overrides of item values.
        global_deformation : float, optional
            If given, D = g everywhere.

        Returns
        -------
        Frame
        """
        t0 = time.perf_counter()
        state = {}
        if self.model_name != "quadratic" and global_deformation is None:
            res = self._run_other(values, None)
            D, pos, R = res.D, np.asarray(res.positions_mm, float), np.asarray(res.rotations, float)
            state = {"warnings": res.warnings, "converged": res.converged}
        else:
            D = self.solve(values, global_deformation)
            last = self._last
            if last is not None and np.array_equal(last[0], D):
                # nothing changed (a paused timeline, a slider released on the same value): leave the
                # poses as they are instead of recomputing them
                return Frame(D=D, positions=last[1], rotations=last[2], quaternions=last[3],
                             hinge_positions=last[4], hinge_quaternions=last[5],
                             timings={"total_s": time.perf_counter() - t0, "hinges_s": 0.0, "reused": True})
            pos, R = self.poses(D)
            self.pose_evaluations += 1
        t2 = time.perf_counter()
        q = matrices_to_quaternions(R)
        hp, hq = self.hinge_frames(pos, R, q)
        t3 = time.perf_counter()
        if self.model_name == "quadratic" or global_deformation is not None:
            self._last = (D.copy(), pos, R, q, hp, hq)
        return Frame(D=D, positions=pos, rotations=R, quaternions=q, hinge_positions=hp, hinge_quaternions=hq,
                     timings={"total_s": t3 - t0, "hinges_s": t3 - t2}, **state)

    def hinge_frames(self, pos, R, q=None):
        """Hinge centres (m, 3) and orientations (m, 4) from the node poses.

        Parameters
        ----------
        pos : numpy.ndarray
            (n, 3) node positions (mm).
        R : numpy.ndarray
            (n, 3, 3) node rotations.
        q : numpy.ndarray, optional
            (n, 4) node quaternions, if already known.

        Returns
        -------
        tuple of numpy.ndarray
            ``(centres (m, 3), quaternions (m, 4))``.
        """
        a, b = self.ja, self.jb
        if len(a) == 0:
            return np.zeros((0, 3)), np.zeros((0, 4))
        pa = pos[a] + np.einsum("nij,nj->ni", R[a], self.ra)
        pb = pos[b] + np.einsum("nij,nj->ni", R[b], self.rb)
        centre = 0.5 * (pa + pb)
        if q is None:
            q = matrices_to_quaternions(R)
        qa, qb = q[a], q[b]
        sign = np.where(np.sum(qa * qb, axis=1) < 0, -1.0, 1.0)[:, None]
        qm = qa + sign * qb
        qm /= np.linalg.norm(qm, axis=1, keepdims=True)
        # V hinges: quaternion product qm * rz(-90 deg)
        if np.any(self.is_v):
            h = math.sqrt(0.5)
            r = np.array([0.0, 0.0, -h, h])
            x1, y1, z1, w1 = qm[self.is_v].T
            x2, y2, z2, w2 = r
            qm[self.is_v] = np.column_stack([
                w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
                w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
                w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2])
        return centre, qm

    # -- markers ---------------------------------------------------------------------------
    def joint_index(self, joint):
        """Index of a joint in the solver's joint order.

        Parameters
        ----------
        joint : str
            A joint name such as ``"H0,1"``.

        Returns
        -------
        int

        Raises
        ------
        SceneError
            If the name is malformed or the joint is not in the layout.
        """
        kind, i, j = parse_joint(joint)
        name = f"{kind}{i},{j}"
        if name not in self.topo.joint_index:
            raise SceneError("joint", f"joint {name} does not exist in this layout ({self.topo.n_joints} joints)")
        return self.topo.joint_index[name]

    def node_index(self, node):
        """``"N1,2"`` -> index.

        Parameters
        ----------
        node : str
            A node name.

        Returns
        -------
        int

        Raises
        ------
        SceneError
            If the name is malformed or the node is not in the layout.
        """
        txt = str(node).strip().upper().lstrip("N").strip("()")
        try:
            i, j = (int(x) for x in txt.split(","))
        except ValueError:
            raise SceneError("node", f"{node!r} is not a node name like \"N1,2\"") from None
        if (i, j) not in self.topo.node_index:
            raise SceneError("node", f"node N{i},{j} does not exist in this layout ({self.topo.n_nodes} nodes)")
        return self.topo.node_index[(i, j)]


def joint_node_indices(scene, joint):
    """The node indices of a joint's nodes.

    Parameters
    ----------
    scene : Scene
    joint : str
        A joint name.

    Returns
    -------
    list of int
    """
    kind, i, j = parse_joint(joint)
    return [scene.topology.node_index[n] for n in joint_nodes(kind, i, j)]
