"""Placement search: which joints get the N servos (greedy forward selection with swaps).

Every candidate placement is an independent evaluation, so the search is written as rounds of
batches handed to a *mapper* ``mapper(fn, problem, batches) -> [fn(problem, batch), ...]``: serial by
default (:func:`serial_map`), a process pool or a Dask cluster through ``metamaterial_wb.parallel``.
The results do not depend on the mapper or the batching (each evaluation is deterministic and runs with
one BLAS thread wherever it runs, ties are broken by the candidate order), which the tests check on a
Dask ``LocalCluster`` and a spawned process pool.

Round structure:

0. **Linearised stage** (default): the free field D* (every node's D free) that best reaches the target
   and the Gauss-Newton metric there turn every placement's cost into a small dense least squares
   ``min_v |B (D0 + G v - D*)|^2``; a beam search (greedy forward selection keeping the ``beam`` best
   partial placements) plus swaps runs on it, and the ``screen`` best placements found get full
   nonlinear fits. The free field's cost is a lower bound of every placement's: a placement that
   reaches it ends the search.
1. **Greedy forward selection** (``strategy="greedy"``): with k servos placed and fitted, every compatible joint is tried as
   servo k + 1. A *screen* ranks all of them by the cost one Gauss-Newton step would reach from the
   warm start (exact Jacobian of the enlarged placement, response by a rank-2 update of the placed
   model's factor: two back-substitutions per candidate); the ``screen`` best get a full values fit,
   and the best fit wins (``screen=0``: full fits for every candidate).
2. **Swaps**: every (placed servo, other joint) exchange is screened and the best candidates fully
   fitted; the best improving swap is applied; repeat until no swap improves the cost by more than
   ``rel_tol``.
3. **Finalists**: the search's fits are capped (40 evaluations), so they rank placements only roughly; the
   ``finalists`` best placements of the linearised stage's full fits travel with the result
   (``SearchResult.finalists``) and ``pipeline.converge`` fits them to convergence with the answer (the lowest
   converged cost wins, :func:`converge_batch`).

Compatibility: a servo fixes D of both nodes of its joint, so two servos (or a servo and an angular
constraint) may not share a node; forbidden joints are never used.
"""
import functools
import itertools
import time
from dataclasses import dataclass, field

import numpy as np

from metamaterial_wb.core.errors import SceneError


def serial_map(fn, problem, batches):
    return [fn(problem, b) for b in batches]


def one_blas_thread(fn, problem, batch):
    """``fn(problem, batch)`` with one BLAS thread: a multi-threaded BLAS sums in another order than a
    single-threaded one (Dask workers and spawned pool workers may run with one thread, the calling
    process with several), and a last-bit difference can send an optimiser down another path. With one
    thread everywhere every mapper gives bitwise the local answer."""
    from metamaterial_wb.core.threads import blas_threads
    with blas_threads(1):
        return fn(problem, batch)


def _chunks(items, n):
    n = max(1, int(n))
    size = max(1, -(-len(items) // n))
    return [items[i:i + size] for i in range(0, len(items), size)]


# ----------------------------------------------------------------------------------------------
# evaluations (top-level functions: picklable for process pools and Dask)
# ----------------------------------------------------------------------------------------------
SEARCH_TOL = 1e-7       # relative cost change that ends a candidate's fit (the final fit uses 1e-15)
COST_FLOOR = 1e-9       # mm^2: costs below this are zero to the fits' round-off (positions to about 3e-5 mm)
FINALISTS = 6           # placements of the linearised stage's full fits that are also fitted to convergence


def below_bound(cost, bound):
    """True where ``cost`` lies below the free-field lower bound ``bound`` by more than 1e-6 of it and the
    round-off floor (``COST_FLOOR``): then the free field did not converge and ``bound`` is no bound. Two costs
    at round-off level (e.g. 7e-12 and 8e-12 mm^2: both exact fits) are not."""
    return cost < bound * (1.0 - 1e-6) - COST_FLOOR


def at_bound(cost, bound):
    """True where ``cost`` reaches the lower bound ``bound``: at most 1e-6 of it or the round-off floor above it
    (a cost below it is caught first by ``below_bound``)."""
    return cost <= bound * (1.0 + 1e-6) + COST_FLOOR


def fit_batch(problem, batch):
    """Full values fits. ``batch``: list of ``(joints, v0 (frames, servos) or None)`` ->
    list of ``(cost, values (frames, servos), nfev)``."""
    out = []
    for joints, v0 in batch:
        fr = problem.fit(joints, v0=v0, tol=SEARCH_TOL, max_nfev=40)
        out.append((fr.cost, fr.values, fr.nfev))
    return out


def converge_batch(problem, batch):
    """Fits to convergence. ``batch``: ``(max_nfev, [(joints, v0 (frames, servos))])`` -> list of FitResult."""
    max_nfev, items = batch
    return [problem.fit(joints, v0=v0, max_nfev=max_nfev) for joints, v0 in items]


def screen_batch(problem, batch):
    """Predicted costs after one Gauss-Newton step. ``batch``: ``(base_joints, base_values (frames, k),
    base_xi [frames], [(candidate joint, start value per frame)])`` -> list of predicted costs."""
    base, vb, xib, cands = batch
    state = problem.base_state(base)
    out = []
    for c, start in cands:
        resp = problem.added_response(state, c)
        if resp is None:
            D0, G = problem.response(tuple(base) + (c,))
        else:
            D0, G = resp
        total = 0.0
        for fi in range(len(problem.frames)):
            v = np.concatenate([np.asarray(vb[fi], dtype=float), [start[fi]]])
            R0, xi = xib[fi]
            r, Jv, Jx, _ = problem.frame_residual(fi, v, xi, R0, D0, G)
            J = np.hstack([Jv, Jx])
            coef, *_ = np.linalg.lstsq(J, r, rcond=None)
            rp = r - J @ coef
            total += 0.5 * float(rp @ rp)
        out.append(total)
    return out


def lin_cost(fields, D0, G):
    """Linearised cost ``sum_frames min_v |B (D0 + G v - D*)|^2`` and the values (frames, servos)."""
    total, vs = 0.0, []
    for Ds, W, _c, _ok in fields:
        e0 = D0 - Ds
        WG = W @ G
        A = G.T @ WG
        b = WG.T @ e0
        try:
            v = -np.linalg.solve(A + 1e-14 * np.trace(A) * np.eye(len(A)), b) if len(A) else np.zeros(0)
        except np.linalg.LinAlgError:
            v = -np.linalg.lstsq(A, b, rcond=None)[0]
        v = np.clip(v, -1.0, 1.0)
        e = e0 + G @ v
        total += float(e @ (W @ e))
        vs.append(v)
    return total, np.array(vs)


def lin_batch(problem, batch):
    """Linearised costs of ``placed + (c,)`` for the candidates c of ``batch = (placed, cands)``:
    ``[(cost, values (frames, servos))]``. Responses by rank-2 updates of the placed model, all
    candidates at once (one multi-right-hand-side back-substitution, batched 2 x 2 and N x N solves);
    candidates touching a node outside the placed model's free set fall back to a fresh model."""
    placed, cands = batch
    state = problem.base_state(placed)
    model, where = state["model"], state["where"]
    n = problem.topo.n_nodes
    if model.fixed.size == 0 and np.all(problem.k1 < 1.0):
        # nothing fixed yet: every node is free, H itself is SPD (k1 < 1), the first servo is a rank-2 step
        import scipy.sparse.linalg as spla

        from metamaterial_wb.core.solver import assemble_hessian
        lu = spla.splu(assemble_hessian(n, problem.topo.joint_pairs, problem.k1, problem.k2).tocsc())
        model = type("_Free", (), {"free": np.arange(n), "_factor": type("_F", (), {"solve": staticmethod(lu.solve)})})
        where = np.arange(n)
    ab = np.array([problem._joint_nodes(c) for c in cands], dtype=np.int64).reshape(-1, 2)
    ok = np.all(where[ab] >= 0, axis=1)
    out = [None] * len(cands)
    for k in np.flatnonzero(~ok):
        D0, G = problem.response(tuple(placed) + (cands[k],))
        out[k] = lin_cost(problem.fields, D0, G)
    idx = np.flatnonzero(ok)
    if idx.size:
        nf = model.free.size
        ia, ib = where[ab[idx, 0]], where[ab[idx, 1]]
        # one two-column back-substitution per candidate (not one for the batch): the result must not
        # depend on how candidates are batched (a multi-column solve rounds differently)
        X = np.empty((idx.size, nf, 2))
        for q in range(idx.size):
            E = np.zeros((nf, 2))
            E[ia[q], 0] = E[ib[q], 1] = 1.0
            X[q] = np.asarray(model._factor.solve(E)).reshape(nf, 2)
        kk = np.arange(idx.size)
        S = np.stack([X[kk, ia], X[kk, ib]], axis=1)                                           # (k, 2, 2)
        det = S[:, 0, 0] * S[:, 1, 1] - S[:, 0, 1] * S[:, 1, 0]
        Sinv = np.stack([np.stack([S[:, 1, 1], -S[:, 0, 1]], 1), np.stack([-S[:, 1, 0], S[:, 0, 0]], 1)], 1)
        K = X @ (Sinv / det[:, None, None])                                                    # X S^-1
        Kfull = np.zeros((idx.size, n, 2))
        Kfull[:, model.free] = K
        M = np.column_stack([state["D0"], state["G"]])                                         # (n, 1 + ns)
        Mab = np.stack([M[ab[idx, 0]], M[ab[idx, 1]]], axis=1)                                 # (k, 2, 1 + ns)
        Mk = M[None] - Kfull @ Mab
        col = Kfull.sum(axis=2)
        Mk[kk, ab[idx, 0]] = 0.0
        Mk[kk, ab[idx, 1]] = 0.0
        col[kk, ab[idx, 0]] = 1.0
        col[kk, ab[idx, 1]] = 1.0
        D0s = Mk[:, :, 0]
        Gs = np.concatenate([Mk[:, :, 1:], col[:, :, None]], axis=2)                           # (k, n, ns)
        costs = np.zeros(idx.size)
        vals = []
        for Ds, W, _c, _ok in problem.fields:
            e0 = D0s - Ds[None]
            WG = W @ Gs                                                   # (k, n, ns), BLAS per batch
            A = np.swapaxes(Gs, 1, 2) @ WG
            b = (np.swapaxes(WG, 1, 2) @ e0[:, :, None])[:, :, 0]
            ns = A.shape[1]
            reg = 1e-14 * np.einsum("kss->k", A)[:, None, None] * np.eye(ns)[None]
            v = np.clip(-np.linalg.solve(A + reg, b[:, :, None])[:, :, 0], -1.0, 1.0)
            e = e0 + (Gs @ v[:, :, None])[:, :, 0]
            costs += np.sum((e @ W) * e, axis=1)
            vals.append(v)
        vals = np.stack(vals, axis=1)                                                          # (k, frames, ns)
        for q, k in enumerate(idx):
            out[k] = (float(costs[q]), vals[q])
    return out


def joints_text(topo):
    """The scene's joint names for a message: ``"32 joints, H0,0 .. H2,5, V0,0 .. V1,6"`` (per kind, the smallest
    and largest row and column)."""
    parts = [f"{topo.n_joints} joints"]
    for kind in ("H", "V"):
        ij = [tuple(int(x) for x in n[1:].split(",")) for n in topo.joint_names if n.startswith(kind)]
        if ij:
            i, j = zip(*ij)
            parts.append(f"{kind}{min(i)},{min(j)} .. {kind}{max(i)},{max(j)}")
    return ", ".join(parts)


@dataclass
class SearchResult:
    joints: tuple
    fit: object                        # FitResult of the final placement
    fits: int                          # full values fits evaluated
    screened: int                      # candidates screened (one Gauss-Newton step each)
    seconds: float
    history: list = field(default_factory=list)
    info: dict = field(default_factory=dict)   # linearised placements evaluated, free-field bound (mm^2)
    finalists: list = field(default_factory=list)   # [(joints, values)]: other placements to fit to convergence


class PlacementSearch:
    def __init__(self, problem, n_servos, forbidden=(), candidates=None, screen=12, mapper=None, workers=1,
                 progress=None, rel_tol=1e-9, max_swap_rounds=10, strategy="linearised", beam=8,
                 finalists=FINALISTS):
        if strategy not in ("linearised", "greedy"):
            raise SceneError("strategy", f"{strategy!r}; allowed: linearised, greedy")
        self.strategy = strategy
        self.beam = max(1, int(beam))
        self.n_finalists = max(0, int(finalists))
        self.runners_up = []               # the linearised stage's best full fits: [(joints, values)]
        self.lin_evaluated = 0
        self.lin_seconds = 0.0
        self.lower_bound = None
        self.pb = problem
        self.n = int(n_servos)
        topo = problem.topo
        forbidden = set(forbidden or ())
        for f in forbidden:
            if not topo.has_joint(f):
                raise SceneError("--forbid", f"joint {f!r} does not exist in this scene ({joints_text(topo)})")
        pool = list(topo.joint_names) if candidates is None else list(candidates)
        for c in pool:
            if not topo.has_joint(c):
                raise SceneError("candidates", f"joint {c!r} does not exist in this scene ({joints_text(topo)})")
        self.nodes = {j: set(problem._joint_nodes(j)) for j in pool}
        self.allowed = [j for j in pool if j not in forbidden and not (self.nodes[j] & problem.fixed_nodes)]
        most = self._max_independent()      # the scene's real limit: joints without a shared node
        if most < 1:
            raise SceneError("--servos", f"{self.n}: no joint can take a servo (every joint is forbidden or at a "
                                         f"constrained node)")
        if self.n < 1:
            raise SceneError("--servos", f"{self.n} is outside the allowed range [1, {most}] (at most {most} joints "
                                         f"without a shared node; forbidden joints and constraints removed)")
        if self.n > most:
            raise SceneError("--servos", f"{self.n} servos do not fit: {self.n} is outside the allowed range "
                                         f"[1, {most}] (at most {most} joints without a shared node are allowed; "
                                         f"forbidden joints and constraints removed)")
        self.screen = int(screen)
        base_map = mapper or serial_map
        # every evaluation with one BLAS thread, wherever it runs (:func:`one_blas_thread`)
        self.map = lambda fn, pb, batches: base_map(functools.partial(one_blas_thread, fn), pb, batches)
        self.workers = max(1, int(workers))
        self.progress = progress or (lambda msg: None)
        self.rel_tol = rel_tol
        self.max_swap_rounds = max_swap_rounds
        self.fits = 0
        self.screened = 0
        self.history = []

    def _max_independent(self):
        used, count = set(), 0
        for j in self.allowed:          # a greedy matching: enough to tell "impossible" in practice
            if not (self.nodes[j] & used):
                used |= self.nodes[j]
                count += 1
        return count

    def compatible(self, joint, placed):
        return joint not in placed and all(not (self.nodes[joint] & self.nodes[p]) for p in placed)

    # -- parallel rounds -----------------------------------------------------------------------
    def _fit_many(self, tasks):
        if not tasks:
            return []
        res = self.map(fit_batch, self.pb, _chunks(tasks, 4 * self.workers if self.workers > 1 else 1))
        self.fits += len(tasks)
        return [x for part in res for x in part]

    def _screen_many(self, groups):
        """``groups``: list of (base, vb, xib, [(cand, start)]) -> flat list of predicted costs."""
        batches = []
        for base, vb, xib, cands in groups:
            for ch in _chunks(cands, 2 * self.workers if self.workers > 1 else 1):
                batches.append((base, vb, xib, ch))
        res = self.map(screen_batch, self.pb, batches)
        self.screened += sum(len(b[3]) for b in batches)
        return [x for part in res for x in part]

    def _best_of(self, placements, warm, preds=None):
        """Fully fit the ``screen`` best placements (all without a screen); return the best."""
        order = list(range(len(placements)))
        if preds is not None and self.screen > 0 and len(order) > self.screen:
            order = sorted(order, key=lambda i: (preds[i], i))[:self.screen]
            order.sort()
        res = self._fit_many([(placements[i], warm[i]) for i in order])
        k = min(range(len(order)), key=lambda q: (res[q][0], order[q]))
        return placements[order[k]], res[k]

    # -- stage 1: the linearised placement problem ---------------------------------------------
    def _lin_many(self, bases):
        """The linearised candidates of several base placements, mapped in batches."""
        batches = []
        for placed in bases:
            cands = [c for c in self.allowed if self.compatible(c, placed)]
            for ch in _chunks(cands, 2 * self.workers if self.workers > 1 else 1):
                batches.append((tuple(placed), ch))
        res = self.map(lin_batch, self.pb, batches)
        out = {}
        for (placed, ch), part in zip(batches, res):
            for c, cv in zip(ch, part):
                out[placed + (c,)] = cv
        return out

    def linearised_stage(self):
        """Greedy + swaps on the linearised cost ``sum_frames min_v |B (D(v) - D*)|^2`` (D* the free-field
        optimum, B its Gauss-Newton factor): every evaluation a small dense least squares."""
        self.fields = [self.pb.free_field(fi) for fi in range(len(self.pb.frames))]
        self.pb.fields = self.fields          # travels with the problem to the workers (set before any map)
        # a bound only where every frame's free field converged (a fit stopped at its evaluation limit is not
        # the optimum: the gripper's cylinder stopped at 25.56 mm^2 where 8.9 is reached, below its answer)
        self.lower_bound = sum(c for _, _, c, _ok in self.fields)
        if not all(ok for *_, ok in self.fields):
            self.progress(f"the free field stopped at its evaluation limit (cost {self.lower_bound:.6g} mm^2): "
                          f"no lower bound")
            self.lower_bound = None
        seen = {}
        beam = [()]
        for _ in range(self.n):            # beam search: keep the ``beam`` best partial placements
            pool = {}
            for q, cv in self._lin_many(beam).items():
                key = tuple(sorted(q))
                if key not in pool or cv[0] < pool[key][1][0]:
                    pool[key] = (q, cv)
            seen.update({q: cv for q, cv in pool.values()})
            ranked_step = sorted(pool.values(), key=lambda t: (t[1][0], t[0]))
            beam = [q for q, _cv in ranked_step[:self.beam]]
        starts = [beam[0]]
        fp = self._force_placement()
        if fp is not None:
            D0, G = self.pb.response(fp)
            seen[fp] = lin_cost(self.fields, D0, G)
            starts.append(fp)
        finals = [self._lin_swaps(p0, seen) for p0 in starts]
        placed, cost = min(finals, key=lambda t: (t[1], t[0]))
        self.lin_evaluated = len(seen)
        canon = {}
        for q, (cq, vq) in seen.items():
            if len(q) == self.n:
                key = tuple(sorted(q))
                if key not in canon or cq < canon[key][1]:
                    canon[key] = (q, cq, vq)
        ranked = sorted(canon.values(), key=lambda t: (t[1], t[0]))
        self.progress(f"linearised search: {', '.join(placed)} (linearised cost {cost:.6g}; "
                      f"{len(seen)} placements evaluated; "
                      + (f"free-field bound {self.lower_bound:.6g} mm^2)" if self.lower_bound is not None
                         else "no free-field bound)"))
        return ranked

    def _force_placement(self):
        """Where the free field's sources are: a servo is the only place where the equilibrium
        ``(H D)_i = 0`` of a free node fails, so the joints whose nodes carry the largest residual
        force ``|H D*|`` (summed over frames) are picked, compatible ones in order."""
        from metamaterial_wb.core.solver import assemble_hessian
        H = assemble_hessian(self.pb.topo.n_nodes, self.pb.topo.joint_pairs, self.pb.k1, self.pb.k2)
        force = sum(np.abs(H @ Ds) for Ds, _W, _c, _ok in self.fields)
        score = {j: sum(force[n] for n in self.nodes[j]) for j in self.allowed}
        placed = ()
        for j in sorted(self.allowed, key=lambda j: (-score[j], self.allowed.index(j))):
            if self.compatible(j, placed):
                placed += (j,)
                if len(placed) == self.n:
                    return placed
        return None

    def _lin_swaps(self, placed, seen):
        cost = seen[placed][0]
        for _ in range(4 * self.n + 10):
            best, bcost = None, cost
            cand = self._lin_many([placed[:p] + placed[p + 1:] for p in range(len(placed))])
            seen.update(cand)
            for q, (cq, _v) in cand.items():
                if cq < bcost * (1.0 - 1e-12) - 1e-300:
                    best, bcost = q, cq
            if best is None:
                break
            placed, cost = best, bcost
        return placed, cost

    # -- the search ------------------------------------------------------------------------------
    def run(self):
        t0 = time.perf_counter()
        nf = len(self.pb.frames)
        placed, values, cost = (), np.zeros((nf, 0)), None
        if self.strategy == "linearised":
            tl = time.perf_counter()
            ranked = self.linearised_stage()[:max(1, self.screen or 1)]
            self.lin_seconds = time.perf_counter() - tl
            res = self._fit_many([(q, vq) for q, _c, vq in ranked])
            order = sorted(range(len(ranked)), key=lambda i: (res[i][0], i))
            k = order[0]
            placed, (cost, values, _n) = ranked[k][0], res[k]
            self.runners_up = [(ranked[i][0], res[i][1]) for i in order[:self.n_finalists]]
            self.history.append({"step": "linearised", "joints": list(placed), "cost": cost})
            self.progress(f"best of {len(ranked)} linearised placements: {', '.join(placed)} (cost {cost:.6g} mm^2)")
        for step in range(self.n if self.strategy == "greedy" else 0):
            cands = [c for c in self.allowed if self.compatible(c, placed)]
            placements = [placed + (c,) for c in cands]
            warm = [np.hstack([values, np.zeros((nf, 1))]) for _ in cands]
            preds = None
            if self.screen > 0 and len(cands) > self.screen:
                xib = self._alignments(placed, values)
                preds = self._screen_many([(placed, values, xib, [(c, np.zeros(nf)) for c in cands])])
            placed, (cost, values, _nfev) = self._best_of(placements, warm, preds)
            self.history.append({"step": f"add {step + 1}", "joints": list(placed), "cost": cost})
            self.progress(f"servo {step + 1}/{self.n}: {', '.join(placed)} (cost {cost:.6g} mm^2, "
                          f"{self.fits} fits, {self.screened} screened)")
        for rnd in range(self.max_swap_rounds):
            if self.lower_bound is not None and below_bound(cost, self.lower_bound):
                self.progress(f"the free field did not converge (cost {self.lower_bound:.6g} above a placement's "
                              f"{cost:.6g}): it is no bound")
                self.lower_bound = None
            if self.lower_bound is not None and at_bound(cost, self.lower_bound):
                self.progress("cost at the free-field lower bound: no swap can improve it")
                break
            placements, warm, groups = [], [], []
            for p in range(len(placed)):
                rest = placed[:p] + placed[p + 1:]
                vrest = np.delete(values, p, axis=1)
                cands = [c for c in self.allowed if self.compatible(c, rest) and c != placed[p]]
                for c in cands:
                    placements.append(rest + (c,))
                    warm.append(np.hstack([vrest, values[:, p:p + 1]]))
                if self.screen > 0:
                    groups.append((rest, vrest, self._alignments(rest, vrest), [(c, values[:, p]) for c in cands]))
            if not placements:
                break
            preds = self._screen_many(groups) if self.screen > 0 and len(placements) > self.screen else None
            best, (bcost, bvalues, _n) = self._best_of(placements, warm, preds)
            if bcost < cost * (1.0 - self.rel_tol) and set(best) != set(placed):
                placed, values, cost = best, bvalues, bcost
                self.history.append({"step": f"swap {rnd + 1}", "joints": list(placed), "cost": cost})
                self.progress(f"swap round {rnd + 1}: {', '.join(placed)} (cost {cost:.6g} mm^2)")
            else:
                self.progress(f"swap round {rnd + 1}: no improving swap")
                break
        placed, values = self._in_scene_order(placed, values)
        finalists = [self._in_scene_order(q, v) for q, v in self.runners_up if set(q) != set(placed)]
        fit = self.pb.fit(placed, v0=values, starts=(0.0, 0.5, -0.5))
        self.fits += 1
        if self.lower_bound is not None and below_bound(fit.cost, self.lower_bound):
            self.progress(f"the free field did not converge (cost {self.lower_bound:.6g} above the answer's "
                          f"{fit.cost:.6g}): it is no bound")
            self.lower_bound = None
        return SearchResult(tuple(placed), fit, self.fits, self.screened, time.perf_counter() - t0, self.history,
                            {"linearised": self.lin_evaluated, "lower_bound": self.lower_bound,
                             "linearised_s": self.lin_seconds}, finalists)

    def _in_scene_order(self, placed, values):
        """``(joints, values)`` with the joints in the scene's joint order (the values' columns with them)."""
        order = sorted(range(len(placed)), key=lambda i: self.pb.topo.joint_names.index(placed[i]))
        return tuple(placed[i] for i in order), np.asarray(values)[:, order]

    def _alignments(self, placed, values):
        """Per frame, the alignment parameters of the warm start (for the screen)."""
        D0, G = self.pb.response(placed)
        out = []
        for fi, fr in enumerate(self.pb.frames):
            pos = self.pb.kin.poses(np.clip(D0 + G @ values[fi], -1, 1))[0]
            out.append(fr.initial_alignment(pos))
        return out


def search_placement(problem, n_servos, **kw):
    return PlacementSearch(problem, n_servos, **kw).run()


def exhaustive_batch(problem, batch):
    starts, combos = batch
    return [problem.fit(c, starts=starts, tol=SEARCH_TOL).cost for c in combos]


def exhaustive(problem, n_servos, forbidden=(), mapper=None, workers=1, starts=(0.5, -0.5)):
    """Every compatible placement fitted from the starts 0 and ``starts`` (small sheets only):
    ``(best joints, best cost, {placement: cost})``."""
    s = PlacementSearch(problem, n_servos, forbidden, screen=0, mapper=mapper, workers=workers)
    combos = [c for c in itertools.combinations(s.allowed, s.n)
              if all(not (s.nodes[a] & s.nodes[b]) for a, b in itertools.combinations(c, 2))]
    res = s.map(exhaustive_batch, problem, [(starts, ch) for ch in _chunks(combos, 4 * s.workers)])
    flat = [x for part in res for x in part]
    costs = dict(zip(combos, flat))
    best = min(combos, key=lambda c: (costs[c], combos.index(c)))
    return best, costs[best], costs
