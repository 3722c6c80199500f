"""Hand-written joint configuration beside a designed one, its keys, and axis names (from an audit):

* ``design`` dropped hand-written ``joint_config`` entries (no ``axis``) when it configured the axes;
* one hand-written entry hid a stale design: ``ensure_configured`` only compared when every entry had ``axis``, so
  a fold changed after designing was solved with the old tilts and no warning;
* an unknown key in a ``joint_config`` entry (``{"tilt": 40}``) was ignored: the joint solved with tilt 0;
* two axes with one name (or a name that is another axis' default name ``v<line>`` / ``h<line>``) were taken:
  ``--fold a=10`` and the design report's reverse fold picked the wrong axis.
"""
import pytest

from metamaterial_wb.core import design
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene


def scene(layout, axes, **kw):
    d = {"layout": layout, "hinge": {"length_mm": 9.5, "width_mm": 0.8, "thickness_mm": 3}, "cell_size_mm": 35,
         "axes": axes}
    d.update(kw)
    return Scene.from_dict(d)


def V(line, fold=0.0, **kw):
    return dict({"direction": "vertical", "line": line, "fold_deg": fold}, **kw)


def test_design_keeps_a_hand_written_tilt_on_a_joint_no_axis_crosses():
    s = scene({"chain": 6}, [V(1, 30.0)], joint_config={"H0,4": {"tilt_deg": 3.0}})
    rep = design.configure(s)
    assert s.joint_config["H0,4"] == {"tilt_deg": 3.0}
    assert s.joint_config["H0,1"]["axis"] == "v1"
    assert s.joint_tilt_deg("H0,4") == 3.0
    assert not any("H0,4" in w for w in rep["warnings"])


def test_a_hand_written_tilt_on_an_axis_joint_wins_and_design_says_so():
    s = scene({"chain": 6}, [V(1, 30.0)], joint_config={"H0,1": {"tilt_deg": 3.0}})
    rep = design.configure(s)
    assert s.joint_config["H0,1"] == {"tilt_deg": 3.0}
    assert any(w.startswith("joint_config.H0,1: its hand-written tilt_deg = 3 wins over") and "axis v1" in w
               for w in rep["warnings"]), rep["warnings"]


def test_a_stale_design_is_found_beside_a_hand_written_entry():
    s = scene({"chain": 6}, [V(1, 30.0)], joint_config={"H0,4": {"tilt_deg": 3.0}})
    design.configure(s)
    designed = s.joint_config["H0,1"]["tilt_deg"]
    s.axes[0].fold_deg = 10.0                        # changed after designing
    rep = design.ensure_configured(s)
    assert rep is not None and "stale" in rep["warnings"][0]
    assert s.joint_config["H0,1"]["fold_deg"] == 10.0 and s.joint_config["H0,1"]["tilt_deg"] != designed
    assert s.joint_config["H0,4"] == {"tilt_deg": 3.0}
    assert design.ensure_configured(s) is None


def test_axes_never_designed_beside_a_hand_written_entry_are_configured():
    """A scene whose joint_config holds only a hand-written entry elsewhere: the axis' joints were solved flat."""
    s = scene({"chain": 6}, [V(1, 30.0)], joint_config={"H0,4": {"tilt_deg": 3.0}})
    rep = design.ensure_configured(s)
    assert rep is not None and s.joint_config["H0,1"]["axis"] == "v1" and s.joint_config["H0,4"]["tilt_deg"] == 3.0


@pytest.mark.parametrize("entry, match", [
    ({"tilt": 40}, r"joint_config\.H0,1\.tilt: unknown field; allowed: \['tilt_deg', 'fold_deg', 'axis'\]"),
    ({"tilt_deg": 4, "axis": 3}, r"joint_config\.H0,1\.axis: expected text \(the axis' name\), got 3"),
])
def test_joint_config_entries_refuse_unknown_fields(entry, match):
    with pytest.raises(SceneError, match=match):
        scene({"chain": 6}, [], joint_config={"H0,1": entry})


def test_two_axes_with_one_name_are_refused():
    with pytest.raises(SceneError, match=r"axes\[1\]\.name: 'a' is already the name of axes\[0\]"):
        scene({"grid": [2, 6]}, [V(1, 30.0, name="a"), V(4, -20.0, name="a")])


def test_a_name_that_is_another_axis_default_name_is_refused():
    H1 = {"direction": "horizontal", "line": 1, "fold_deg": 10.0, "name": "v4"}
    with pytest.raises(SceneError, match=r"axes\[1\]\.name: 'v4' is already the default name of axes\[0\]"):
        scene({"grid": [3, 6]}, [V(4, 20.0), H1])
    scene({"grid": [3, 6]}, [V(4, 20.0, name="v4"), V(1, 10.0)])      # its own default name: fine
