"""What docs/scene-format.md and README.md say about names, ranges, versions and errors is what the code does
(audit: module names with a dot loaded and solved but `build --modules` refused them; the tilt and fold ranges
were checked but not documented; an actuator's naming message left out the 64-character limit; a `version` of
1.0 was read as 1; argparse errors printed a usage block before a second error line)."""
import json
import re
from pathlib import Path

import pytest

from metamaterial_wb.core.errors import SceneError

REPO = Path(__file__).resolve().parents[2]
SCENE_DOC = REPO / "docs" / "scene-format.md"


def _doc(path=SCENE_DOC):
    return path.read_text(encoding="utf-8")


def _scene(**kw):
    from metamaterial_wb.core.scene import Scene
    d = {"format": "metamaterial-scene", "version": 1, "name": "t", "layout": {"grid": [2, 3]}}
    d.update(kw)
    return Scene.from_dict(d)


def _refused(**kw):
    with pytest.raises(SceneError) as e:
        _scene(**kw)
    return str(e.value)


def _build_modules(sc):
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    from metamaterial_wb.geometry.modules import parse_modules
    return parse_modules(sc, fabrication_params(sc, effective_tilts_deg(sc)))


# 1. module names: one rule at load and at build, the one the doc gives

def test_the_doc_names_modules_under_the_shared_naming_rule():
    doc = _doc()
    m = re.search(r"Names \(actuators, constraints, axes, modules\): ([^\n]*\n[^\n]*)", doc)
    assert m, "docs/scene-format.md lost its naming rule"
    assert "letters, digits and `_ . -`" in m.group(1) and "64 characters" in m.group(1), m.group(1)


@pytest.mark.parametrize("name", ["pad.left", "a.b.c", "hub_1-x.2", "_" + "a" * 63])
def test_a_module_name_the_doc_allows_loads_and_builds(name):
    sc = _scene(modules=[{"type": "connection_hub", "name": name, "node": "N0,1"}])
    specs = _build_modules(sc)
    assert [s.name for s in specs] == [name]


def test_a_dotted_module_name_makes_safe_distinct_file_names():
    from metamaterial_wb.export.package import check_output_names
    names = [n for n, _, _ in check_output_names("t", ["pad.left", "pad_left", "pad.left.x"])]
    assert "t_pad.left.step" in names and "t_pad.left.3mf" in names, names
    assert all("/" not in n and "\\" not in n and not n.endswith(".") for n in names), names
    assert len({n.casefold() for n in names}) == len(names), names


@pytest.mark.parametrize("name", ["pad left", "1pad", "pad/left", "pad\n", "a" * 65, "p\u0663", "é"])
def test_a_bad_module_name_is_refused_at_load_with_the_full_rule(name):
    msg = _refused(modules=[{"type": "connection_hub", "name": name, "node": "N0,1"}])
    assert msg.startswith("modules[0].name:"), msg
    assert "not a valid module name" in msg, msg
    assert "letters, digits, _ . -" in msg and "starting with a letter or _" in msg and "at most 64 characters" in msg, msg


def test_the_build_check_gives_the_same_message_as_the_load_check():
    """The fabrication package's own check (also run on module lists the GUI edits) says the same rule."""
    sc = _scene(modules=[{"type": "connection_hub", "name": "ok", "node": "N0,1"}])
    sc.modules = [{"type": "connection_hub", "name": "pad left", "node": "N0,1"}]
    with pytest.raises(SceneError) as e:
        _build_modules(sc)
    build_msg = str(e.value)
    load_msg = _refused(modules=[{"type": "connection_hub", "name": "pad left", "node": "N0,1"}])
    assert build_msg == load_msg, (build_msg, load_msg)


@pytest.mark.parametrize("text", ["N\u0663,1", "N0,\u0661", "N\uff11,0"])
def test_a_module_node_with_non_ascii_digits_is_refused(text):
    from metamaterial_wb.geometry.modules import parse_node
    sc = _scene()
    with pytest.raises(SceneError, match="is not a node name"):
        parse_node(text, sc, "modules[0].node")


@pytest.mark.parametrize("text", ["N0,1", " n(0, 1) ", "\u2003N0,1", "N\u0663,1", "N0,\u0661", "N\uff11,0", "N0,1\n",
                                  "N0,1x"])
def test_the_build_reads_a_module_node_as_the_scene_does(text):
    """A node name the scene loads is one the build reads (and the other way round)."""
    from metamaterial_wb.geometry.modules import parse_node
    sc = _scene()
    try:
        at_load = sc._node(text, "modules[0].node")
    except SceneError:
        at_load = None
    try:
        at_build = parse_node(text, sc, "modules[0].node")
    except SceneError:
        at_build = None
    assert at_load == at_build, (text, at_load, at_build)


# 2. the tilt and fold ranges the loader checks are the ones the doc gives

def _section(doc, start, end):
    i = doc.index(start)
    j = doc.index(end, i + len(start))
    return doc[i:j]


def test_the_doc_gives_the_tilt_and_fold_ranges():
    from metamaterial_wb.core.scene.names import MAX_TILT_DEG
    from metamaterial_wb.core.scene.sections import FOLD_RANGE
    tilt = f"[-{MAX_TILT_DEG:g}, {MAX_TILT_DEG:g}] deg"
    fold = f"[{FOLD_RANGE[0]:g}, {FOLD_RANGE[1]:g}] deg"
    assert (tilt, fold) == ("[-80, 80] deg", "[-180, 180] deg")
    doc = _doc()
    joints = _section(doc, "### `joints[]`", "###")
    assert re.search(r"`\"?tilt_deg\"?`[^.]*" + re.escape(tilt), joints), joints
    axes = _section(doc, "* `axes[]`", "* `joint_config`")
    assert re.search(r"`fold_deg`[^.]*" + re.escape(fold), axes), axes
    jc = _section(doc, "* `joint_config`", "* `material.")
    assert re.search(r"`tilt_deg`[^.]*" + re.escape(tilt), jc), jc
    assert re.search(r"`fold_deg`[^.]*" + re.escape(fold), jc), jc


@pytest.mark.parametrize("where, kw", [
    ("joints[0].tilt_deg", lambda v: {"joints": [{"joint": "H0,1", "tilt_deg": v}]}),
    ("joint_config.H0,1.tilt_deg", lambda v: {"joint_config": {"H0,1": {"tilt_deg": v}}}),
])
def test_the_tilt_range_is_checked_at_load(where, kw):
    _scene(**kw(80))
    _scene(**kw(-80))
    msg = _refused(**kw(80.001))
    assert msg.startswith(where) and re.search(r"\[-80(\.0)?, 80(\.0)?\]", msg), msg


@pytest.mark.parametrize("where, kw", [
    ("axes[0].fold_deg", lambda v: {"axes": [{"direction": "vertical", "line": 1, "fold_deg": v}]}),
    ("joint_config.H0,1.fold_deg", lambda v: {"joint_config": {"H0,1": {"fold_deg": v}}}),
])
def test_the_fold_range_is_checked_at_load(where, kw):
    _scene(**kw(180))
    _scene(**kw(-180))
    msg = _refused(**kw(-180.001))
    assert msg.startswith(where) and re.search(r"\[-180(\.0)?, 180(\.0)?\]", msg), msg


# 3. a stored global_deformation is solved only without --set

def test_the_doc_says_set_drops_the_stored_global_deformation():
    from metamaterial_wb.cli.solve import chosen_global
    sc = _scene(global_deformation=0.5, actuators=[{"name": "m1", "joint": "V0,0", "value": 0.2}])
    assert chosen_global(None, [], sc) == 0.5
    assert chosen_global(None, [("m1", 0.3)], sc) is None
    row = next(line for line in _doc().splitlines() if line.startswith("| `global_deformation`"))
    assert "without `--set`" in row, row


# 4. the actuator / constraint naming message gives the whole rule

@pytest.mark.parametrize("listname", ["actuators", "constraints"])
@pytest.mark.parametrize("name", ["a" * 65, "1m", "m 1"])
def test_an_actuator_name_message_gives_the_64_character_limit(listname, name):
    msg = _refused(**{listname: [{"name": name, "joint": "V0,0", "value": 0.5}]})
    assert msg.startswith(f"{listname}[0].name:"), msg
    assert "letters, digits, _ . -" in msg and "starting with a letter or _" in msg and "at most 64 characters" in msg, msg


def test_a_64_character_actuator_name_loads():
    sc = _scene(actuators=[{"name": "a" * 64, "joint": "V0,0", "value": 0.5}])
    assert sc.actuators[0].name == "a" * 64


# 5. version is the whole number 1

@pytest.mark.parametrize("ver", [1.0, True, "1", 2, 0])
def test_a_version_other_than_the_whole_number_1_is_refused(ver):
    msg = _refused(version=ver)
    assert msg.startswith("version:") and "1" in msg, msg


def test_a_version_1_0_says_why():
    msg = _refused(version=1.0)
    assert "1.0" in msg and "whole number 1" in msg, msg


def test_version_1_and_no_version_load():
    _scene(version=1)
    from metamaterial_wb.core.scene import Scene
    Scene.from_dict({"format": "metamaterial-scene", "layout": {"grid": [1, 1]}})


def test_no_stored_file_writes_version_1_0():
    hits = []
    for folder in ("examples", "benchmarks", "docs"):
        for p in (REPO / folder).rglob("*"):
            if p.suffix in (".json", ".md") and p.is_file():
                if re.search(r'"version"\s*:\s*1\.0\b', p.read_text(encoding="utf-8", errors="replace")):
                    hits.append(str(p))
    assert not hits, hits


# 6. bad command lines: status 2 and one error line, as README.md says

def _run_cli(capsys, argv):
    from metamaterial_wb.cli import main
    with pytest.raises(SystemExit) as e:
        main(argv)
    out, err = capsys.readouterr()
    return e.value.code, out, err


def test_the_readme_promises_one_error_line():
    readme = _doc(REPO / "README.md")
    assert "Bad input exits with status 2 and one error line on stderr" in readme


@pytest.mark.parametrize("argv, needle, prog", [
    (["solve", "examples/fish.json"], "the following arguments are required: --out", "python3 -m metamaterial_wb solve"),
    (["solve", "examples/fish.json", "--out", "x.json", "--bogus"], "unrecognized arguments: --bogus",
     "python3 -m metamaterial_wb solve"),
    (["solve", "examples/fish.json", "--out", "x.json", "--global", "nan"], "argument --global: 'nan' is not a number",
     "python3 -m metamaterial_wb solve"),
    (["nosuchcommand"], "invalid choice: 'nosuchcommand'", "python3 -m metamaterial_wb"),
    ([], "the following arguments are required: COMMAND", "python3 -m metamaterial_wb"),
    (["--bogus"], "", "python3 -m metamaterial_wb"),
])
def test_an_argparse_error_is_one_line_with_status_2(capsys, tmp_path, monkeypatch, argv, needle, prog):
    monkeypatch.chdir(REPO)
    code, out, err = _run_cli(capsys, argv)
    assert code == 2
    assert out == ""
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("error: ") and needle in lines[0], err
    assert lines[0].endswith(f"({prog} --help)"), err
    assert "usage:" not in err
    assert not (REPO / "x.json").exists()


def test_an_argparse_error_from_the_shell(tmp_path):
    import subprocess
    import sys
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "solve", str(REPO / "examples" / "fish.json")],
                       cwd=REPO, capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and r.stdout == "", (r.returncode, r.stdout)
    assert r.stderr.splitlines() == ["error: the following arguments are required: --out "
                                     "(python3 -m metamaterial_wb solve --help)"], r.stderr


def test_help_still_prints_the_usage(capsys):
    code, out, err = _run_cli(capsys, ["solve", "--help"])
    assert code == 0 and out.startswith("usage: python3 -m metamaterial_wb solve") and "--out" in out, out
    code, out, err = _run_cli(capsys, ["--help"])
    assert code == 0 and out.startswith("usage: python3 -m metamaterial_wb") and "COMMAND" in out, out


def test_the_scene_json_examples_load():
    """Every example scene still loads under the stricter version and module-name checks."""
    from metamaterial_wb.core.scene import Scene
    for p in sorted((REPO / "examples").glob("*.json")):
        d = json.loads(p.read_text(encoding="utf-8"))
        if isinstance(d, dict) and d.get("format") == "metamaterial-scene":
            Scene.from_dict(d)
