"""Task panels of the workbench, one panel per file (the FreeCAD Draft / FEM way).

``base`` holds the shared :class:`~metamaterial_wb.gui.panels.base.BasePanel` (layout, the error label,
OK / Cancel, transactions, picking), ``jobs`` the background-job helper (progress bar + Cancel),
``stream`` the controller that streams motor values to the servo firmware. :func:`active` is the panel
being shown (the GUI tests drive it through its widgets).
"""
from metamaterial_wb.gui.panels import base
from metamaterial_wb.gui.panels.add_module import AddModulePanel
from metamaterial_wb.gui.panels.animate import AnimatePanel, hardware_available
from metamaterial_wb.gui.panels.base import BasePanel, pick_index, show, transaction
from metamaterial_wb.gui.panels.export import ExportPanel
from metamaterial_wb.gui.panels.flexibility import FlexibilityPanel
from metamaterial_wb.gui.panels.folded_shape import FoldedShapePanel
from metamaterial_wb.gui.panels.new_structure import NewStructurePanel
from metamaterial_wb.gui.panels.open_example import OpenExamplePanel, example_files
from metamaterial_wb.gui.panels.place_item import PlaceItemPanel
from metamaterial_wb.gui.panels.rotary_axes import RotaryAxesPanel
from metamaterial_wb.gui.panels.simulate import SimulatePanel
from metamaterial_wb.gui.panels.sleeve import SleevePanel, sleeve_summary_text

__all__ = ["AddModulePanel", "AnimatePanel", "BasePanel", "ExportPanel", "FlexibilityPanel", "FoldedShapePanel",
           "NewStructurePanel", "OpenExamplePanel", "PlaceItemPanel", "RotaryAxesPanel", "SimulatePanel",
           "SleevePanel", "active", "example_files", "hardware_available", "pick_index", "show",
           "sleeve_summary_text", "transaction"]


def active():
    """The task panel being shown (None when no Metamaterial panel is open)."""
    return base.ACTIVE
