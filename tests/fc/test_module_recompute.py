"""Every module type's document object recomputes valid, in a child process (issue 13).

FreeCAD 1.0 / 1.1 died (SIGSEGV) when a servo housing's object recomputed: ``Part.makeCompound`` crashes
when FreeCAD runs as a module of a plain Python interpreter, as our App tests, the CLI and scripts use it.
A crash in OpenCASCADE kills the interpreter, so each module is built in a child process and a dead child
is a failure that names the module, not a dead test run. Runs on every lane (scripts/test.sh).
"""
import json
import os
import shutil
import signal
import subprocess
import sys

import pytest

pytest.importorskip("FreeCAD")

from metamaterial_wb.objects.structure import MODULE_TYPES  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PROBE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "_module_probe.py")

CASES = {  # one example each module type is valid on
    "servo_housing": ("fish", "V0,1", {}),
    "connection_hub": ("fish", "N0,6", {}),
    "stable_hub": ("fish", "H1,2", {}),
    "friction_pad": ("fish", "N2,3", {}),
    "constraint_clip": ("umbrella_holder", "V0,0", {}),
}


def test_every_module_type_has_a_case():
    assert sorted(CASES) == sorted(MODULE_TYPES)


def _run(cmd, mtype, tmp_path):
    example, target, data = CASES[mtype]
    out = tmp_path / f"{mtype}.json"
    env = dict(os.environ, MM_PROBE=json.dumps([REPO, example, mtype, target, json.dumps(data), str(out)]))
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=300, cwd=str(tmp_path), env=env)
    if proc.returncode < 0:
        pytest.fail(f"module {mtype} on {example} {target}: FreeCAD died with "
                    f"{signal.Signals(-proc.returncode).name} while the module recomputed\n{proc.stderr[-2000:]}")
    if not out.exists():   # FreeCAD's own crash handler turns SIGSEGV into exit 1 without a word
        pytest.fail(f"module {mtype} on {example} {target}: FreeCAD died (exit {proc.returncode}) while the "
                    f"module recomputed\n{proc.stdout[-2000:]}\n{proc.stderr[-2000:]}")
    res = json.loads(out.read_text())
    assert res["valid"], (mtype, res)
    assert res["source"] == "geometry.modules" and res["volume"] > 0, (mtype, res)


@pytest.mark.parametrize("mtype", MODULE_TYPES)
def test_module_object_recomputes_valid_in_python(mtype, tmp_path):
    """FreeCAD imported as a module of this interpreter (what the App tests and the CLI do)."""
    _run([sys.executable, PROBE], mtype, tmp_path)


@pytest.mark.skipif(shutil.which("freecadcmd") is None, reason="freecadcmd is not installed")
@pytest.mark.parametrize("mtype", MODULE_TYPES)
def test_module_object_recomputes_valid_in_freecadcmd(mtype, tmp_path):
    """FreeCAD's own console application (what a macro or the Addon Manager's tests run in)."""
    _run(["freecadcmd", PROBE], mtype, tmp_path)
