"""Animate: timeline from the motors' motion profiles or a simulated trajectory; streaming.

The clock follows wall time: each timer tick shows the frame of *now* (start time + elapsed wall time
x speed), so a frame that costs more than its slot makes the next ones skip ahead (frames are dropped,
time is not). The panel shows the achieved frame rate and the real-time factor (timeline seconds played
per wall second, across the loop's wraps; 1.00 = real time, 2.00 at speed 2). The stream controller sends the values for the wall-clock
time, whatever the view manages to draw: it calls ``clock()`` from its own thread, which reads only plain
attributes (one anchor tuple replaced whole, and copies of the play / length / loop settings kept by the
widgets' signals), never a Qt widget. Frames are drawn by the Coin preview (``gui/preview.py``), which
writes nothing into the document; Cancel removes it. The motors' profile rows (table or per-motor form,
keyframes, reading the profiles back) are ``animate_table.ProfileRows``, the clock ``animate_clock.PlaybackClock``.
"""
import json
import math
import os
import threading

import FreeCAD
from PySide import QtCore, QtGui

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.objects import structure
from metamaterial_wb.gui.panels.animate_clock import PlaybackClock
from metamaterial_wb.gui.panels.animate_table import OnResize, ProfileRows, set_profile
from metamaterial_wb.gui.panels.base import BasePanel, _slider, np_zeros
from metamaterial_wb.gui.panels.jobs import JobBox, ThreadJob
from metamaterial_wb.gui.panels.overlays import FloorOverlay
from metamaterial_wb.gui.panels.profiles import KeyframeTable
from metamaterial_wb.gui.panels.stream import ServoAngles, StreamController, hardware_available
from metamaterial_wb.gui.panels import ranges
from metamaterial_wb.gui.panels.widgets import SliderKeys
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate


class AnimatePanel(ProfileRows, PlaybackClock, BasePanel):
    """Timeline from the motors' motion profiles: play / pause / loop / speed, optional streaming."""
    VIEW_ATTRS = ("floor",)
    TITLE = QT_TRANSLATE_NOOP("Metamaterial", "Animate")
    ICON = "MM_Animate.svg"
    ITEM_ROWS = True

    def __init__(self, scene_obj):
        from metamaterial_wb.gui import preferences
        fps = preferences.checked("AnimationFps")     # before anything is built: out of 1..120 opens nothing
        super().__init__()
        self.obj = scene_obj
        self.scene = structure.compose_scene(scene_obj)
        self.solver = structure.solver_for(scene_obj, self.scene)
        self.angles = ServoAngles(self.scene)    # the angle stream sends for a value, per motor
        # the profile rows (animate_table.ProfileRows): table or per-motor form, keyframe table, period note;
        # the keyframe table's class is looked up here (tests replace animate.KeyframeTable)
        self._build_profile_rows(KeyframeTable)
        self.layout.addWidget(self.problem_label("profiles"))
        tl = QtGui.QGridLayout()
        self.play_btn = QtGui.QPushButton(translate("Metamaterial", "Play"))
        self.play_btn.setCheckable(True)
        self.loop = QtGui.QCheckBox(translate("Metamaterial", "Loop"))
        self.loop.setChecked(True)
        self.speed = QtGui.QDoubleSpinBox()
        self.speed.setRange(0.05, 10.0)
        ranges.ui_only(self.speed, "playback speed (not stored)")
        self.speed.setValue(1.0)
        self.speed.setSuffix(" x")
        self.duration = QtGui.QDoubleSpinBox()
        self.duration.setRange(0.1, 600.0)
        ranges.ui_only(self.duration, "timeline length shown (not stored)")
        self.duration.setValue(self.default_duration())
        self.duration.setSuffix(" s")
        tl.addWidget(self.play_btn, 0, 0)        # two by two: the panel fits a narrow task dock
        tl.addWidget(QtGui.QLabel(translate("Metamaterial", "speed")), 0, 1)
        tl.addWidget(self.speed, 0, 2)
        tl.addWidget(self.loop, 1, 0)
        tl.addWidget(QtGui.QLabel(translate("Metamaterial", "length")), 1, 1)
        tl.addWidget(self.duration, 1, 2)
        tl.setColumnStretch(2, 1)
        self.layout.addLayout(tl)
        self.timeline = _slider(0, 1000, 0)
        self._slider_keys = SliderKeys()          # Home / End / arrows / Page keys scrub (not FreeCAD's view Home)
        self.timeline.installEventFilter(self._slider_keys)
        self.time_label = QtGui.QLabel(translate("Metamaterial", "t = 0.00 s"))
        self.layout.addWidget(self.timeline)
        self.layout.addWidget(self.time_label)
        hl = QtGui.QHBoxLayout()
        self.connect_btn = QtGui.QPushButton(translate("Metamaterial", "Connect"))
        self.connect_btn.setCheckable(True)
        from metamaterial_wb.gui import preferences
        self.port = QtGui.QLineEdit(preferences.get("SerialPort"))
        hl.addWidget(QtGui.QLabel(translate("Metamaterial", "Port")))
        hl.addWidget(self.port)
        hl.addWidget(self.connect_btn)
        self.layout.addLayout(hl)
        from metamaterial_wb.hardware.link import pyserial_available, pyserial_help
        if not hardware_available():
            self.connect_btn.setEnabled(False)
            self.connect_btn.setToolTip(translate("Metamaterial", "the hardware package (metamaterial_wb.hardware) is not available"))
        elif not pyserial_available():
            self.connect_btn.setEnabled(False)
            self.connect_btn.setToolTip(pyserial_help())
            self.serial_note = QtGui.QLabel(pyserial_help())   # says how to install it; playing still works
            self.serial_note.setWordWrap(True)
            self.layout.addWidget(self.serial_note)
        else:
            self.connect_btn.setToolTip(translate("Metamaterial", "Stream the values shown to the servo firmware at 50 Hz "
                                        "(port loop:// = dry run without hardware)"))
        # simulated trajectory (core.dynamics): load DIR/trajectory.json or simulate in the background
        tg = QtGui.QGroupBox(translate("Metamaterial", "Simulated trajectory"))   # a title never wraps: short
        tv = QtGui.QVBoxLayout(tg)
        what = QtGui.QLabel(translate("Metamaterial", "dynamics: gravity, floor contact, friction"))
        what.setWordWrap(True)
        tv.addWidget(what)
        th = QtGui.QHBoxLayout()
        th2 = QtGui.QHBoxLayout()
        self.traj_load_btn = QtGui.QPushButton(translate("Metamaterial", "Load..."))
        self.traj_load_btn.setToolTip(translate("Metamaterial", "Play DIR/trajectory.json written by "
                                      "'python3 -m metamaterial_wb simulate SCENE --seconds S --out DIR'"))
        self.traj_seconds = QtGui.QDoubleSpinBox()
        self.traj_seconds.setRange(0.05, 600.0)
        ranges.ui_only(self.traj_seconds, "simulated seconds of a background run (not stored in the scene)")
        self.traj_seconds.setValue(4.0)
        self.traj_seconds.setSuffix(" s")
        self.traj_sim_btn = QtGui.QPushButton(translate("Metamaterial", "Simulate"))
        self.traj_sim_btn.setToolTip(translate("Metamaterial", "Run the dynamics model on this structure in the background, then play it"))
        self.traj_off_btn = QtGui.QPushButton(translate("Metamaterial", "Motors"))
        self.traj_off_btn.setToolTip(translate("Metamaterial", "Back to the motion profiles (quadratic model)"))
        self.traj_off_btn.setEnabled(False)
        th.addWidget(self.traj_seconds, 1)      # two lines: the panel fits a narrow task dock
        th.addWidget(self.traj_sim_btn, 1)
        th2.addWidget(self.traj_load_btn, 1)
        th2.addWidget(self.traj_off_btn, 1)
        tv.addLayout(th)
        tv.addLayout(th2)
        self.sim_box = JobBox()
        self.traj_progress = self.sim_box.progress
        tv.addWidget(self.sim_box)
        self.traj_label = QtGui.QLabel(translate("Metamaterial", "playing: the motors' profiles"))
        self.traj_label.setWordWrap(True)
        tv.addWidget(self.traj_label)
        self.layout.addWidget(tg)
        self.values_label = QtGui.QLabel("")
        self.values_label.setWordWrap(True)       # these lines wrap in a narrow task dock
        self.values_label.setToolTip("\n".join([translate(
            "Metamaterial", "motor values now: the angle sent to each servo (value in -1..1)"), self.angles.tooltip()]))
        self.layout.addWidget(self.values_label)
        self.rate_label = QtGui.QLabel("")
        self.rate_label.setWordWrap(True)
        self.rate_label.setToolTip(translate("Metamaterial", "achieved frame rate while playing and the real-time factor (timeline "
                                   "seconds played per wall second): 1.00 = real time, 2.00 at speed 2"))
        self.layout.addWidget(self.rate_label)
        self.stats = QtGui.QLabel("")
        self.stats.setWordWrap(True)
        self.layout.addWidget(self.stats)
        self.finish_layout()
        self._resized = OnResize(self._fit_profiles)   # a resize shows the profiles as a table or as a form
        self.form.installEventFilter(self._resized)
        self.trajectory = None
        self.trajectory_data = None
        self.playing_text = ""            # the label's text for the loaded trajectory (show_playing)
        self.floor = None
        self.sim = ThreadJob(self.sim_box, self._simulated, self._simulation_failed, self._simulation_cancelled)
        self.traj_load_btn.clicked.connect(self._browse_trajectory)
        self.traj_sim_btn.clicked.connect(lambda: self.simulate_trajectory(self.traj_seconds.value()))
        self.traj_off_btn.clicked.connect(self.clear_trajectory)
        self.t = 0.0
        self.frames = 0
        self.frame_ms = None
        self.frame_times = []
        self.stream = StreamController(self.values_at, self.clock, looping=lambda: self._loop)
        self.shown_values = {}
        # (wall time, animation time, speed) of the last start / scrub / speed change / wrap: one tuple, replaced
        # whole on the GUI thread; clock() (also called by the streaming thread) reads it under _clock_lock
        self.anchor = None
        self._clock_lock = threading.Lock()
        # the settings clock() needs, copied from the widgets on the GUI thread (no widget reads elsewhere)
        self._playing = False
        self._duration = self.duration.value()
        self._loop = self.loop.isChecked()
        self.rate_window = []         # (wall, timeline time played) of the frames shown while playing
        self.played_before_anchor = 0.0   # timeline time played in this rate window up to the anchor (loop wraps)
        self.preview_scene = self.scene
        self.dt = 1.0 / fps
        self.timer = QtCore.QTimer()
        self.timer.setInterval(max(1, int(1000 / fps)))
        self.timer.setTimerType(QtCore.Qt.TimerType.PreciseTimer)
        self.timer.timeout.connect(self.tick)
        self.speed.valueChanged.connect(self._speed_changed)
        self.duration.valueChanged.connect(self._duration_changed)
        self.loop.toggled.connect(self._loop_toggled)
        self.play_btn.toggled.connect(self._play_toggled)
        self.timeline.valueChanged.connect(self._scrub)    # drag, click on the groove, keys (show_time blocks it)
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

    def values_at(self, t):
        from metamaterial_wb.core.motion import scene_values_at
        return self.solver.values_with(scene_values_at(self.preview_scene, t))

    # simulated trajectory ---------------------------------------------------------------------
    def _busy_simulating(self, action):
        """While the background simulation runs, Load... and Motors are refused (red line: why, what to do): the
        label keeps saying "simulating ...", and the run's trajectory, which then plays as Simulate says, does not
        replace what the user chose meanwhile. ``action`` is the translated button text. True when refused."""
        if not self.sim.running:
            return False
        self._busy_said = translate("Metamaterial", "{0} refused: a simulation is running; wait for it to end (its "
                                    "trajectory then plays) or press Cancel, then {0} again").format(action)
        self.show_error(self._busy_said)
        return True

    def _clear_busy_note(self):
        """The run ended: a refusal of Load... / Motors it caused no longer holds (another message stays)."""
        if self.error.text() and self.error.text() == getattr(self, "_busy_said", None):
            self.clear_error()

    def _browse_trajectory(self):
        if self._busy_simulating(translate("Metamaterial", "Load...")):   # before the file dialog opens
            return
        path, _ = QtGui.QFileDialog.getOpenFileName(self.form, translate("Metamaterial", "Trajectory"), "",
                                                    translate("Metamaterial", "Trajectory (*.json)"))
        if path:
            self.load_trajectory(path)

    def load_trajectory(self, source):
        """Play a trajectory: a path to ``trajectory.json`` (or the ``simulate --out`` folder holding it) or
        its parsed dict. Returns True on success (False with the reason shown in the panel; also while the
        background simulation runs)."""
        from metamaterial_wb.core.playback import TrajectoryPlayer
        if self._busy_simulating(translate("Metamaterial", "Load...")):
            return False
        try:
            if isinstance(source, dict):
                data, label = source, translate("Metamaterial", "simulated here")
            else:
                if os.path.isdir(source):                  # the simulate --out folder
                    source = os.path.join(source, "trajectory.json")
                try:
                    with open(source, encoding="utf-8") as f:
                        data = json.load(f)
                except (OSError, ValueError) as exc:
                    raise MetamaterialError(translate("Metamaterial", "trajectory {0}: cannot read it ({1})").format(
                        source, exc)) from None
                label = os.path.basename(os.path.dirname(os.path.abspath(source))) + "/" + os.path.basename(source)
            flat, _R = self.solver.poses(np_zeros(self.scene.topology.n_nodes))
            player = TrajectoryPlayer(data, self.scene, flat, source=None if isinstance(source, dict) else source)
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
        self.motor_form.setEnabled(False)
        self.traj_off_btn.setEnabled(True)
        self.playing_text = translate("Metamaterial", "playing: {0}, {1} frames, {2:.2f} s, incline {3:g} deg (side view mapped onto the x-z plane: one rigid body per column)").format(label, player.times.size, player.duration, math.degrees(player.incline))
        self.show_playing()
        self.error.setText("")
        self.show_time(0.0)
        return True

    def show_playing(self, note=None):
        """The trajectory label says what plays now: the loaded trajectory (its file / frames) or the motors'
        profiles; ``note`` (a translated "...{0}" text) wraps it: a cancelled simulation keeps what was playing."""
        text = (self.playing_text if self.trajectory is not None
                else translate("Metamaterial", "playing: the motors' profiles"))
        self.traj_label.setText(text if note is None else note.format(text))

    def _remove_floor(self):
        if getattr(self, "floor", None) is not None:
            self.floor.remove()
        self.floor = None

    def clear_trajectory(self):
        """Motors: back to the motion profiles (refused while the background simulation runs). True when done."""
        if self._busy_simulating(translate("Metamaterial", "Motors")):
            return False
        self.pause()
        self._remove_floor()
        self.trajectory = self.trajectory_data = None
        self.table.setEnabled(True)
        self.motor_form.setEnabled(True)
        self.traj_off_btn.setEnabled(False)
        self.show_playing()
        self.duration.setValue(self.default_duration())
        self.solver._last = None
        self.show_time(0.0)
        return True

    @property
    def sim_job(self):
        return self.sim if self.sim.running else None

    def simulate_trajectory(self, seconds):
        """Run core.dynamics on this structure in a background thread (progress bar + Cancel); plays it
        when done."""
        from metamaterial_wb.core.playback import check_run_dynamics, run_dynamics
        if self.sim.running:
            self.show_error(translate("Metamaterial", "a simulation is already running"))
            return False
        scene = structure.compose_scene(self.obj)
        d = scene.to_dict()
        prof = self.profiles()
        for a in d["actuators"]:
            set_profile(a, prof[a["name"]])
        scene = Scene.from_dict(d)
        fps = 1.0 / self.dt
        try:                           # at once, before the background thread: over the budget, a belt scene
            check_run_dynamics(scene, float(seconds), fps)
        except MetamaterialError as exc:
            self._simulation_failed(str(exc))
            return False
        self.traj_sim_btn.setEnabled(False)
        self.traj_label.setText(translate("Metamaterial", "simulating {0:g} s ...").format(seconds))
        self.clear_error()
        return self.sim.start(lambda report: run_dynamics(scene, float(seconds), fps=fps,
                                                          progress=lambda f: report(f)),
                              text=translate("Metamaterial", "simulating {0:g} s of dynamics ...").format(seconds))

    def _simulated(self, result):
        self.traj_sim_btn.setEnabled(True)
        data, summary = result
        self.last_simulation = summary
        if self.load_trajectory(data):
            self.playing_text = translate("Metamaterial", "{0}; centre of mass moved {1:+.2f} mm").format(
                self.playing_text, summary["displacement_mm"])
            self.show_playing()
            if summary.get("warnings"):   # what simulate prints (energy ledger, Newton, fallbacks): never hidden
                self.show_error(translate("Metamaterial", "simulation warning: {0}").format(
                    "\n".join(summary["warnings"])))
        else:                             # refused (the red line says why): what played before still plays
            self.show_playing()

    def _simulation_failed(self, message):
        self.traj_sim_btn.setEnabled(True)
        self.show_error(translate("Metamaterial", "simulation failed: {0}").format(message))
        self.show_playing()

    def _simulation_cancelled(self):
        self.traj_sim_btn.setEnabled(True)
        self._clear_busy_note()
        self.show_playing(translate("Metamaterial", "simulation cancelled; {0}"))

    def wait_simulation(self, timeout_s=60.0):
        """Block (processing events) until the background simulation is done (tests, scripts)."""
        return self.sim.wait(timeout_s)

    # hardware ---------------------------------------------------------------------------
    def _connect_toggled(self, on):
        if on:
            self.connect(self.port.text().strip())
        else:
            self.disconnect()

    @property
    def streamer(self):
        return self.stream.streamer

    def connect(self, port):
        """Open the serial link, hand-shake, ARM and stream the values of the animation clock (50 Hz)."""
        try:
            if not self.shown_values:
                self.show_time(self.t)
            QtGui.QApplication.setOverrideCursor(QtCore.Qt.CursorShape.WaitCursor)   # the whole timeline: up to
            try:                                                                    # seconds on a long one
                problem = self.stream.follow_problem(self.preview_scene, self.duration.value(), self.speed.value())
            finally:
                QtGui.QApplication.restoreOverrideCursor()
            if problem:
                raise MetamaterialError(problem)
            self.stream.connect(port, self.preview_scene)
        except Exception as exc:  # noqa: BLE001 - shown in the panel
            self.show_error(translate("Metamaterial", "cannot stream to {0}: {1}").format(port, exc))
            self.connect_btn.blockSignals(True)
            self.connect_btn.setChecked(False)
            self.connect_btn.blockSignals(False)
            return False
        self.clear_error()
        self.connect_btn.blockSignals(True)
        self.connect_btn.setChecked(True)
        self.connect_btn.blockSignals(False)
        self.connect_btn.setText(translate("Metamaterial", "Disconnect"))
        return True

    def disconnect(self):
        stats = self.stream.disconnect()
        self.connect_btn.blockSignals(True)
        self.connect_btn.setChecked(False)
        self.connect_btn.blockSignals(False)
        self.connect_btn.setText(translate("Metamaterial", "Connect"))
        if stats is not None:
            self.stats.setText(translate("Metamaterial", "streamed {0} frames, {1} acknowledged").format(stats.frames, stats.acked))
        return stats

    def target_lost(self):
        """The structure is gone: playback, the background simulation and the stream stop, the floor goes."""
        self._stop_timer()                # every time: Play pressed again stops at its first frame
        self.play_btn.blockSignals(True)
        self.play_btn.setChecked(False)
        self.play_btn.setText(translate("Metamaterial", "Play"))
        self.play_btn.blockSignals(False)
        if getattr(self, "_lost", False):
            return
        for stop in (self.sim.stop, self._remove_floor, self.disconnect):
            try:
                stop()
            except Exception as exc:  # pragma: no cover - its view / link went with the structure
                FreeCAD.Console.PrintWarning(f"Metamaterial: {exc}\n")
        super().target_lost()

    def cleanup(self):
        try:
            self.form.removeEventFilter(self._resized)
        except RuntimeError:  # pragma: no cover - the form is gone already
            pass
        self._stop_timer()
        self.sim.stop()               # the daemon thread stops at its next progress report
        self._remove_floor()
        self.disconnect()
        super().cleanup()

    def apply(self):
        self._stop_timer()
        prof = self.profiles()
        doc = self.obj.Document

        def change():
            import json
            for it in self.obj.Items:
                p = prof.get(it.ItemName)
                if it.Kind != "actuator" or p is None:
                    continue
                if p["shape"] == "sine":
                    if it.ProfileShape != "sine":
                        it.ProfileShape = "sine"
                    for prop, key in (("Amplitude", "amplitude"), ("FrequencyHz", "frequency_hz"),
                                      ("PhaseDeg", "phase_deg")):
                        if abs(getattr(it, prop) - p[key]) > 1e-12:
                            setattr(it, prop, p[key])
                else:
                    data = json.dumps({k: v for k, v in p.items() if k != "shape"})
                    if it.ProfileShape != p["shape"]:
                        it.ProfileShape = p["shape"]
                    if it.ProfileData != data:
                        it.ProfileData = data
        self.commit(doc, "Animate: motion profiles", change)

    def reject(self):
        self._stop_timer()
        return super().reject()


# ----------------------------------------------------------------------------------------------
