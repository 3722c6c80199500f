"""Fixtures of the firmware tests: one AVR + harness build per session (in a temporary directory, with the
project Makefile), a simavr instance per test, and a handshaken pyserial link to it."""
import os
import sys

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "firmware", "test", "sim"))

import simrun  # noqa: E402


@pytest.fixture(scope="session")
def fw_build(tmp_path_factory):
    reason = simrun.tools_missing()
    if reason:
        pytest.skip(reason)
    d = str(tmp_path_factory.mktemp("fwbuild"))
    paths = simrun.build(d)
    paths["dir"] = d
    return paths


@pytest.fixture
def sim(fw_build, tmp_path):
    pytest.importorskip("serial")
    with simrun.SimAVR(fw_build, log_dir=str(tmp_path)) as s:
        yield s


@pytest.fixture
def link(sim):
    from metamaterial_wb.hardware import Link

    lk = Link.open(sim.port)
    lk.handshake()
    yield lk
    lk.close()
