"""Animate: timeline from the motors' motion profiles or a simulated trajectory; streaming."""
import json
import math
import os
import time

import FreeCAD
from PySide import QtCore, QtGui

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.objects import structure
from metamaterial_wb.gui.panels.base import BasePanel, transaction, _slider, np_zeros
from metamaterial_wb.gui.panels.overlays import FloorOverlay


def hardware_available():
    """True when the hardware package (serial link + streamer) can be imported."""
    try:
        from metamaterial_wb.hardware import Link, Streamer, channel_map  # noqa: F401
        return True
    except ImportError:
        return False


class AnimatePanel(BasePanel):
    """Timeline from the motors' motion profiles: play / pause / loop / speed, optional streaming."""
    TITLE = "Animate"
    ICON = "MM_Animate.svg"

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        self.saved = structure.display_state(scene_obj)
        self.scene = structure.compose_scene(scene_obj)
        self.solver = structure.solver_for(scene_obj, self.scene)
        self.table = QtGui.QTableWidget(len(self.scene.actuators), 4)
        self.table.setHorizontalHeaderLabels(["motor", "amplitude", "freq (Hz)", "phase (deg)"])
        self.spins = {}
        for r, a in enumerate(self.scene.actuators):
            p = a.profile or {"shape": "sine", "amplitude": 0.0, "frequency_hz": 0.5, "phase_deg": 0.0}
            self.table.setItem(r, 0, QtGui.QTableWidgetItem(a.name))
            sp = []
            for c, (key, lo, hi, default) in enumerate((("amplitude", 0.0, 1.0, 0.5), ("frequency_hz", 0.0, 50.0, 0.5),
                                                         ("phase_deg", -360.0, 360.0, 0.0)), start=1):
                w = QtGui.QDoubleSpinBox()
                w.setRange(lo, hi)
                w.setSingleStep(0.05 if key != "phase_deg" else 15.0)
                w.setValue(float(p.get(key, default)) if p.get("shape", "sine") == "sine" else default)
                w.setEnabled(p.get("shape", "sine") == "sine")
                w.valueChanged.connect(self._profiles_changed)
                self.table.setCellWidget(r, c, w)
                sp.append(w)
            self.spins[a.name] = sp
        self.table.setMaximumHeight(40 + 30 * max(1, len(self.scene.actuators)))
        self.table.horizontalHeader().setStretchLastSection(True)
        self.layout.addWidget(self.table)
        tl = QtGui.QHBoxLayout()
        self.play_btn = QtGui.QPushButton("Play")
        self.play_btn.setCheckable(True)
        self.loop = QtGui.QCheckBox("Loop")
        self.loop.setChecked(True)
        self.speed = QtGui.QDoubleSpinBox()
        self.speed.setRange(0.05, 10.0)
        self.speed.setValue(1.0)
        self.speed.setSuffix(" x")
        self.duration = QtGui.QDoubleSpinBox()
        self.duration.setRange(0.1, 600.0)
        self.duration.setValue(self.default_duration())
        self.duration.setSuffix(" s")
        tl.addWidget(self.play_btn)
        tl.addWidget(self.loop)
        tl.addWidget(QtGui.QLabel("speed"))
        tl.addWidget(self.speed)
        tl.addWidget(QtGui.QLabel("length"))
        tl.addWidget(self.duration)
        self.layout.addLayout(tl)
        self.timeline = _slider(0, 1000, 0)
        self.time_label = QtGui.QLabel("t = 0.00 s")
        self.layout.addWidget(self.timeline)
        self.layout.addWidget(self.time_label)
        hl = QtGui.QHBoxLayout()
        self.connect_btn = QtGui.QPushButton("Connect")
        self.connect_btn.setCheckable(True)
        from metamaterial_wb.gui import preferences
        self.port = QtGui.QLineEdit(preferences.get("SerialPort"))
        hl.addWidget(QtGui.QLabel("Port"))
        hl.addWidget(self.port)
        hl.addWidget(self.connect_btn)
        self.layout.addLayout(hl)
        if not hardware_available():
            self.connect_btn.setEnabled(False)
            self.connect_btn.setToolTip("the hardware package (metamaterial_wb.hardware) is not available")
        else:
            self.connect_btn.setToolTip("Stream the values shown to the servo firmware at 50 Hz "
                                        "(port loop:// = dry run without hardware)")
        # simulated trajectory (core.dynamics): load DIR/trajectory.json or simulate in the background
        tg = QtGui.QGroupBox("Simulated trajectory (dynamics: gravity, floor contact, friction)")
        tv = QtGui.QVBoxLayout(tg)
        th = QtGui.QHBoxLayout()
        self.traj_load_btn = QtGui.QPushButton("Load...")
        self.traj_load_btn.setToolTip("Play DIR/trajectory.json written by "
                                      "'python3 -m metamaterial_wb simulate SCENE --seconds S --out DIR'")
        self.traj_seconds = QtGui.QDoubleSpinBox()
        self.traj_seconds.setRange(0.05, 600.0)
        self.traj_seconds.setValue(4.0)
        self.traj_seconds.setSuffix(" s")
        self.traj_sim_btn = QtGui.QPushButton("Simulate")
        self.traj_sim_btn.setToolTip("Run the dynamics model on this structure in the background, then play it")
        self.traj_off_btn = QtGui.QPushButton("Motors")
        self.traj_off_btn.setToolTip("Back to the motion profiles (quadratic model)")
        self.traj_off_btn.setEnabled(False)
        th.addWidget(self.traj_load_btn)
        th.addWidget(self.traj_seconds)
        th.addWidget(self.traj_sim_btn)
        th.addWidget(self.traj_off_btn)
        tv.addLayout(th)
        self.traj_progress = QtGui.QProgressBar()
        self.traj_progress.setRange(0, 1000)
        self.traj_progress.setValue(0)
        self.traj_progress.setVisible(False)
        tv.addWidget(self.traj_progress)
        self.traj_label = QtGui.QLabel("playing: the motors' profiles")
        self.traj_label.setWordWrap(True)
        tv.addWidget(self.traj_label)
        self.layout.addWidget(tg)
        self.stats = QtGui.QLabel("")
        self.layout.addWidget(self.stats)
        self.finish_layout()
        self.trajectory = None
        self.trajectory_data = None
        self.floor = None
        self.sim_job = None
        self.sim_timer = QtCore.QTimer()
        self.sim_timer.setInterval(100)
        self.sim_timer.timeout.connect(self._poll_simulation)
        self.traj_load_btn.clicked.connect(self._browse_trajectory)
        self.traj_sim_btn.clicked.connect(lambda: self.simulate_trajectory(self.traj_seconds.value()))
        self.traj_off_btn.clicked.connect(self.clear_trajectory)
        self.t = 0.0
        self.frames = 0
        self.streamer = None
        self.link = None
        self.stream_error = None
        self.shown_values = {}
        self.preview_scene = self.scene
        fps = max(1, int(preferences.get("AnimationFps")))
        self.dt = 1.0 / fps
        self.timer = QtCore.QTimer()
        self.timer.setInterval(int(1000 / fps))
        self.timer.timeout.connect(self.tick)
        self.play_btn.toggled.connect(self._play_toggled)
        self.timeline.sliderMoved.connect(self._scrub)
        self.connect_btn.toggled.connect(self._connect_toggled)
        self._profiles_changed()
        self.show_time(0.0)

    def default_duration(self):
        freqs = [a.profile.get("frequency_hz", 0) for a in self.scene.actuators
                 if a.profile and a.profile.get("shape", "sine") == "sine" and a.profile.get("frequency_hz", 0) > 0]
        if freqs:
            return round(max(1.0 / min(freqs), 0.5), 3)
        periods = [a.profile.get("period_s") for a in self.scene.actuators if a.profile and a.profile.get("period_s")]
        return float(max(periods)) if periods else 4.0

    def profiles(self):
        out = {}
        for a in self.scene.actuators:
            if a.profile is not None and a.profile.get("shape", "sine") != "sine":
                out[a.name] = dict(a.profile)
                continue
            amp, f, ph = (w.value() for w in self.spins[a.name])
            p = {"shape": "sine", "amplitude": float(amp), "frequency_hz": float(f), "phase_deg": float(ph)}
            if a.profile and a.profile.get("offset"):
                p["offset"] = a.profile["offset"]
            out[a.name] = p
        return out

    def set_profile(self, name, amplitude=None, frequency_hz=None, phase_deg=None):
        w = self.spins[name]
        for spin, v in zip(w, (amplitude, frequency_hz, phase_deg)):
            if v is not None:
                spin.setValue(v)

    def _profiles_changed(self, *_):
        d = self.scene.to_dict()
        prof = self.profiles()
        for a in d["actuators"]:
            a["profile"] = prof[a["name"]]
        try:
            self.preview_scene = Scene.from_dict(d)
            self.error.setText("")
        except MetamaterialError as exc:
            self.show_error(str(exc))

    def values_at(self, t):
        from metamaterial_wb.core.motion import scene_values_at
        return self.solver.values_with(scene_values_at(self.preview_scene, t))

    # simulated trajectory ---------------------------------------------------------------------
    def _browse_trajectory(self):  # pragma: no cover - modal file dialog, tests call load_trajectory
        path, _ = QtGui.QFileDialog.getOpenFileName(self.form, "Trajectory", "", "Trajectory (*.json)")
        if path:
            self.load_trajectory(path)

    def load_trajectory(self, source):
        """Play a trajectory: a path to ``trajectory.json`` (or the ``simulate --out`` folder holding it) or
        its parsed dict. Returns True on success (False with the reason shown in the panel)."""
        from metamaterial_wb.objects.engine import TrajectoryPlayer
        try:
            if isinstance(source, dict):
                data, label = source, "simulated here"
            else:
                if os.path.isdir(source):                  # the simulate --out folder
                    source = os.path.join(source, "trajectory.json")
                try:
                    with open(source) as f:
                        data = json.load(f)
                except (OSError, ValueError) as exc:
                    raise MetamaterialError(f"trajectory {source}: cannot read it ({exc})") from None
                label = os.path.basename(os.path.dirname(os.path.abspath(source))) + "/" + os.path.basename(source)
            flat, _R = self.solver.poses(np_zeros(self.scene.topology.n_nodes))
            player = TrajectoryPlayer(data, self.scene, flat)
        except MetamaterialError as exc:
            self.show_error(str(exc))
            return False
        self.pause()
        self._remove_floor()
        self.trajectory, self.trajectory_data = player, data
        try:
            self.floor = FloorOverlay(self.obj.Document, player.floor_corners(float(self.scene.cell_size_mm)))
        except Exception as exc:  # pragma: no cover - display only (no 3D view)
            FreeCAD.Console.PrintWarning(f"Metamaterial: no floor shown ({exc})\n")
        self.duration.setValue(max(0.1, round(player.duration, 3)))
        self.table.setEnabled(False)
        self.traj_off_btn.setEnabled(True)
        self.traj_label.setText(f"playing: {label}, {player.times.size} frames, {player.duration:.2f} s, "
                                f"incline {math.degrees(player.incline):g} deg (side view mapped onto the "
                                "x-z plane: one rigid body per column)")
        self.error.setText("")
        self.show_time(0.0)
        return True

    def _remove_floor(self):
        if getattr(self, "floor", None) is not None:
            self.floor.remove()
        self.floor = None

    def clear_trajectory(self):
        self.pause()
        self._remove_floor()
        self.trajectory = self.trajectory_data = None
        self.table.setEnabled(True)
        self.traj_off_btn.setEnabled(False)
        self.traj_label.setText("playing: the motors' profiles")
        self.duration.setValue(self.default_duration())
        self.solver._last = None
        self.show_time(0.0)

    def simulate_trajectory(self, seconds):
        """Run core.dynamics on this structure in a background thread (progress bar); plays it when done."""
        import threading

        from metamaterial_wb.objects.engine import run_dynamics
        if self.sim_job is not None:
            self.show_error("a simulation is already running")
            return False
        scene = structure.compose_scene(self.obj)
        d = scene.to_dict()
        prof = self.profiles()
        for a in d["actuators"]:
            a["profile"] = prof[a["name"]]
        scene = Scene.from_dict(d)
        job = {"progress": 0.0, "result": None, "error": None, "done": False, "seconds": float(seconds),
               "fps": 1.0 / self.dt}

        def work():
            try:
                job["result"] = run_dynamics(scene, job["seconds"], fps=job["fps"],
                                             progress=lambda f: job.__setitem__("progress", f))
            except Exception as exc:  # noqa: BLE001 - reported in the panel
                job["error"] = str(exc)
            job["done"] = True

        self.sim_job = job
        self.traj_sim_btn.setEnabled(False)
        self.traj_progress.setValue(0)
        self.traj_progress.setVisible(True)
        self.traj_label.setText(f"simulating {seconds:g} s ...")
        job["thread"] = threading.Thread(target=work, daemon=True)
        job["thread"].start()
        self.sim_timer.start()
        return True

    def _poll_simulation(self):
        job = self.sim_job
        if job is None:
            self.sim_timer.stop()
            return
        self.traj_progress.setValue(int(1000 * min(1.0, job["progress"])))
        if not job["done"]:
            return
        self.sim_timer.stop()
        self.sim_job = None
        self.traj_sim_btn.setEnabled(True)
        self.traj_progress.setVisible(False)
        if job["error"]:
            self.show_error(f"simulation failed: {job['error']}")
            self.traj_label.setText("playing: the motors' profiles")
            return
        data, summary = job["result"]
        self.last_simulation = summary
        if self.load_trajectory(data):
            self.traj_label.setText(self.traj_label.text() + f"; centre of mass moved "
                                    f"{summary['displacement_mm']:+.2f} mm")

    def wait_simulation(self, timeout_s=60.0):
        """Block (processing events) until the background simulation is done (tests, scripts)."""
        end = time.perf_counter() + timeout_s
        while self.sim_job is not None and time.perf_counter() < end:
            QtGui.QApplication.processEvents()
            time.sleep(0.01)
        return self.sim_job is None

    def show_time(self, t):
        t0 = time.perf_counter()
        self.t = t
        vals = self.values_at(t)
        try:
            if self.trajectory is not None:
                frame = self.trajectory.frame(self.solver, min(t, self.trajectory.duration))
            else:
                frame = self.solver.frame(values=vals)
        except MetamaterialError as exc:
            self.show_error(str(exc))
            self.pause()
            return
        structure.apply_frame(self.obj, self.solver, frame, purge=True)
        self.frames += 1
        self.last_values = vals
        dur = self.duration.value()
        self.timeline.blockSignals(True)
        self.timeline.setValue(int(round(1000 * min(t, dur) / dur)))
        self.timeline.blockSignals(False)
        self.time_label.setText(f"t = {t:.2f} s")
        # what is shown is what the streamer sends (its thread reads this dict at 50 Hz)
        self.shown_values = {a.name: float(vals[a.name]) for a in self.scene.actuators}
        if self.stream_error:
            self.show_error(f"streaming stopped: {self.stream_error}")
            self.stream_error = None
            self.connect_btn.setChecked(False)
        self.stats.setText(f"frame {self.frames}: {1000 * (time.perf_counter() - t0):.1f} ms (no recompute)")

    def step(self, n=1):
        """Advance ``n`` frames as the timer would (tests and scripted playback)."""
        for _ in range(n):
            self.tick()

    def tick(self):
        t = self.t + self.dt * self.speed.value()
        dur = self.duration.value()
        if t > dur:
            if self.loop.isChecked():
                t = t - dur
            else:
                t = dur
                self.pause()
        self.show_time(t)

    def play(self):
        self.play_btn.setChecked(True)

    def pause(self):
        self.play_btn.setChecked(False)

    def _play_toggled(self, on):
        if on:
            self.play_btn.setText("Pause")
            self.timer.start()
        else:
            self.play_btn.setText("Play")
            self.timer.stop()

    def _scrub(self, v):
        self.show_time(v / 1000.0 * self.duration.value())

    # hardware ---------------------------------------------------------------------------
    def _connect_toggled(self, on):
        if on:
            self.connect(self.port.text().strip())
        else:
            self.disconnect()

    def connect(self, port):
        """Open the serial link, hand-shake, ARM and stream what the panel shows (50 Hz thread)."""
        from metamaterial_wb.hardware import Link, Streamer, channel_map
        link = None
        try:
            dry = port.startswith("loop://")
            link = Link.open(port, dry_run=dry)
            streamer = Streamer(link, channel_map(self.preview_scene))
            streamer.prepare()
            streamer.on_error = self._stream_failed
            if not self.shown_values:
                self.show_time(self.t)
            streamer.start(lambda _t: dict(self.shown_values))
        except Exception as exc:
            if link is not None:
                try:
                    link.close()
                except Exception:
                    pass
            self.show_error(f"cannot stream to {port}: {exc}")
            self.connect_btn.blockSignals(True)
            self.connect_btn.setChecked(False)
            self.connect_btn.blockSignals(False)
            return False
        self.link, self.streamer = link, streamer
        self.connect_btn.blockSignals(True)
        self.connect_btn.setChecked(True)
        self.connect_btn.blockSignals(False)
        self.connect_btn.setText("Disconnect")
        return True

    def _stream_failed(self, message):  # called from the streaming thread
        self.stream_error = message

    def disconnect(self):
        stats = None
        if self.streamer is not None:
            try:
                stats = self.streamer.stop(disarm=False)
            except Exception:
                pass
        if self.link is not None:
            try:
                self.link.close()
            except Exception:
                pass
        self.streamer = self.link = None
        self.connect_btn.blockSignals(True)
        self.connect_btn.setChecked(False)
        self.connect_btn.blockSignals(False)
        self.connect_btn.setText("Connect")
        if stats is not None:
            self.stats.setText(f"streamed {stats.frames} frames, {stats.acked} acknowledged")
        return stats

    def cleanup(self):
        self.timer.stop()
        self.sim_timer.stop()
        self._remove_floor()
        if self.sim_job is not None:
            self.sim_job = None       # the daemon thread finishes on its own; its result is dropped
        self.disconnect()
        super().cleanup()

    def apply(self):
        self.timer.stop()
        structure.restore_display(self.obj, self.saved)
        prof = self.profiles()
        doc = self.obj.Document
        with transaction(doc, "Animate: motion profiles"):
            for it in self.obj.Items:
                p = prof.get(it.ItemName)
                if it.Kind != "actuator" or p is None or p.get("shape") != "sine":
                    continue
                if it.ProfileShape != "sine":
                    it.ProfileShape = "sine"
                for prop, key in (("Amplitude", "amplitude"), ("FrequencyHz", "frequency_hz"),
                                  ("PhaseDeg", "phase_deg")):
                    if abs(getattr(it, prop) - p[key]) > 1e-12:
                        setattr(it, prop, p[key])
            doc.recompute()

    def reject(self):
        self.timer.stop()
        structure.restore_display(self.obj, self.saved)
        return super().reject()


# ----------------------------------------------------------------------------------------------
