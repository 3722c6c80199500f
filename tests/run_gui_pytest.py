"""Run pytest on tests/gui inside the FreeCAD GUI (a macro), then exit with pytest's status.

    xvfb-run -a -s "-screen 0 1600x1000x24" freecad -u <copy of resources/test_user.cfg> \
        tests/run_gui_pytest.py -M "$PWD"

Extra pytest arguments can be given in the environment variable MM_GUI_PYTEST_ARGS; when they name test
files or folders (``tests/gui/test_gui_export.py``, ``tests/gui/test_x.py::test_y``) only those run,
otherwise the whole of tests/gui, e.g.

    MM_GUI_PYTEST_ARGS="tests/gui/test_gui_folded.py -x" xvfb-run ... tests/run_gui_pytest.py -M "$PWD"

A watchdog ends FreeCAD with status 124 if the tests hang; FreeCAD never stays open (os._exit).
"""
import os
import shlex
import sys

from PySide import QtCore

HERE = os.path.dirname(os.path.abspath(__file__))
WATCHDOG_S = int(os.environ.get("MM_GUI_WATCHDOG_S", "1500"))   # the whole GUI run: ~10 min with two lanes at once


def _run():
    rc = 99
    try:
        sys.stdout = sys.__stdout__
        sys.stderr = sys.__stderr__
        import pytest

        extra = shlex.split(os.environ.get("MM_GUI_PYTEST_ARGS", ""))
        root = os.path.dirname(HERE)
        named = [a for a in extra if not a.startswith("-") and os.path.exists(os.path.join(root, a.split("::")[0]))]
        extra = [os.path.join(root, a) if a in named else a for a in extra]
        args = ["-q", "-p", "no:cacheprovider", f"--rootdir={root}"] + ([] if named else
                                                                              [os.path.join(HERE, "gui")]) + extra
        rc = int(pytest.main(args))
    except BaseException as exc:  # noqa: BLE001 - report and leave
        print(f"run_gui_pytest: {exc!r}", file=sys.__stderr__)
    finally:
        try:
            sys.__stdout__.flush()
            sys.__stderr__.flush()
        finally:
            os._exit(rc)


def _watchdog():
    print(f"run_gui_pytest: watchdog after {WATCHDOG_S} s", file=sys.__stderr__)
    sys.__stderr__.flush()
    os._exit(124)


QtCore.QTimer.singleShot(WATCHDOG_S * 1000, _watchdog)
QtCore.QTimer.singleShot(0, _run)
