"""End to end: the real ATmega328P firmware in simavr (firmware/test/sim/simhost.c exposes UART0 as a pty and
measures the servo pins), driven by the Python link through pyserial.

Expected pulse widths are written here in closed form from the documented mapping
(1500 us + angle / 90 deg * 1000 us for the default 500..2500 us range), independent of the code."""
import json
import math
import os
import subprocess
import sys
import time

import pytest

from metamaterial_wb.hardware import Link, Streamer, channel_map
from metamaterial_wb.hardware import protocol as P
from metamaterial_wb.hardware.link import LinkError

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
VEC = json.load(open(os.path.join(REPO, "firmware", "test_vectors", "protocol.json")))
GAIT = json.load(open(os.path.join(REPO, "tests", "vectors", "gait_rule.json")))
TOL_US = 10.0


def _joint(parity_a, v, lh=8.0, cell=27.0):
    """The fish's actuated joints, closed form: -2 p_A v phi_max(sign v), plate contact asin(lh / 2s), 45 deg open."""
    phi = math.asin(lh / (2 * (cell - lh))) if v >= 0 else math.pi / 4
    return math.degrees(-2 * parity_a * v * phi)


def HEAD(v):  # V0,1, node A = N0,1 (parity -1)
    return _joint(-1, v)


def TAIL(v):  # V1,5, node A = N1,5 (parity +1)
    return _joint(+1, v)


def settle_pulses(sim, link, ms=100):
    """Pulses after at least ``ms`` of *firmware* time has passed since everything sent so far was processed
    (a loaded machine may run the simulator slower than the wall clock)."""
    t0 = link.ping()["uptime_ms"]
    end = time.perf_counter() + 20
    while link.ping()["uptime_ms"] < t0 + ms and time.perf_counter() < end:
        time.sleep(0.02)
    return sim.pulses()


def _boot_banner(port, timeout_s=10.0):
    """The packets the firmware sends before anyone talks to it, read from the pty without flushing it.

    pyserial's open() flushes the input (tcflush), so a banner that arrives before Link.open returns is gone:
    whether the test saw it depended on how fast the emulator booted. The pty itself keeps it (simhost holds
    the slave open and sets it raw), so a plain read gets it every time."""
    import select
    fd = os.open(port, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
    try:
        reader, pkts = P.FrameReader(), []
        end = time.perf_counter() + timeout_s
        while not pkts and time.perf_counter() < end:
            if select.select([fd], [], [], 0.05)[0]:
                pkts += reader.feed(os.read(fd, 256))
        return pkts
    finally:
        os.close(fd)


def test_boot_banner_then_handshake(sim):
    # the unsolicited HELLO_ACK of the boot (seq 0) waits in the pty
    pkts = _boot_banner(sim.port)
    assert [(p.type, p.seq) for p in pkts] == [(P.HELLO_ACK, 0)], pkts
    assert P.parse_reply(pkts[0]).kind == "HELLO_ACK"
    with Link.open(sim.port) as link:
        info = link.handshake()
        assert (info.proto_major, info.n_channels, info.watchdog_ms) == (1, 8, 500)
        assert info.caps & P.CAP_OSC and info.caps & P.CAP_GAIT and info.caps & P.CAP_CONTACT_PINS
        st = link.get_state()
        assert st["state"] == P.ST_DISARMED and st["pulse_us"] == [0] * 8
    # no pulses before ARM
    assert all(w is None for w in sim.pulses().values())


def test_malformed_and_refused_frames_get_the_right_nak(link):
    n = 0
    for e in VEC["exchanges"]:
        (link.arm if e["armed"] else link.disarm)()
        if "raw_hex" in e:
            link.write_raw(bytes.fromhex(e["raw_hex"]))
        else:
            link.write_raw(P.build_frame(e["type"], e["seq"], bytes.fromhex(e["payload_hex"])))
        want = e["reply"]
        r = link.wait_reply(want["seq"], 0.5)
        assert r is not None, e["name"]
        kind = {P.NAK: "NAK", P.ACK: "ACK", P.HELLO_ACK: "HELLO_ACK"}[want["type"]]
        assert r.kind == kind, (e["name"], r)
        if "code" in want:
            assert r.code == want["code"], (e["name"], r.reason)
        if "detail" in want:
            assert r.detail == want["detail"], e["name"]
        n += 1
    assert n == len(VEC["exchanges"]) >= 10
    stats = link.ping()
    assert stats["crc_err"] >= 1 and stats["framing_err"] >= 3


def test_pulse_widths_match_commanded_angles(link, sim):
    cfg = {  # channel: servo fields -> closed-form expected width for an angle a
        0: ({}, lambda a: 1500 + a / 90 * 1000),
        1: ({"invert": True}, lambda a: 1500 - a / 90 * 1000),
        2: ({"trim_deg": 5.0}, lambda a: 1500 + (a + 5) / 90 * 1000),
        3: ({"min_us": 1000, "max_us": 2000}, lambda a: 1500 + a / 90 * 500),
        4: ({"limits_deg": [-45, 45]}, lambda a: 1500 + max(-45, min(45, a)) / 90 * 1000),
        5: ({"min_us": 544, "max_us": 2400}, lambda a: 1472 + a / 90 * 928),
        6: ({}, lambda a: 1500 + a / 90 * 1000),
        7: ({}, lambda a: 1500 + a / 90 * 1000),
    }
    from metamaterial_wb.hardware.mapping import ChannelConfig
    chans = []
    for ch, (spec, _) in cfg.items():
        c = ChannelConfig(f"c{ch}", ch, **{k: tuple(v) if k == "limits_deg" else v for k, v in spec.items()})
        chans.append(c)
    link.configure(chans)
    link.arm()
    worst = 0.0
    for angles in ([0] * 8, [90, 60, 30, 0, -30, -60, -90, 45], [-90, -45, 12.34, 89.99, 80, 1, -0.5, 7.5]):
        seq = link.send(P.SET_ANGLES, P.set_angles_payload(0, [round(a * 100) for a in angles]))
        r = link.wait_reply(seq, 0.5)
        assert r.kind == "ACK" and r.data[2] == 8
        clamped = {ch for ch in range(8) if r.clamp_mask >> ch & 1}
        assert clamped == ({4} if abs(angles[4]) > 45 else set())
        got = settle_pulses(sim, link)
        for ch, a in enumerate(angles):
            want = cfg[ch][1](a)
            assert got[ch] is not None
            worst = max(worst, abs(got[ch] - want))
            assert abs(got[ch] - want) <= TOL_US, (ch, a, got[ch], want)
    # the firmware's own report agrees with the pins
    st = link.get_state()
    assert all(abs(u - sim.pulses()[ch]) <= TOL_US for ch, u in enumerate(st["pulse_us"]))


def test_1000_frames_at_50_hz_all_acknowledged(link, sim):
    chans = [c for c in channel_map(_scene_8())]
    st = Streamer(link, chans, catch_up=True, reply_timeout_s=5.0)
    # a 2 s link watchdog: a loaded CI machine may stall this Python process for longer than the default
    # 500 ms (then the firmware would rightly hold and refuse); the watchdog has its own test below
    st.prepare(watchdog_ms=2000, handshake=False)
    before = link.ping()

    def motion(t):
        return {f"a{k}": 0.9 * math.sin(2 * math.pi * 0.5 * t + k * math.pi / 4) for k in range(8)}

    stats = st.run(motion, 20.0)
    assert stats.frames == 1000, stats.summary()
    assert stats.acked == 1000 and stats.naked == 0 and stats.lost == 0, stats.summary()
    assert stats.duration_s >= 19.9  # paced at 50 Hz (never faster)
    assert stats.events == []  # the watchdog never tripped
    ping = link.ping()  # the firmware's own counters: every frame arrived intact and in sequence
    assert ping["rx_ok"] - before["rx_ok"] == 1001
    assert (ping["crc_err"], ping["framing_err"], ping["seq_gaps"]) == (
        before["crc_err"], before["framing_err"], before["seq_gaps"])
    # the pins hold the last frame's angles (t = 19.98 s)
    last = motion(999 / 50)
    got = settle_pulses(sim, link)
    for k, c in enumerate(chans):
        assert abs(got[k] - (1500 + c.angle_deg(last[c.name]) / 90 * 1000)) <= TOL_US


def _scene_8():
    from metamaterial_wb.core.scene import Scene
    d = json.load(open(os.path.join(REPO, "examples", "fish.json")))
    d["layout"] = {"grid": [2, 6]}
    # servo.scale_deg 90: channels commanded v * 90 deg, so that the sine sweeps the servos' whole range
    d["actuators"] = [{"name": f"a{k}", "joint": j, "value": 0.0, "servo": {"scale_deg": 90}} for k, j in
                      enumerate(["V0,1", "V1,5", "V0,2", "V0,3", "V0,4", "V1,1", "V1,2", "V1,3"])]
    return Scene.from_dict(d)


def test_watchdog_holds_parks_releases_and_needs_arm(link, sim):
    link.configure_watchdog(watchdog_ms=200, park_after_ms=300, release_after_ms=800)
    link.arm()
    r = link.wait_reply(link.send(P.SET_ANGLES, P.set_angles_payload(0, [6000, -3000])), 0.5)
    assert r.kind == "ACK"
    last_rx = link.ping()["uptime_ms"]  # the last frame before the host goes silent
    seen = {}
    end = time.perf_counter() + 20
    while time.perf_counter() < end and "RELEASE" not in seen:
        link.poll(0.01)
        for _, e in link.events:
            if e.kind == "EVENT" and P.EVENT_NAMES[e.code] not in seen:
                seen[P.EVENT_NAMES[e.code]] = e.time_ms
    # firmware time: HOLD just after 200 ms of silence, PARK 300 ms later, RELEASE 800 ms after that
    assert list(seen) == ["HOLD", "PARK", "RELEASE"], seen
    assert 200 < seen["HOLD"] - last_rx <= 215
    assert seen["PARK"] - seen["HOLD"] == 300
    assert seen["RELEASE"] - seen["PARK"] == 800
    after = settle_pulses(sim, link)  # the harness reports a pin "off" 60 ms after its last pulse
    lines = [(t, w) for t, ch, w in sim.pulse_lines() if ch == 0]
    hold_s, park_s, rel_s = (seen[k] / 1000 for k in ("HOLD", "PARK", "RELEASE"))
    # HOLD keeps the last position
    held = [w for t, w in lines if t <= park_s]
    assert held and abs(held[-1] - (1500 + 60 / 90 * 1000)) <= TOL_US
    # PARK ramps to the park angle (0 deg) at 90 deg/s, not a jump: 60 deg take ~0.67 s
    ramp = [(t, w) for t, w in lines if park_s < t <= rel_s + 0.001 and w is not None]
    assert sum(1 for _, w in ramp if 1550 < w < 2100) >= 10
    reached = next(t for t, w in ramp if abs(w - 1500) <= TOL_US)
    assert 0.6 <= reached - park_s <= 0.75
    # RELEASE stops the pulses on every pin
    assert lines[-1][1] is None and lines[-1][0] >= rel_s
    assert all(w is None for w in after.values()), (after, sim.pulse_lines()[-20:])
    with pytest.raises(LinkError, match="NOT_ARMED"):
        link.request(P.SET_ANGLES, P.set_angles_payload(0, [0]))
    link.arm()
    r = link.request(P.SET_ANGLES, P.set_angles_payload(0, [-4500]))
    assert r.kind == "ACK"
    assert abs(settle_pulses(sim, link)[0] - 1000) <= TOL_US


def test_osc_mode_generates_the_sine_on_board(link, sim):
    link.arm()
    link.request(P.OSC_SET, P.osc_set_payload(0, 4500, 0, 1000, 0))  # 45 deg, 1 s
    t_mode = link.request(P.SET_MODE, bytes([P.MODE_OSC])) and link.ping()["uptime_ms"]
    end = time.perf_counter() + 30
    while link.ping()["uptime_ms"] < t_mode + 2300 and time.perf_counter() < end:  # pings feed the watchdog
        time.sleep(0.05)
    lines = [(t, w) for t, ch, w in sim.pulse_lines() if ch == 0 and w is not None]
    ts = [t for t, _ in lines]
    ws = [w for _, w in lines]
    assert max(ws) == pytest.approx(2000, abs=TOL_US) and min(ws) == pytest.approx(1000, abs=TOL_US)
    # period from upward crossings of 1500 us
    ups = [ts[i] for i in range(1, len(ws)) if ws[i - 1] < 1500 <= ws[i]]
    periods = [b - a for a, b in zip(ups, ups[1:])]
    assert periods and all(abs(p - 1.0) < 0.03 for p in periods), periods


def test_gait_rule_vectors_in_the_emulator(link):
    n = 0
    for v in GAIT["vectors"]:
        cells = len(v["c_air"])
        link.request(P.GAIT_SET, P.gait_set_payload(cells, v["n1"], v["n2"], closed=v["closed"]))
        r = link.request(P.GAIT_CONTACTS, P.pack_mask(v["c_air"]))
        assert P.unpack_mask(r.data, cells) == v["act"], v["name"]
        n += 1
    assert n == len(GAIT["vectors"]) >= 10


def test_gait_mode_drives_the_servos(link, sim):
    # the shared vector "belt8_high_torque": cells 0..2 on the ground -> cells 3 and 7 inflate
    v = next(x for x in GAIT["vectors"] if x["name"] == "belt8_high_torque")
    link.request(P.GAIT_SET, P.gait_set_payload(8, v["n1"], v["n2"], closed=True, inflate_cdeg=6000,
                                                vent_cdeg=-3000))
    link.request(P.GAIT_CONTACTS, P.pack_mask(v["c_air"]))
    link.arm()
    link.request(P.SET_MODE, bytes([P.MODE_GAIT]))
    got = settle_pulses(sim, link, 200)
    for ch in range(8):
        want = 1500 + (60 if v["act"][ch] else -30) / 90 * 1000
        assert abs(got[ch] - want) <= TOL_US, (ch, got[ch], want)
    # the ground moves on: new contacts, new actuation
    c2 = v["c_air"][-1:] + v["c_air"][:-1]  # rotate by one cell
    link.request(P.GAIT_CONTACTS, P.pack_mask(c2))
    got = settle_pulses(sim, link, 200)
    act2 = v["act"][-1:] + v["act"][:-1]  # the rule is shift-equivariant on a closed belt
    for ch in range(8):
        assert abs(got[ch] - (1500 + (60 if act2[ch] else -30) / 90 * 1000)) <= TOL_US
    with pytest.raises(LinkError, match="MODE"):
        link.request(P.SET_ANGLES, P.set_angles_payload(0, [0]))


def test_cli_streams_the_fish_into_the_emulator(sim, tmp_path):
    rep = tmp_path / "stream.json"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "stream", os.path.join(REPO, "examples", "fish.json"),
                        "--port", sim.port, "--seconds", "2", "--report", str(rep)],
                       capture_output=True, text=True, cwd=REPO, timeout=60)
    assert r.returncode == 0, r.stdout + r.stderr
    d = json.loads(rep.read_text())
    assert d["frames"] == d["acked"] and d["lost"] == 0 and d["naked"] == 0
    assert d["frames"] + d["skipped"] == 100 and d["frames"] >= 80  # a loaded machine may skip a late frame
    # the last frame (t = 1.98 s unless skipped): head 0.3 sin(2 pi 0.5 t), tail 0.9 sin(2 pi t + 90 deg), as the
    # simulated rotations of their joints (closed form: tests/hardware/test_stream.py)
    t = d["last_t"]
    head = HEAD(0.3 * math.sin(math.pi * t))
    tail = TAIL(0.9 * math.sin(2 * math.pi * t + math.pi / 2))
    # the whole centidegrees sent
    assert d["frames_sent"][-1]["angles_deg"] == pytest.approx({"0": head, "1": tail}, abs=0.005 + 1e-9)
    with Link.open(sim.port) as link:
        got = settle_pulses(sim, link)
    assert abs(got[0] - (1500 + head / 90 * 1000)) <= TOL_US
    assert abs(got[1] - (1500 + tail / 90 * 1000)) <= TOL_US


def test_panel_style_streaming_follows_the_shown_values(sim):
    """What the Animate panel's Connect does: a streamer thread sends whatever the GUI shows right now."""
    from metamaterial_wb.core.scene import Scene
    scene = Scene.load(os.path.join(REPO, "examples", "fish.json"))
    shown = {"head": 0.0, "tail": 0.0}
    with Link.open(sim.port) as link:
        st = Streamer(link, channel_map(scene))
        st.prepare()
        st.start(lambda _t: dict(shown))
        try:
            for head, tail in ((0.5, -0.5), (-0.25, 0.9), (0.0, 0.1)):
                shown.update(head=head, tail=tail)  # the GUI thread moves the slider / timeline
                time.sleep(0.1)
                got = settle_pulses(sim, link)
                assert abs(got[0] - (1500 + HEAD(head) / 90 * 1000)) <= TOL_US
                assert abs(got[1] - (1500 + TAIL(tail) / 90 * 1000)) <= TOL_US
            assert st.running
        finally:
            stats = st.stop(disarm=True)
        assert not st.running and stats.lost == 0 and stats.naked == 0 and stats.acked == stats.frames > 10
        assert all(w is None for w in settle_pulses(sim, link).values())  # disarmed: servos limp


def test_pca9685_back_end_over_i2c(fw_build, tmp_path):
    """The BACKEND=pca9685 firmware drives an emulated PCA9685 (harness --pca9685: register file on the TWI
    bus, PRESCALE writable only while asleep, auto-increment); its LEDn registers, converted with the chip's
    own timing (count x (PRESCALE + 1) / 25 MHz), match the commanded angles within +-10 us."""
    import simrun
    with simrun.SimAVR(fw_build, log_dir=str(tmp_path), pca9685=True) as sim, Link.open(sim.port) as link:
        info = link.handshake()
        assert info.caps & P.CAP_PCA9685
        link.arm()
        for angles in ([90, -90, 0, 45, 1, -30, 60, -89.5], [0] * 8):
            r = link.request(P.SET_ANGLES, P.set_angles_payload(0, [round(a * 100) for a in angles]))
            assert r.clamp_mask == 0
            got = settle_pulses(sim, link)
            for ch, a in enumerate(angles):
                assert abs(got[ch] - (1500 + a / 90 * 1000)) <= TOL_US, (ch, a, got[ch])
        link.disarm()
        assert all(w is None for w in settle_pulses(sim, link).values())  # full-off bits


def test_cli_osc_mode_runs_the_fish_on_board(sim, tmp_path):
    """``stream --mode osc``: the fish's sines run on the chip; the pins show the amplitudes, the periods and the
    tail's 90 deg phase lead from the start of the mode (firmware time)."""
    rep = tmp_path / "osc.json"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "stream", os.path.join(REPO, "examples", "fish.json"),
                        "--port", sim.port, "--mode", "osc", "--seconds", "2.6", "--report", str(rep)],
                       capture_output=True, text=True, cwd=REPO, timeout=60)
    assert r.returncode == 0, r.stdout + r.stderr
    t_mode = json.loads(rep.read_text())["firmware_start_ms"] / 1000.0
    lines = sim.pulse_lines()
    for ch, joint, amp, period in ((0, HEAD, 0.3, 2.0), (1, TAIL, 0.9, 1.0)):
        # from one servo frame (+ one 10 ms generator step) after the start: earlier pulses began before it
        pts = [(t, w) for t, c, w in lines if c == ch and w is not None and t >= t_mode + 0.031]
        ws = [w for _, w in pts]
        # the two half-waves of the sine in v: the joint closes (to plate contact) and opens by different angles
        ends = sorted(1500 + joint(x) / 90 * 1000 for x in (amp, -amp))
        assert min(ws) == pytest.approx(ends[0], abs=TOL_US) and max(ws) == pytest.approx(ends[1], abs=TOL_US)
        # every logged width agrees with the profile at its firmware time (t_mode: from the SET_MODE ACK)
        phase = math.pi / 2 if ch == 1 else 0.0
        err = [abs(w - (1500 + joint(amp * math.sin(2 * math.pi * (t - t_mode) / period + phase)) / 90 * 1000))
               for t, w in pts]
        # the generator is sampled every 10 ms and a pin shows a new width at its next 20 ms servo frame
        slope = 2 * math.pi * (ends[1] - ends[0]) / 2 / period  # us per second at the steepest point
        assert max(err) <= TOL_US + slope * 0.031, max(err)


def test_firmware_gait_rule_matches_the_python_reference_on_random_chains(link):
    """Differential test beyond the fixed vectors: 150 random chains (1..64 cells, open or closed, random n1,
    n2, random contacts) through the firmware and through core/gait.py (written independently)."""
    import random

    from metamaterial_wb.core.gait import gait_rule_step
    from metamaterial_wb.hardware.onboard import FirmwareGait
    rnd = random.Random(2026)
    for _ in range(50):
        n = rnd.randint(1, 64)
        n1, n2, closed = rnd.randrange(n), rnd.randrange(n), rnd.random() < 0.5
        g = FirmwareGait(link, n, n1, n2, closed=closed)
        for _ in range(3):
            c = [int(rnd.random() < 0.6) for _ in range(n)]
            assert g.step(c) == gait_rule_step(c, n1, n2, closed), (n, n1, n2, closed, c)


def test_gait_mode_reads_the_contact_switches(fw_build, tmp_path):
    """GAIT mode with contacts from the pins (A0..A5; switch closed = on the ground), as on a robot with a
    switch per cell: the harness drives the input pins, the servos follow Algorithm 1."""
    import simrun

    from metamaterial_wb.core.gait import gait_rule_step
    from metamaterial_wb.hardware.onboard import FirmwareGait
    with simrun.SimAVR(fw_build, log_dir=str(tmp_path), contacts=True) as sim, Link.open(sim.port) as link:
        link.handshake()
        g = FirmwareGait(link, 6, 1, 1, closed=True, pins=True, inflate_deg=60, vent_deg=-30)
        with pytest.raises(LinkError, match="MODE"):
            g.step([1] * 6)  # the contacts come from the pins
        link.arm()
        g.start()
        for c in ([0, 0, 1, 1, 1, 1], [1, 1, 0, 0, 0, 1], [1, 0, 1, 1, 0, 1], [0, 0, 0, 0, 0, 0]):
            sim.set_contacts(c)
            got = settle_pulses(sim, link, 100)
            act = gait_rule_step(c, 1, 1, closed=True)
            for ch in range(6):
                assert abs(got[ch] - (1500 + (60 if act[ch] else -30) / 90 * 1000)) <= TOL_US, (c, ch)
            assert abs(got[6] - 1500) <= TOL_US and abs(got[7] - 1500) <= TOL_US  # no cell: channels hold
        with pytest.raises(LinkError, match="RANGE"):  # 7 cells: more than the board's 6 inputs
            FirmwareGait(link, 7, 1, 1, pins=True)


def test_two_boards_share_one_chain(link, sim):
    """A 16-cell belt driven by two boards: this one is given first_cell = 8 and drives cells 8..15 on its
    channels 0..7 from the whole chain's contacts (the other board would take cells 0..7)."""
    from metamaterial_wb.core.gait import gait_rule_step
    from metamaterial_wb.hardware.onboard import FirmwareGait
    c = [0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 1, 1, 1]
    g = FirmwareGait(link, 16, 2, 1, closed=True, first_cell=8, inflate_deg=45, vent_deg=0)
    act = gait_rule_step(c, 2, 1, closed=True)
    assert g.step(c) == act
    link.arm()
    g.start()
    got = settle_pulses(sim, link, 100)
    for ch in range(8):
        assert abs(got[ch] - (2000 if act[8 + ch] else 1500)) <= TOL_US, (ch, got[ch], act[8 + ch])
    assert sum(act[8:]) >= 2 and sum(act[8:]) < 8  # the check sees both angles


def test_simulated_timeline_drives_the_pins_to_the_solved_joint_angles(sim, tmp_path):
    """Issue 16 item 9: a timeline simulated by the solver (the fish's two actuators at five keyframes) streamed
    into the firmware: at each keyframe the pins show 1500 us + (solved relative rotation of the joint) x
    1000 us / 90 deg, the rotation taken from the result's node rotations (signed joints[].hinge_rotation_deg)."""
    from metamaterial_wb.core.models import run_model
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.hardware.joint_angle import signed_joint_rotation_deg
    d = json.load(open(os.path.join(REPO, "examples", "fish.json")))
    for a in d["actuators"]:
        a.pop("profile", None)
    keys = [(0.0, 0.0), (0.3, -0.9), (-0.3, 0.9), (1.0, -1.0), (-0.6, 0.45)]
    timeline = []
    for head, tail in keys:  # the simulation: solve the scene at each keyframe
        d["actuators"][0]["value"], d["actuators"][1]["value"] = head, tail
        sc = Scene.from_dict(d)
        res = run_model("quadratic", sc)
        timeline.append(({"head": head, "tail": tail},
                         [signed_joint_rotation_deg(sc, res.rotations, j) for j in ("V0,1", "V1,5")]))
    scene = Scene.from_dict(d)
    with Link.open(sim.port) as link:
        st = Streamer(link, channel_map(scene), reply_timeout_s=2.0)
        st.prepare(watchdog_ms=3000)
        shown = dict(timeline[0][0])
        st.start(lambda _t: dict(shown))
        try:
            for values, solved in timeline:
                shown.update(values)
                time.sleep(0.1)
                got = settle_pulses(sim, link)
                for ch, angle in enumerate(solved):
                    assert abs(got[ch] - (1500 + angle / 90 * 1000)) <= TOL_US, (values, ch, got[ch], angle)
        finally:
            stats = st.stop(disarm=True)
    assert stats.lost == 0 and stats.naked == 0 and stats.clamped_frames == 0, stats.summary()
    # the keyframes reach plate contact (v = +1: 24.3 deg, within the channel's default limits) and 90 deg open
    assert max(abs(a) for _, s in timeline for a in s) == pytest.approx(90.0, abs=1e-6)
