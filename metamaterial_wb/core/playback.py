"""Playing a simulated trajectory on the structure: ``TrajectoryPlayer`` maps a dynamics trajectory (side
view, floor frame; ``simulate --out DIR`` -> ``DIR/trajectory.json``) onto node and hinge poses for the 3D
view, and ``run_dynamics`` produces one. Pure numpy (core layer): no FreeCAD, no Qt. The live solver of the
same scene (``core/live.py``) supplies the hinge frames."""
import math

import numpy as np

from metamaterial_wb.core.errors import SceneError, check_integer, check_number
from metamaterial_wb.core.live import Frame, matrices_to_quaternions

ONLY_SHEET = ("only the 'sheet' model maps onto a structure's nodes (the belt has no sheet nodes; use "
              "simulate --frames for its pictures)")
START_TOL_S = 1e-6      # the first recorded time is 0 s within this (simulate writes times_s rounded to 6 decimals)


class TrajectoryPlayer:
    """Map a dynamics trajectory (side view, floor frame) onto the structure's node poses.

    The dynamics ``sheet`` model is planar, seen from the side: each column of nodes is one rigid
    body with a pose ``(x, y, angle)`` in the floor frame (x along the floor towards increasing
    column index, y up, angle counter-clockwise). The 3D view shows the sheet in its x-y plane with
    z up, so the side plane is the view's x-z plane:

    * a node of body ``b`` keeps its flat y (its row); its x and z are the body's x and y, rotated
      by the incline about the y axis;
    * its orientation is a rotation about the y axis by ``-(angle + incline)`` (counter-clockwise
      in the side view seen from the front, i.e. looking along +y);
    * constant offsets put the first recorded frame of a flat sheet exactly onto the flat layout:
      ``ox`` = mean of (flat node x - body x at frame 0), ``oz`` = the bodies' mean rest height.

    The in-plane rotation of the squares (what the quadratic model shows) is not part of the side
    view model, so the plates stay square to the sheet; hinges follow their two nodes as usual.
    Between recorded frames the poses are interpolated linearly.
    """

    def __init__(self, data, scene, flat_positions, source=None):
        """``data``: the parsed ``trajectory.json``; ``source``: its path, named in every refusal (``(in PATH)``).

        Every field read is checked before anything is kept: a refusal is a :class:`SceneError` naming the field
        (``trajectory.poses[3][2][1]``), the value and what is allowed; nothing is converted, rounded or clamped
        (a body index 1.7 is no body, a NaN time is no time)."""
        try:
            self._read(data, scene, flat_positions)
        except SceneError as exc:
            if source:
                raise SceneError(exc.field, f"{exc.message} (in {source})") from None
            raise

    def _read(self, data, scene, flat_positions):
        if not isinstance(data, dict) or data.get("format") != "metamaterial-trajectory":
            raise SceneError("trajectory", f"format {_short(data.get('format') if isinstance(data, dict) else data)}; "
                                           "expected 'metamaterial-trajectory' (simulate --out DIR writes "
                                           "DIR/trajectory.json)")
        if data.get("model") != "sheet":
            raise SceneError("trajectory.model", f"{data.get('model')!r}: {ONLY_SHEET}")
        self.times = _times(data.get("times_s"))
        poses = _poses(data.get("poses"), self.times.size)
        nb = poses.shape[1]
        if "bodies" in data and (type(data["bodies"]) is not int or data["bodies"] != nb):
            raise SceneError("trajectory.bodies", f"{_short(data['bodies'])}; expected {nb}, the number of bodies "
                                                  "in each frame of poses")
        self.poses = poses
        from metamaterial_wb.core.dynamics.builders import INCLINE_RANGE_DEG
        incline = data.get("incline_deg", 0.0)
        if not _is_number(incline):
            raise SceneError("trajectory.incline_deg", f"{_short(incline)}; allowed: a number of degrees in "
                                                       f"[{INCLINE_RANGE_DEG[0]:g}, {INCLINE_RANGE_DEG[1]:g}]")
        self.incline = math.radians(check_number("trajectory.incline_deg", incline, *INCLINE_RANGE_DEG, "deg"))
        topo = scene.topology
        body_of_node = data.get("body_of_node")
        if not isinstance(body_of_node, dict) or not body_of_node:
            raise SceneError("trajectory.body_of_node", f"{_short(body_of_node)}; expected an object mapping each "
                                                        "node (\"N0,3\") to its body index")
        self.node_body = np.zeros(topo.n_nodes, dtype=int)
        for k, (i, j) in enumerate(topo.nodes):
            key = f"N{i},{j}"
            if key not in body_of_node:
                raise SceneError("trajectory.body_of_node",
                                 f"node {key} of the structure is not in the trajectory (simulated from a "
                                 "different layout?)")
            self.node_body[k] = check_integer(f"trajectory.body_of_node.{key}", body_of_node[key], 0, nb - 1,
                                              f"a body of the trajectory, which has {nb}")
        if len(body_of_node) != topo.n_nodes:
            raise SceneError("trajectory.body_of_node", f"{len(body_of_node)} nodes; the structure has "
                                                        f"{topo.n_nodes} (simulated from a different layout?)")
        flat = np.asarray(flat_positions, dtype=float)
        self.flat = flat
        x0, y0 = self._floor_to_view(poses[0, :, 0], poses[0, :, 1])
        self.ox = float(np.mean(flat[:, 0] - x0[self.node_body]))
        self.oz = float(np.mean(y0))
        self.duration = float(self.times[-1])

    def _floor_to_view(self, x, y):
        c, s = math.cos(self.incline), math.sin(self.incline)
        return c * x - s * y, s * x + c * y

    def body_poses(self, t):
        """(bodies, 3) pose at time ``t`` (clamped to the recorded range), linear interpolation.

        Parameters
        ----------
        t : float
            Time (s).

        Returns
        -------
        numpy.ndarray
        """
        T = self.times
        if t <= T[0]:
            return self.poses[0].copy()
        if t >= T[-1]:
            return self.poses[-1].copy()
        k = int(np.searchsorted(T, t, side="right")) - 1
        w = (t - T[k]) / (T[k + 1] - T[k])
        return (1 - w) * self.poses[k] + w * self.poses[k + 1]

    def node_poses(self, t):
        """Node positions (n, 3) mm and rotation matrices (n, 3, 3) at time ``t``.

        Parameters
        ----------
        t : float
            Time (s).

        Returns
        -------
        tuple of numpy.ndarray
            ``(positions, rotations)``.
        """
        p = self.body_poses(t)
        X, Z = self._floor_to_view(p[:, 0], p[:, 1])
        b = self.node_body
        pos = np.column_stack([X[b] + self.ox, self.flat[:, 1], Z[b] - self.oz + self.flat[:, 2]])
        beta = -(np.radians(p[b, 2]) + self.incline)          # rotation about +y
        c, s = np.cos(beta), np.sin(beta)
        R = np.zeros((b.size, 3, 3))
        R[:, 0, 0] = c
        R[:, 0, 2] = s
        R[:, 1, 1] = 1.0
        R[:, 2, 0] = -s
        R[:, 2, 2] = c
        return pos, R

    def floor_corners(self, margin_mm=20.0):
        """(4, 3) corners of the floor (floor-frame y = 0) under the whole motion, in view coordinates.

        Parameters
        ----------
        margin_mm : float, optional
            Margin around the swept footprint.

        Returns
        -------
        numpy.ndarray
            (4, 3).
        """
        xs = self.poses[:, :, 0]
        x_lo, x_hi = float(xs.min()) - margin_mm, float(xs.max()) + margin_mm
        y_lo, y_hi = float(self.flat[:, 1].min()) - margin_mm, float(self.flat[:, 1].max()) + margin_mm
        out = []
        for xf, yv in ((x_lo, y_lo), (x_hi, y_lo), (x_hi, y_hi), (x_lo, y_hi)):
            X, Z = self._floor_to_view(xf, 0.0)
            out.append([X + self.ox, yv, Z - self.oz])
        return np.array(out)

    def frame(self, solver, t):
        """A :class:`Frame` (nodes, hinges) for ``objects.display.apply_frame``.

        Parameters
        ----------
        solver : LiveSolver
            The live solver of the same scene (for the hinge frames).
        t : float
            Time (s).

        Returns
        -------
        Frame
        """
        pos, R = self.node_poses(t)
        q = matrices_to_quaternions(R)
        hp, hq = solver.hinge_frames(pos, R, q)
        return Frame(D=None, positions=pos, rotations=R, quaternions=q, hinge_positions=hp, hinge_quaternions=hq,
                     timings={})


def _short(value, n=60):
    """``repr`` of a value in a message, cut to ``n`` characters (a whole list is not repeated)."""
    r = repr(value)
    return r if len(r) <= n else r[:n - 3] + "..."


def _is_number(v):
    return type(v) in (int, float) or (isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(
        v, (bool, np.bool_)))


def _as_floats(field, value, what):
    """``value`` (numbers, checked) as a float array: a JSON integer too large for a float is refused."""
    try:
        return np.asarray(value, dtype=float)
    except OverflowError:
        raise SceneError(field, f"a number too large; allowed: {what}") from None


def _times(value):
    """``times_s``: at least one finite number of seconds, increasing strictly, the first 0 (within ``START_TOL_S``)."""
    field = "trajectory.times_s"
    what = "finite numbers of seconds, increasing"
    if not isinstance(value, (list, tuple, np.ndarray)) or len(value) == 0:
        raise SceneError(field, f"{_short(value)}; expected a list of the recorded times ({what})")
    for k, v in enumerate(value):
        if not _is_number(v):
            raise SceneError(f"{field}[{k}]", f"{_short(v)}; allowed: a finite number of seconds")
    t = _as_floats(field, value, what)
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        k = int(bad[0])
        raise SceneError(f"{field}[{k}]", f"{value[k]!r} is not a finite number; allowed: a finite number of seconds")
    back = np.flatnonzero(np.diff(t) <= 0)
    if back.size:
        k = int(back[0]) + 1
        raise SceneError(f"{field}[{k}]", f"{value[k]!r} after {value[k - 1]!r}: times must increase")
    if abs(t[0]) > START_TOL_S:
        # simulate records its first frame at t = 0 (the initial state): a later start is a cut or edited file,
        # and playing it would hold frame 0 from 0 s to its first time, silently
        raise SceneError(f"{field}[0]", f"{value[0]!r} s; a trajectory starts at 0 s (allowed: 0 s within "
                                        f"{START_TOL_S:g} s; simulate records its first frame at t = 0)")
    return t


def _poses(value, frames):
    """``poses``: ``frames`` x bodies x (x mm, y mm, angle deg), finite numbers, the same bodies in every frame."""
    field = "trajectory.poses"
    num = "a finite number (x mm, y mm, angle deg)"
    if not isinstance(value, (list, tuple, np.ndarray)) or len(value) != frames:
        n = f"{len(value)} frames" if isinstance(value, (list, tuple, np.ndarray)) else _short(value)
        raise SceneError(field, f"{n}; expected one frame per time of times_s ({frames}), each a list of the "
                                "bodies' [x, y, angle]")
    nb = None
    for f, frame in enumerate(value):
        if not isinstance(frame, (list, tuple, np.ndarray)) or len(frame) == 0 or (nb is not None and len(frame) != nb):
            n = f"{len(frame)} bodies" if isinstance(frame, (list, tuple, np.ndarray)) else _short(frame)
            want = f"the {nb} bodies of frame 0" if nb is not None else "at least one body"
            raise SceneError(f"{field}[{f}]", f"{n}; expected a list of {want}, each [x, y, angle]")
        nb = len(frame)
        for b, pose in enumerate(frame):
            if not isinstance(pose, (list, tuple, np.ndarray)) or len(pose) != 3:
                raise SceneError(f"{field}[{f}][{b}]", f"{_short(pose)}; expected [x, y, angle] (3 numbers)")
            for c, v in enumerate(pose):
                if not _is_number(v):
                    raise SceneError(f"{field}[{f}][{b}][{c}]", f"{_short(v)}; allowed: {num}")
    p = _as_floats(field, value, num)
    bad = np.argwhere(~np.isfinite(p))
    if bad.size:
        f, b, c = (int(x) for x in bad[0])
        raise SceneError(f"{field}[{f}][{b}][{c}]", f"{value[f][b][c]!r} is not a finite number; allowed: {num}")
    return p


class _ProgressActuation:
    """Wraps a dynamics model's actuation callback to report the simulated time (attributes forwarded)."""

    def __init__(self, inner, seconds, progress):
        self._inner, self._seconds, self._progress = inner, max(float(seconds), 1e-12), progress

    def __call__(self, t, sim):
        self._progress(min(1.0, t / self._seconds))
        return self._inner(t, sim)

    def __getattr__(self, name):
        return getattr(self._inner, name)


def check_run_dynamics(scene, seconds, fps):
    """Refuse, before any simulation work, a run of :func:`run_dynamics` that is over the command line's size
    budget or could not be played: a scene whose ``dynamics.model`` is not ``"sheet"`` (checked first: the belt has
    no sheet nodes, :class:`TrajectoryPlayer` refuses its trajectory), more than ``MAX_FRAMES`` recorded frames, more than ``MAX_STEPS`` time steps at
    the scene's ``dynamics.integrator.dt_s``, more than ``MAX_POSES`` recorded body poses of the built model (the
    build is cheap: no settling, no integration). The step the integrator chooses itself (no
    ``dt_s``) is checked by ``simulate`` before its first step. The Animate panel calls this before it starts its
    background thread, so the refusal shows at once.

    Parameters
    ----------
    scene : Scene
    seconds : float
        Simulated duration (s).
    fps : float
        Frames per second recorded.

    Returns
    -------
    tuple
        ``(cfg, model)``: the scene's dynamics configuration and the built model.

    Raises
    ------
    SceneError
        Naming the field, the value and the limit.
    """
    from metamaterial_wb.core.dynamics.builders import build, dynamics_config
    from metamaterial_wb.core.dynamics.simulate import check_output_budget, check_step_budget

    cfg = dynamics_config(scene)
    if cfg["model"] != "sheet":         # first: a belt is never played, whatever its length
        raise SceneError("dynamics.model", f"{cfg['model']!r}: {ONLY_SHEET}")
    check_output_budget(seconds, fps)
    dt = cfg["integrator"]["dt_s"]
    if dt is not None:
        check_step_budget(seconds, dt, how=f"{seconds:g} s / dynamics.integrator.dt_s {dt:g} s")
    model = build(scene, cfg)
    check_output_budget(seconds, fps, int(model.system.n))
    if model.kind != "sheet":
        raise SceneError("dynamics.model", f"{model.kind!r}: {ONLY_SHEET}")
    return cfg, model


def run_dynamics(scene, seconds, fps=30.0, progress=None):
    """Simulate ``scene`` with core.dynamics (as ``simulate --out``) and return
    ``(trajectory dict, summary dict)``; the dict is what ``DIR/trajectory.json`` holds.

    Parameters
    ----------
    scene : Scene
    seconds : float
        Simulated duration (s).
    fps : float, optional
        Frames per second recorded.
    progress : callable, optional
        Called with progress updates.

    Returns
    -------
    tuple of dict
        ``(trajectory, summary)``.
    """
    from metamaterial_wb.core.results import trajectory_dict
    from metamaterial_wb.core.dynamics.simulate import simulate

    cfg, model = check_run_dynamics(scene, seconds, fps)   # before any work: the budget, the model
    model.scene_nodes = scene.topology.nodes
    if progress is not None and model.actuate is not None:
        model.actuate = _ProgressActuation(model.actuate, seconds, progress)
    # frames are states at time steps (core.dynamics.frames): at most one per step of the scene's dt_s. The panel
    # plays by times_s, interpolating between frames, so recording at the step rate below the timer's rate loses
    # nothing; the summary's integrator.recording says what was recorded (the command line refuses --fps > 1 / dt)
    dt = cfg["integrator"]["dt_s"]
    record_dt = max(1.0 / fps, dt) if dt else 1.0 / fps
    summary, traj, model, _sim = simulate(scene, seconds, record_dt=record_dt, cfg=cfg, model=model)
    if progress is not None:
        progress(1.0)
    return trajectory_dict(model, traj), summary
