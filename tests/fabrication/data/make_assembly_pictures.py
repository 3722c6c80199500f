"""Pictures of docs/fabrication.md "Assembly guide": every module in its print pose, and assembled.

    /usr/bin/python3 tests/fabrication/data/make_assembly_pictures.py [OUT_DIR (default docs/img)]
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))
sys.path.insert(0, REPO)
sys.path.append("/usr/lib/freecad-python3/lib")

SCENE = {"format": "metamaterial-scene", "version": 1, "name": "guide", "cell_size_mm": 22,
         "hinge": {"length_mm": 2, "width_mm": 0.8, "thickness_mm": 7}, "layout": {"grid": [2, 4]},
         "actuators": [{"name": "m", "joint": "V0,1", "value": 0.0,
                        "profile": {"shape": "sine", "amplitude": 0.5, "frequency_hz": 1.0}}],
         "modules": [{"type": "servo_housing", "name": "servo", "joint": "V0,1"},
                     {"type": "friction_pad", "name": "pad", "node": "N2,0"},
                     {"type": "connection_hub", "name": "hub", "node": "N0,4"},
                     {"type": "stable_hub", "name": "stable", "joint": "H2,2"},
                     {"type": "constraint_clip", "name": "clip", "joint": "V1,4", "angle_deg": 5.0}]}


def servo_dummy(result, spec):
    """The servo body, its tabs and horn as meshes at their place (grey), for the assembled view."""
    import FreeCAD as App
    import Part
    from metamaterial_wb.export.mesh import tessellate, transform
    from metamaterial_wb.geometry.fc import matrix4
    from metamaterial_wb.geometry.modules import module_placement, servo_layout
    v = spec.values
    lay = servo_layout(spec, result.params)
    su, sv = v["shaft_u_mm"], v["shaft_v_mm"]
    a, L, W = v["shaft_offset_mm"], v["body_length_mm"], v["body_width_mm"]
    zb = lay["zb"]
    V_ = App.Vector
    body = Part.makeBox(L, W, v["body_height_mm"], V_(su + a - L, sv - W / 2, zb))
    ext = 0.5 * (v["tab_length_mm"] - L)
    tabs = Part.makeBox(v["tab_length_mm"], W, v["tab_thickness_mm"], V_(su + a - L - ext, sv - W / 2, zb + v["tab_z_mm"]))
    shaft = Part.makeCylinder(2.4, v["shaft_top_mm"] - v["body_height_mm"], V_(su, sv, zb + v["body_height_mm"]))
    horn = Part.makeCylinder(0.5 * v["horn_hub_diameter_mm"], v["horn_thickness_mm"], V_(su, sv, lay["z_arm"])).fuse(
        Part.makeBox(v["horn_arm_length_mm"], v["horn_arm_width_mm"], v["horn_thickness_mm"],
                     V_(su, sv - 0.5 * v["horn_arm_width_mm"], lay["z_arm"])))
    M = matrix4(module_placement(spec, result.params))
    out = []
    for k, sh in enumerate((body.fuse(tabs).fuse(shaft).removeSplitter(), horn)):
        P, T = tessellate(sh, 0.1)
        out.append((f"servo_dummy_{k}", transform(P, M), T, "SERVO" if k == 0 else "HORN", 1))
    return out


def main(out_dir):
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.export.mesh import part_meshes
    from metamaterial_wb.export.printpose import forced_poses, lay_out_best_poses
    from metamaterial_wb.export.render import render_meshes_png
    from metamaterial_wb.geometry.build import build_scene
    os.makedirs(out_dir, exist_ok=True)
    r = build_scene(Scene.from_dict(SCENE), progress=False)
    colours = {"SERVO": "#3A6EA5", "HORN": "#F5F5F5"}
    for spec in r.modules:
        parts = [q for q in r.parts if q.group == spec.name]
        meshes, reps = lay_out_best_poses(part_meshes(r, parts, 0.1), forced=forced_poses(parts))
        flags = "\n".join(f"{n[len(spec.name) + 1:]}: {rep['pose']}, "
                          f"{'no supports' if rep['supports_free'] else 'needs supports'}" for n, rep in reps.items())
        render_meshes_png(meshes, os.path.join(out_dir, f"fab-print-{spec.type}.png"), elev=28, azim=-55,
                          size_in=(5.0, 3.6), title=f"{spec.type} as printed\n{flags}", zoom=0.6)
    sheet = part_meshes(r, [q for q in r.parts if q.group == "sheet"], 0.1)
    mods = part_meshes(r, [q for q in r.parts if q.role == "module"], 0.1)
    servo = [m for m in r.modules if m.type == "servo_housing"][0]
    render_meshes_png(sheet + mods + servo_dummy(r, servo), os.path.join(out_dir, "fab-assembled.png"),
                      elev=38, azim=-62, size_in=(8.0, 5.0), title="assembled: sheet, servo (blue), modules", zoom=0.55,
                      colours=colours)
    near = [q for q in r.parts if q.group in ("sheet", servo.name)
            and (q.role == "module" or q.info.get("node") in ("N0,1", "N1,1", "N0,0", "N0,2", "N1,0", "N1,2")
                 or q.info.get("joint") in ("V0,1", "H0,0", "H0,1", "H1,0", "H1,1"))]
    render_meshes_png(part_meshes(r, near, 0.1) + servo_dummy(r, servo), os.path.join(out_dir, "fab-assembled-servo.png"),
                      elev=30, azim=-40, size_in=(6.0, 4.5), title="servo inserted, shaft on the hinge V0,1", zoom=0.5,
                      colours=colours)
    blind_rivet_section(r, servo, out_dir)
    return 0


def blind_rivet_section(r, servo, out_dir):
    """A section through the axis of the housing's blind rivet under the servo (the plane of the prongs'
    bending): node A, the housing's foot, floor and trough, the rivet (head in the socket's bottom
    counterbore, barb latched in the housing's blind socket) -- filled outlines of FreeCAD slices."""
    import FreeCAD as App
    import Part
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from metamaterial_wb.core.materials import MATERIALS, hex_to_rgb
    from metamaterial_wb.geometry.modules import module_placement
    rivets = [q for q in r.groups()[servo.name] if q.name.startswith(f"{servo.name}_housing_rivet_")]
    sx, sy = servo.pivot.point_mm[:2]
    q = min(rivets, key=lambda q: (r.placed_shape(q).BoundBox.Center.x - sx) ** 2
            + (r.placed_shape(q).BoundBox.Center.y - sy) ** 2)      # the one under the servo's cavity
    rv = r.placed_shape(q)
    c = rv.BoundBox.Center
    rot = module_placement(servo, r.params).Rotation
    xdir, normal = rot.multVec(App.Vector(1, 0, 0)), rot.multVec(App.Vector(0, 1, 0))
    node = [p for p in r.parts if p.info.get("node") == f"N{servo.a[0]},{servo.a[1]}"][0]
    crop = Part.makeBox(24, 24, 20, App.Vector(c.x - 12, c.y - 12, -1.0))
    pieces = [("node A (PLA)", r.placed_shape(node), MATERIALS["PLA"]),
              ("housing (ABS)", r.placed_shape(r.by_name(f"{servo.name}_housing")), MATERIALS["ABS"]),
              ("blind rivet (ABS)", rv, "#D9822B")]
    fig, ax = plt.subplots(figsize=(6.0, 4.6))
    for label, sh, col in pieces:
        first = True
        for w in sh.common(crop).slice(normal, normal.dot(c)):
            pts = [((p - c).dot(xdir), p.z) for p in w.discretize(Deflection=0.005)]
            ax.fill(*zip(*pts), color=hex_to_rgb(col), alpha=0.85, lw=0.8, ec="black",
                    label=label if first else None)
            first = False
    T = r.params.sheet_thickness_mm
    ax.axhline(0, color="0.5", lw=0.5, ls=":")
    ax.axhline(T, color="0.5", lw=0.5, ls=":")
    ax.set_xlim(-8, 8)
    ax.set_aspect("equal")
    ax.set_xlabel("across the rivet (mm): the prongs bend in this plane")
    ax.set_ylabel("z (mm): sheet 0..%g, housing above" % T)
    ax.set_title("blind rivet under the servo, section through its axis:\nhead in node A's bottom counterbore, "
                 "barb latched in the housing's blind socket", fontsize=9)
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "fab-blind-rivet-section.png"), dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(REPO, "docs", "img")))
