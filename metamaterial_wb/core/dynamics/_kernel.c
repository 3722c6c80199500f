/* Compiled kernel of the planar dynamics (see fastkernel.py, which compiles this file with the
 * system C compiler at first use into a per-user cache directory and loads it with ctypes).
 *
 * It evaluates exactly the equations of system.py (PlanarSystem.forces, _hinge_blocks,
 * _contact_blocks, band_system_matrix) and runs the Newton loop of Simulator.step_implicit
 * (integrators.py) with the same convergence test, the same Jacobian-reuse rules and the same
 * statistics; only the order of floating-point sums and the LU implementation (a band LU with
 * partial pivoting, the algorithm of LAPACK dgbtf2 / dgbtrs) differ, i.e. round-off.
 *
 * Matrix layout: the Newton matrix A = M - h dQ/dv - h^2 dQ/dq is stored in LAPACK band storage
 * (column major, leading dimension ldab = 2 kl + ku + 1, A[i][j] at ab[kl + ku + i - j + j * ldab])
 * in a permuted dof order chosen by Python (reverse Cuthill-McKee for chains and rings; the natural
 * order with kl = ku = N - 1 for small general systems). hmap / cmap / dmap give, for each hinge block
 * entry (6 x 6), contact block entry (3 x 3) and diagonal entry, its index in ab (-1: dropped because
 * it touches a fixed dof).
 */
#include <math.h>
#include <string.h>
#include <stdint.h>

typedef struct {
    int64_t n, m, p;                 /* bodies, hinges, contacts */
    const double *M;                 /* (n, 3) mass, mass, inertia */
    const double *gravity;           /* (2) */
    const uint8_t *free_dof;         /* (3n) */
    const int64_t *ha, *hb, *cb;
    const double *ra, *rb, *kp, *cp, *kr, *cr, *theta0;     /* hinges */
    const double *rc, *mu, *kn, *cn, *kt, *ct;               /* contacts */
    int64_t N, kl, ku, ldab;
    const int64_t *hmap, *cmap, *dmap, *perm;                /* (m*36), (p*9), (N), (N) */
    /* workspace (owned by Python, sizes: N, N, p each, ldab*N) */
    double *Q, *R, *dv, *x;
    double *cth, *sth;               /* (n) cos / sin of the body angles at the last evaluation */
    double *ux, *uy, *fn, *ft, *sgn;
    uint8_t *inside, *stick, *pushing;
    /* factorisation state */
    double *lu;                      /* ldab * N */
    int64_t *ipiv;                   /* N */
    uint8_t *f_push, *f_stick;       /* (p) flags the factorisation was built with */
    int64_t f_valid, f_age, f_singular;
    double f_h;
} Sys;

/* ----------------------------------------------------------------------------------------- */
/* forces: Q (n*3), the contact state, returns the damper power                                */
/* ----------------------------------------------------------------------------------------- */
double mm_forces(Sys *S, const double *q, const double *v, const double *anchors, double *Q)
{
    int64_t n = S->n, m = S->m, p = S->p, i;
    double damp = 0.0, damp_r = 0.0;
    const double *cth = S->cth, *sth = S->sth;
    for (i = 0; i < n; i++) {
        S->cth[i] = cos(q[3 * i + 2]);
        S->sth[i] = sin(q[3 * i + 2]);
        Q[3 * i] = S->M[3 * i] * S->gravity[0];
        Q[3 * i + 1] = S->M[3 * i + 1] * S->gravity[1];
        Q[3 * i + 2] = 0.0;
    }
    for (i = 0; i < m; i++) {
        int64_t a = S->ha[i], b = S->hb[i];
        double tha = q[3 * a + 2], thb = q[3 * b + 2];
        double ca = cth[a], sa = sth[a], cb = cth[b], sb = sth[b];
        double rax = S->ra[2 * i], ray = S->ra[2 * i + 1], rbx = S->rb[2 * i], rby = S->rb[2 * i + 1];
        double Rax = ca * rax - sa * ray, Ray = sa * rax + ca * ray;
        double Rbx = cb * rbx - sb * rby, Rby = sb * rbx + cb * rby;
        double wa = v[3 * a + 2], wb = v[3 * b + 2];
        double dx = q[3 * b] + Rbx - q[3 * a] - Rax;
        double dy = q[3 * b + 1] + Rby - q[3 * a + 1] - Ray;
        double vdx = v[3 * b] - wb * Rby - v[3 * a] + wa * Ray;
        double vdy = v[3 * b + 1] + wb * Rbx - v[3 * a + 1] - wa * Rax;
        double fx = -S->kp[i] * dx - S->cp[i] * vdx;
        double fy = -S->kp[i] * dy - S->cp[i] * vdy;
        double dw = wb - wa;
        double tr = -S->kr[i] * (thb - tha - S->theta0[i]) - S->cr[i] * dw;
        damp += S->cp[i] * (vdx * vdx + vdy * vdy);
        damp_r += S->cr[i] * (dw * dw);
        Q[3 * b] += fx;
        Q[3 * a] -= fx;
        Q[3 * b + 1] += fy;
        Q[3 * a + 1] -= fy;
        Q[3 * b + 2] += Rbx * fy - Rby * fx + tr;
        Q[3 * a + 2] += Ray * fx - Rax * fy - tr;
    }
    for (i = 0; i < p; i++) {
        int64_t c = S->cb[i];
        double cc = cth[c], sc = sth[c];
        double rcx = S->rc[2 * i], rcy = S->rc[2 * i + 1];
        double ux = cc * rcx - sc * rcy, uy = sc * rcx + cc * rcy;
        double w = v[3 * c + 2];
        double px = q[3 * c] + ux, py = q[3 * c + 1] + uy;
        double vpx = v[3 * c] - w * uy, vpy = v[3 * c + 1] + w * ux;
        int ins = py < 0;
        double fn = 0.0, ft = 0.0;
        if (ins) {
            fn = -S->kn[i] * py - S->cn[i] * vpy;
            if (!(fn > 0.0)) fn = 0.0;          /* np.maximum(0, x): x if x > 0 (NaN propagates) */
            if (isnan(-S->kn[i] * py - S->cn[i] * vpy)) fn = NAN;
        }
        double trial = -S->kt[i] * (px - anchors[i]) - S->ct[i] * vpx;
        double cap = S->mu[i] * fn;
        int stk = fabs(trial) <= cap;
        double sg = (trial > 0) ? 1.0 : ((trial < 0) ? -1.0 : (isnan(trial) ? NAN : 0.0));
        if (ins) ft = stk ? trial : sg * cap;
        S->ux[i] = ux;
        S->uy[i] = uy;
        S->fn[i] = fn;
        S->ft[i] = ft;
        S->sgn[i] = sg;
        S->inside[i] = (uint8_t)ins;
        S->stick[i] = (uint8_t)stk;
        S->pushing[i] = (uint8_t)(ins && fn > 0.0);
        Q[3 * c] += ft;
        Q[3 * c + 1] += fn;
        Q[3 * c + 2] += ux * fn - uy * ft;
    }
    return damp + damp_r;
}

/* ----------------------------------------------------------------------------------------- */
/* Newton matrix A = M - h dQ/dv - h^2 dQ/dq in band storage (ab, ldab * N), at (q, v) and the  */
/* contact state of the last mm_forces call                                                     */
/* ----------------------------------------------------------------------------------------- */
static void assemble(Sys *S, const double *q, const double *v, double h, double *ab, int trig_ready)
{
    int64_t m = S->m, p = S->p, N = S->N, i, r, c;
    double h2 = h * h;
    double *cth = S->cth, *sth = S->sth;
    if (!trig_ready)
        for (i = 0; i < S->n; i++) {
            cth[i] = cos(q[3 * i + 2]);
            sth[i] = sin(q[3 * i + 2]);
        }
    memset(ab, 0, sizeof(double) * S->ldab * N);
    for (i = 0; i < N; i++) {
        int64_t k = S->dmap[i];
        /* fixed dofs: identity rows */
        ab[k] += S->free_dof[i] ? S->M[i] : 1.0;
    }
    for (i = 0; i < m; i++) {
        int64_t a = S->ha[i], b = S->hb[i];
        double ca = cth[a], sa = sth[a], cb = cth[b], sb = sth[b];
        double rax = S->ra[2 * i], ray = S->ra[2 * i + 1], rbx = S->rb[2 * i], rby = S->rb[2 * i + 1];
        double Rax = ca * rax - sa * ray, Ray = sa * rax + ca * ray;
        double Rbx = cb * rbx - sb * rby, Rby = sb * rbx + cb * rby;
        double wa = v[3 * a + 2], wb = v[3 * b + 2];
        double kp = S->kp[i], cp = S->cp[i], kr = S->kr[i], cr = S->cr[i];
        double J[2][6] = {{-1.0, 0.0, Ray, 1.0, 0.0, -Rby}, {0.0, -1.0, -Rax, 0.0, 1.0, Rbx}};
        /* G: column 2 = wa Ra, column 5 = -wb Rb */
        double G2[2] = {wa * Rax, wa * Ray}, G5[2] = {-wb * Rbx, -wb * Rby};
        double dx = q[3 * b] + Rbx - q[3 * a] - Rax;
        double dy = q[3 * b + 1] + Rby - q[3 * a + 1] - Ray;
        double vdx = v[3 * b] + wb * (-Rby) - v[3 * a] - wa * (-Ray);
        double vdy = v[3 * b + 1] + wb * Rbx - v[3 * a + 1] - wa * Rax;
        double fx = -kp * dx - cp * vdx, fy = -kp * dy - cp * vdy;
        double K[6][6], C[6][6];
        _Pragma("GCC unroll 6") for (r = 0; r < 6; r++)
            _Pragma("GCC unroll 6") for (c = 0; c < 6; c++) {
                double jtj = J[0][r] * J[0][c] + J[1][r] * J[1][c];
                double jg = 0.0;
                if (c == 2) jg = J[0][r] * G2[0] + J[1][r] * G2[1];
                else if (c == 5) jg = J[0][r] * G5[0] + J[1][r] * G5[1];
                K[r][c] = -kp * jtj - cp * jg;
                C[r][c] = -cp * jtj;
            }
        K[2][2] += Rax * fx + Ray * fy;
        K[5][5] -= Rbx * fx + Rby * fy;
        K[5][5] -= kr; K[5][2] += kr; K[2][5] += kr; K[2][2] -= kr;
        C[5][5] -= cr; C[5][2] += cr; C[2][5] += cr; C[2][2] -= cr;
        const int64_t *mp = S->hmap + 36 * i;
        _Pragma("GCC unroll 6") for (r = 0; r < 6; r++)
            _Pragma("GCC unroll 6") for (c = 0; c < 6; c++) {
                int64_t k = mp[6 * r + c];
                if (k >= 0) ab[k] -= h * C[r][c] + h2 * K[r][c];
            }
    }
    for (i = 0; i < p; i++) {
        if (!(S->pushing[i] || S->ft[i] != 0.0 || S->fn[i] != 0.0)) continue;
        int64_t cbody = S->cb[i];
        double ux = S->ux[i], uy = S->uy[i], w = v[3 * cbody + 2];
        int push = S->pushing[i], stk = S->stick[i];
        double on = push ? 1.0 : 0.0, st_ = (push && stk) ? 1.0 : 0.0, sl = (push && !stk) ? 1.0 : 0.0;
        double Kl[2][2], Cl[2][2];
        Kl[1][1] = on * S->kn[i]; Cl[1][1] = on * S->cn[i];
        Kl[0][0] = st_ * S->kt[i]; Cl[0][0] = st_ * S->ct[i];
        Kl[0][1] = sl * S->mu[i] * S->sgn[i] * S->kn[i];
        Cl[0][1] = sl * S->mu[i] * S->sgn[i] * S->cn[i];
        Kl[1][0] = 0.0; Cl[1][0] = 0.0;
        double Jp[2][3] = {{1.0, 0.0, -uy}, {0.0, 1.0, ux}};
        double Dq[2][3] = {{0.0, 0.0, -w * ux}, {0.0, 0.0, -w * uy}};
        double KJ[2][3], CJ[2][3], CD[2][3];
        for (r = 0; r < 2; r++)
            for (c = 0; c < 3; c++) {
                KJ[r][c] = Kl[r][0] * Jp[0][c] + Kl[r][1] * Jp[1][c];
                CJ[r][c] = Cl[r][0] * Jp[0][c] + Cl[r][1] * Jp[1][c];
                CD[r][c] = Cl[r][0] * Dq[0][c] + Cl[r][1] * Dq[1][c];
            }
        const int64_t *mp = S->cmap + 9 * i;
        for (r = 0; r < 3; r++)
            for (c = 0; c < 3; c++) {
                double Kc = -(Jp[0][r] * (KJ[0][c] + CD[0][c]) + Jp[1][r] * (KJ[1][c] + CD[1][c]));
                double Cc = -(Jp[0][r] * CJ[0][c] + Jp[1][r] * CJ[1][c]);
                if (r == 2 && c == 2) Kc -= ux * S->ft[i] + uy * S->fn[i];
                int64_t k = mp[3 * r + c];
                if (k >= 0) ab[k] -= h * Cc + h2 * Kc;
            }
    }
}

void mm_assemble(Sys *S, const double *q, const double *v, double h, double *ab)
{
    assemble(S, q, v, h, ab, 0);
}

/* ----------------------------------------------------------------------------------------- */
/* band LU with partial pivoting (LAPACK dgbtf2) and solve (dgbtrs, no transpose)               */
/* ----------------------------------------------------------------------------------------- */
#define AB(i, j) ab[(kv + (i) - (j)) + (j) * ldab]

int64_t mm_gbtrf(int64_t n, int64_t kl, int64_t ku, double *ab, int64_t ldab, int64_t *ipiv)
{
    int64_t kv = ku + kl, i, j, info = 0, ju = 0;
    for (j = 0; j < n; j++) {
        int64_t km = kl < n - 1 - j ? kl : n - 1 - j, jp = 0;
        double big = fabs(AB(j, j));
        for (i = 1; i <= km; i++) {
            double t = fabs(AB(j + i, j));
            if (t > big) { big = t; jp = i; }
        }
        ipiv[j] = j + jp;
        if (AB(j + jp, j) != 0.0) {
            int64_t e = j + ku + jp < n - 1 ? j + ku + jp : n - 1;
            if (e > ju) ju = e;
            if (jp != 0) {
                for (int64_t c = j; c <= ju; c++) {
                    double t = AB(j + jp, c);
                    AB(j + jp, c) = AB(j, c);
                    AB(j, c) = t;
                }
            }
            if (km > 0) {
                double rp = 1.0 / AB(j, j);
                for (i = 1; i <= km; i++) AB(j + i, j) *= rp;
                const double *restrict l = &AB(j + 1, j);
                for (int64_t c = j + 1; c <= ju; c++) {
                    double u = AB(j, c);
                    double *restrict col = &AB(j + 1, c);
                    if (u != 0.0)
                        for (i = 0; i < km; i++) col[i] -= l[i] * u;
                }
            }
        } else if (info == 0) {
            info = j + 1;
        }
    }
    return info;
}

void mm_gbtrs(int64_t n, int64_t kl, int64_t ku, const double *ab, int64_t ldab, const int64_t *ipiv, double *b)
{
    int64_t kv = ku + kl, i, j;
    for (j = 0; j < n - 1; j++) {
        int64_t lm = kl < n - 1 - j ? kl : n - 1 - j, l = ipiv[j];
        if (l != j) { double t = b[l]; b[l] = b[j]; b[j] = t; }
        double bj = b[j];
        if (bj != 0.0)
            for (i = 1; i <= lm; i++) b[j + i] -= AB(j + i, j) * bj;
    }
    for (j = n - 1; j >= 0; j--) {
        if (b[j] != 0.0) {
            b[j] /= AB(j, j);
            double bj = b[j];
            int64_t i0 = j - kv > 0 ? j - kv : 0;
            for (i = i0; i < j; i++) b[i] -= AB(i, j) * bj;
        }
    }
}
#undef AB

/* Solve A x = r with the current factorisation (r, x in natural dof order; x may alias r) */
static void solve_perm(Sys *S, const double *r, double *x)
{
    int64_t N = S->N, i;
    if (S->f_singular) {
        for (i = 0; i < N; i++) x[i] = NAN;
        return;
    }
    for (i = 0; i < N; i++) S->x[i] = r[S->perm[i]];
    mm_gbtrs(N, S->kl, S->ku, S->lu, S->ldab, S->ipiv, S->x);
    for (i = 0; i < N; i++) x[S->perm[i]] = S->x[i];
}

static void factor(Sys *S, const double *q, const double *v, double h)
{
    assemble(S, q, v, h, S->lu, 1);       /* cos / sin of the body angles from mm_forces at this q */
    S->f_singular = mm_gbtrf(S->N, S->kl, S->ku, S->lu, S->ldab, S->ipiv) > 0;
    memcpy(S->f_push, S->pushing, (size_t)S->p);
    memcpy(S->f_stick, S->stick, (size_t)S->p);
    S->f_valid = 1;
    S->f_age = 0;
    S->f_h = h;
}

/* One implicit step's Newton solve, Simulator.step_implicit (integrators.py):
 *   q1 = qh + h v1,  R = M (v1 - vh) - h Q(q1, v1),  A dv = R,  v1 -= dv
 * v1: predictor in, solution out. q1 (n*3) is workspace / the last iterate.
 * stats (out): [0] force evaluations, [1] Jacobians, [2] Newton iterations (Python's count),
 *              [3] converged (0/1), [4] damper power at the first iterate */
void mm_newton(Sys *S, const double *qh, const double *vh, double *v1, double *q1, double h,
               const double *anchors, int64_t max_it, double tol_abs, double tol_rel, int64_t max_age,
               int64_t refactor_on_contact_change, double *stats)
{
    int64_t N = S->N, p = S->p, i, it;
    double prev = -1.0;
    int refresh = 0, converged = 0;
    stats[0] = stats[1] = stats[2] = stats[3] = 0.0;
    for (it = 0; it < max_it; it++) {
        for (i = 0; i < N; i++) q1[i] = qh[i] + h * v1[i];
        double dp = mm_forces(S, q1, v1, anchors, S->Q);
        stats[0] += 1.0;
        if (it == 0) stats[4] = dp;
        for (i = 0; i < N; i++) S->R[i] = S->free_dof[i] ? S->M[i] * (v1[i] - vh[i]) - h * S->Q[i] : 0.0;
        /* reuse the factorisation while the step, the touching / sticking set and the rate allow */
        int reuse = !refresh && S->f_valid && S->f_h == h && S->f_age < max_age
                    && (!refactor_on_contact_change || (memcmp(S->f_push, S->pushing, (size_t)p) == 0
                                                        && memcmp(S->f_stick, S->stick, (size_t)p) == 0));
        if (!reuse) {
            factor(S, q1, v1, h);
            stats[1] += 1.0;
        }
        solve_perm(S, S->R, S->dv);
        double nrm = 0.0, vmax = 0.0;
        int bad = 0;
        for (i = 0; i < N; i++) {
            double d = S->dv[i];
            v1[i] -= d;
            if (isnan(d)) bad = 1;
            d = fabs(d);
            if (d > nrm) nrm = d;
        }
        if (bad || !isfinite(nrm)) break;
        for (i = 0; i < N; i++) {
            double a = fabs(v1[i]);
            if (a > vmax || isnan(a)) vmax = a;
        }
        if (nrm <= tol_abs + tol_rel * vmax) { converged = 1; break; }
        refresh = prev >= 0.0 && nrm > 0.25 * prev;
        prev = nrm;
        stats[2] += 1.0;
    }
    stats[3] = converged;
    if (S->f_valid) S->f_age += 1;
}

/* Simulator._update_anchors (integrators.py): stick anchors, slip, friction work, penetration.
 * inside: previous flags in, new flags out. acc (in/out): [0] friction work J, [1] max penetration mm */
void mm_update_anchors(Sys *S, const double *q, const double *v, double *anchors, uint8_t *inside, double *acc)
{
    int64_t p = S->p, i;
    int any_in = 0;
    double pen = -INFINITY, fr = 0.0;
    for (i = 0; i < S->n; i++) {
        S->cth[i] = cos(q[3 * i + 2]);
        S->sth[i] = sin(q[3 * i + 2]);
    }
    for (i = 0; i < p; i++) {
        int64_t c = S->cb[i];
        double cc = S->cth[c], sc = S->sth[c];
        double rcx = S->rc[2 * i], rcy = S->rc[2 * i + 1];
        double ux = cc * rcx - sc * rcy, uy = sc * rcx + cc * rcy;
        double px = q[3 * c] + ux, py = q[3 * c + 1] + uy;
        int ins = py < 0;
        int isnew = ins && !inside[i];
        if (!(ins && !isnew)) anchors[i] = px;
        inside[i] = (uint8_t)ins;
        S->ux[i] = px;          /* scratch: contact point and lever arm */
        S->uy[i] = py;
        S->sgn[i] = ux;
        if (ins) any_in = 1;
    }
    if (!any_in) return;
    for (i = 0; i < p; i++) {
        int64_t c = S->cb[i];
        double px = S->ux[i], py = S->uy[i];
        double ux = S->sgn[i];
        if (-py > pen || isnan(py)) pen = -py;
        if (!inside[i]) continue;
        double vpy = v[3 * c + 1] + v[3 * c + 2] * ux;
        double fn = -S->kn[i] * py - S->cn[i] * vpy;
        if (!(fn > 0.0) && !isnan(fn)) fn = 0.0;
        double spring = -S->kt[i] * (px - anchors[i]);
        double cap = S->mu[i] * fn;
        if (fabs(spring) > cap) {
            double sg = spring > 0 ? 1.0 : (spring < 0 ? -1.0 : 0.0);
            double anc = px + sg * cap / (S->kt[i] > 0 ? S->kt[i] : 1.0);
            fr += cap * fabs(anc - anchors[i]);
            anchors[i] = anc;
        }
    }
    acc[0] += fr;
    pen *= 1e3;
    if (pen > acc[1]) acc[1] = pen;
}

/* Simulator._actuation_jump (integrators.py): the elastic energy at positions q with the current actuation
 * (S->theta0, S->ra, S->rb) minus that with the old one (th_old, ra_old, rb_old). An unchanged pin gives the
 * same distance both ways, so its terms cancel exactly, as the numpy path's skip of them. */
double mm_actuation_jump(Sys *S, const double *q, const double *th_old, const double *ra_old, const double *rb_old)
{
    double w = 0.0;
    int64_t i;
    for (i = 0; i < S->m; i++) {
        int64_t a = S->ha[i], b = S->hb[i];
        double rel = q[3 * b + 2] - q[3 * a + 2];
        double dn = rel - S->theta0[i], dold = rel - th_old[i];
        w += S->kr[i] * (dn * dn - dold * dold);
        double ca = cos(q[3 * a + 2]), sa = sin(q[3 * a + 2]), cb = cos(q[3 * b + 2]), sb = sin(q[3 * b + 2]);
        double e[2] = {0.0, 0.0};
        int k;
        for (k = 0; k < 2; k++) {
            const double *ra = k ? ra_old : S->ra, *rb = k ? rb_old : S->rb;
            double dx = q[3 * b] + cb * rb[2 * i] - sb * rb[2 * i + 1] - q[3 * a]
                        - (ca * ra[2 * i] - sa * ra[2 * i + 1]);
            double dy = q[3 * b + 1] + sb * rb[2 * i] + cb * rb[2 * i + 1] - q[3 * a + 1]
                        - (sa * ra[2 * i] + ca * ra[2 * i + 1]);
            e[k] = dx * dx + dy * dy;
        }
        w += S->kp[i] * (e[0] - e[1]);
    }
    return 0.5 * w;
}

/* PlanarSystem._contact_damper_power (system.py) for contact i at (q, v): its height (py) and the contact
 * dampers' power (0 in the air); the normal damper and a clamped point's lost penalty energy (capped at its
 * penalty energy per step dt), and the tangential damper of a sticking point. */
static double damper_power(Sys *S, int64_t i, const double *q, const double *v, const double *anchors, double dt,
                           double *py_out)
{
    int64_t c = S->cb[i];
    double cc = cos(q[3 * c + 2]), sc = sin(q[3 * c + 2]);
    double rcx = S->rc[2 * i], rcy = S->rc[2 * i + 1];
    double ux = cc * rcx - sc * rcy, uy = sc * rcx + cc * rcy;
    double py = q[3 * c + 1] + uy;
    *py_out = py;
    if (!(py < 0)) return 0.0;
    double vpx = v[3 * c] - v[3 * c + 2] * uy, vpy = v[3 * c + 1] + v[3 * c + 2] * ux;
    double pen = -py, kn = S->kn[i];
    double fn = kn * pen - S->cn[i] * vpy;
    if (!(fn > 0.0) && !isnan(fn)) fn = 0.0;
    double dn = -(fn - kn * pen) * vpy;
    if (!(fn > 0.0)) {
        double cap = 0.5 * kn * pen * pen / dt;
        if (cap < dn) dn = cap;
    }
    double trial = -S->kt[i] * (q[3 * c] + ux - anchors[i]) - S->ct[i] * vpx;
    if (fabs(trial) <= S->mu[i] * fn) dn += S->ct[i] * vpx * vpx;
    return dn;
}

/* PlanarSystem.dissipation_power(q, v, anchors, dt, q_start, v_start, hinges=False) (system.py): the contact
 * dampers' power over a step from (q0, v0) to (q, v); a point that enters the floor counts for the part of its
 * motion spent in it, one that leaves counts, at the start state's power, for the part before it left. */
double mm_contact_damping(Sys *S, const double *q, const double *v, const double *q0, const double *v0,
                          const double *anchors, double dt)
{
    double pc = 0.0, py, py0;
    int64_t i;
    for (i = 0; i < S->p; i++) {
        double p_end = damper_power(S, i, q, v, anchors, dt, &py);
        int64_t c = S->cb[i];
        double rcx = S->rc[2 * i], rcy = S->rc[2 * i + 1];
        py0 = q0[3 * c + 1] + sin(q0[3 * c + 2]) * rcx + cos(q0[3 * c + 2]) * rcy;
        if (py0 < 0 && py < 0)
            pc += p_end;
        else if (py0 >= 0 && py < 0)
            pc += p_end * (-py) / (py0 - py);
        else if (py0 < 0 && py >= 0)
            pc += damper_power(S, i, q0, v0, anchors, dt, &py0) * (-py0) / (py - py0);
    }
    return pc;
}

/* ----------------------------------------------------------------------------------------- */
/* One whole implicit step (Simulator._burst, burst.py):         what step_implicit's compiled   */
/* branch, _end_implicit_step, the ledger's actuation halves and _update_anchors do around     */
/* mm_newton, in the same order with the same operations, so a run of steps costs one call    */
/* per step. The actuation (S->theta0, ra, rb) has been set for the step's end by Python; the  */
/* one it replaced is in th_old / ra_old / rb_old (saved by the previous call, or by Python).  */
/* ----------------------------------------------------------------------------------------- */
typedef struct {
    const double *q, *v;             /* (N) state at the step's start (rotated by mm_step) */
    const double *qp, *vp;           /* (N) the state before it (BDF2) */
    double *out;                     /* (2N) q then v at the step's end; advanced by 2N per step */
    double *anchors;                 /* (p) in place */
    uint8_t *inside;                 /* (p) in place */
    double *th_old, *ra_old, *rb_old;  /* (m), (2m), (2m) */
    const double *w;                 /* (n) centre-of-mass weights */
    double *qh, *vh, *v1, *q1;       /* (N) workspace */
    double *ns;                      /* (5) mm_newton's stats */
    /* ledger and statistics accumulators (in / out) */
    double aw, damp, cdamp, fric, pen, com_min, com_max;
    int64_t fe, jac, nit, unconv, bdf2_steps;
    /* settings */
    double dt, tol_abs, tol_rel;
    int64_t bdf2, use_bdf2, max_it, max_age, refactor;
} Step;

void mm_save_actuation(Sys *S, Step *T)
{
    memcpy(T->th_old, S->theta0, (size_t)S->m * sizeof(double));
    memcpy(T->ra_old, S->ra, (size_t)(2 * S->m) * sizeof(double));
    memcpy(T->rb_old, S->rb, (size_t)(2 * S->m) * sizeof(double));
}

void mm_step(Sys *S, Step *T)
{
    int64_t N = S->N, m = S->m, i;
    const double *q = T->q, *v = T->v;
    double *qo = T->out, *vo = T->out + N;
    double dt = T->dt, h;
    int changed = 0;
    /* ledger._set_actuation's comparison (np.array_equal: a NaN counts as a change) */
    for (i = 0; i < m && !changed; i++) changed = S->theta0[i] != T->th_old[i];
    for (i = 0; i < 2 * m && !changed; i++) changed = S->ra[i] != T->ra_old[i] || S->rb[i] != T->rb_old[i];
    if (changed) T->aw += 0.5 * mm_actuation_jump(S, q, T->th_old, T->ra_old, T->rb_old);
    if (T->bdf2) {
        h = 2.0 * dt / 3.0;
        for (i = 0; i < N; i++) {
            T->qh[i] = (4.0 * q[i] - T->qp[i]) / 3.0;
            T->vh[i] = (4.0 * v[i] - T->vp[i]) / 3.0;
            T->v1[i] = 2.0 * v[i] - T->vp[i];
        }
        T->bdf2_steps += 1;
    } else {
        h = dt;
        for (i = 0; i < N; i++) {
            T->qh[i] = q[i];
            T->vh[i] = v[i];
            T->v1[i] = v[i];
        }
    }
    mm_newton(S, T->qh, T->vh, T->v1, T->q1, h, T->anchors, T->max_it, T->tol_abs, T->tol_rel, T->max_age,
              T->refactor, T->ns);
    T->fe += (int64_t)T->ns[0];
    T->jac += (int64_t)T->ns[1];
    T->nit += (int64_t)T->ns[2];
    if (!T->ns[3]) T->unconv += 1;
    for (i = 0; i < N; i++) {
        vo[i] = S->free_dof[i] ? T->v1[i] : 0.0;
        qo[i] = T->qh[i] + h * vo[i];
    }
    if (changed) T->aw += 0.5 * mm_actuation_jump(S, qo, T->th_old, T->ra_old, T->rb_old);
    double pc = mm_contact_damping(S, qo, vo, q, v, T->anchors, dt);
    T->damp += dt * T->ns[4];
    T->cdamp += dt * pc;
    if (S->p) {
        double acc[2] = {T->fric, T->pen};
        mm_update_anchors(S, qo, vo, T->anchors, T->inside, acc);
        T->fric = acc[0];
        T->pen = acc[1];
    }
    double x = 0.0;
    for (i = 0; i < S->n; i++) x += T->w[i] * qo[3 * i];
    if (x < T->com_min) T->com_min = x;
    else if (x > T->com_max) T->com_max = x;
    if (changed) mm_save_actuation(S, T);
    T->qp = q;
    T->vp = v;
    T->q = qo;
    T->v = vo;
    T->out = T->out + 2 * N;
    T->bdf2 = T->use_bdf2;
}

/* ----------------------------------------------------------------------------------------- */
/* n implicit steps of a sheet driven by its servos (SheetController, controllers.py, whose     */
/* actuation depends on the time only): before each step the actuation of the step's end is     */
/* copied from its row of the block SheetController.block_actuation computed in numpy with the  */
/* ufuncs of __call__ (numpy's cos / sin may be SVML, not libm, on AVX-512: computing them here */
/* would differ in the last bit from the per-step path there)                                  */
/* ----------------------------------------------------------------------------------------- */
typedef struct {
    const double *ra, *rb, *th;   /* (n, m) each: the anchors' x (half pitch, minus it) and rest angles per step */
} SheetAct;

static void sheet_actuate(Sys *S, const SheetAct *A, int64_t k)
{
    int64_t i, m = S->m;
    double *ra = (double *)S->ra, *rb = (double *)S->rb, *th = (double *)S->theta0;   /* the system's, in place */
    const double *a = A->ra + k * m, *b = A->rb + k * m, *t = A->th + k * m;
    for (i = 0; i < m; i++) {
        ra[2 * i] = a[i];
        rb[2 * i] = b[i];
        th[i] = t[i];
    }
}

void mm_sheet_steps(Sys *S, Step *T, int64_t n, const SheetAct *A)
{
    int64_t k;
    for (k = 0; k < n; k++) {
        sheet_actuate(S, A, k);
        mm_step(S, T);
    }
}

/* the actuation of the block's first row alone (tests) */
void mm_sheet_actuate(Sys *S, const SheetAct *A)
{
    sheet_actuate(S, A, 0);
}
