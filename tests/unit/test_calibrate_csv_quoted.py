"""A user audit of ``calibrate measured``'s ANGLES.csv: the line ``"N0,0",0.4,7`` (a quoted node name, its angle and
a stray third cell) was taken for the unquoted three-column form ``N0,0,angle`` and refused as
``'N0,0,0.4' is not a node name`` -- a node name nobody wrote. The CSV is read with the csv module (a quoted cell
keeps its comma); a line with a quoted node name and a third cell is refused naming the node, the angle and the extra
cell, and the two valid forms (quoted two columns, unquoted three columns) still load."""
import math

import pytest

from metamaterial_wb.core import calibrate as C
from metamaterial_wb.core.errors import SceneError


def read(tmp_path, text):
    p = tmp_path / "angles.csv"
    p.write_text(text, encoding="utf-8")
    return p, C.read_angles_csv(str(p), C.test_piece(2.0))


def test_a_quoted_node_with_a_third_cell_names_what_is_wrong(tmp_path):
    with pytest.raises(SceneError) as e:
        read(tmp_path, 'node,angle_deg\n"N0,0",0.4,7\n"N0,1",-0.37\n')
    p = tmp_path / "angles.csv"
    assert e.value.field == f"{p}:2", e.value.field
    msg = e.value.message
    assert "N0,0,0.4" not in msg, msg                     # the misleading joined name is gone
    assert "'N0,0'" in msg and "'0.4'" in msg and "'7'" in msg and "3 columns" in msg, msg


@pytest.mark.parametrize("line", ['"N0,0",0.4,', '"N0,0",0.4,7,8', '"N(0,0)",0.4,x'])
def test_other_extra_cells_after_a_quoted_node_are_refused_too(tmp_path, line):
    with pytest.raises(SceneError) as e:
        read(tmp_path, f'node,angle_deg\n{line}\n"N0,1",-0.37\n')
    assert "is not a node name" not in e.value.message, e.value.message
    assert "columns" in e.value.message, e.value.message


@pytest.mark.parametrize("text", ['node,angle_deg\n"N0,0",0.4\n"N0,1",-0.37\n',
                                  'N0,0,0.4\nN0,1,-0.37\n',
                                  'node,angle_deg\n" N0,0 ",0.4\n"N(0,1)",-0.37\n'],
                         ids=["quoted", "three-columns", "spaces-and-parentheses"])
def test_the_valid_forms_still_load(tmp_path, text):
    _p, (idx, ang) = read(tmp_path, text)
    assert len(idx) == 2
    assert ang == pytest.approx([math.radians(0.4), math.radians(-0.37)])


def test_an_unquoted_line_that_is_no_node_still_says_so(tmp_path):
    with pytest.raises(SceneError) as e:
        read(tmp_path, 'node,angle_deg\nX0,0,0.4\nN0,1,-0.37\n')
    assert "is not a node name" in e.value.message, e.value.message
