"""The Sleeve panel's summary says an incomplete snapping order is undetermined, and why (the core's note). Before:
every null ``symmetric`` read "nothing snapped", also when cells did snap but a type could not be ordered."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)


def summary(**seq):
    return {"unit_cells": [], "ring": {"rings": 1, "cells": 4, "peaks": [0.03], "valleys": [0.01]},
            "sequence": dict({"loading": [0], "unloading": [0], "events_loading": [], "events_unloading": []}, **seq)}


def order_line(lines):
    return [ln for ln in lines if ln.startswith("sequence: loading")][0]


def test_sleeve_summary_names_an_incomplete_order_undetermined():
    from metamaterial_wb.gui.panels.sleeve import sleeve_summary_text
    note = "type 1 has no pillar between two cells of its own type"
    ev = [{"d": 0.1, "units": [0, 3], "snapped": True}]
    lines = sleeve_summary_text(summary(symmetric=None, note=note, events_loading=ev, events_unloading=ev))
    assert order_line(lines).endswith("-> undetermined"), lines
    assert any(note in ln for ln in lines), lines
    lines = sleeve_summary_text(summary(symmetric=None, loading=[], unloading=[]))
    assert order_line(lines).endswith("-> nothing snapped"), lines
    assert order_line(sleeve_summary_text(summary(symmetric=False, events_loading=ev))).endswith("-> asymmetric")
    assert order_line(sleeve_summary_text(summary(symmetric=True, events_loading=ev))).endswith("-> symmetric")
