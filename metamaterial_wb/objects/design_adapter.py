"""The design stage as the workbench sees it: axis rules, maximum folds, joint configuration.

The panels call these; the rules that the panels must show (the seed's two axis rules, section 4.1)
are worded here per axis, then ``metamaterial_wb.core.design`` adds its own validation, the maximum
folds and the joint configuration.
"""
from metamaterial_wb.core import design
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.scene import Scene


def candidate_lines(scene):
    """``{"vertical": [cell columns], "horizontal": [cell rows]}`` that an axis may lie on."""
    cols = sorted({c[1] for c in scene.cells})
    rows = sorted({c[0] for c in scene.cells})
    return {"vertical": cols, "horizontal": rows}


def axis_violations(scene, axes):
    """Messages for every broken rule (empty list = fine).

    1. the line must exist in the layout;
    2. an axis runs through the whole structure: the cells on its line form one unbroken run
       (otherwise it would stop short inside the structure);
    3. axes may not cross: a vertical and a horizontal axis cross when the cell at their
       intersection exists;
    4. no axis twice.
    5. ``core.design.validate_axes`` (when the four above hold).
    """
    msgs = []
    cells = set(scene.cells)
    seen = set()
    for k, a in enumerate(axes):
        d, line = a["direction"], int(a["line"])
        label = f"axis {k + 1} ({d} line {line})"
        if (d, line) in seen:
            msgs.append(f"{label} is given twice")
            continue
        seen.add((d, line))
        if d == "vertical":
            run = sorted(i for (i, j) in cells if j == line)
        else:
            run = sorted(j for (i, j) in cells if i == line)
        if not run:
            msgs.append(f"{label} lies outside the layout: no cell on that line")
            continue
        if run[-1] - run[0] + 1 != len(run):
            gap = next(x for x in range(run[0], run[-1]) if x not in run)
            where = f"cell ({gap}, {line})" if d == "vertical" else f"cell ({line}, {gap})"
            msgs.append(f"{label} stops short: {where} is missing, an axis must run through the whole structure")
    verts = [a for a in axes if a["direction"] == "vertical"]
    hors = [a for a in axes if a["direction"] == "horizontal"]
    for v in verts:
        for h in hors:
            if (int(h["line"]), int(v["line"])) in cells:
                msgs.append(f"vertical axis on line {v['line']} crosses horizontal axis on line {h['line']} "
                            f"at cell ({h['line']}, {v['line']}); axes may not cross")
    if not msgs:
        try:
            design.validate_axes(Scene.from_dict(dict(scene.to_dict(), axes=axes)))
        except MetamaterialError as exc:
            msgs.append(str(exc))
    return msgs


def max_fold_deg(scene, axis_index):
    """Largest fold (deg) the axis can reach at D = 1 (``core.design.max_fold_deg``)."""
    return float(design.max_fold_deg(scene, axis_index))


def configure(scene):
    """Run the joint configuration on a copy; returns ``(configured Scene, report or None)``.

    Raises :class:`MetamaterialError` when the design rejects the input (e.g. a fold beyond the axis
    maximum: the message gives the maximum).
    """
    sc = scene.copy()
    report = design.configure(sc)
    return sc, report if isinstance(report, dict) else None


def ensure_configured(scene):
    """Configure a scene with axes but no (or a stale, design-made) joint configuration, in place.

    Returns the design warnings to show, on every call (not only when it configures): those of the
    configuration run, else :func:`design_warnings` of the current configuration.
    """
    if not scene.axes:
        return []
    report = design.ensure_configured(scene)
    if not report:
        return design_warnings(scene)
    return list(report.get("warnings", [])) or ["joint configuration computed from the axes"]


def design_warnings(scene):
    """The design check's warnings (e.g. a fold whose hinge tilts do not fit their node plates: ``build`` will
    reject it) for a scene whose design-made joint configuration is current. The check runs on a copy: the
    scene is not changed. A hand-written configuration (entries without ``"axis"``, kept as it is by
    ``core.design.ensure_configured``) gets none: the axes' check does not describe its tilts.
    """
    config = scene.joint_config
    if not scene.axes or not config or not all("axis" in c for c in config.values()):
        return []
    report = design.configure(scene.copy(), strict=False)
    return list(report.get("warnings", [])) if isinstance(report, dict) else []
