"""Result files of a static solve: field selection and a binary ``.npz`` form beside the JSON.

A JSON result lists every node as a dictionary (``docs/scene-format.md``, "Result file"); for a
million nodes that is a 700 MB text file whose encoding costs most of the run. ``result_arrays``
gives the same data as arrays (vectorised, no per-node Python objects), ``write_npz`` stores them
uncompressed in NumPy's ``.npz`` format (readable with ``numpy.load`` without pickles) and
``read_result`` reads either form back into the same dictionary of arrays.

Fields (``FIELDS``): ``D`` (node deformations), ``poses`` (positions in mm, rotation matrices and the
in-plane rotation in degrees) and ``joints`` (per joint: its two nodes, fold, hinge rotation and
hinge tilt in degrees). Node indices ``i, j`` are always written.
"""
from __future__ import annotations

import json
import os

import numpy as np

from .errors import SceneError

FIELDS = ("D", "poses", "joints")
NPZ_FORMAT = "metamaterial-result-npz"


def parse_fields(text):
    """``"D,poses"`` -> ``("D", "poses")``; an unknown, empty or repeated name is a :class:`SceneError`."""
    names = [s.strip() for s in str(text).split(",")]
    if not names or any(not s for s in names):
        raise SceneError("--fields", f"{text!r}: expected a comma-separated list of {', '.join(FIELDS)}")
    bad = [s for s in names if s not in FIELDS]
    if bad:
        raise SceneError("--fields", f"{', '.join(bad)}: unknown; allowed: {', '.join(FIELDS)}")
    twice = [s for i, s in enumerate(names) if s in names[:i]]
    if twice:
        raise SceneError("--fields", f"{text!r}: {twice[0]} given twice; give each of {', '.join(FIELDS)} "
                                     f"at most once")
    return tuple(f for f in FIELDS if f in names)


def result_arrays(scene, res, fields=FIELDS):
    """The per-node and per-joint data of a solve as arrays (keys as in the ``.npz`` file)."""
    topo = scene.topology
    ij = np.asarray(topo.nodes, dtype=np.int64).reshape(-1, 2)
    out = {"ij": ij}
    if "D" in fields:
        out["D"] = np.asarray(res.D, dtype=float)
    if "poses" in fields:
        R = np.asarray(res.rotations, dtype=float).reshape(-1, 3, 3)
        out["position_mm"] = np.asarray(res.positions_mm, dtype=float).reshape(-1, 3)
        out["rotation"] = R
        out["rotation_deg"] = np.degrees(np.arctan2(R[:, 1, 0], R[:, 0, 0]))
    if "joints" in fields:
        from . import design, kinematics
        fold, psi = kinematics.joint_angles(scene, res.rotations)
        out["joint_names"] = np.asarray(list(topo.joint_names), dtype=str)
        out["joint_nodes"] = np.asarray(topo.joint_pairs, dtype=np.int64).reshape(-1, 2)
        out["joint_fold_deg"] = np.asarray(fold, dtype=float)
        out["joint_hinge_rotation_deg"] = np.asarray(psi, dtype=float)
        out["joint_tilt_deg"] = np.asarray(design.effective_tilts_deg(scene), dtype=float)
    return out


def node_list(arrays):
    """The JSON ``nodes`` list from :func:`result_arrays` (only the fields present)."""
    ij = arrays["ij"].tolist()
    cols = {"i": [a for a, _ in ij], "j": [b for _, b in ij], "name": [f"N{a},{b}" for a, b in ij]}
    if "D" in arrays:
        cols["D"] = arrays["D"].tolist()
    if "position_mm" in arrays:
        cols["rotation_deg"] = arrays["rotation_deg"].tolist()
        cols["position_mm"] = arrays["position_mm"].tolist()
        cols["rotation"] = arrays["rotation"].tolist()
    keys = list(cols)
    return [dict(zip(keys, row)) for row in zip(*(cols[k] for k in keys))]


def joint_list(arrays):
    """The JSON ``joints`` list from :func:`result_arrays`."""
    ij = arrays["ij"]
    names = [f"N{a},{b}" for a, b in ij.tolist()]
    return [{"name": n, "nodes": [names[a], names[b]], "fold_deg": f, "hinge_rotation_deg": p, "tilt_deg": t}
            for n, (a, b), f, p, t in zip(arrays["joint_names"].tolist(), arrays["joint_nodes"].tolist(),
                                          arrays["joint_fold_deg"].tolist(),
                                          arrays["joint_hinge_rotation_deg"].tolist(),
                                          arrays["joint_tilt_deg"].tolist())]


def npz_path_for(json_path):
    """The ``.npz`` written beside a JSON result: ``R.json`` (or ``R``) -> ``R.npz``. A JSON path that itself
    ends in ``.npz`` is a :class:`SceneError` (the JSON would be written under the arrays' name)."""
    json_path = os.fspath(json_path)
    if json_path.lower().endswith(".npz"):
        raise SceneError("--out", f"{json_path}; allowed with --npz: a JSON name such as R.json (the arrays go "
                                  "to R.npz beside it)")
    return (json_path[:-5] if json_path.endswith(".json") else json_path) + ".npz"


def write_npz(path, arrays, meta):
    """Write ``arrays`` and the JSON metadata ``meta`` (``meta_json`` entry) atomically to ``path``
    (``fileio.write_atomic``: a temporary file, a rename, the usual permissions)."""
    from .fileio import write_atomic
    payload = dict(arrays)
    payload["meta_json"] = np.asarray(json.dumps(dict(meta, format=NPZ_FORMAT), allow_nan=False))
    write_atomic(os.fspath(path), lambda fh: np.savez(fh, **payload), mode="wb")


def _read_npz(path):
    with np.load(path, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files if k != "meta_json"}
        meta = json.loads(str(z["meta_json"]))
    return meta, arrays


def _arrays_beside(path, ref):
    """The arrays of the ``.npz`` file a JSON result of ``solve --npz`` names (``"arrays": {"file", "keys"}``),
    read from the JSON's folder; a missing or unreadable file, or one without the listed arrays, is a
    :class:`SceneError` naming it."""
    name = ref.get("file") if isinstance(ref, dict) else None
    if not isinstance(name, str) or not name or name != os.path.basename(name) or name in (".", ".."):
        raise SceneError("arrays.file", f"{name!r} in {path}; expected the file name of the arrays (R.npz) "
                                        f"beside the JSON result")
    npz = os.path.join(os.path.dirname(os.path.abspath(path)), name)
    if not os.path.isfile(npz):
        raise SceneError("arrays.file", f"{npz} (named in {path}) is missing: the JSON half of a `solve --npz` "
                                        f"result holds no per-node data; keep the .npz file beside it")
    try:
        _, arrays = _read_npz(npz)
    except (OSError, ValueError, KeyError) as exc:
        raise SceneError("arrays.file", f"{npz} (named in {path}) is not a readable result .npz file "
                                        f"({exc})") from None
    keys = ref.get("keys")
    missing = sorted(set(keys) - set(arrays)) if isinstance(keys, list) and all(isinstance(k, str) for k in keys) \
        else []
    if missing:
        raise SceneError("arrays.file", f"{npz} (named in {path}) lacks the arrays {', '.join(missing)} its JSON "
                                        f"lists; the two files do not belong together")
    return arrays


def read_result(path):
    """``(meta dict, arrays dict)`` from a ``.npz`` result or a JSON result (converted to arrays). The JSON half
    of a ``solve --npz`` result (no ``nodes``, an ``"arrays"`` entry) gets its arrays from the ``.npz`` file it
    names, beside it (:class:`SceneError` naming that file when it is missing)."""
    path = os.fspath(path)
    if path.endswith(".npz"):
        return _read_npz(path)
    with open(path, encoding="utf-8") as fh:
        doc = json.load(fh)
    if "arrays" in doc and "nodes" not in doc:
        arrays = _arrays_beside(path, doc["arrays"])
        return {k: v for k, v in doc.items() if k not in ("nodes", "joints")}, arrays
    nodes = doc.get("nodes", [])
    arrays = {"ij": np.array([[n["i"], n["j"]] for n in nodes], dtype=np.int64).reshape(-1, 2)}
    if nodes and "D" in nodes[0]:
        arrays["D"] = np.array([n["D"] for n in nodes], float)
    if nodes and "position_mm" in nodes[0]:
        arrays["position_mm"] = np.array([n["position_mm"] for n in nodes], float)
        arrays["rotation"] = np.array([n["rotation"] for n in nodes], float)
        arrays["rotation_deg"] = np.array([n["rotation_deg"] for n in nodes], float)
    if "joints" in doc:
        index = {f"N{a},{b}": k for k, (a, b) in enumerate(arrays["ij"].tolist())}
        js = doc["joints"]
        arrays["joint_names"] = np.array([j["name"] for j in js], dtype=str)
        arrays["joint_nodes"] = np.array([[index[j["nodes"][0]], index[j["nodes"][1]]] for j in js],
                                         dtype=np.int64).reshape(-1, 2)
        for key in ("fold_deg", "hinge_rotation_deg", "tilt_deg"):
            arrays["joint_" + key] = np.array([j[key] for j in js], float)
    meta = {k: v for k, v in doc.items() if k not in ("nodes", "joints")}
    return meta, arrays
