"""Titles of the pictures drawn with matplotlib from a user-given text (``render``'s scene name or ``--title``,
``inverse``'s result.png), through the real CLI.

The rule (metamaterial_wb/core/render.py, fit_title): a title is drawn literally, a newline starting a line,
within the picture's width and a quarter of its height. A ``--title`` that does not fit is refused naming
``--title``, its length and how much of it fits; a title made from the scene name (the scene format allows a
100 000-character name) is shortened -- the name only, ending in '…' -- and that is said once. Characters the
font cannot draw are named once in one line. Never a traceback, never a raw library warning.

Audit findings these pin down:
* a 4000-character scene name, or a --title of 3000 characters, crashed render with
  ``RuntimeError: In draw_glyphs_to_bitmap: Could not convert glyph to bitmap (raster overflow ...)``;
* an emoji / CJK name printed one raw ``UserWarning: Glyph 128031 (\\N{FISH}) missing from current font.`` per
  glyph; a name of many lines a raw ``UserWarning: Tight layout not applied``;
* a title with ``$...$`` was read as math: ``--title '$\\foo$'`` crashed with a mathtext parse error.
"""
import json
import os

from tests.clihelpers import REPO, one_line_error, run_cli

FISH = os.path.join(REPO, "examples", "fish.json")
WORM = os.path.join(REPO, "examples", "worm.json")
WORM_TARGET = os.path.join(REPO, "examples", "worm_gait_target.json")


def _scene(tmp_path, name, base=FISH):
    with open(base, encoding="utf-8") as f:
        d = json.load(f)
    d["name"] = name
    p = tmp_path / "scene.json"
    p.write_text(json.dumps(d), encoding="utf-8")
    return str(p)


def _clean(r):
    """No traceback, no raw library warning; every stderr line is one of ours."""
    assert "Traceback" not in r.stderr, r.stderr
    assert "UserWarning" not in r.stderr and "Glyph " not in r.stderr, r.stderr
    for line in r.stderr.splitlines():
        assert line.startswith(("warning: ", "error: ", "inverse: ")), r.stderr


def _png(path):
    with open(path, "rb") as f:
        return f.read(8) == b"\x89PNG\r\n\x1a\n"


def test_a_long_scene_name_is_shortened_in_the_title_and_said_once(tmp_path):
    out = tmp_path / "pic.png"
    r = run_cli("render", _scene(tmp_path, "fish_" + "x" * 4000), "--out", out)
    assert r.returncode == 0, r.stderr
    _clean(r)
    assert _png(out)
    lines = r.stderr.splitlines()
    assert len(lines) == 1, r.stderr
    w = lines[0]
    assert "scene name (4005 characters)" in w and "shortened" in w and "1200 x 800 px" in w and "--title" in w, w


def test_a_title_too_long_for_the_picture_is_refused_naming_title_its_length_and_what_fits(tmp_path):
    out = tmp_path / "pic.png"
    r = run_cli("render", FISH, "--out", out, "--title", "a" * 3000)
    one_line_error(r, "--title")
    assert "3000 characters" in r.stderr and "1200 x 800 px" in r.stderr, r.stderr
    assert "the first " in r.stderr and "--size" in r.stderr, r.stderr
    assert not out.exists()
    # the same title in a picture wide enough is drawn as typed
    r = run_cli("render", FISH, "--out", out, "--title", "a" * 300, "--size", "8000x800")
    assert r.returncode == 0 and r.stderr == "", r.stderr
    assert _png(out)


def test_characters_the_font_cannot_draw_are_named_once_in_one_line(tmp_path):
    out = tmp_path / "pic.png"
    r = run_cli("render", _scene(tmp_path, "\U0001F41F Fisch mit \u00dcmlaut \u65e5\u672c"), "--out", out)
    assert r.returncode == 0, r.stderr
    _clean(r)
    assert _png(out)
    lines = r.stderr.splitlines()
    assert len(lines) == 1, r.stderr
    assert "U+1F41F FISH" in lines[0] and "U+65E5" in lines[0] and "U+672C" in lines[0], lines[0]
    assert "U+00DC" not in lines[0], lines[0]          # the font has U with diaeresis
    # the same in a --title
    r = run_cli("render", FISH, "--out", out, "--title", "\U0001F41F\U0001F41F fish")
    assert r.returncode == 0, r.stderr
    _clean(r)
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and "1 character" in lines[0] and "U+1F41F FISH" in lines[0], r.stderr


def test_a_name_of_many_lines_is_drawn_as_lines_and_shortened_said(tmp_path):
    out = tmp_path / "pic.png"
    r = run_cli("render", _scene(tmp_path, "\n".join(["line1", "line2"] * 100)), "--out", out)
    assert r.returncode == 0, r.stderr
    _clean(r)
    assert "Tight layout" not in r.stderr, r.stderr
    assert _png(out)
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and "200 lines" in lines[0] and "shortened" in lines[0], r.stderr
    # a title of a few lines fits and is drawn without a word
    r = run_cli("render", FISH, "--out", out, "--title", "first line\nsecond line")
    assert r.returncode == 0 and r.stderr == "", r.stderr
    # too many lines for the picture's height: refused like a too wide one
    r = run_cli("render", FISH, "--out", tmp_path / "other.png", "--title", "x\n" * 40)
    one_line_error(r, "--title")
    assert "41 lines" in r.stderr, r.stderr


def test_a_title_is_drawn_literally_not_read_as_math(tmp_path):
    out = tmp_path / "pic.png"
    r = run_cli("render", FISH, "--out", out, "--title", "$\\foo$ costs 5")
    assert r.returncode == 0 and r.stderr == "", r.stderr
    assert _png(out)
    r = run_cli("render", _scene(tmp_path, "Fisch $\\alpha_{1}$"), "--out", out)
    assert r.returncode == 0 and r.stderr == "", r.stderr


def test_inverse_picture_shortens_a_long_scene_name_and_says_so(tmp_path):
    out = tmp_path / "inv"
    r = run_cli("inverse", _scene(tmp_path, "worm_" + "x" * 4000, base=WORM), "--target", WORM_TARGET,
                "--out", out, "--values-only", "--fab-checks", "off", "--evaluate", "quadratic", timeout=600)
    assert r.returncode == 0, r.stderr
    _clean(r)
    assert _png(out / "result.png")
    said = [line for line in r.stderr.splitlines() if "warning" in line]
    assert len(said) == 1 and "result.png" in said[0] and "scene name (4005 characters)" in said[0], r.stderr
