"""Regenerate tests/vectors/gait_rule.json (run: /usr/bin/python3 tests/dynamics/gen_gait_vectors.py).

The expected outputs come from ``reference_rule`` below: a deliberately plain per-cell loop written
straight from the seed's Algorithm 1, independent of the numpy implementation in core/gait.py.
The first vectors were also checked by hand (flag "hand_checked").
"""
import json
import os
import random


def reference_rule(c, n1, n2, closed):
    n = len(c)
    out = []
    for i in range(n):
        if c[i] != 1:          # on the ground -> vent
            out.append(0)
            continue
        fire = 0
        for j in (i + n1, i - n2):
            if closed:
                j %= n
            elif j < 0 or j >= n:
                continue       # neighbour does not exist: its term is false
            if c[j] == 0:
                fire = 1
        out.append(fire)
    return out


HEADER = {
    "format": (
        "Test vectors of the distributed gait rule (seed 001, Algorithm 1). "
        "Each entry of 'vectors' has: name (string); closed (true = circular belt, indices wrap modulo N; "
        "false = open strip, a neighbour index outside 0..N-1 does not exist and its term is false); "
        "n1, n2 (integers, 0 <= n1, n2 < N; 0 switches that term off); "
        "c_air (array of N integers, sensor state per cell: 1 = in the air, 0 = touching the ground); "
        "act (array of N integers, the expected output: 1 = inflate, 0 = vent); "
        "hand_checked (true if a person verified 'act' by hand). "
        "Rule: act[i] = c_air[i] AND (NOT c_air[i+n1] OR NOT c_air[i-n2])."),
    "source": "../shared/seeds/001_7ea2199d529842b1.txt, section 3, Algorithm 1",
    "generator": "tests/dynamics/gen_gait_vectors.py (reference_rule, a plain loop independent of core/gait.py)",
    "max_cells": 64,
}

HAND = [
    # name, closed, n1, n2, c_air, act (worked out by hand)
    ("belt8_flat_n1_1", True, 1, 0, [0, 0, 0, 1, 1, 1, 1, 1], [0, 0, 0, 0, 0, 0, 0, 1]),
    ("belt8_flat_n1_2", True, 2, 0, [0, 0, 0, 1, 1, 1, 1, 1], [0, 0, 0, 0, 0, 0, 1, 1]),
    ("belt8_high_torque", True, 1, 1, [0, 0, 0, 1, 1, 1, 1, 1], [0, 0, 0, 1, 0, 0, 0, 1]),
    ("belt8_high_torque_2_2", True, 2, 2, [0, 0, 0, 1, 1, 1, 1, 1], [0, 0, 0, 1, 1, 0, 1, 1]),
    ("belt8_wrap", True, 1, 0, [1, 1, 1, 1, 1, 0, 0, 0], [0, 0, 0, 0, 1, 0, 0, 0]),
    ("all_air", True, 1, 1, [1, 1, 1, 1, 1, 1, 1, 1], [0, 0, 0, 0, 0, 0, 0, 0]),
    ("all_ground", True, 1, 1, [0, 0, 0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0, 0, 0]),
    ("n_zero_off", True, 0, 0, [0, 1, 0, 1, 1, 0, 1, 0], [0, 0, 0, 0, 0, 0, 0, 0]),
    ("open_edge_ignored", False, 1, 1, [0, 1, 1, 1, 1, 1, 1, 1], [0, 1, 0, 0, 0, 0, 0, 0]),
    ("closed_same_input", True, 1, 1, [0, 1, 1, 1, 1, 1, 1, 1], [0, 1, 0, 0, 0, 0, 0, 1]),
    ("open_two_islands", False, 1, 1, [1, 0, 0, 1, 1, 1, 1, 1], [1, 0, 0, 1, 0, 0, 0, 0]),
    ("single_cell_air", True, 0, 0, [1], [0]),
]


def main():
    vectors = []
    for name, closed, n1, n2, c, act in HAND:
        ref = reference_rule(c, n1, n2, closed)
        assert ref == act, (name, ref, act)
        vectors.append({"name": name, "closed": closed, "n1": n1, "n2": n2, "c_air": c, "act": act,
                        "hand_checked": True})
    rng = random.Random(20261125)
    for k in range(40):
        n = rng.choice([3, 5, 8, 8, 8, 12, 16, 31, 64])
        closed = rng.random() < 0.7
        n1 = rng.randrange(n)
        n2 = rng.randrange(n) if rng.random() < 0.6 else 0
        if rng.random() < 0.5:      # belt-like: one contiguous ground arc
            g0, glen = rng.randrange(n), rng.randint(1, max(1, n // 2))
            c = [1] * n
            for j in range(glen):
                c[(g0 + j) % n] = 0
        else:
            c = [rng.randint(0, 1) for _ in range(n)]
        vectors.append({"name": f"random_{k:02d}", "closed": closed, "n1": n1, "n2": n2, "c_air": c,
                        "act": reference_rule(c, n1, n2, closed), "hand_checked": False})
    out = dict(HEADER, vectors=vectors)
    path = os.path.join(os.path.dirname(__file__), "..", "vectors", "gait_rule.json")
    # compact one-line-per-vector layout, easy to diff and to read from C
    lines = ["{"]
    for k, v in HEADER.items():
        lines.append(f" {json.dumps(k)}: {json.dumps(v)},")
    lines.append(' "vectors": [')
    lines.append(",\n".join("  " + json.dumps(v) for v in vectors))
    lines.append(" ]")
    lines.append("}")
    text = "\n".join(lines) + "\n"
    json.loads(text)
    with open(path, "w") as f:
        f.write(text)
    print(f"wrote {len(vectors)} vectors to {os.path.normpath(path)}")


if __name__ == "__main__":
    main()
