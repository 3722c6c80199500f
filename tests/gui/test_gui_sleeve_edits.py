"""The Sleeve actuator panel checks the spec on every edit a user makes, and blocks only on fields it shows (audit).

1. The t / h spin boxes of the cell-types table are cell widgets: their edits never reached ``check_spec`` (it
   listened to ``itemChanged``, which cell widgets never send), nor did **Add type**. A stale error stayed with OK
   disabled after the user fixed it (L = 10, then h = 5 in both rows; ring ``0, 0, 1, 2``, then Add type), and a new
   one was never shown (c = 10, then t = 4.5: OK enabled, then OK failed).
2. The panel carried the example's ``actuator.core_diameter_mm`` (24.6 mm, the cap) into every spec without showing
   it: a 3- or 2-cell ring, L = 10 or T = 4 was refused naming a field the panel has not. The cap is now a field of
   the panel: **automatic** (the validator's default, which follows a narrower sleeve's inner diameter; the example
   loaded first starts on it) or a value the user types, never changed."""
import json
import os

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtGui  # noqa: E402

from guihelpers import click, dialog_button, doc, press_ok, process, qtest, run_panel, type_into  # noqa: E402
from guihelpers import workbench  # noqa: E402,F401

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXAMPLE = os.path.join(ROOT, "examples", "sleeve.json")


@pytest.fixture
def built(monkeypatch):
    """What OK hands to the geometry: a box stands in for the sleeve's B-rep (minutes on a shared machine)."""
    from metamaterial_wb.geometry import sleeve as geo
    specs = []

    def stand_in(sp, d):
        specs.append(sp)
        return [d.addObject("Part::Box", "sleeve")]
    monkeypatch.setattr(geo, "add_to_document", stand_in)
    return specs


def problem(p):
    return p.problem_label("spec").text()


def ok_enabled():
    return dialog_button("Ok").isEnabled()


def sleeve_part(doc):
    return [o for o in doc.Objects if o.TypeId == "App::Part" and hasattr(o, "SleeveSpec")][-1]


# ---- 1. the cell-types table is checked on every edit ------------------------------------------------------

def test_fixing_h_in_the_table_clears_the_error_and_ok_builds(doc, built):
    p = run_panel("MM_Sleeve")
    type_into(p.dims["L_mm"], "10")
    assert p.dims["L_mm"].value() == 10.0
    assert "cell_types[0].h_mm: 7.092 mm is outside" in problem(p) and not ok_enabled(), problem(p)
    type_into(p.types.cellWidget(0, 1), "5")
    assert "cell_types[0]" not in problem(p), f"row 0 fixed, its error stayed: {problem(p)}"
    assert "cell_types[1].h_mm: 7.488 mm is outside" in problem(p) and not ok_enabled(), problem(p)
    type_into(p.types.cellWidget(1, 1), "5")
    assert problem(p) == "" and ok_enabled(), f"every value fixed, the error stayed: {problem(p)}"
    assert press_ok(), p.error.text()
    assert len(built) == 1 and built[0].L == 10.0 and [g.h for g in built[0].cells] == [5.0, 5.0]


def test_a_new_error_in_the_table_is_shown_at_once(doc, built):
    p = run_panel("MM_Sleeve")
    type_into(p.dims["c_mm"], "10")
    assert problem(p) == "" and ok_enabled(), problem(p)
    type_into(p.types.cellWidget(0, 0), "4.5")
    assert p.types.cellWidget(0, 0).value() == 4.5
    assert "c_mm" in problem(p) and "no free beam" in problem(p), f"t = 4.5 with c = 10 not shown: {problem(p)!r}"
    assert not ok_enabled() and not press_ok() and not built
    type_into(p.types.cellWidget(0, 0), "1.1")                   # fixed again: the error goes
    assert problem(p) == "" and ok_enabled(), problem(p)


def test_add_type_rechecks_the_pattern_that_names_it(doc, built):
    p = run_panel("MM_Sleeve")
    type_into(p.ring, "0, 0, 1, 2")
    assert "ring[3]" in problem(p) and not ok_enabled(), problem(p)
    add = [b for b in p.form.findChildren(QtGui.QPushButton) if b.text() == "Add type"][0]
    click(add)
    assert p.types.rowCount() == 3
    assert problem(p) == "" and ok_enabled(), f"type 2 added, the error stayed: {problem(p)}"
    assert press_ok(), p.error.text()
    assert len(built) == 1 and built[0].pattern == [[0, 0, 1, 2]] and len(built[0].cells) == 3


def test_remove_last_still_rechecks(doc):
    p = run_panel("MM_Sleeve")
    click([b for b in p.form.findChildren(QtGui.QPushButton) if b.text() == "Remove last"][0])
    assert "ring[2]" in problem(p) and not ok_enabled(), problem(p)
    click([b for b in p.form.findChildren(QtGui.QPushButton) if b.text() == "Add type"][0])
    assert problem(p) == "" and ok_enabled(), problem(p)
    p.reject()


# ---- 2. the cap (actuator.core_diameter_mm) is a field of the panel -------------------------------------------

# the automatic cap of a sleeve too narrow for 24.6 mm: the widest its end rings hold, the inner diameter less two
# 0.4 mm ring walls
@pytest.mark.parametrize("field, text, inner", [("ring", "0, 0, 1", 3 * 22 / 3.141592653589793 - 1.8 - 0.8),
                                                 ("ring", "0, 1", 2 * 22 / 3.141592653589793 - 1.8 - 0.8),
                                                 ("T_mm", "4", 4 * 22 / 3.141592653589793 - 4.0 - 0.8)])
def test_a_narrower_sleeve_builds_with_the_automatic_cap(doc, built, field, text, inner):
    p = run_panel("MM_Sleeve")
    type_into(p.ring if field == "ring" else p.dims[field], text)
    assert problem(p) == "" and ok_enabled(), f"{field} = {text}: {problem(p)}"
    assert p.cap_auto.isChecked(), "the example's cap (24.6 mm, the default) starts on automatic"
    assert "core_diameter_mm" not in p.spec_dict().get("actuator", {})
    # the box shows the cap the sleeve gets: the widest its rings hold (the default 24.6 mm does not fit), and says so
    assert p.cap.value() == pytest.approx(inner, abs=1e-3) and not p.cap.isEnabled()
    assert "inner diameter" in p.cap.toolTip(), p.cap.toolTip()
    assert press_ok(), p.error.text()
    assert len(built) == 1 and built[0].core_diameter == pytest.approx(inner)
    assert "core_diameter_mm" not in json.loads(sleeve_part(doc).SleeveSpec).get("actuator", {})


def test_l_10_with_h_5_builds_with_the_automatic_cap(doc, built):
    p = run_panel("MM_Sleeve")
    type_into(p.dims["L_mm"], "10")
    for r in range(2):
        type_into(p.types.cellWidget(r, 1), "5")
    assert problem(p) == "" and ok_enabled(), problem(p)
    assert p.cap.value() == pytest.approx(4 * 14 / 3.141592653589793 - 1.8 - 0.8, abs=1e-3)
    assert press_ok(), p.error.text()
    assert built[0].core_diameter == pytest.approx(4 * 14 / 3.141592653589793 - 1.8 - 0.8)


def test_a_typed_cap_is_kept_and_refused_naming_the_field_the_panel_shows(doc, built):
    p = run_panel("MM_Sleeve")
    assert p.cap.value() == pytest.approx(24.6) and p.cap.property("validator_field")
    labels = [w.text() for w in p.form.findChildren(QtGui.QLabel) if w.isVisible()]
    assert any("core_diameter_mm" in t for t in labels), labels
    click(p.cap_auto)
    assert not p.cap_auto.isChecked() and p.cap.isEnabled()
    type_into(p.cap, "22")
    assert problem(p) == "" and ok_enabled(), problem(p)
    assert p.spec_dict()["actuator"]["core_diameter_mm"] == 22.0
    type_into(p.ring, "0, 0, 1")                    # the typed cap no longer fits: said, never changed
    assert "actuator.core_diameter_mm: 22.0 mm is outside the allowed range (0, 18.4085]" in problem(p), problem(p)
    assert not ok_enabled() and p.cap.value() == 22.0 and p.spec_dict()["actuator"]["core_diameter_mm"] == 22.0
    type_into(p.cap, "15")
    assert problem(p) == "" and ok_enabled(), problem(p)
    assert press_ok(), p.error.text()
    assert built[0].core_diameter == 15.0 and built[0].N == 3
    assert json.loads(sleeve_part(doc).SleeveSpec)["actuator"] == {"core_diameter_mm": 15.0, "membrane_kPa_per_mL": 0}


def test_ticking_automatic_again_gives_the_cap_back_to_the_sleeve(doc, built):
    p = run_panel("MM_Sleeve")
    click(p.cap_auto)
    type_into(p.cap, "300")                         # past the box's 240 mm: the box keeps 30 and says so
    assert p.cap.value() == 30.0 and "240" in p.cap.property("refused_input")
    type_into(p.cap, "22")
    type_into(p.ring, "0, 0, 1")
    assert "actuator.core_diameter_mm" in problem(p)
    type_into(p.cap, "300")
    assert p.cap.property("refused_input")
    click(p.cap_auto)                               # the refused keystroke goes with the value typed
    assert p.cap.property("refused_input") == ""
    assert p.cap_auto.isChecked() and not p.cap.isEnabled()
    assert problem(p) == "" and ok_enabled(), problem(p)
    assert p.cap.value() == pytest.approx(18.4085, abs=1e-3)
    # unticked once more, the box starts from the cap shown and keeps it exactly (18.4085 shows as 18.408 / 18.409)
    click(p.cap_auto)
    assert problem(p) == "" and ok_enabled(), problem(p)
    assert p.spec_dict()["actuator"]["core_diameter_mm"] == pytest.approx(18.408452488130185, rel=1e-12)
    assert press_ok(), p.error.text()
    assert built[0].core_diameter == pytest.approx(18.408452488130185, rel=1e-12)


def test_a_spec_files_own_cap_is_kept_as_given(doc, tmp_path):
    spec = json.load(open(EXAMPLE))
    spec["actuator"]["core_diameter_mm"] = 20.5
    path = tmp_path / "cap.json"
    path.write_text(json.dumps(spec))
    p = run_panel("MM_Sleeve")
    assert p.load_spec(str(path)), p.error.text()
    assert not p.cap_auto.isChecked() and p.cap.isEnabled() and p.cap.value() == 20.5
    assert p.spec_dict()["actuator"]["core_diameter_mm"] == 20.5 and "automatic" not in p.cap.toolTip()
    type_into(p.ring, "0, 0, 1")
    assert "actuator.core_diameter_mm: 20.5 mm is outside" in problem(p) and not ok_enabled(), problem(p)
    # the example opened as a file is the user's choice too: its 24.6 mm is kept
    assert p.load_spec(EXAMPLE), p.error.text()
    assert not p.cap_auto.isChecked() and p.spec_dict()["actuator"]["core_diameter_mm"] == 24.6
    assert problem(p) == "" and ok_enabled(), problem(p)
    # a spec without a cap: automatic
    del spec["actuator"]["core_diameter_mm"]
    path.write_text(json.dumps(spec))
    assert p.load_spec(str(path)), p.error.text()
    assert p.cap_auto.isChecked() and not p.cap.isEnabled() and p.cap.value() == pytest.approx(24.6)
    assert p.spec_dict()["actuator"] == {"membrane_kPa_per_mL": 0}
    p.reject()


def test_loading_a_valid_spec_clears_an_error_the_fields_had(doc):
    p = run_panel("MM_Sleeve")
    type_into(p.dims["L_mm"], "10")
    assert problem(p) and not ok_enabled()
    assert p.load_spec(EXAMPLE), p.error.text()
    assert problem(p) == "" and ok_enabled(), problem(p)
    p.reject()


def test_the_name_is_checked_as_it_is_typed(doc, built):
    """The name was checked on OK only: 201 characters kept OK enabled, and OK then failed (audit, session 27)."""
    p = run_panel("MM_Sleeve")
    type_into(p.name, "s" * 201)
    assert "name: " in problem(p) and "at most 200 characters" in problem(p) and not ok_enabled(), problem(p)
    type_into(p.name, "my sleeve")
    assert problem(p) == "" and ok_enabled(), problem(p)
    press_ok()
    assert sleeve_part(FreeCAD.ActiveDocument).Label == "my sleeve"
