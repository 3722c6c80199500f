"""Scene items: actuators, constraints and rotary axes."""
import copy
from dataclasses import dataclass, field


@dataclass
class Actuator:
    """A servo across a joint: fixes D of both nodes of the joint to ``value`` in [-1, 1]."""
    name: str
    joint: str
    value: float = 0.0
    profile: dict = None
    extra: dict = field(default_factory=dict)

    def to_dict(self):
        d = {"name": self.name, "joint": self.joint, "value": self.value}
        if self.profile is not None:
            d["profile"] = copy.deepcopy(self.profile)
        d.update(copy.deepcopy(self.extra))
        return d


@dataclass
class Constraint:
    """An angular constraint (clip) on a joint: fixes D of both nodes of the joint to ``value``."""
    name: str
    joint: str
    value: float = 0.0
    extra: dict = field(default_factory=dict)

    def to_dict(self):
        d = {"name": self.name, "joint": self.joint, "value": self.value}
        d.update(copy.deepcopy(self.extra))
        return d


@dataclass
class Axis:
    """A rotary axis: a straight grid line through the whole structure (design stage, seed 4.1).

    ``direction`` "vertical": runs down cell column ``line`` and crosses every joint ``H(i, line)``;
    "horizontal": runs along cell row ``line`` and crosses every joint ``V(line, j)``.
    ``fold_deg``: the fold about this axis in the fully deformed state (every D = 1).
    """
    direction: str
    line: int
    fold_deg: float = 0.0
    name: str = ""
    extra: dict = field(default_factory=dict)

    def to_dict(self):
        d = {"direction": self.direction, "line": self.line, "fold_deg": self.fold_deg}
        if self.name:
            d["name"] = self.name
        d.update(copy.deepcopy(self.extra))
        return d


