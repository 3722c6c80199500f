"""Update one marked section of docs/benchmarks.md without touching the others.

A section is the text between ``<!-- begin:KEY -->`` and ``<!-- end:KEY -->``; it is appended at
the end of the file when it is not there yet.
"""
import os
import platform
import time

DOC = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "docs", "benchmarks.md")


def best_of(fn, repeat):
    """``(shortest wall time in s, last result)`` of ``repeat`` calls of ``fn()``."""
    ts, out = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t)
    return min(ts), out


def machine_line():
    return (f"Measured {time.strftime('%Y-%m-%d')} on {os.cpu_count()} cores, Python {platform.python_version()}"
            f" ({platform.machine()}).")


def update_section(key, body, path=DOC):
    begin, end = f"<!-- begin:{key} -->", f"<!-- end:{key} -->"
    text = open(path, encoding="utf-8").read() if os.path.exists(path) else "# Benchmarks\n"
    block = f"{begin}\n{body.rstrip()}\n{end}"
    if begin in text and end in text:
        pre, rest = text.split(begin, 1)
        _, post = rest.split(end, 1)
        text = pre + block + post
    else:
        text = text.rstrip() + "\n\n" + block + "\n"
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)
