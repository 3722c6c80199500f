"""The firmware builds for the ATmega328P with -Werror inside its flash/RAM budget (both servo back ends),
its portable core passes the host unit tests under ASan/UBSan with the shared vectors, and the frame parser
survives a time-bounded fuzz run."""
import json
import os
import re
import shutil

import pytest

import simrun

REPO = simrun.FIRMWARE and os.path.dirname(simrun.FIRMWARE)
GAIT_VECTORS = os.path.join(REPO, "tests", "vectors", "gait_rule.json")


@pytest.fixture(scope="module")
def build_dir(tmp_path_factory):
    reason = simrun.tools_missing()
    if reason:
        pytest.skip(reason)
    return str(tmp_path_factory.mktemp("fw"))


def sizes(out):
    m = re.search(r"flash=(\d+)/(\d+) ram=(\d+)/(\d+)", out)
    assert m, out
    return tuple(int(x) for x in m.groups())


@pytest.mark.parametrize("backend", ["isr", "pca9685"])
def test_avr_build_werror_within_budget(build_dir, backend):
    r = simrun.make(build_dir, "avr", extra=[f"BACKEND={backend}"])
    assert r.returncode == 0, r.stdout + r.stderr
    flash, fbudget, ram, rbudget = sizes(r.stdout)
    assert fbudget == 30720 and rbudget == 1536
    assert 1000 < flash <= fbudget and 100 < ram <= rbudget
    name = "servolink" if backend == "isr" else "servolink-pca9685"
    hexfile = os.path.join(build_dir, "avr", name + ".hex")
    lines = open(hexfile).read().split()
    assert lines[-1] == ":00000001FF"  # Intel HEX end record
    # the hex holds exactly the flash image the size check counted (data records, bytes 1..)
    assert sum(int(ln[1:3], 16) for ln in lines if ln[7:9] == "00") == flash


def test_werror_and_budget_checks_are_real(build_dir, tmp_path):
    """A warning breaks the AVR build, and a budget below the image size fails the size check."""
    probe = tmp_path / "warn.h"
    probe.write_text("static void sl_unused_probe(void) {}\n")  # -Wunused-function in every unit
    r = simrun.make(build_dir + "/warn", "avr", extra=[f"CFLAGS_EXTRA=-include {probe}"])
    out = r.stdout + r.stderr
    assert r.returncode != 0 and "sl_unused_probe" in out and "-Werror" in out
    r = simrun.make(build_dir, "avr", extra=["FLASH_BUDGET=2000"])
    assert r.returncode != 0 and "OVER BUDGET" in r.stderr


def test_host_unit_tests_under_sanitizers(build_dir):
    assert os.path.exists(GAIT_VECTORS), "the dynamics engineer's shared gait vectors"
    r = simrun.make(build_dir, "host-test", extra=[f"GAIT_VECTORS={GAIT_VECTORS}"])
    out = r.stdout + r.stderr
    assert r.returncode == 0, out
    results = re.findall(r"^(test_\w+): (\d+) passed, (\d+) failed$", out, re.M)
    assert {n for n, _, _ in results} == {"test_proto", "test_servo", "test_link", "test_gait", "test_outputs"}, out
    assert all(int(p) > 0 and f == "0" for _, p, f in results), out
    # built with the sanitizers
    nm = shutil.which("nm")
    if nm:
        import subprocess
        syms = subprocess.run([nm, os.path.join(build_dir, "host", "test_link")], capture_output=True, text=True).stdout
        assert "__asan" in syms and "__ubsan" in syms


def test_host_tests_really_read_the_vectors(build_dir, tmp_path):
    """Changing one expected pulse width in a copy of the vectors makes the C test fail."""
    vec = json.load(open(os.path.join(simrun.FIRMWARE, "test_vectors", "protocol.json")))
    vec["angle_to_us"][1]["us"] += 1
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(vec))
    r = simrun.make(build_dir, "host-test", extra=[f"VECTORS={bad}", f"GAIT_VECTORS={GAIT_VECTORS}"])
    assert r.returncode != 0
    assert re.search(r"test_servo: \d+ passed, 1 failed", r.stdout)


def test_invariant_fuzzing_200k_executions(build_dir):
    """The invariant fuzz target (limits, HOLD/PARK/RELEASE, ARM gating, counters, a reference pulse mapping)
    passes every regression input and the corpus, then 200 000 fresh executions under ASan + UBSan."""
    r = simrun.make(build_dir, "fuzz-ci", extra=["FUZZ_RUNS=200000"])
    out = r.stdout + r.stderr
    assert r.returncode == 0, out[-3000:]
    m = re.search(r"fuzz-regress: (\d+) inputs passed", out)
    assert m and int(m.group(1)) >= 17, out[-2000:]
    m = re.search(r"Done (\d+) runs|fuzz_link: (\d+) runs", out)
    assert m, out[-2000:]
    assert int(m.group(1) or m.group(2)) >= 200000
    if shutil.which("clang"):
        assert "INFO: seed corpus" in out or "INITED" in out  # libFuzzer loaded the committed corpus


def test_fuzz_regressions_catch_the_issue_19_defects(build_dir, tmp_path):
    """Mutation check of the harness: with one of the four fixed defects put back into a copy of the firmware (HOLD
    dropping a SET_PULSES override; CONFIG_CH not refreshing the pulse memo), the regression inputs fail."""
    src = os.path.join(simrun.FIRMWARE, "src", "core", "link.c")
    text = open(src).read()
    mutants = {
        "hold": ("l->target[ch] = l->cur[ch]; /* keep the last pulse",
                 "l->raw_us[ch] = 0, l->target[ch] = l->cur[ch]; /* keep the last pulse"),
        "memo": ("l->memo_ok &= (uint8_t)~(1u << ch);", "(void)0;"),
    }
    for name, (a, b) in mutants.items():
        assert a in text, name
        fw = tmp_path / name
        shutil.copytree(simrun.FIRMWARE, fw, ignore=shutil.ignore_patterns("build"))
        (fw / "src" / "core" / "link.c").write_text(text.replace(a, b))
        r = __import__("subprocess").run(["make", "-s", "-C", str(fw), f"BUILD={tmp_path / (name + '-b')}",
                                          "fuzz-regress"], capture_output=True, text=True, timeout=300)
        out = r.stdout + r.stderr
        assert r.returncode != 0 and "fuzz invariant violated" in out, (name, out[-2000:])
