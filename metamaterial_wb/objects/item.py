"""Markers: motors (``Kind`` actuator, red sphere) and angular constraints (blue disc) on a joint."""

import FreeCAD

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.objects.common import (ProxyBase, attach_proxy, count_execute, ensure_property, ensure_range,
                                            json_property, tag_proxy)

PROFILE_SHAPES = ["none", "sine", "constant", "steps", "keyframes"]
VALUE_RANGE = (-1.0, 1.0, 0.05)   # (low, high, step) of Value (a D): re-applied on restore, FreeCAD does not save it


class ItemProxy(ProxyBase):
    """A servo (``Kind`` actuator, red sphere) or an angular-constraint clip (constraint, blue disc)."""
    Type = "MetamaterialItem"

    def __init__(self, obj):
        attach_proxy(obj, self)
        self._ensure_properties(obj)

    def _ensure_properties(self, obj):
        if ensure_property(obj, "App::PropertyEnumeration", "Kind", "Item", "actuator (servo) or constraint"):
            obj.Kind = ["actuator", "constraint"]
        ensure_property(obj, "App::PropertyString", "ItemName", "Item", "Name in the scene (unique)")
        ensure_property(obj, "App::PropertyString", "Joint", "Item", "Joint, e.g. V0,1 or H2,3")
        ensure_property(obj, "App::PropertyFloatConstraint", "Value", "Item",
                        "Deformation the item imposes on both nodes of its joint, in [-1, 1]",
                        (0.0,) + VALUE_RANGE)
        if ensure_property(obj, "App::PropertyEnumeration", "ProfileShape", "Motion",
                           "Motion profile over time (actuators)"):
            obj.ProfileShape = PROFILE_SHAPES
        ensure_property(obj, "App::PropertyFloat", "Amplitude", "Motion", "Sine amplitude (0..1)", 0.5)
        ensure_property(obj, "App::PropertyFloat", "FrequencyHz", "Motion", "Sine frequency (Hz)", 0.5)
        ensure_property(obj, "App::PropertyFloat", "PhaseDeg", "Motion", "Sine phase offset (deg)", 0.0)
        ensure_property(obj, "App::PropertyFloat", "Offset", "Motion", "Sine offset", 0.0)
        ensure_property(obj, "App::PropertyString", "ProfileData", "Motion",
                        "JSON of a constant / steps / keyframes profile")
        ensure_property(obj, "App::PropertyString", "ExtraJSON", "Item", "Other fields of the item (JSON)",
                        hidden=True)
        ensure_property(obj, "App::PropertyLength", "Radius", "Display", "Marker size (mm)", 4.0)

    def onDocumentRestored(self, obj):
        self._ensure_properties(obj)
        ensure_range(obj, "Value", *VALUE_RANGE)
        tag_proxy(obj, self)   # files saved before the split name objects.structure (still importable)

    def execute(self, obj):
        count_execute(obj)
        import Part
        r = max(0.1, float(obj.Radius.Value))
        pl = FreeCAD.Placement(obj.Placement)
        if obj.Kind == "actuator":
            shape = Part.makeSphere(r)
        else:
            shape = Part.makeCylinder(r, 0.6 * r, FreeCAD.Vector(0, 0, -0.3 * r))
        item_to_dict(obj)  # validates the profile fields (raises with the object's name)
        obj.Shape = shape
        obj.Placement = pl


def item_to_dict(obj):
    d = json_property(obj, "ExtraJSON", "an object of the item's other fields")
    d.update({"name": obj.ItemName or obj.Name, "joint": obj.Joint, "value": float(obj.Value)})
    if obj.Kind == "actuator" and obj.ProfileShape != "none":
        if obj.ProfileShape == "sine":
            prof = {"shape": "sine", "amplitude": float(obj.Amplitude), "frequency_hz": float(obj.FrequencyHz),
                    "phase_deg": float(obj.PhaseDeg)}
            if obj.Offset:
                prof["offset"] = float(obj.Offset)
        else:
            prof = json_property(obj, "ProfileData", f"an object with the {obj.ProfileShape} profile's fields, e.g. "
                                 '{"times_s": [0, 1], "values": [0, 0.5]}')
            prof["shape"] = obj.ProfileShape
        from metamaterial_wb.core.motion import validate_profile
        try:
            validate_profile(prof, f"{obj.Label}.profile")
        except SceneError:
            raise
        d["profile"] = prof
    return d
