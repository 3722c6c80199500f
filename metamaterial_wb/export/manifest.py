"""``DIR/manifest.json``: what ``build`` wrote (docs/fabrication.md, "The build manifest").

Every part with its placement (sheet coordinates, mm) and file, every module with its sockets, its
snap-fit design (strain and material limit), its print pose check and, for a servo, the shaft axis
and its joint's pivot; the fabrication parameters and which checks ran.
"""
import json
import math

FORMAT = "metamaterial-build-manifest"
VERSION = 1


def _placement(pl):
    b = pl.Base
    r = pl.Rotation
    ax = r.Axis
    return {"base_mm": [round(b.x, 6), round(b.y, 6), round(b.z, 6)],
            "axis": [round(ax.x, 9), round(ax.y, 9), round(ax.z, 9)],
            "angle_deg": round(math.degrees(r.Angle), 9)}


def _jsonable(v):
    if isinstance(v, dict):
        return {str(k): _jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_jsonable(x) for x in v]
    if isinstance(v, float):
        return round(v, 9)
    return v


def build_manifest(result, files_by_group, stem, checks_ran, poses=None):
    """The manifest as a dict. ``files_by_group``: ``{group: [file names]}``; ``poses``: ``{part name:
    print pose report}`` of the separate prints."""
    from metamaterial_wb.geometry.validity import ALL_CHECKS

    p = result.params
    poses = poses or {}
    parts = []
    for q in result.parts:
        parts.append({"name": q.name, "role": q.role, "group": q.group, "material": q.material,
                      "extruder": q.extruder, "placement": _placement(q.placement),
                      "files": files_by_group.get(q.group, []) + files_by_group.get("assembly", []),
                      "info": _jsonable(q.info)})
    modules = []
    for spec in result.modules:
        m = {"name": spec.name, "type": spec.type, "side": spec.side, "material": spec.material,
             "extruder": spec.extruder, "sockets": [f"N{ij[0]},{ij[1]}:{lab}" for ij, lab in spec.sockets],
             "parts": [q.name for q in result.parts if q.group == spec.name],
             "files": files_by_group.get(spec.name, []), **spec.target_fields()}
        if spec.snap is not None:
            m["snap_fit"] = _jsonable(spec.snap.as_dict())
        rivets = [q for q in result.parts if q.group == spec.name and q.info.get("rivet")]
        if rivets:          # separate snap pins printed lying (geometry/rivet.py)
            m["rivets"] = {"count": len(rivets), "parts": [q.name for q in rivets],
                           "length_mm": [q.info["length_mm"] for q in rivets],
                           "print_pose": [q.info["print_pose"] for q in rivets],
                           "ends": rivets[0].info.get("ends", 1),      # 2: barbed at both ends (hub)
                           # "sheet": blind rivets pushed in from the sheet's far face (servo housing)
                           "inserted_from": rivets[0].info.get("inserted_from", "module"),
                           "strain": spec.snap.strain, "limit": spec.snap.limit, "bending": spec.snap.bending}
        if spec.note:
            m["note"] = spec.note
        if spec.pivot is not None:
            m["joint_pivot"] = spec.pivot.as_dict()
        if spec.type == "servo_housing":
            v = spec.values
            m["servo"] = {"model": v.get("servo"), "shaft_point_mm": list(spec.pivot.point_mm),
                          "shaft_axis": list(spec.pivot.axis),
                          "body_mm": [v["body_length_mm"], v["body_width_mm"], v["body_height_mm"]],
                          "range_deg": list(spec.pivot.range_deg),
                          "hinge_length_error": spec.pivot.length_error}
        if spec.type == "constraint_clip":
            m["angle_deg"] = spec.values["angle_deg"]
        pp = {q.name: poses[q.name] for q in result.parts if q.group == spec.name and q.name in poses}
        if pp:
            m["print_pose"] = _jsonable(pp)
        modules.append(m)
    ran = list(checks_ran)
    return {
        "format": FORMAT, "version": VERSION, "scene": result.scene.name or stem, "units": "mm",
        "fabrication": _jsonable({k: v for k, v in p.as_dict().items() if k != "hinges"}),
        "min_wall_mm": p.min_wall_mm,
        "checks": {"parameters": True, "ran": ran, "skipped": [c for c in ALL_CHECKS if c not in ran]},
        "files": sorted({f for fs in files_by_group.values() for f in fs}),
        # the sheet's 3MF files hold it moved by this much (onto the bed); STEP keeps sheet coordinates
        "sheet_3mf_offset_mm": getattr(result, "bed_offset_mm", None),
        "parts": parts, "modules": modules,
    }


def write_manifest(path, manifest):
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(manifest, fh, indent=1)
        fh.write("\n")
