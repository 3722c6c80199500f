"""CalculiX (``ccx``) as a subprocess: write an Abaqus-format deck, run it with a time limit, parse ``.dat``.

``ccx`` is Debian's ``calculix-ccx`` (the solver behind FreeCAD's FEM workbench). It runs single-threaded
here (the machines this runs on are shared) in a temporary directory; :func:`run` returns the parsed
``*NODE PRINT`` tables. :func:`available` says whether the solver is there; callers that find it missing
report so and carry on (the FE rung is optional).
"""
import os
import re
import shutil
import subprocess
import tempfile
import time

import numpy as np

from metamaterial_wb.core.errors import MetamaterialError


class FEError(MetamaterialError):
    """CalculiX is missing, failed, or ran out of time."""


def ccx_path():
    return shutil.which("ccx") or shutil.which("ccx_2.20") or shutil.which("calculix")


def available():
    """``(True, path)`` or ``(False, reason)``."""
    p = ccx_path()
    return (True, p) if p else (False, "CalculiX (ccx) is not installed: apt-get install calculix-ccx")


_HEADER = re.compile(r"^\s*(displacements|forces|stresses|strains)\s*\(.*\)\s*for set\s+(\S+)\s+and time\s+(\S+)",
                     re.IGNORECASE)


def parse_dat(text):
    """``{(quantity, set): [(time, {node: values}), ...]}`` from a ``.dat`` file's ``*NODE PRINT`` tables
    (quantity ``"displacements"`` or ``"forces"``; times in the order printed)."""
    out = {}
    cur = None
    for line in text.splitlines():
        m = _HEADER.match(line)
        if m:
            cur = {}
            out.setdefault((m.group(1).lower(), m.group(2).upper()), []).append((float(m.group(3)), cur))
            continue
        if cur is None:
            continue
        parts = line.split()
        if not parts:
            continue
        try:
            node = int(parts[0])
            vals = [float(p) for p in parts[1:]]
        except ValueError:
            cur = None
            continue
        cur[node] = np.array(vals)
    return out


_EIGEN = "E I G E N V A L U E   O U T P U T"


def parse_eigenvalues(text):
    """Every ``*FREQUENCY`` step's eigenvalues (omega^2, in the order printed; negative for an unstable
    state) from a ``.dat`` file: a list with one list per frequency step."""
    out = []
    for block in text.split(_EIGEN)[1:]:
        vals = []
        for line in block.splitlines()[1:]:
            parts = line.split()
            if not parts:
                continue
            if parts[0].isdigit() and len(parts) >= 3:
                vals.append(float(parts[1]))
            elif vals or parts[0] == "P":
                break
        out.append(vals)
    return out


def run(deck, name="job", timeout_s=600.0, keep_dir=None, partial=False):
    """Run ``deck`` (the text of an ``.inp`` file) through ccx. Returns ``(tables, info)``: the parsed
    ``.dat`` (:func:`parse_dat`) and ``{"wall_s", "dir"?}``. Raises :class:`FEError` if ccx is missing, fails,
    does not converge or exceeds ``timeout_s`` (it is then killed). With ``partial=True`` a run that stops
    early (no convergence, time limit) returns the increments it converged, with ``info["stopped"]`` saying
    why (a path traced as far as the solver goes)."""
    from metamaterial_wb.fe.checks import number
    number("timeout_s", timeout_s, 0, None, "s", low_open=True)
    ok, path = available()
    if not ok:
        raise FEError(path)
    tmp = keep_dir or tempfile.mkdtemp(prefix="mmwb-ccx-")
    try:
        with open(os.path.join(tmp, name + ".inp"), "w") as f:
            f.write(deck)
        env = dict(os.environ, OMP_NUM_THREADS="1", CCX_NPROC_EQUATION_SOLVER="1", CCX_NPROC_STIFFNESS="1",
                   CCX_NPROC_RESULTS="1")
        t0 = time.perf_counter()
        try:
            proc = subprocess.run([path, "-i", name], cwd=tmp, env=env, stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, timeout=timeout_s)
        except subprocess.TimeoutExpired:
            stopped = f"ccx did not finish within {timeout_s:g} s (job {name!r}); it was stopped"
            if not partial:
                raise FEError(stopped) from None
            proc, log = None, ""
        else:
            log = proc.stdout.decode("utf-8", "replace")
            stopped = None
        wall = time.perf_counter() - t0
        dat = os.path.join(tmp, name + ".dat")
        if proc is not None and (proc.returncode != 0 or "*ERROR" in log or not os.path.exists(dat)):
            tail = "\n".join(l for l in log.splitlines() if l.strip())[-1500:]
            stopped = f"ccx failed on job {name!r} (exit code {proc.returncode}):\n{tail}"
            if not partial or not os.path.exists(dat):
                raise FEError(stopped)
        if not os.path.exists(dat):
            raise FEError(stopped or f"ccx wrote no .dat file for job {name!r}")
        with open(dat, encoding="utf-8", errors="replace") as f:     # a .dat that is not ccx's: its tables are missing
            text = f.read()
        tables = parse_dat(text)
        info = {"wall_s": wall, "log_tail": log[-400:]}
        eig = parse_eigenvalues(text)
        if eig:
            info["eigenvalues"] = eig
        if stopped:
            info["stopped"] = stopped
        return tables, info
    finally:
        if keep_dir is None:
            shutil.rmtree(tmp, ignore_errors=True)


def table(tables, key, job, nodes=(), info=None):
    """The ``*NODE PRINT`` table ``key`` (``(quantity, set)``, :func:`parse_dat`) of job ``job``'s ``.dat``: its rows
    ``[(time, {node: values}), ...]``, each holding every node of ``nodes``. A table that is missing or empty, or a
    row without one of ``nodes``, raises :class:`FEError` naming the job and the table (a ``.dat`` that is empty,
    truncated or not ccx's; ``info["stopped"]``, a partial run's reason, is added), never a KeyError. A partial run's
    last row may lack nodes (ccx stopped while printing it): it is dropped."""
    rows = list(tables.get(key) or ())
    why = (info or {}).get("stopped")
    need = [int(n) for n in np.asarray(nodes, dtype=np.int64).ravel()]
    if rows and need and why and any(n not in rows[-1][1] for n in need):
        rows = rows[:-1]
    if not rows:
        raise FEError(f"ccx job {job!r}: no {key[0]} table for node set {key[1]} in its .dat "
                      + (f"({why})" if why else "(ccx printed no converged increment, or the file is not ccx's)"))
    for t, vals in rows:
        gone = [n for n in need if n not in vals]
        if gone:
            raise FEError(f"ccx job {job!r}: the {key[0]} table for node set {key[1]} at time {t:g} lacks "
                          f"{len(gone)} of its {len(need)} nodes (node {gone[0]} first): a truncated .dat")
    return rows


def fmt_nodes(nodes, first=1):
    """``*NODE`` lines (1-based ids from ``first``)."""
    return "".join(f"{first + i},{x:.9g},{y:.9g},{z:.9g}\n" for i, (x, y, z) in enumerate(nodes))


def fmt_elements(elements, ids, node_base=1):
    """``*ELEMENT`` data lines for 20-node bricks: 16 node ids on the first line, the rest continued."""
    lines = []
    for eid, conn in zip(ids, elements + node_base):
        c = [str(int(v)) for v in conn]
        lines.append(f"{eid}," + ",".join(c[:15]) + ",\n" + ",".join(c[15:]) + "\n")
    return "".join(lines)


def fmt_set(ids, per_line=12):
    ids = [str(int(i)) for i in ids]
    return "".join(",".join(ids[k:k + per_line]) + ",\n" for k in range(0, len(ids), per_line))
