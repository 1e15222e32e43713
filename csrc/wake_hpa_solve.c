/**
 * @file wake_hpa_solve.c
 * @brief The HPA's ridge solve: (G + lambda I) w = b by L D L' (no square root), each attempt refused when a
 *        bound a positive semi-definite G keeps is not kept (docs/studies/verification.md, "The solve").
 */
#include "internal/wake_hpa_internal.h"

/**
 * The bounds of one ridge attempt (factor, scale = trace(G) / J), each a guard of solve_ridge that a positive
 * semi-definite G never reaches (docs/studies/verification.md, "The solve"): with M = G + lambda I, lambda = factor
 * scale, and the pivots d_j >= PIVOT_FLOOR lambda,
 *   |G_ij| <= sqrt(G_ii G_jj) <= trace(G)                           -> gmax = 2 J scale
 *   L_ij^2 d_j <= M_ii <= (2 J + factor) scale                      -> |L_ij| <= lmax, the smallest power of two
 *                                                                      with lmax^2 >= 2 (2 J + factor) / (PIVOT_FLOOR factor)
 *   z = D L' w, so |w| <= 32 gives |z_i| <= d_i 32 (1 + (J - 1) lmax) -> zlim = 64 (1 + (J - 1) lmax) (2 J + factor) scale
 * Each holds with a factor of 2 (sqrt 2 for lmax) to spare for the roundings.
 */
typedef struct {
    float lambda; /**< the ridge factor scale */
    float dmin;   /**< the smallest pivot, PIVOT_FLOOR lambda */
    float gmax;   /**< the largest |G_ij| */
    float lmax;   /**< the largest |L_ij| */
    float zlim;   /**< the largest |z_i| of L z = b */
} solve_bounds_t;

static solve_bounds_t solve_bounds(unsigned J, float factor, float scale)
{
    const float f = max_f(factor, RIDGE_FLOOR);
    const float side = (2.0f * (float)J) + f;
    const float need = (2.0f * side) / (PIVOT_FLOOR * f);
    solve_bounds_t s;
    unsigned n;
    s.lambda = factor * scale;
    s.dmin = PIVOT_FLOOR * s.lambda;
    s.gmax = 2.0f * (float)J * scale;
    s.lmax = 1.0f;
    /* need <= 4 (2 J + f) / f < 2^36 for J <= WAKE_HPA_MAX_LEVEL and f >= RIDGE_FLOOR: 18 doublings at most */
    for (n = 0; n < LMAX_DOUBLINGS; ++n) { /* wcet-loop: 18 */
        if ((s.lmax * s.lmax) < need) {
            s.lmax *= 2.0f;
        }
    }
    s.zlim = 64.0f * (1.0f + (((float)J - 1.0f) * s.lmax)) * side * scale;
    return s;
}

/**
 * G + lambda I = L D L' (no square root), D in dg, L below the diagonal of h->chol; 0 if a bound of @p s
 * is not kept (a pivot below the floor or not finite, |G_ij| or |L_ij| above its bound).
 */
static int factor_ridge(wake_hpa_t *h, const solve_bounds_t *s, float *dg)
{
    const unsigned J = h->cfg.level;
    float *L = h->chol;
    unsigned i, j, k;
    for (j = 0; j < J; ++j) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        /* d_j = M_jj - sum_k L_jk^2 d_k, in [dmin, M_jj] (each term subtracted is >= 0) */
        const float gjj = h->gram[j * J + j];
        float top;
        float dj;
        if (!((gjj <= s->gmax) && (gjj >= -s->gmax))) {
            return 0;
        }
        top = gjj + s->lambda;
        dj = top;
        for (k = 0; k < j; ++k) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            dj -= L[j * J + k] * L[j * J + k] * dg[k];
        }
        if (!(dj > 0.0f) || !(dj >= s->dmin) || !(dj <= top) || !is_finite(dj)) { /* NaN fails each */
            return 0;
        }
        dg[j] = dj;
        /* L_ij = (M_ij - sum_k L_ik L_jk d_k) / d_j */
        for (i = j + 1u; i < J; ++i) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            const float gij = h->gram[i * J + j];
            float v;
            float lij;
            if (!((gij <= s->gmax) && (gij >= -s->gmax))) {
                return 0;
            }
            v = gij;
            for (k = 0; k < j; ++k) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
                v -= L[i * J + k] * L[j * J + k] * dg[k];
            }
            lij = v / dj;
            if (!((lij <= s->lmax) && (lij >= -s->lmax))) {
                return 0;
            }
            L[i * J + j] = lij;
        }
    }
    return 1;
}

/**
 * L z = b, |z_i| <= zlim (0 if not);  D y = z;  L' w = y: the substitutions of one right-hand side @p b.
 */
static int substitute(const wake_hpa_t *h, const solve_bounds_t *s, const float *dg, const float *b, float *w)
{
    const unsigned J = h->cfg.level;
    const float *L = h->chol;
    unsigned i;
    unsigned k;
    for (i = 0; i < J; ++i) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        float v = b[i];
        for (k = 0; k < i; ++k) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            v -= L[i * J + k] * w[k];
        }
        if (!((v <= s->zlim) && (v >= -s->zlim))) {
            return 0;
        }
        w[i] = v;
    }
    for (i = 0; i < J; ++i) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        w[i] /= dg[i];
    }
    for (i = J; i-- > 0;) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        float v = w[i];
        for (k = i + 1u; k < J; ++k) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            v -= L[k * J + i] * w[k];
        }
        w[i] = v;
    }
    return 1;
}

/**
 * WAKE_HPA_RIDGE_CENTRED: (G_c + lambda I + z z' / rows) w = b_c + z 1'y / rows (wake_hpa_fit.c) by Sherman-Morrison,
 * with p = M^-1 b_c (wake_hpa_solve_ridge, the attempt's first piece, leaves it in @p w and D on the diagonal of
 * h->chol) and q = M^-1 u, u = z / zmax (|u_i| <= 1), M = G_c + lambda I = L D L':
 *   w = p + q zmax (1'y - z'p) / (rows + zmax^2 u'q),   1'y - z'p = (sy - c'p) + rows mu (1 - s'p)
 * q's substitution keeps the guard of a right-hand side (|u_i| <= 1, within the bound of one); a guard not kept,
 * a sum not finite, or weights not finite or above their limit, and the ridge rises.
 */
int wake_hpa_solve_rank_one(wake_hpa_t *h, float factor, float *w)
{
    const unsigned J = h->cfg.level;
    const solve_bounds_t s = solve_bounds(J, factor, h->scale);
    const float fr = (float)h->rows, mu = h->mean;
    float dg[WAKE_HPA_MAX_LEVEL], u[WAKE_HPA_MAX_LEVEL], q[WAKE_HPA_MAX_LEVEL];
    float zmax = 0.0f, cp = -h->sy, sp = -1.0f, uq = 0.0f, num, den, t;
    unsigned i;
    for (i = 0; i < J; ++i) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        dg[i] = h->chol[i * J + i];
        zmax = max_f(zmax, abs_f(h->colall[i]));
    }
    if (!(zmax > 0.0f) || !is_finite(zmax)) {
        return weights_ok(w, J);   /* no column sums: no rank one */
    }
    for (i = 0; i < J; ++i) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        u[i] = h->colall[i] / zmax;
    }
    if (!substitute(h, &s, dg, u, q)) {
        return 0;
    }
    for (i = 0; i < J; ++i) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        cp += h->colsum[i] * w[i];
        sp += h->rowsum[i] * w[i];
        uq += u[i] * q[i];
    }
    num = -(cp + fr * mu * sp);            /* 1'y - z'p */
    den = fr + zmax * zmax * uq;           /* >= rows: M is positive definite */
    if (!(den >= fr) || !is_finite(den) || !is_finite(num)) {
        return 0;
    }
    t = zmax * (num / den);
    for (i = 0; i < J; ++i) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        w[i] += q[i] * t;
        if (!is_finite(w[i])) {
            return 0;
        }
    }
    return weights_ok(w, J);
}

/**
 * (G + factor scale I) w = b by L D L' (no square root); 0 (the ridge rises) if a bound of solve_bounds
 * is not kept or a weight is not finite or above the limit.  WAKE_HPA_RIDGE_CENTRED: G and b are the centred
 * Gram and right-hand side, w the centred solve p (not yet within the limit: the rank one follows,
 * wake_hpa_solve_rank_one), D kept on the diagonal of h->chol for it.
 */
int wake_hpa_solve_ridge(wake_hpa_t *h, float factor, float *w)
{
    const unsigned J = h->cfg.level;
    const solve_bounds_t s = solve_bounds(J, factor, h->scale);
    float dg[WAKE_HPA_MAX_LEVEL];
    unsigned i;
    for (i = 0; i < (unsigned)WAKE_HPA_MAX_LEVEL; ++i) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        dg[i] = 0.0f;   /* factor_ridge writes the first J; zeroed for the compiler's flow analysis */
    }
    if (!factor_ridge(h, &s, dg)) {
        return 0;
    }
    if (h->cfg.ridge_scale == WAKE_HPA_RIDGE_CENTRED) {
        for (i = 0; i < J; ++i) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            h->chol[i * J + i] = dg[i];
        }
        return substitute(h, &s, dg, h->rhs, w);
    }
    return substitute(h, &s, dg, h->rhs, w) && weights_ok(w, J);
}
