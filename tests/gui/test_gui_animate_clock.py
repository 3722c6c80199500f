"""Defect 3 of issue 15: the animation clock follows wall time (frames that cost more than their slot
are dropped, time is not), the panel shows the achieved frame rate and the real-time factor, and the
stream sends the values of the wall-clock time, not the last frame drawn. Driven by clicks on Play /
Pause / Connect; a frame is made expensive (80 ms, like a software-rendered 20 x 20 sheet)."""
import time

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from metamaterial_wb.core.motion import scene_values_at  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import click, doc, press_ok, process, run_panel, type_into, workbench  # noqa: E402,F401

FRAME_COST_S = 0.08


def open_fish(doc):
    p = run_panel("MM_OpenExample")
    p.select("fish")
    assert press_ok()
    return structure.find_scene_objects(doc)[-1]


@pytest.fixture
def slow_frames(monkeypatch):
    """Every frame drawn costs FRAME_COST_S more (the panels draw through the Coin preview)."""
    from metamaterial_wb.gui.preview import Preview
    real = Preview.show

    def slow(self, *a, **kw):
        time.sleep(FRAME_COST_S)
        return real(self, *a, **kw)
    monkeypatch.setattr(Preview, "show", slow)


def play_for(p, seconds):
    click(p.play_btn)
    t0 = time.perf_counter()
    process(int(seconds * 1000))
    click(p.play_btn)          # Pause
    return time.perf_counter() - t0


def test_clock_follows_wall_time_and_drops_frames(doc, slow_frames):
    open_fish(doc)
    p = run_panel("MM_Animate")
    p.loop.setChecked(False)
    p.duration.setValue(30.0)
    f0 = p.frames
    wall = play_for(p, 1.5)
    frames = p.frames - f0
    assert p.t == pytest.approx(wall, abs=0.25), f"animation time {p.t:.2f} s after {wall:.2f} s of wall time"
    assert frames < 0.6 * wall / p.dt, f"{frames} frames: expensive frames must be dropped"
    text = p.rate_label.text()
    assert "frames/s achieved" in text and "real-time factor" in text, text
    assert 0.8 < p.real_time_factor < 1.2 and 0 < p.achieved_fps < 0.6 / p.dt, text
    # twice the speed: twice the animation time per wall second
    p.speed.setValue(2.0)
    t_before = p.t
    wall = play_for(p, 1.0)
    # (the pause click waits for the frame being drawn: up to one slow frame + a software render of wall
    # time is not animated; a clock adding 1/30 s x speed per tick would reach ~0.5 s here)
    assert p.t - t_before == pytest.approx(2.0 * wall, abs=0.6)


def test_stream_sends_the_wall_clock_values(doc, slow_frames):
    from metamaterial_wb.gui.panels import hardware_available
    if not hardware_available():
        pytest.skip("metamaterial_wb.hardware is not in this checkout")
    pytest.importorskip("serial")
    from metamaterial_wb.hardware import channel_map
    sc = open_fish(doc)
    scene = structure.compose_scene(sc)
    chans = {c.name: c for c in channel_map(scene)}
    p = run_panel("MM_Animate")
    p.port.setText("loop://")
    click(p.connect_btn)
    assert p.connect_btn.text() == "Disconnect", p.error.text()
    sent = []
    p.streamer.on_frame = lambda t, angles: sent.append((time.perf_counter(), p.clock(), dict(angles)))
    f0 = p.frames
    play_for(p, 1.2)
    frames = p.frames - f0
    playing = [s for s in sent if s[1] > 0.05]
    distinct = {tuple(sorted(a.items())) for _w, _t, a in playing}
    assert len(distinct) > 1.5 * frames, f"{len(distinct)} distinct streamed frames vs {frames} drawn"
    # the value streamed was computed a few ms before the callback read the clock; on a loaded machine the
    # streaming thread may wait for the GIL between the two (a software-GL redraw holds it ~100 ms), so a
    # few frames read a later clock: nine in ten must agree (values of another time, e.g. of the last
    # drawn frame, disagree on most of them)
    checked = [(name, ang, chans[name].angle_deg(scene_values_at(scene, t)[name]))
               for _w, t, angles in playing[5:-5] for name, ang in angles.items()]
    off = [(n, a, w) for n, a, w in checked if abs(a - w) > 6.0]
    assert checked and len(off) <= 0.1 * len(checked), f"{len(off)} of {len(checked)} streamed angles off: {off[:5]}"
    click(p.connect_btn)
    assert p.connect_btn.text() == "Connect"


def test_streamed_clock_never_runs_back_on_a_speed_change(doc):
    """The streaming thread reads clock() while the user turns the speed: a speed change must re-anchor the
    clock at the animation time *now* (old anchor, old speed), not at the last frame drawn, which lags the
    clock by up to a timer tick x speed (the stream jumped back by up to 0.11 s). Sampled from a Python
    thread every 0.5 ms while the speed switches 5 <-> 0.2 x every few ms; with loop on, the only drop
    allowed is a wrap at the end of the timeline (by nearly the whole duration)."""
    import threading
    import traceback
    open_fish(doc)
    p = run_panel("MM_Animate")
    p.loop.setChecked(True)
    p.duration.setValue(2.0)
    dur = p.duration.value()
    click(p.play_btn)
    process(200)
    samples, errors, stop = [], [], threading.Event()

    def sample():
        try:
            while not stop.is_set():
                samples.append(p.clock())
                time.sleep(0.0005)
        except Exception:  # noqa: BLE001 - reported below
            errors.append(traceback.format_exc())

    th = threading.Thread(target=sample, daemon=True)
    th.start()
    # at least 4 s, 120 speed changes and 1000 samples, however loaded the machine (two CI lanes share its
    # cores: a fixed 4 s once gave 99 changes); at most 60 s
    changes, t0 = 0, time.perf_counter()
    try:
        while time.perf_counter() - t0 < 60.0 and (time.perf_counter() - t0 < 4.0 or changes < 120
                                                   or len(samples) < 1000):
            p.speed.setValue(5.0 if changes % 2 == 0 else 0.2)
            changes += 1
            process(7)
    finally:
        stop.set()
        th.join(5)
        click(p.play_btn)      # Pause
    assert not errors, errors[0]
    assert changes > 100 and len(samples) > 1000, (changes, len(samples))
    back = [(k, a, b) for k, (a, b) in enumerate(zip(samples, samples[1:]))
            if b < a - 1e-9 and not (a - b > 0.5 * dur and b < 0.5 * dur)]   # a wrap goes back ~dur to ~0
    wraps = sum(1 for a, b in zip(samples, samples[1:]) if a - b > 0.5 * dur)
    assert wraps >= 1, "the clock never wrapped: the test did not play through the timeline"
    assert not back, (f"{len(back)} of {len(samples)} clock samples went back (up to "
                      f"{max(a - b for _k, a, b in back):.4f} s) over {changes} speed changes: {back[:5]}")


def test_connect_is_refused_when_the_links_frames_cannot_follow_the_motion(doc):
    """The link sends 50 frames a (wall) second of the animation clock: at 10x the fish's 1 Hz tail swings ten
    times a second, five frames a swing, and the servo, moving straight from frame to frame, strays tens of degrees
    from the motion (the stream command refuses such a rate; Connect streamed it). Connect is refused naming the
    speed and the fastest one that follows; at 1x it connects; speeding up while connected is warned of."""
    from metamaterial_wb.gui.panels import hardware_available
    if not hardware_available():
        pytest.skip("metamaterial_wb.hardware is not in this checkout")
    pytest.importorskip("serial")
    open_fish(doc)
    p = run_panel("MM_Animate")
    p.port.setText("loop://")
    type_into(p.speed, "10")
    assert p.speed.value() == 10.0
    click(p.connect_btn)
    assert p.connect_btn.text() == "Connect" and not p.stream.connected
    text = p.error.text()
    assert "10x" in text and "tail" in text and "deg off" in text, text
    follows = float(text.split("; ")[-1].split("x follows")[0])
    assert 1.0 <= follows < 10.0, text
    type_into(p.speed, f"{follows:g}")
    click(p.connect_btn)
    assert p.connect_btn.text() == "Disconnect", p.error.text()
    assert p.error.text() == ""
    type_into(p.speed, "10")
    assert p.stream.connected and "10x" in p.error.text(), p.error.text()
    click(p.connect_btn)
    assert p.connect_btn.text() == "Connect"
