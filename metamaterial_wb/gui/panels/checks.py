"""Design checks the panels run before anything is written: what the Scene object's recompute would
meet (the joint configuration of the stored folds, the calibration range of the hinge sizes)."""
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.objects import design_adapter


def unconfigured(scene):
    """A copy of ``scene`` without a design-made joint configuration (entries naming their axis): the
    limits of the axes are those of the untilted sheet, whatever configuration was stored before."""
    sc = scene.copy()
    if sc.joint_config and all("axis" in c for c in sc.joint_config.values()):
        sc.joint_config = {}
    return sc


def design_problem(scene):
    """The reason ``scene`` cannot be built and solved as it is (a message naming field, value and
    allowed range), or "" when it can."""
    try:
        sc = unconfigured(scene)
        design_adapter.ensure_configured(sc)
        from metamaterial_wb.core.calibration import joint_stiffness
        joint_stiffness(sc)
    except MetamaterialError as exc:
        return str(exc)
    return ""


PREFERENCE_LABELS = {"RigidMaterial": "Rigid material", "FlexibleMaterial": "Flexible material",
                     "ModuleMaterial": "Module material", "DefaultServo": "Default servo"}


def preference_problem(keys):
    """The first of the workbench preferences ``keys`` whose value the fabrication refuses (a material not in
    ``core.materials.MATERIALS``, a servo not among the presets), as a message naming where to change it; "" when
    they are all known. The preferences page takes free text: without this the error came only after OK or in
    the background export, naming no preference."""
    from metamaterial_wb.core.materials import MATERIALS
    from metamaterial_wb.geometry.servo import SERVO_PRESETS
    from metamaterial_wb.gui import preferences
    for key in keys:
        v = preferences.get(key)
        allowed = sorted(SERVO_PRESETS) if key == "DefaultServo" else sorted(MATERIALS)
        if not isinstance(v, str) or v.upper() not in allowed:
            return (f"Edit > Preferences > Metamaterial > {PREFERENCE_LABELS[key]}: {v!r} is not a known "
                    f"{'servo' if key == 'DefaultServo' else 'material'}; allowed: {', '.join(allowed)}")
    return ""
