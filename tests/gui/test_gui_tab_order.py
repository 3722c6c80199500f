"""New structure: Tab follows the panel's visual order, Name, Rows, Columns, Cell size, the presets, the cell
toggles row by row, then the scene file field and "Load scene file..." (the toggles sit above the file field; they
used to come last, after the file button), also after rows are added."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)


from guihelpers import doc, run_panel, tab_chain, type_into, workbench  # noqa: E402,F401




def _name(p, w):
    known = {p.name: "name", p.rows: "rows", p.cols: "cols", p.cell: "cell", p.grid_btn: "Grid",
             p.chain_btn: "Chain", p.clear_btn: "Clear", p.file: "file", p.browse: "browse"}
    known.update({b: "cell[%d,%d]" % k for k, b in p.buttons.items()})
    while w is not None:
        if w in known:
            return known[w]
        w = w.parentWidget()                                    # a spin box's line edit
    return "other"


def _expected(p):
    cells = ["cell[%d,%d]" % k for k in sorted(p.buttons)]
    return ["rows", "cols", "cell", "Grid", "Chain", "Clear"] + cells + ["file", "browse"]


def test_tab_follows_the_visual_order(doc):
    p = run_panel("MM_NewStructure")
    want = _expected(p)
    got = [_name(p, w) for w in tab_chain(p.name, len(want))[1:]]
    assert got == want, got
    type_into(p.rows, "3")                                      # one more row: its toggles come before the file field
    assert len(p.buttons) == 18
    want = _expected(p)
    got = [_name(p, w) for w in tab_chain(p.name, len(want))[1:]]
    assert got == want, got
    p.reject()
