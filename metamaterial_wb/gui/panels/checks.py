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
