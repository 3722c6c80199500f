"""High level: simulate a scene for some seconds and summarise (used by the CLI, tests, benchmarks)."""
from __future__ import annotations

import time

import numpy as np

from .builders import build, dynamics_config
from .integrators import Simulator


class Trajectory:
    def __init__(self):
        self.t = []
        self.q = []
        self.extra = []

    def arrays(self):
        return np.array(self.t), np.array(self.q)


def simulate(scene, seconds, method=None, dt=None, record_dt=None, cfg=None, model=None):
    """Run the scene's dynamics. Returns ``(summary dict, Trajectory, model, simulator)``."""
    t_wall = time.perf_counter()
    cfg = cfg or dynamics_config(scene)
    model = model or build(scene, cfg)
    method = method or cfg["integrator"]["method"]
    if dt is None:
        dt = cfg["integrator"]["dt_s"]
    sim = Simulator(model.system, model.q0, actuate=model.actuate)
    sim.energy_scale = float(model.system.mass.sum() * 9.81 * 0.05)
    traj = Trajectory()
    if record_dt is None:
        record_dt = max(seconds / 200.0, 1e-3)

    def rec(S):
        traj.t.append(S.t)
        traj.q.append(S.q.copy())
        if model.kind == "belt":
            traj.extra.append(model.actuate.p.copy())

    t_build = time.perf_counter() - t_wall
    sim.run(seconds, method=method, dt=dt, record_dt=record_dt, on_record=rec)
    t, q = traj.arrays()
    com = np.array([model.com_x(qq) for qq in q])
    disp_mm = (com[-1] - com[0]) * 1e3
    summary = {
        "format": "metamaterial-simulation", "version": 1, "scene": scene.name, "model": model.kind,
        "seconds": seconds, "displacement_mm": disp_mm,
        "mean_speed_mm_s": disp_mm / seconds if seconds > 0 else 0.0,
        "min_com_displacement_mm": float((com.min() - com[0]) * 1e3),
        "max_com_displacement_mm": float((com.max() - com[0]) * 1e3),
        "energy": sim.energy_report(),
        "integrator": dict(sim.stats, build_s=t_build, realtime_factor=seconds / max(sim.stats["wall_s"], 1e-9)),
        "incline_deg": cfg["incline_deg"],
        "model_info": model.info,
    }
    if model.kind == "belt":
        # "rolls back": the centre of mass ends more than one cell length downhill / backwards
        summary["rolled_back"] = bool(disp_mm < -cfg["belt"]["cell_length_mm"])
    return summary, traj, model, sim
