"""core.numbers reads typed numbers strictly: what float()/int() take beyond a person's number is refused, and
every refusal names the field and the text."""
import argparse

import pytest

from metamaterial_wb.cli import integer, number
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.numbers import parse_float, parse_int


@pytest.mark.parametrize("text,value", [("12", 12.0), ("-0.5", -0.5), ("+.5", 0.5), ("1e-3", 1e-3), ("3.", 3.0),
                                        (" 7 ", 7.0), ("-0", 0.0), ("2.2250738585072014e-308", 2.2250738585072014e-308)])
def test_ordinary_numbers_read_as_python_does(text, value):
    assert parse_float("--x", text) == value == float(text)


@pytest.mark.parametrize("text", ["1_0", "\u0663", "\uff11", "1\u0660", "inf", "-Infinity", "nan", "0x10", "", " ",
                                  "1e", "1.2.3", "--1", "1,5", "1e999", "5e-320", "-4e-310"])
def test_what_float_takes_beyond_a_number_is_refused(text):
    with pytest.raises(SceneError) as e:
        parse_float("--dt", text)
    assert str(e.value).startswith("--dt: ") and repr(text) in str(e.value)


def test_python_float_would_have_taken_them():
    # the reason for the module: these are numbers to Python
    assert float("1_0") == 10 and float("\u0663") == 3 and float("\uff11") == 1 and float("5e-320") > 0


@pytest.mark.parametrize("text,value", [("3", 3), ("-12", -12), ("+4", 4), (" 0 ", 0)])
def test_whole_numbers(text, value):
    assert parse_int("--n", text) == value


@pytest.mark.parametrize("text", ["1_0", "\u0663", "3.0", "1e3", "", "0x1", "1" * 20, "True"])
def test_what_int_takes_beyond_a_whole_number_is_refused(text):
    with pytest.raises(SceneError) as e:
        parse_int("--n", text)
    assert "--n" in str(e.value) and repr(text) in str(e.value)


def test_non_text_is_refused():
    with pytest.raises(SceneError):
        parse_float("x", 1.0)


def test_argparse_types_name_the_flag(capsys):
    p = argparse.ArgumentParser(prog="t")
    p.add_argument("--dt", type=number)
    p.add_argument("--n", type=integer)
    assert vars(p.parse_args(["--dt=-0.25", "--n", "7"])) == {"dt": -0.25, "n": 7}
    for args, flag in ((["--dt", "1_0"], "--dt"), (["--n", "\u0663"], "--n")):
        with pytest.raises(SystemExit):
            p.parse_args(args)
        err = capsys.readouterr().err
        assert f"argument {flag}:" in err and "not a" in err


def test_minus_zero_reads_as_zero():
    import math
    assert math.copysign(1.0, parse_float("--global", "-0")) == 1.0
    assert math.copysign(1.0, parse_float("--global", "-0.0e5")) == 1.0


@pytest.mark.parametrize("text", ["1e-400", "-2.5e-330", "0.0000001e-320"])
def test_a_number_too_small_to_hold_is_refused_not_read_as_zero(text):
    # float() gives 0.0 for these; a typed non-zero is not zero (a subnormal 1e-310 was refused already)
    with pytest.raises(SceneError, match="too close to zero"):
        parse_float("--set tail", text)


@pytest.mark.parametrize("text", ["0", "0.000", "-0e-400", "0e5"])
def test_zeros_are_zero(text):
    assert parse_float("--x", text) == 0.0


@pytest.mark.parametrize("text,ok", [("999999999999999999", True), ("+999999999999999999", True),
                                     ("-999999999999999999", True), ("9999999999999999999", False),
                                     ("+9999999999999999999", False)])
def test_the_digit_limit_counts_digits_not_the_sign(text, ok):
    if ok:
        assert parse_int("--n", text) == int(text)
    else:
        with pytest.raises(SceneError, match="at most 18 digits"):
            parse_int("--n", text)
