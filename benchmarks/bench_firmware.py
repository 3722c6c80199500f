"""Firmware link benchmark (issue 7): frame round trip in the emulator and frames lost out of 1000.

    /usr/bin/python3 benchmarks/bench_firmware.py [--frames 1000] [--json OUT.json]

Builds the firmware and the simavr harness (make, in a temporary directory), then streams N 8-channel
SET_ANGLES frames at 50 Hz to the real ATmega328P firmware running in simavr paced to the wall clock
(--realtime), through pyserial on the harness's pty, and reports the round trip (send -> ACK parsed).

Baselines measured in the same run:
* "pty echo": the same host code against a Python fake device on a pseudo-terminal that answers each frame
  at once (host + pty overhead, no emulator, no UART timing);
* "wire floor": the bytes of one frame and its ACK at 115200 baud (24 + 11 bytes x 10 bits), which a real
  board cannot beat;
* the emulator free-running (not paced), to show how much of the round trip is simulated UART time.
Targets: median round trip <= 5 ms, 0 frames lost in 1000.

    /usr/bin/python3 benchmarks/bench_firmware.py --stream-check [--seconds 600] [--doc]

The host side only (no build, no emulator): the ``stream`` command's check of a long stream (check_motion: the
limits, the servo reach, the rate and the firmware's slew limit) on the fish with a slew limit on its tail that
follows the motion, so that every tick is compared. The slew part (rates._check_slew) with its vectorised
slew_ticks against the Python loop per 10 ms tick it replaced (kept here as the baseline); ratios only, best of
three. ``--doc`` writes the table into docs/benchmarks.md (section stream-check).
"""
import argparse
import json
import math
import os
import statistics
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, REPO)
sys.path.insert(0, os.path.join(REPO, "firmware", "test", "sim"))

import simrun  # noqa: E402

from metamaterial_wb.hardware import Link, Streamer  # noqa: E402
from metamaterial_wb.hardware import protocol as P  # noqa: E402
from metamaterial_wb.hardware.mapping import ChannelConfig  # noqa: E402

CHANNELS = [ChannelConfig(f"a{k}", k) for k in range(8)]


def motion(t):
    return {f"a{k}": 0.9 * math.sin(2 * math.pi * 0.5 * t + k * math.pi / 4) for k in range(8)}


def stream(link, frames, watchdog_ms=500):
    st = Streamer(link, CHANNELS, catch_up=True, reply_timeout_s=5.0)
    st.prepare(watchdog_ms=watchdog_ms, handshake=link.info is None)
    stats = st.run(motion, frames / 50.0)
    return stats


def fake_pty_device():
    import pty
    import select
    import tty

    master, slave = pty.openpty()
    tty.setraw(slave)
    stop = threading.Event()

    def run():
        rd = P.FrameReader()
        while not stop.is_set():
            r, _, _ = select.select([master], [], [], 0.02)
            if not r:
                continue
            for pkt in rd.feed(os.read(master, 512)):
                if pkt.type == P.HELLO:
                    out = P.build_frame(P.HELLO_ACK, pkt.seq,
                                        bytes([1, 0, 1, 0, 0, 8, 100, 0xF4, 1, 3, 0x28, 0, 0, 0, 0]))
                else:
                    out = P.build_frame(P.ACK, pkt.seq, bytes([pkt.type, 1, 0, 0, 8]))
                os.write(master, out)
    th = threading.Thread(target=run, daemon=True)
    th.start()
    return os.ttyname(slave), (stop, th, master, slave)


def row(name, s):
    d = s.summary()
    return {"case": name, "frames": d["frames"], "acked": d["acked"], "lost": d["lost"], "naked": d["naked"],
            "rtt_ms_median": d["rtt_ms_median"], "rtt_ms_p99": d["rtt_ms_p99"], "rtt_ms_max": d["rtt_ms_max"],
            "rate_hz": d["rate_hz"]}


def plot_fish(paths, png):
    """Stream examples/fish.json for 4 s into the emulator; plot the angles sent and the pin pulse widths."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.hardware import channel_map

    scene = Scene.load(os.path.join(REPO, "examples", "fish.json"))
    sent = []
    with simrun.SimAVR(paths) as sim, Link.open(sim.port) as link:
        st = Streamer(link, channel_map(scene))
        st.prepare()
        st.on_frame = lambda t, angles: sent.append((t, angles["head"], angles["tail"]))
        t0 = link.ping()["uptime_ms"] / 1000.0  # firmware time of the first frame (within a few ms)
        stats = st.run(scene, 4.0)
        time.sleep(0.1)
        lines = sim.pulse_lines()
    fig, ax = plt.subplots(figsize=(8, 3.6), dpi=110)
    ax2 = ax.twinx()
    ts = [s[0] for s in sent]
    for k, (name, col) in enumerate((("head", "tab:blue"), ("tail", "tab:orange"))):
        ax.plot(ts, [s[1 + k] for s in sent], color=col, lw=1.2, label=f"{name}: angle sent (ch{k}, pin D{4 + k})")
        pts = [(t - t0, w) for t, ch, w in lines if ch == k and w is not None and 0 <= t - t0 <= 4.0]
        ax2.plot([p[0] for p in pts], [p[1] for p in pts], ".", color=col, ms=2.5,
                 label=f"{name}: pulse width on the pin")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("commanded angle (deg)")
    ax.set_ylim(-95, 95)
    ax2.set_ylim(1500 - 95 / 90 * 1000, 1500 + 95 / 90 * 1000)
    ax2.set_ylabel("pulse width (us)")
    ax.grid(alpha=0.3)
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=7, loc="lower left", ncol=2)
    d = stats.summary()
    ax.set_title(f"fish -> ATmega328P firmware in simavr: {d['frames']} frames, {d['acked']} acked, "
                 f"round trip median {d['rtt_ms_median']:.1f} ms", fontsize=9)
    fig.tight_layout()
    fig.savefig(png)
    print(f"plot: {png}")


def tick_loop_slew(target_deg, max_slew_dps, start_deg=None):
    """The baseline: slew_ticks as it was, a Python loop over the 10 ms ticks."""
    import numpy as np
    from metamaterial_wb.hardware import rates
    y = np.asarray(target_deg, dtype=float)
    if not max_slew_dps:
        return y.copy()
    step = max_slew_dps * rates.SLEW_PERIOD_MS / 1000.0
    out = np.empty_like(y)
    cur = y[..., 0].copy() if start_deg is None else np.broadcast_to(np.asarray(start_deg, float), y[..., 0].shape)
    for i in range(y.shape[-1]):
        cur = cur + np.clip(y[..., i] - cur, -step, step)
        out[..., i] = cur
    return out


def stream_check(seconds, doc=False):
    """Time the stream command's check of ``seconds`` of the fish (tail max_slew_dps 480: the limit acts near the
    steepest places, within the tolerance): the whole check, and its slew part vectorised and as the tick loop."""
    import json as _json

    from benchmarks._report import best_of, machine_line, update_section

    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.hardware import channel_map, check_motion, rates

    with open(os.path.join(REPO, "examples", "fish.json"), encoding="utf-8") as f:
        d = _json.load(f)
    d["actuators"][1]["servo"] = {"max_slew_dps": 480}
    scene = Scene.from_dict(d)
    ch = channel_map(scene)
    tracks = rates._rate_tracks(scene, ch, False)

    def slew_part():
        for c, angles, steps in tracks:
            rates._check_slew(c, angles, seconds, 50.0, rates.RATE_TOLERANCE_DEG, steps)
    t_all, _ = best_of(lambda: check_motion(scene, ch, seconds, 50.0), 3)
    t_vec, _ = best_of(slew_part, 3)
    vectorised = rates.slew_ticks
    rates.slew_ticks = tick_loop_slew
    try:
        t_loop, _ = best_of(slew_part, 3)
    finally:
        rates.slew_ticks = vectorised
    rest = t_all - t_vec
    rows = [("check_motion, whole (vectorised slew)", t_all), ("  of it: slew check (rates._check_slew)", t_vec),
            ("  the rest (limits, reach, rate)", rest), ("slew check with the tick loop (before)", t_loop)]
    print(f"stream check of {seconds:g} s of the fish at 50 Hz (tail max_slew_dps 480, {int(seconds * 100)} ticks)")
    for name, t in rows:
        print(f"{name:42s} {t * 1000:9.1f} ms")
    print(f"slew check: tick loop / vectorised = x{t_loop / t_vec:.1f}; slew / rest of the check: before "
          f"{t_loop / rest:.2f}, now {t_vec / rest:.2f}")
    if doc:
        body = "\n".join([
            "## Stream check: the slew limit, vectorised",
            "",
            f"`/usr/bin/python3 benchmarks/bench_firmware.py --stream-check --seconds {seconds:g} --doc`: the `stream` "
            "command's check of a long stream (`check_motion`: limits, servo reach, rate, slew limit) on the fish "
            "with `max_slew_dps` 480 on its tail (its motion peaks at 509 deg/s: the limit acts near the steepest "
            "places, within the tolerance, so the whole stream is compared). The slew part with `slew_ticks` "
            "vectorised (one numpy pass per phase of the limit) against the Python loop per 10 ms tick it replaced. "
            "Best of three; ratios only matter (shared machine).",
            "",
            machine_line(),
            "",
            "| case | time |",
            "|---|---|",
            *[f"| {name.strip()} | {t * 1000:.0f} ms |" for name, t in rows],
            "",
            f"Slew check: the tick loop / vectorised = **x{t_loop / t_vec:.1f}**; the slew check / the rest of the "
            f"check: {t_loop / rest:.2f} before, {t_vec / rest:.2f} now.",
        ])
        update_section("stream-check", body)
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=1000)
    ap.add_argument("--json", help="write the results as JSON")
    ap.add_argument("--plot", metavar="PNG", help="also stream the fish for 4 s and plot sent angles vs pin pulses")
    ap.add_argument("--stream-check", action="store_true", help="time the host's stream check instead (no build)")
    ap.add_argument("--seconds", type=float, default=600.0, help="--stream-check: seconds of motion (600)")
    ap.add_argument("--doc", action="store_true", help="--stream-check: write docs/benchmarks.md's section")
    args = ap.parse_args()
    if args.stream_check:
        return stream_check(args.seconds, args.doc)
    reason = simrun.tools_missing()
    if reason:
        sys.exit(f"cannot run: {reason}")
    out = {"frames": args.frames, "rows": []}
    with tempfile.TemporaryDirectory() as d:
        t0 = time.perf_counter()
        paths = simrun.build(d)
        out["build_s"] = round(time.perf_counter() - t0, 2)
        out["size"] = paths["size_line"]
        print(f"build: {out['build_s']} s; {paths['size_line']}", flush=True)

        # baseline: Python fake device on a pty
        port, ctx = fake_pty_device()
        with Link.open(port) as link:
            link.handshake()
            out["rows"].append(row("pty echo (baseline)", stream(link, min(args.frames, 250))))
        ctx[0].set()
        ctx[1].join(1)
        os.close(ctx[2])
        os.close(ctx[3])

        for name, realtime, n in (("emulator, real time", True, args.frames),
                                  ("emulator, free-running", False, min(args.frames, 250))):
            sim = simrun.SimAVR(paths, realtime=realtime).start()
            try:
                with Link.open(sim.port) as link:
                    link.handshake()
                    # free-running, 20 ms of wall time are a second or more of firmware time: the watchdog
                    # must not trip between frames
                    r = row(name, stream(link, n, 500 if realtime else 10000))
                    r["firmware_counters"] = link.ping()
                    out["rows"].append(r)
            finally:
                proc = sim.proc
                sim.proc = None
                proc.terminate()
                proc.wait(5)
                r["simulator"] = proc.stderr.read().strip()
                proc.stdout.close()
                proc.stderr.close()
        if args.plot:
            plot_fish(paths, args.plot)
    wire_ms = (24 + 11) * 10 / 115200 * 1000
    out["wire_floor_ms"] = round(wire_ms, 3)
    base = out["rows"][0]["rtt_ms_median"]
    print(f"\n{'case':26s} {'frames':>6s} {'acked':>6s} {'lost':>5s} {'median ms':>9s} {'p99 ms':>7s} "
          f"{'max ms':>7s} {'rate Hz':>7s} {'x wire':>7s} {'x pty':>7s}")
    for r in out["rows"]:
        print(f"{r['case']:26s} {r['frames']:6d} {r['acked']:6d} {r['lost']:5d} {r['rtt_ms_median']:9.3f} "
              f"{r['rtt_ms_p99']:7.3f} {r['rtt_ms_max']:7.3f} {r['rate_hz']:7.2f} "
              f"{r['rtt_ms_median'] / wire_ms:7.2f} {r['rtt_ms_median'] / base:7.1f}")
        if "simulator" in r:
            print(f"{'':26s} {r['simulator']}")
    print(f"wire floor (24 B frame + 11 B ACK at 115200 baud): {wire_ms:.3f} ms")
    rt = out["rows"][1]
    ok = rt["rtt_ms_median"] <= 5.0 and rt["lost"] == 0 and rt["acked"] == rt["frames"] == args.frames
    print(f"target (emulator real time: median round trip <= 5 ms, no frame lost in {args.frames}): "
          f"{'MET' if ok else 'NOT MET'}")
    try:
        out["load_average"] = os.getloadavg()
    except OSError:
        pass
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
