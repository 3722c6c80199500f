"""Metamaterial Workbench: sparsely actuated modular metamaterials for FreeCAD.

The package never imports FreeCAD at top level; ``core`` never imports it at all.
"""
import os

__version__ = "0.2.0"

PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))
REPO_DIR = os.path.dirname(PACKAGE_DIR)
RESOURCES_DIR = os.path.join(REPO_DIR, "resources")
EXAMPLES_DIR = os.path.join(REPO_DIR, "examples")
# the workbench's parameter group (preferences page, objects' fabrication defaults): the one definition
PREFS_PATH = "User parameter:BaseApp/Preferences/Mod/Metamaterial"


def icon_path(name):
    """Absolute path of an icon in resources/icons."""
    return os.path.join(RESOURCES_DIR, "icons", name)


def example_path(name):
    """Absolute path of a bundled example scene (``fish`` or ``fish.json``)."""
    if not name.endswith(".json"):
        name += ".json"
    return os.path.join(EXAMPLES_DIR, name)
