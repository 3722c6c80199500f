"""Design checks the panels run before anything is written: what the Scene object's recompute would
meet (the joint configuration of the stored folds, the calibration range of the hinge sizes)."""
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate
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


# the labels of the preferences page (resources/ui/preferences.ui), translated where they are shown
PREFERENCE_LABELS = {"PrinterClearance": QT_TRANSLATE_NOOP("Metamaterial", "Snap-fit clearance (mm)"),
                     "RigidMaterial": QT_TRANSLATE_NOOP("Metamaterial", "Rigid material (nodes)"),
                     "FlexibleMaterial": QT_TRANSLATE_NOOP("Metamaterial", "Flexible material (hinges)"),
                     "ModuleMaterial": QT_TRANSLATE_NOOP("Metamaterial", "Module material"),
                     "DefaultServo": QT_TRANSLATE_NOOP("Metamaterial", "Default servo")}


def clearance_problem(scene=None, snap_pins=True):
    """The snap-fit clearance preference, when it is chosen (``objects.module.fabrication_overrides``) and not below
    the socket lip the modules' snap pins latch on (``scene``'s ``fabrication.socket_lip_mm``, else the default), as
    a message naming the preference, its value and allowed range; "" otherwise, and "" where no snap pin is designed:
    ``snap_pins`` False (Export: sockets unticked, or no module exported) or ``scene``'s ``fabrication.sockets``
    false (its modules are refused for that, which the clearance does not change)."""
    from metamaterial_wb.core.fabrication import FAB_DEFAULTS
    from metamaterial_wb.objects.module import clearance_preference_clash
    given = getattr(scene, "extra", {}).get("fabrication") if scene is not None else None
    given = given if isinstance(given, dict) else {}
    lip = given.get("socket_lip_mm")
    lip = lip if isinstance(lip, (int, float)) and not isinstance(lip, bool) else FAB_DEFAULTS["socket_lip_mm"]
    clr = clearance_preference_clash(lip, snap_pins and given.get("sockets") is not False)
    if clr is None:   # (a scene's invalid socket_lip_mm is the fabrication's own error)
        return ""
    return translate("Metamaterial", "Edit > Preferences > Metamaterial > {0}: {1} mm is not below the {2} mm socket "
                     "lip, so the modules' snap pins have nothing to latch on; allowed range [0, {2}) mm").format(
        translate("Metamaterial", PREFERENCE_LABELS["PrinterClearance"]), f"{clr:g}", f"{lip:g}")


def preference_problem(keys, scene=None, snap_pins=True):
    """The first of the workbench preferences ``keys`` whose value the fabrication refuses (a material not in
    ``core.materials.MATERIALS``, a servo not among the presets), as a message naming where to change it; "" when
    they are all known. The preferences page takes free text: without this the error came only after OK or in
    the background export, naming no preference. The snap-fit clearance is checked with the module material (both
    shape the modules' snap pins): :func:`clearance_problem` for ``scene`` (None: the default socket lip) and
    ``snap_pins`` (whether the snap pins are designed at all)."""
    from metamaterial_wb.core.materials import MATERIALS
    from metamaterial_wb.geometry.servo import SERVO_PRESETS
    from metamaterial_wb.gui import preferences
    if "ModuleMaterial" in keys or "PrinterClearance" in keys:
        text = clearance_problem(scene, snap_pins)
        if text:
            return text
    for key in keys:
        if key == "PrinterClearance":
            continue
        v = preferences.get(key)
        allowed = sorted(SERVO_PRESETS) if key == "DefaultServo" else sorted(MATERIALS)
        if not isinstance(v, str) or v.upper() not in allowed:
            text = translate("Metamaterial", "Edit > Preferences > Metamaterial > {0}: {1} is not a known servo; "
                             "allowed: {2}") if key == "DefaultServo" else \
                translate("Metamaterial", "Edit > Preferences > Metamaterial > {0}: {1} is not a known material; "
                          "allowed: {2}")
            return text.format(translate("Metamaterial", PREFERENCE_LABELS[key]), repr(v), ", ".join(allowed))
    return ""
