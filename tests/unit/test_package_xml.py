"""package.xml carries what FreeCAD's Addon Manager needs to list and install us (issue 13)."""
import os
import xml.etree.ElementTree as ET

import pytest

import metamaterial_wb
from metamaterial_wb import REPO_DIR

NS = {"p": "https://wiki.freecad.org/Package_Metadata"}
PATH = os.path.join(REPO_DIR, "package.xml")


@pytest.fixture(scope="module")
def root():
    return ET.parse(PATH).getroot()


def test_urls_icon_versions_and_dependencies(root):
    urls = {u.get("type"): u.text for u in root.findall("p:url", NS)}
    assert urls.get("repository", "").startswith("https://") and root.find("p:url[@type='repository']", NS).get("branch")
    assert urls.get("bugtracker", "").startswith("https://")
    assert root.findtext("p:version", namespaces=NS) == metamaterial_wb.__version__
    assert root.findtext("p:freecadmin", namespaces=NS) == "0.20.0"
    assert root.findtext("p:pythonmin", namespaces=NS)
    deps = {d.text: d.attrib for d in root.findall("p:depend", NS)}
    assert deps["numpy"].get("type") == "python" and deps["scipy"].get("type") == "python"
    # no pyserial: FreeCAD 0.20's Addon Manager ignores optional="true" and imports "pyserial" (the module is
    # "serial"), so every install said "Missing Requirement" (tests/hardware/test_package_deps.py)
    assert "pyserial" not in deps
    for icon in [root.findtext("p:icon", namespaces=NS)] + [w.findtext("p:icon", namespaces=NS)
                                                            for w in root.iter("{%s}workbench" % NS["p"])]:
        path = os.path.join(REPO_DIR, icon)
        assert os.path.getsize(path) < 10 * 1024, (icon, "the Addon Manager wants icons under 10 KB")


def test_workbench_class_is_the_one_initgui_defines(root):
    wb = root.find("p:content/p:workbench", NS)
    src = open(os.path.join(REPO_DIR, "InitGui.py"), encoding="utf-8").read()
    assert f"class {wb.findtext('p:classname', namespaces=NS)}" in src
    assert wb.findtext("p:subdirectory", namespaces=NS) == "./"


def test_freecad_reads_our_metadata():
    """FreeCAD's own package.xml reader (App.Metadata, used by the Addon Manager) accepts the file."""
    FreeCAD = pytest.importorskip("FreeCAD")
    md = FreeCAD.Metadata(PATH)
    assert md.Name == "Metamaterial Workbench"
    assert md.Version == metamaterial_wb.__version__
    assert any(u["type"] == "bugtracker" for u in md.Urls)
    assert [c.Classname for c in md.Content["workbench"]] == ["MetamaterialWorkbench"]
