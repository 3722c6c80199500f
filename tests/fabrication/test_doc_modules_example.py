"""The *Modules* example of docs/scene-format.md builds with its modules: the earlier example (a clip on V1,0
beside a servo housing on V0,1, turned 20 deg) was refused by build's collision check (an audit, session 26)."""
import json
import os
import re

from fabhelpers import REPO, run_build


def doc_example():
    with open(os.path.join(REPO, "docs", "scene-format.md"), encoding="utf-8") as f:
        doc = f.read()
    section = doc[doc.index("\n## Modules"):]
    block = re.search(r"```json\n(.*?)```", section, re.S).group(1)
    return json.loads(block)


def test_the_doc_modules_example_builds(fc, tmp_path):
    scene = doc_example()
    assert {m["type"] for m in scene["modules"]} == {"servo_housing", "friction_pad", "constraint_clip"}
    r, out = run_build(tmp_path, scene, "--modules")
    assert r.returncode == 0, r.stderr
    manifest = json.loads((out / "manifest.json").read_text())
    assert len(manifest["modules"]) == 3, manifest.keys()
