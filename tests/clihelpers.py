"""The command line as a user runs it, for tests in every folder: ``run_cli`` starts ``python -m
metamaterial_wb`` in a subprocess (the checkout first on the path) and ``one_line_error`` checks a refusal is
what every refusal of the CLI is (exit 2, one line ``error: FIELD: ...``, no traceback).

The arguments go out and the output comes back as UTF-8 whatever the test process's locale (CI's pytest process
reads the C locale's ASCII once FreeCAD is loaded: a typed '٣' in an error message failed to decode there), and the
command runs in Python's UTF-8 mode, as in a UTF-8 terminal."""
import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run_cli(*args, timeout=300):
    """``subprocess.CompletedProcess`` of ``python -m metamaterial_wb ARGS`` run in the checkout (text output)."""
    argv = [sys.executable, "-m", "metamaterial_wb", *map(str, args)]
    return subprocess.run([a.encode("utf-8") for a in argv], cwd=REPO, capture_output=True, encoding="utf-8",
                          timeout=timeout, env=dict(os.environ, PYTHONPATH=REPO, PYTHONUTF8="1"))


def one_line_error(r, field):
    assert r.returncode == 2, (r.stdout, r.stderr)
    assert r.stderr.startswith(f"error: {field}: "), r.stderr
    assert r.stderr.strip().count("\n") == 0, r.stderr
    assert "Traceback" not in r.stderr
