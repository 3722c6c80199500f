"""Every error of a field of the command's input file that is checked after the file was read names the file, once
(session 33): ``dynamics.friction: 99 ...`` (simulate), ``fabrication.clearance_mm`` (build), a servo's fields
(stream), the test piece's ``joints`` (calibrate), the sleeve spec's ``ring`` (sleeve) ended without
``(in FILE)``, while the load's own errors and, since e5bd3cb, hinge sizes outside the calibration table end with
it. An error of another input (``--channels FILE``, calibrate's ``ANGLES.csv``) or of a flag names no scene file,
also when that file's name starts like a scene field (``joints.csv``)."""
import json
import os

from clihelpers import REPO, one_line_error, run_cli

from metamaterial_wb import cli as CLI

FISH = os.path.join(REPO, "examples", "fish.json")
SLEEVE = os.path.join(REPO, "examples", "sleeve.json")


def edited(tmp_path, edit, src=FISH, name="bad scene.json"):
    with open(src, encoding="utf-8") as fh:
        d = json.load(fh)
    edit(d)
    p = tmp_path / name              # a space: the path is named as given
    p.write_text(json.dumps(d), encoding="utf-8")
    return p


def names_it_once(r, field, path, words):
    one_line_error(r, field)
    assert words in r.stderr, r.stderr
    assert r.stderr.rstrip().endswith(f"(in {path})"), r.stderr
    assert r.stderr.count(str(path)) == 1, r.stderr


def test_simulate_dynamics_friction(tmp_path):
    scene = edited(tmp_path, lambda d: d.update(dynamics={"friction": 99}))
    r = run_cli("simulate", scene, "--seconds", "0.1", "--out", tmp_path / "sim")
    names_it_once(r, "dynamics.friction", scene, "99 is outside the allowed range")
    assert not (tmp_path / "sim").exists()


def test_build_fabrication_field(tmp_path):
    scene = edited(tmp_path, lambda d: d.update(fabrication={"clearance_mm": 99}))
    r = run_cli("build", scene, "--out", tmp_path / "out", "--quiet")
    names_it_once(r, "fabrication.clearance_mm", scene, "99 mm is outside the allowed range")
    assert not (tmp_path / "out").exists()


def test_build_a_flag_names_the_flag_not_the_scene(tmp_path):
    """The value came from --clearance: the flag is named, and no scene file."""
    r = run_cli("build", FISH, "--clearance", "99", "--out", tmp_path / "out", "--quiet")
    one_line_error(r, "--clearance (fabrication.clearance_mm)")
    assert "(in " not in r.stderr and FISH not in r.stderr, r.stderr


def test_stream_servo_field(tmp_path):
    scene = edited(tmp_path, lambda d: d["actuators"][0].update(servo={"min_us": 2400, "max_us": 1000}))
    r = run_cli("stream", scene, "--dry-run", "--seconds", "0.1")
    names_it_once(r, "actuators[0].servo.min_us", scene, "2400 us must be below max_us 1000 us")


def test_calibrate_piece_joints(tmp_path):
    from metamaterial_wb.core import calibrate as C
    sc = C.test_piece(2.0)
    d = json.loads(sc.to_json())
    d["joints"] = [{"joint": sc.topology.joint_names[0], "k1": 0.5}]
    piece = tmp_path / "piece.json"
    piece.write_text(json.dumps(d), encoding="utf-8")
    csv = tmp_path / "angles.csv"
    csv.write_text("node,angle_deg\n" + "".join(f"\"N{i},{j}\",0.5\n" for i, j in sc.topology.nodes),
                   encoding="utf-8")
    r = run_cli("calibrate", "measured", piece, csv)
    names_it_once(r, "joints", piece, "set k1 / k2 directly")


def test_sleeve_spec_field(tmp_path, monkeypatch, capsys):
    """The end pieces (--step) do not fit the ring: refused before any FreeCAD work (FreeCAD's check stubbed)."""
    from metamaterial_wb.geometry import fc
    monkeypatch.setattr(fc, "freecad", lambda: None)

    def small(d):
        d.update(L_mm=6, c_mm=1.5, delta_mm=0.3, T_mm=1.2, cell_types=[{"t_mm": 0.5, "h_mm": 2.0}], ring=[0, 0])
        for k in ("actuator", "pattern", "rings"):
            d.pop(k, None)
    spec = edited(tmp_path, small, SLEEVE, "small sleeve.json")
    capsys.readouterr()
    assert CLI.main(["sleeve", str(spec), "--out", str(tmp_path / "out"), "--step", "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: ring: ") and "too small for the end pieces" in err, err
    assert err.endswith(f"(in {spec})") and err.count(str(spec)) == 1, err


# ---- other inputs and flags: no scene file named --------------------------------------------------------------
def test_a_file_named_like_a_scene_field_is_not_taken_for_one(tmp_path, monkeypatch, capsys):
    """calibrate's ANGLES.csv called joints.csv (its errors' field is ``joints.csv:LINE``), and a --channels file
    called hinge.json (``hinge.json: expected an object``): each names its own file only."""
    from metamaterial_wb.core import calibrate as C
    monkeypatch.chdir(tmp_path)
    piece = tmp_path / "piece.json"
    piece.write_text(C.test_piece(2.0).to_json(), encoding="utf-8")
    (tmp_path / "joints.csv").write_text("node,angle_deg\nfoo,1\n", encoding="utf-8")
    (tmp_path / "hinge.json").write_text("[]", encoding="utf-8")
    for argv, start in ((["calibrate", "measured", str(piece), "joints.csv"], "error: joints.csv:2: "),
                        (["stream", FISH, "--dry-run", "--seconds", "0.1", "--channels", "hinge.json"],
                         "error: hinge.json: ")):
        capsys.readouterr()
        assert CLI.main(argv) == 2
        err = capsys.readouterr().err.strip().splitlines()[-1]
        assert err.startswith(start) and "(in " not in err, err


def test_an_error_that_names_the_scene_already_is_not_named_twice(tmp_path):
    """design's "FILE has no rotary axes" (field ``axes``) names the scene in its words."""
    r = run_cli("design", FISH, "--out", tmp_path / "c.json")
    one_line_error(r, "axes")
    assert r.stderr.count(FISH) == 1 and "(in " not in r.stderr, r.stderr
