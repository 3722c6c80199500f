"""package.xml's python dependencies: FreeCAD 0.20's Addon Manager ignores optional="true" and checks each one
with ``__import__(name)``, so a name that is not the module's import name (pyserial -> serial) shows
"Missing Requirement" on every install. Every python <depend> must be importable by its own name."""
import os
import xml.etree.ElementTree as ET

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
NS = {"p": "https://wiki.freecad.org/Package_Metadata"}
# distribution names whose import name differs (the common ones)
IMPORT_NAME = {"pyserial": "serial", "pillow": "PIL", "pyyaml": "yaml", "opencv-python": "cv2",
               "scikit-learn": "sklearn", "scikit-image": "skimage", "beautifulsoup4": "bs4",
               "python-dateutil": "dateutil", "pyqt5": "PyQt5", "pyside2": "PySide2"}


def python_depends():
    root = ET.parse(os.path.join(REPO, "package.xml")).getroot()
    return [d.text.strip() for d in root.iter("{%s}depend" % NS["p"]) if d.get("type") == "python"]


def test_python_depends_are_import_names():
    deps = python_depends()
    assert "numpy" in deps and "scipy" in deps
    for name in deps:
        assert name.isidentifier(), f"package.xml <depend type=\"python\">{name}: not a module name"
        assert name.lower() not in IMPORT_NAME, (f"package.xml <depend type=\"python\">{name}: the Addon Manager "
                                                 f"imports it by that name; the module is {IMPORT_NAME[name.lower()]}")


def test_streaming_still_explains_how_to_get_pyserial():
    from metamaterial_wb.hardware.link import pyserial_help
    assert "pip install pyserial" in pyserial_help() and "python3-serial" in pyserial_help()
