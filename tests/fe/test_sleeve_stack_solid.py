"""Issue 18: two sleeve rings stacked in series as one curved CalculiX solid, a free plate between them.

The seed's combination 2 snaps asymmetrically in the seed; the mixed solid ring does not, the frame's stacked rings
do. The stack as a solid: its mesh (two rings, the second on the first), its deck (two rigid plates, the middle one
free but for its in-plane translation, the bias on the top plate alone), its reading of the order (each ring a
hysteron of its type), and a tiny real ccx run that must act as two springs in series.
"""
import numpy as np
import pytest

from metamaterial_wb.bench.fe_ring3d_combinations import combination_cells
from metamaterial_wb.bench import fe_ring3d_stack as fs
from metamaterial_wb.bench.fe_ring3d_stack import stack_sequence
from metamaterial_wb.fe import ccx, sleeve3d, sleeve3d_stack

needs_ccx = pytest.mark.skipif(not ccx.available()[0],
                               reason="CalculiX (ccx) not installed (Debian calculix-ccx; not in every lane's root)")


def test_the_stack_is_two_whole_rings_the_second_on_the_first():
    a, b = combination_cells("2")
    m = sleeve3d_stack.stack_mesh([a, b], 4, 1)
    ra, rb = sleeve3d.ring_mesh(a, 4, 1), sleeve3d.ring_mesh(b, 4, 1)
    assert m.n_nodes == ra.n_nodes + rb.n_nodes and m.n_elements == ra.n_elements + rb.n_elements
    assert m.height == pytest.approx(a.height + b.height) and m.heights == pytest.approx([a.height, b.height])
    assert m.volume() == pytest.approx(ra.volume() + rb.volume(), rel=1e-12)
    # the second ring sits on the first: its nodes are its own ring's, raised by the first ring's height
    assert np.allclose(m.nodes[m.offset:], rb.nodes + [0.0, 0.0, a.height])
    assert m.elements.max() == m.n_nodes - 1 and m.elements[ra.n_elements:].min() == m.offset
    ends = m.beam_ends()
    assert len(ends) == 2 and ends[1]["outer"].min() >= m.offset > ends[0]["outer"].max()
    # each end lies where its own ring's does (the second's raised)
    assert np.allclose(m.nodes[ends[1]["outer"]], rb.nodes[rb.beam_ends()["outer"]] + [0.0, 0.0, a.height])


def test_types_of_different_widths_cannot_stack_and_the_refusals_name_the_value():
    import dataclasses
    a, b = combination_cells("1")
    wide = dataclasses.replace(b, L=1.1 * b.L)             # a longer span: a wider cell
    with pytest.raises(ValueError, match=r"cells: widths .* allowed: equal widths"):
        sleeve3d_stack.stack_mesh([a, wide])
    with pytest.raises(ValueError, match=r"cells: 1 cell types; allowed: 2"):
        sleeve3d_stack.stack_mesh([a])
    for kw, msg in (({"d_max": 4.0 * a.L}, r"d_max: .* allowed: 0 < d_max <= 3 L"),
                    ({"d_max": 0.0}, r"d_max: 0.0 mm"),
                    ({"bias": float("nan")}, r"bias: nan; allowed: 0 to 0.001"),
                    ({"method": "explicit"}, r"method: 'explicit'; allowed: 'static', 'dynamic'"),
                    ({"increments": 0}, r"increments: 0; allowed: an integer >= 1"),
                    ({"watch": [10 ** 6]}, r"watch: 1 node ids from 1000000 to 1000000; allowed: 1 or more of 0 to")):
        with pytest.raises(ValueError, match=msg):
            sleeve3d_stack.stack_deck3d([a, b], **kw)


def test_deck_holds_two_plates_the_middle_one_free_to_rise_tilt_and_twist():
    a, b = combination_cells("2")
    deck, meta = sleeve3d_stack.stack_deck3d([a, b], 4, 1, d_max=0.2 * a.L, increments=10, watch=[0, 1])
    M, MR, R, RR = sleeve3d_stack.MREF, sleeve3d_stack.MROT, sleeve3d.REF, sleeve3d.ROT
    assert f"*RIGID BODY, NSET=TOP, REF NODE={R}, ROT NODE={RR}\n" in deck
    assert f"*RIGID BODY, NSET=MID, REF NODE={M}, ROT NODE={MR}\n" in deck
    # the middle plate: only its in-plane translation held (never along an amplitude); its rotation node free
    assert f"*BOUNDARY\n{M},1,2,0\n" in deck and f"{M},3" not in deck and f"\n{MR}," not in deck.split("*STEP")[1]
    assert f"*BOUNDARY, AMPLITUDE=UPDOWN\nBOTTOM,1,3,0\n{R},1,2,0\n{R},3,3,{0.2 * a.L:.12g}\n" in deck
    # the bias moment on the top plate alone, held through the unloading
    cload = deck.split("*CLOAD, AMPLITUDE=HOLD\n")[1].split("*")[0].splitlines()
    assert [ln.split(",")[0] for ln in cload] == [str(RR), str(RR)]
    assert "*DYNAMIC, ALPHA=-0.3\n0.1,2.0," in deck and "*DENSITY\n" in deck and deck.count("*STEP") == 1
    # the middle set holds the first ring's top and the second ring's bottom, nothing else
    X = meta["mesh"].nodes
    mid = np.array([int(v) for v in deck.split("*NSET, NSET=MID\n")[1].split("*")[0].replace("\n", ",").split(",")
                    if v.strip()]) - 1
    assert np.allclose(X[mid, 2], a.height)
    assert (mid < meta["mesh"].offset).sum() == (np.abs(X[:meta["mesh"].offset, 2] - a.height) < 1e-9).sum()
    assert (mid >= meta["mesh"].offset).sum() == (np.abs(X[meta["mesh"].offset:, 2] - a.height) < 1e-9).sum()
    assert meta["heights_mm"] == pytest.approx([a.height, b.height])
    up, _ = sleeve3d_stack.stack_deck3d([a, b], 4, 1, d_max=0.2 * a.L, increments=10, method="static",
                                        unload=False, bias=0.0)
    assert "AMPLITUDE" not in up and "*CLOAD" not in up and "*DENSITY" not in up and "*STATIC\n0.1,1.0," in up
    # the rubber's own damping (mass-proportional): one card in the material, the rest of the deck the same
    damped, m2 = sleeve3d_stack.stack_deck3d([a, b], 4, 1, d_max=0.2 * a.L, increments=10, watch=[0, 1],
                                             damping=200.0)
    assert "*DENSITY\n1e-10\n*DAMPING, ALPHA=200, BETA=0.\n*SOLID SECTION" in damped and m2["damping"] == 200.0
    assert damped.replace("*DAMPING, ALPHA=200, BETA=0.\n", "") == deck and "*DAMPING" not in deck
    for bad, msg in ((-1.0, r"damping: -1.0 1/s; allowed: 0 to 1000 1/s"), (float("nan"), r"damping: nan 1/s"),
                     (2e3, r"damping: 2000.0 1/s; allowed: 0 to 1000 1/s")):
        with pytest.raises(ValueError, match=msg):
            sleeve3d_stack.stack_deck3d([a, b], damping=bad)
    with pytest.raises(ValueError, match=r"damping: 200.0 1/s damps implicit dynamics; method 'static' has no time"):
        sleeve3d_stack.stack_deck3d([a, b], method="static", damping=200.0)


def _run(order_up, order_down, d=(0.0, 0.3, 0.6, 0.9, 1.2, 0.9, 0.6, 0.3, 0.0)):
    """A made-up stack cycle: one half per ring (unit 0 the first ring's, 1 the second's), each snapping (rising
    past its h / L) at the listed points."""
    a, b = combination_cells("2")
    h = [a.h / a.L, b.h / b.L]
    k = len(d)
    rises = np.zeros((k, 2))
    turn = int(np.argmax(d))
    for j, (i_up, i_down) in enumerate(zip(order_up, order_down)):
        rises[i_up:i_down, j] = h[j] + 0.1
    return {"combination": "2", "d": list(d), "rises": rises.tolist(), "units": [0, 1], "types": [0, 1],
            "tilt_rad": [[0.0, 0.01 if i <= turn else -0.02] for i in range(k)],
            "unloading": [int(i > turn) for i in range(k)], "stopped": ""}


def test_the_order_is_read_ring_by_ring_as_the_frame_reads_it():
    # ring 0 snaps first (point 2), ring 1 at 3; on unloading ring 0 snaps back first (point 6), ring 1 at 7
    s = stack_sequence(_run((2, 3), (6, 7)))
    assert s["loading"] == [0, 1] and s["unloading"] == [0, 1] and not s["symmetric"] and s["rings"] == 2
    s = stack_sequence(_run((2, 3), (7, 6)))
    assert s["unloading"] == [1, 0] and s["symmetric"]
    assert s["lean_reverses"]
    # a run stopped on its way down gives its order once every ring that snapped has snapped back, else none
    assert stack_sequence(dict(_run((2, 3), (7, 6)), stopped="stopped by hand"))["unloading"] == [1, 0]
    assert stack_sequence(_run((2, 3), (6, 99)))["unloading"] == [0]
    assert stack_sequence(dict(_run((2, 3), (6, 99)), stopped="stopped by hand")) is None


def test_ring_events_name_each_rings_snaps_and_fold_a_chatter():
    run = _run((2, 3), (6, 7))
    assert fs.ring_events(run) == [(2, 0.6, 0, "snaps"), (3, 0.9, 1, "snaps"), (6, 0.6, 0, "snaps back"),
                                   (7, 0.3, 1, "snaps back")]
    assert fs.events_text(fs.ring_events(run)) == ("ring 0 snaps at d/L 0.600, ring 1 snaps at 0.900, "
                                                   "ring 0 snaps back at 0.600, ring 1 snaps back at 0.300")
    # ring 0 crossing its h back and forth after ring 1's snap (as combination 2's stack does): one entry
    d = [0.1 * i for i in range(12)]
    rises = np.zeros((12, 2))
    h = [g.h / g.L for g in combination_cells("2")]
    rises[2:, 1] = h[1] + 0.1
    for i, up in zip(range(1, 12), [1, 1, 0, 1, 0, 1, 0, 1, 1, 1, 1]):
        rises[i, 0] = h[0] + (0.1 if up else -0.1)
    chatter = {"combination": "2", "d": d, "rises": rises.tolist(), "units": [0, 1], "types": [0, 1],
               "unloading": [0] * 12}
    assert fs.ring_states(chatter)[:4].tolist() == [[0, 0], [1, 0], [1, 1], [0, 1]]
    text = fs.events_text(fs.ring_events(chatter))
    assert text == "ring 0 snaps at d/L 0.100, ring 1 snaps at 0.200, ring 0 back and forth 6 times from 0.300 to 0.800"


@needs_ccx
def test_tiny_stack_acts_as_two_rings_in_series():
    """Static, to d/L 0.02 in two increments (about a minute): the stack's force is each of its rings' own (run
    alone, the same solid, the same plate) at the rise the middle plate gives that ring - the two share their force
    and add their rises, as springs in series (to 1 %: the stacked ring's ends are held by a plate that tilts
    with the other ring)."""
    a, b = combination_cells("2")
    seen = {}
    run = ccx.run

    def keep(deck, *args, **kw):
        seen["tables"], info = run(deck, *args, **kw)
        return seen["tables"], info
    import unittest.mock
    with unittest.mock.patch.object(ccx, "run", keep):
        c, info = sleeve3d_stack.solve_stack3d([a, b], 4, 1, d_max=0.02 * a.L, increments=2, method="static",
                                               unload=False, partial=False)
    # a .dat read while ccx still writes it (its last increment's watched nodes not yet printed): the points
    # every table holds, the same numbers
    tables = dict(seen["tables"])
    tables[("displacements", "WATCH")] = tables[("displacements", "WATCH")][:-1]
    _, meta = sleeve3d_stack.stack_deck3d([a, b], 4, 1, d_max=0.02 * a.L, increments=2, method="static",
                                          unload=False, watch="ends")
    live = sleeve3d_stack.read_stack(tables, meta)
    assert len(live["d"]) == len(c["d"]) - 1 and np.allclose(live["rises"], c["rises"][:-1])
    assert np.allclose(live["F"], c["F"][:-1])
    assert info["d_reached"] == pytest.approx(0.02) and c["ring_rises"].shape == (3, 2)
    assert c["ring_rises"][-1].sum() == pytest.approx(0.02, rel=1e-9)
    assert np.all(c["ring_rises"][-1] > 0.004)                        # both rings take part of the rise
    F = c["F"][-1]
    for k, g in enumerate((a, b)):
        alone, _ = sleeve3d.solve_ring3d(g, 4, 1, 1, d_max=0.02 * g.L, increments=2, element="C3D20",
                                         partial=False)
        own = np.interp(c["ring_rises"][-1, k], alone["d"], alone["F"])
        assert own == pytest.approx(F, rel=0.01)
    assert c["rises"].shape == (3, 16) and set(c["types"].tolist()) == {0, 1}
    assert np.all(c["rises"][-1] > 0) and np.all(c["rises"][-1] < 0.01)     # no half has snapped this low


def test_stored_stacked_solids_act_in_series_in_the_rules_order():
    """The stored runs (``bench_sleeve_ring3d.py --stacked-solid``, r = 1 and 2, implicit dynamics). Each stack's peaks
    on loading are its two rings' own first peaks (each ring run alone on the same mesh) and its valleys the
    first-snapping ring's and the higher of the two, to 0.5 %: two hysterons in series, as the frame's stack. Both
    combinations snap loading in the two-hysteron order on those thresholds; combination 1 comes back down in the
    rule's (and the seed's) symmetric order; combination 2's run, where stored as stopped, says why. The docs'
    table is the report's of these runs."""
    import json
    import os
    from metamaterial_wb.bench.fe_ring3d_combinations import seed_order, solid_rule
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    raw = json.load(open(os.path.join(root, "benchmarks", "results", "fe-ring3d.json")))
    stacked, solid, attempts = raw["stacked_solid"], raw["combinations"], raw.get("stacked_solid_attempts", {})
    assert set(stacked) == {"1", "2"}
    for key, runs in stacked.items():
        for mesh, run in [(m, r) for m in runs for r in [runs[m]] + attempts.get(key, {}).get(m, [])]:
            rule = solid_rule(solid[key][mesh])
            dp, dv = fs.series_check(run, solid[key][mesh])
            assert dp < 0.005 and dv < 0.005, (key, mesh, dp, dv)
            events = fs.ring_events(run)
            assert [(j, what) for _, _, j, what in events[:2]] == [(rule["loading"][0], "snaps"),
                                                                   (rule["loading"][1], "snaps")]
            seq = fs.stack_sequence(run)
            assert not run["stopped"] or run["note"]                        # a run stopped by hand says why
            if seq is None:
                assert run["stopped"] and not any(run["unloading"])
            else:
                assert [seq["loading"], seq["unloading"]] == [rule["loading"], rule["unloading"]], key
                assert run["stopped"] or run["d_reached"] == pytest.approx(0.0, abs=1e-9)
    seq = fs.stack_sequence(stacked["1"]["r1"])
    assert (seq["loading"], seq["unloading"], seq["symmetric"]) == tuple(seed_order("1").values())
    frame = json.load(open(os.path.join(root, "benchmarks", "results", "frame3d.json")))["stacked"]
    text = fs.stacked_solid_markdown(stacked, solid, frame, attempts)
    assert "| 1 | r = 1, undamped | [0, 1] \\| [1, 0] (symmetric) | ring 0 snaps at d/L 0.380" in text
    assert text in open(os.path.join(root, "docs", "sleeves.md")).read()
    assert os.path.exists(os.path.join(root, "docs", fs.IMG))
