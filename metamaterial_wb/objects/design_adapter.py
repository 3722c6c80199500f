"""The design stage as the workbench sees it: axis rules, maximum folds, joint configuration.

``metamaterial_wb.core.design`` (the design-pipeline package) is used when it is present; the rules
that the panels must show even without it (the seed's two axis rules, section 4.1) are checked here
too, so that a violation is always reported, never silently ignored.
"""
from metamaterial_wb.core.errors import MetamaterialError, SceneError


def _design():
    try:
        from metamaterial_wb.core import design  # type: ignore
        return design
    except ImportError:
        return None


def design_available():
    return _design() is not None


def candidate_lines(scene):
    """``{"vertical": [cell columns], "horizontal": [cell rows]}`` that an axis may lie on."""
    cols = sorted({c[1] for c in scene.cells})
    rows = sorted({c[0] for c in scene.cells})
    return {"vertical": cols, "horizontal": rows}


def axis_joints(scene, direction, line):
    """Joints an axis crosses: vertical line k -> every H(i, k); horizontal line k -> every V(k, j)."""
    topo = scene.topology
    if direction == "vertical":
        return [n for n in topo.joint_names if n.startswith("H") and int(n[1:].split(",")[1]) == line]
    return [n for n in topo.joint_names if n.startswith("V") and int(n[1:].split(",")[0]) == line]


def axis_violations(scene, axes):
    """Messages for every broken rule (empty list = fine).

    1. the line must exist in the layout;
    2. an axis runs through the whole structure: the cells on its line form one unbroken run
       (otherwise it would stop short inside the structure);
    3. axes may not cross: a vertical and a horizontal axis cross when the cell at their
       intersection exists;
    4. no axis twice.
    The design package's own validation is added when it is installed.
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
    design = _design()
    if design is not None and not msgs:
        fn = getattr(design, "validate_axes", None) or getattr(design, "check_axes", None)
        if fn is not None:
            try:
                sc = scene.copy()
                sc.axes = []
                from metamaterial_wb.core.scene import Scene
                sc = Scene.from_dict(dict(sc.to_dict(), axes=axes))
                fn(sc)
            except MetamaterialError as exc:
                msgs.append(str(exc))
            except TypeError:
                pass
    return msgs


def max_fold_deg(scene, axis_index):
    """Largest fold (deg) the axis can reach at D = 1, from the design package (None if unknown)."""
    design = _design()
    if design is None:
        return None
    for name in ("max_fold_deg", "axis_max_fold_deg", "maximum_fold_deg"):
        fn = getattr(design, name, None)
        if fn is None:
            continue
        try:
            return float(fn(scene, axis_index))
        except TypeError:
            try:
                return float(fn(scene, scene.axes[axis_index]))
            except Exception:
                continue
    fn = getattr(design, "max_folds_deg", None) or getattr(design, "max_folds", None)
    if fn is not None:
        try:
            return float(list(fn(scene))[axis_index])
        except Exception:
            return None
    return None


def configure(scene):
    """Run the joint configuration on a copy; returns ``(configured Scene, report or None)``.

    Raises :class:`MetamaterialError` when the design package is missing or rejects the input
    (e.g. a fold beyond the axis maximum: the message gives the maximum).
    """
    design = _design()
    if design is None:
        raise MetamaterialError("joint configuration needs metamaterial_wb.core.design, which is not installed "
                                "in this checkout yet")
    sc = scene.copy()
    fn = getattr(design, "configure", None)
    if fn is None:
        raise SceneError("design", "metamaterial_wb.core.design has no configure(scene)")
    report = fn(sc)
    return sc, report if isinstance(report, dict) else None


def ensure_configured(scene):
    """Configure a scene with axes but no (or a stale, design-made) joint configuration, in place.

    Returns the warnings to show (empty when nothing was done or the design package is missing).
    """
    design = _design()
    if design is None or not scene.axes:
        return []
    fn = getattr(design, "ensure_configured", None)
    if fn is None:
        return []
    report = fn(scene)
    if not report:
        return []
    return list(report.get("warnings", [])) or ["joint configuration computed from the axes"]
