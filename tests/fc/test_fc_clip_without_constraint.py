"""An angular-constraint clip made by a script on a joint without a constraint (App level): the module is invalid with
one clear line in the user's names -- the module's label once, its field, the joint, what to do -- and never the
one-module scene's internal name ``constraint_clip_1`` (it read "module Module_constraint_clip: angle_deg
(constraint_clip_1): give the clip's angle (degrees, range [-60, 60]); ...", a range the joint may not even turn)."""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")

from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from test_fc_objects import doc  # noqa: E402,F401 - the App tests' document fixture

CHAIN = {"format": "metamaterial-scene", "version": 1, "layout": {"chain": 7}}


def _chain(doc):
    return structure.make_structure(doc, Scene.from_dict(CHAIN))


def test_a_clip_without_constraint_is_invalid_with_one_clear_line(doc):
    sc = _chain(doc)
    m = structure.make_module(doc, sc, "constraint_clip", "H0,4")
    doc.recompute()
    assert not m.isValid() and sc.isValid(), (m.State, sc.State)
    msg = m.getStatusString()
    assert msg.count(m.Label) == 1, msg
    assert msg.startswith(f"module {m.Label}: angle_deg: "), msg
    assert "constraint_clip_1" not in msg and "(" + "constraint_clip" not in msg, msg
    assert "joint H0,4 has no constraint" in msg and "place a constraint on H0,4" in msg, msg
    assert "range [-60, 60]" not in msg, msg            # the joint's own range, not the clip's outer limits
    lines = [w for w in sc.SolveWarnings if m.Label in w]
    assert lines == [msg], list(sc.SolveWarnings)


def test_the_angle_range_in_the_message_is_one_the_clip_takes(doc):
    sc = _chain(doc)
    m = structure.make_module(doc, sc, "constraint_clip", "H0,4")
    doc.recompute()
    msg = m.getStatusString()
    lo, hi = (float(x) for x in msg.rsplit("[", 1)[1].split("]")[0].split(","))
    assert lo < 0 < hi, msg
    for angle in (lo, hi):                              # the printed bounds typed back are taken
        m.ModuleData = json.dumps({"angle_deg": angle})
        doc.recompute()
        assert m.isValid(), (angle, m.getStatusString())


def test_an_angle_out_of_range_names_the_field_without_the_internal_name(doc):
    sc = _chain(doc)
    m = structure.make_module(doc, sc, "constraint_clip", "H0,4", {"angle_deg": 90})
    doc.recompute()
    msg = m.getStatusString()
    assert not m.isValid() and msg.startswith(f"module {m.Label}: angle_deg: 90"), msg
    assert "constraint_clip_1" not in msg, msg


def test_a_clip_with_a_constraint_on_its_joint_builds(doc):
    sc = _chain(doc)
    structure.make_item(doc, sc, "constraint", "hold", "H0,4", value=0.3)
    m = structure.make_module(doc, sc, "constraint_clip", "H0,4")
    doc.recompute()
    assert m.isValid() and sc.isValid(), m.getStatusString()
