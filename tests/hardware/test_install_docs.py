"""README's install one-liners work on a fresh account: the Mod folder is created before the link into it
(``ln -s`` fails when ~/.local/share/FreeCAD/Mod does not exist yet)."""
import os
import re
import subprocess

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def one_liners():
    text = open(os.path.join(REPO, "README.md"), encoding="utf-8").read()
    return [c for c in re.findall(r"`([^`]*ln -s [^`]*)`", text) if "/Mod/" in c]


def test_every_link_into_a_mod_folder_creates_it_first():
    cmds = one_liners()
    assert len(cmds) >= 2, cmds
    for c in cmds:
        target = re.search(r'ln -s "\$PWD" (\S+)/MetamaterialWorkbench', c)
        assert target, c
        assert f"mkdir -p {target.group(1)} &&" in c, c


def test_the_one_liners_run_in_an_empty_home(tmp_path):
    src = tmp_path / "checkout"
    src.mkdir()
    for c in one_liners():
        home = tmp_path / f"home{abs(hash(c))}"
        home.mkdir()
        r = subprocess.run(["sh", "-c", c], cwd=src, env={"HOME": str(home), "PATH": os.environ["PATH"]},
                           capture_output=True, text=True)
        assert r.returncode == 0, (c, r.stderr)
        link = re.search(r"ln -s \"\$PWD\" ~/(\S+)", c).group(1)
        assert os.path.realpath(home / link) == str(src), c
