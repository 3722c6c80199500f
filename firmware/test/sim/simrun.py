"""Run the servolink firmware in simavr (through the simhost harness) for tests and benchmarks.

    from simrun import build, SimAVR
    paths = build("/tmp/fwbuild")                   # make avr sim -> {"elf": ..., "simhost": ...}
    with SimAVR(paths) as sim:                       # starts simhost --realtime, waits for its pty
        link = Link.open(sim.port)
        ...
        sim.pulses()                                 # {channel: last pulse width in us, or None if off}

A test tool (the harness links GPL-3 libsimavr); it is not part of the workbench package.
"""
import os
import subprocess
import tempfile
import time

FIRMWARE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def tools_missing():
    """A reason string if the AVR toolchain or libsimavr is absent, else ''."""
    import shutil

    for tool in ("avr-gcc", "avr-objcopy", "avr-size", "make", "gcc"):
        if not shutil.which(tool):
            return f"{tool} not installed (tools/apt-packages.txt)"
    if not os.path.exists("/usr/include/simavr/sim_avr.h"):
        return "libsimavr-dev not installed (tools/apt-packages.txt)"
    return ""


def make(build_dir, *targets, extra=()):
    cmd = ["make", "-s", "-C", FIRMWARE, f"BUILD={build_dir}", *extra, *targets]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=300)


def build(build_dir):
    """Both firmware variants (ISR pins, PCA9685) and the harness."""
    r = make(build_dir, "avr", "sim")
    r2 = make(build_dir, "avr", extra=["BACKEND=pca9685"])
    for x in (r, r2):
        if x.returncode:
            raise RuntimeError(f"firmware build failed:\n{x.stdout}\n{x.stderr}")
    return {"elf": os.path.join(build_dir, "avr", "servolink.elf"),
            "elf_pca9685": os.path.join(build_dir, "avr", "servolink-pca9685.elf"),
            "simhost": os.path.join(build_dir, "sim", "simhost"), "size_line": r.stdout.strip()}


class SimAVR:
    def __init__(self, paths, realtime=True, log_dir=None, pca9685=False, contacts=False):
        self.paths = paths
        self.realtime = realtime
        self.pca9685 = pca9685  # the PCA9685 firmware with an emulated PCA9685 on I2C
        self.log_dir = log_dir or tempfile.mkdtemp(prefix="simavr-")
        self.pulse_log = os.path.join(self.log_dir, "pulses.txt")
        self.contacts_file = os.path.join(self.log_dir, "contacts.txt") if contacts else None
        self.proc = None
        self.port = None

    def start(self, timeout=10.0):
        cmd = [self.paths["simhost"], "--pulse-log", self.pulse_log,
               self.paths["elf_pca9685" if self.pca9685 else "elf"]]
        if self.realtime:
            cmd.insert(1, "--realtime")
        if self.pca9685:
            cmd.insert(1, "--pca9685")
        if self.contacts_file:
            self.set_contacts([1] * 6)
            cmd[1:1] = ["--contacts", self.contacts_file]
        self.proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            line = self.proc.stdout.readline()
            if not line:
                break
            if line.startswith("PTY "):
                self.port = line.split()[1]
                return self
        self.stop()
        raise RuntimeError("simhost did not report its pty")

    def set_contacts(self, c_air):
        """Contact switches: c_air[i] = 1 -> cell i in the air (open), 0 -> on the ground (closed)."""
        tmp = self.contacts_file + ".tmp"
        with open(tmp, "w") as f:
            f.write("".join("1" if v else "0" for v in c_air))
        os.replace(tmp, self.contacts_file)

    def stop(self):
        if self.proc is not None:
            self.proc.terminate()
            try:
                self.proc.wait(5)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
            for f in (self.proc.stdout, self.proc.stderr):
                if f:
                    f.close()
            self.proc = None

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.stop()

    def pulse_lines(self):
        """[(sim_time_s, channel, width_us or None)] in order."""
        out = []
        if not os.path.exists(self.pulse_log):
            return out
        with open(self.pulse_log) as f:
            for line in f:
                p = line.split()
                if len(p) != 3:
                    continue
                out.append((float(p[0]), int(p[1]), None if p[2] == "off" else float(p[2])))
        return out

    def pulses(self):
        """{channel: the latest pulse width in us, None once the pin stopped pulsing}."""
        last = {}
        for _, ch, w in self.pulse_lines():
            last[ch] = w
        return last
