"""Add module: the hover marker in the 3D view lights only targets of the chosen module's kind.

A hinge under the cursor while a node module (friction pad) is chosen, or a node while a joint module (servo
housing) is chosen, is named in the panel as "not a target" and must not light the yellow marker; a valid
target lights it. Changing the module kind while the cursor rests on a target re-judges the marker at once.
A click on the wrong kind still picks nothing.
"""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from guihelpers import (click_view, doc, hinge_mid, hover_view, process, run_panel,  # noqa: E402,F401
                        screen_point, workbench)
from test_gui_design_panels import node_point, open_example  # noqa: E402


def lit(p):
    return p.picker.switch.whichChild.getValue() == 0


def test_hover_marker_lights_only_targets_of_the_module_kind(doc):
    sc = open_example("fish")
    p = run_panel("MM_AddModule")
    p.set_type("friction_pad")                   # goes on a node
    process()
    p.target.setCurrentText("N0,0")              # the user chooses the target (the panel opens with none)
    hinge = screen_point(hinge_mid(sc, "H0,2"))
    node = screen_point(node_point(sc, "N0,3"))
    hover_view(node)
    assert p.pick_label.text() == "under the cursor: node N0,3 (click to pick it)"
    assert lit(p), "a node under the cursor is a target for a friction pad: the marker lights it"
    hover_view(hinge)
    assert p.pick_label.text().startswith("under the cursor: hinge H0,2 (not a target"), p.pick_label.text()
    assert not lit(p), "the marker lights a hinge, which is no target for a friction pad"
    click_view(hinge)                            # a click on the wrong kind still picks nothing
    assert p.target.currentText() == "N0,0" and not lit(p)
    # the cursor rests on the hinge; the module becomes a joint module: the hinge is a target now
    p.set_type("servo_housing")
    process()
    p.target.setCurrentText("H0,0")
    assert lit(p), "after choosing a servo housing the hinge under the cursor is a target"
    hover_view(node)
    assert p.pick_label.text().startswith("under the cursor: node N0,3 (not a target"), p.pick_label.text()
    assert not lit(p), "the marker lights a node, which is no target for a servo housing"
    click_view(node)
    assert p.target.currentText() == "H0,0" and not lit(p)
    p.set_type("connection_hub")                 # a node module again, the cursor on the node: lit
    process()
    assert lit(p)
    hover_view(hinge)
    assert not lit(p)
    hover_view(node)
    assert lit(p)
    click_view(node)
    assert p.target.currentText() == "N0,3" and p.pick_label.text() == "picked node N0,3"
    p.reject()
