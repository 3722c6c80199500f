"""Fit to target's Workers box and the command line's ``inverse --workers`` take one range (session 35): the box
stopped at 64 while ``inverse --workers`` allows 1..256, so 100 typed into the box was cut to 10. Both now read
``core.inverse.WORKERS_RANGE``."""
import argparse

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from metamaterial_wb.cli import inverse as cli_inverse  # noqa: E402
from metamaterial_wb.core.inverse import WORKERS_RANGE  # noqa: E402
from metamaterial_wb.gui.panels import ranges  # noqa: E402
from guihelpers import doc, process, run_panel, type_into, workbench  # noqa: E402,F401
from test_gui_fit_target import _structure  # noqa: E402


def cli_workers_help():
    parser = argparse.ArgumentParser()
    cli_inverse.add_arguments(parser)
    act = next(a for a in parser._actions if "--workers" in a.option_strings)
    return act.help


def test_the_workers_box_takes_the_command_lines_range(doc):
    lo, hi = WORKERS_RANGE
    assert cli_inverse.WORKERS_RANGE == (lo, hi)
    assert f"{lo}..{hi}" in cli_workers_help(), cli_workers_help()
    _structure(doc)
    p = run_panel("MM_FitTarget")
    assert (p.workers.minimum(), p.workers.maximum()) == (lo, hi)
    type_into(p.workers, "100")         # beyond the box's old 64
    assert p.workers.value() == 100 and not p.workers.property(ranges.REFUSED), p.workers.property(ranges.REFUSED)
    type_into(p.workers, str(hi))
    assert p.workers.value() == hi and not p.workers.property(ranges.REFUSED)
    type_into(p.workers, str(hi + 1))   # one beyond: refused and said, not cut in silence
    process()
    said = p.workers.property(ranges.REFUSED) or ""
    assert said and str(hi) in said, said
    p.reject()
