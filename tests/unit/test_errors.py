"""``core/errors``: one range rule for the scene's numbers and the models' options (``in_range``)."""
import pytest

from metamaterial_wb.core.errors import SceneError, check_number, in_range
from metamaterial_wb.core.models import Option, check_option


def test_closed_bound_computed_from_fields_admits_the_written_value():
    assert 0.6 * 18 == 10.799999999999999
    assert in_range(10.8, high=0.6 * 18) and check_number("f", 10.8, high=0.6 * 18) == 10.8
    assert not in_range(10.8 + 1e-9, high=0.6 * 18)


@pytest.mark.parametrize("v,ok", [(0.0, False), (1e-300, True), (1.0, True), (1.0 + 1e-12, False)])
def test_open_low_closed_high(v, ok):
    assert in_range(v, 0.0, 1.0, low_open=True) is ok


def test_option_and_scene_number_share_the_rule():
    opt = Option("float", meaning="m", low=0.0, high=0.6 * 18)
    assert check_option("quadratic", "x", "10.8", opt) == 10.8      # the margin the scene's numbers get
    with pytest.raises(SceneError, match=r"--option x: '10.81'; allowed: a number in \[0, 10.8\] \(m\)"):
        check_option("quadratic", "x", "10.81", opt)
    opt = Option("float", low=0.0, high=1.0, low_open=True)
    with pytest.raises(SceneError):
        check_option("quadratic", "x", 0.0, opt)
