"""The *Modules* example of docs/scene-format.md builds with its modules: the earlier example (a clip on V1,0
beside a servo housing on V0,1, turned 20 deg) was refused by build's collision check (an audit, session 26)."""
import json
import os
import re
import subprocess
import sys

from fabhelpers import REPO


def doc_example():
    with open(os.path.join(REPO, "docs", "scene-format.md"), encoding="utf-8") as f:
        doc = f.read()
    section = doc[doc.index("\n## Modules"):]
    block = re.search(r"```json\n(.*?)```", section, re.S).group(1)
    return json.loads(block)


def test_the_doc_modules_example_builds(fc, tmp_path):
    scene = doc_example()
    assert {m["type"] for m in scene["modules"]} == {"servo_housing", "friction_pad", "constraint_clip"}
    path = tmp_path / "modules.json"
    path.write_text(json.dumps(scene))
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "build", str(path), "--out", str(tmp_path / "out"),
                        "--modules"], capture_output=True, text=True, cwd=REPO, timeout=600)
    assert r.returncode == 0, r.stderr
    manifest = json.loads((tmp_path / "out" / "manifest.json").read_text())
    assert len(manifest["modules"]) == 3, manifest.keys()
