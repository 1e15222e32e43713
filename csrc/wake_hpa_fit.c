/**
 * @file wake_hpa_fit.c
 * @brief The HPA's fit (wake.hpa.fit.fit_weights): the normal equations from the centred sums, and the ridge
 *        schedule: the ridge raised tenfold until the solve (wake_hpa_solve.c) gives weights within their limit.
 *
 *   STEP_GRAM      G = B (Rxx B') + mean terms, b            (one entry G[l][k] per slice)
 *   STEP_SOLVE     (G + lambda I) w = b, raising lambda      (one attempt per slice)
 */
#include "internal/wake_hpa_internal.h"

/**
 * The normal equations of the causal fit from the centred sums.  With the
 * window mean mu, A = A_c + mu 1 s' (s = row sums of B) and y = y_c + mu 1:
 *   G  = B (Rxx B') + mu (c s' + s c') + rows mu^2 s s',   c = A_c'1 = B wsum
 * With WAKE_HPA_RIDGE_CENTRED the system is kept as the centred Gram plus a rank one (A less its column means,
 * z = A'1 = c + rows mu s its column sums, 1'y = sy + rows mu), which single precision holds where the mean terms
 * (gravity on an axis) would swamp G:
 *   G = G_c + z z' / rows,   G_c = B (Rxx B') - c c' / rows,   b = b_c + z 1'y / rows,   b_c = B Cxy - c sy / rows
 * and the solve (wake_hpa_solve.c) adds the rank one by Sherman-Morrison.
 *   b  = B Cxy + mu c + mu sy s + rows mu^2 s,             sy = 1'y_c = -sum vhead
 * The centred target is v_c(t) = F(t) + slope r(t): F the low bins X' of x_c
 * minus the end-point line, r(t) = t - (n-1)/2 the line's ramp (STEP_RAMP has
 * put the ramp's part into Cxy and vhead), and with sum F = sum r = 0,
 * sum r^2 = n (n^2-1)/12:
 *   y'y = (2/n) (sum |X'_m|^2 + 2 slope sum Re X'_m conj R_m) + slope^2 sum r^2
 *         - sum vhead^2 + 2 mu sy + rows mu^2
 *   R  = max((sum x_c^2 - 2 slope sum x_c r + slope^2 sum r^2 - (2/n) sum |X'_m|^2) / n, 1e-6 var x)
 */
void wake_hpa_step_gram(wake_hpa_t *h)
{
    const unsigned J = h->cfg.level, N = 1u << J, l = h->d, k = h->t;
    const float mu = h->mean, fr = (float)h->rows;
    const int centred = h->cfg.ridge_scale == WAKE_HPA_RIDGE_CENTRED;
    float g = 0.0f, full;
    unsigned i;
    if (k == 0u) {
        /* row l's first piece: s_l, c_l = (B wsum)_l, (B Cxy)_l */
        float sl = 0.0f, cl = 0.0f, bl = 0.0f;
        if (l == 0u) {
            h->sy = 0.0f;
            h->vv = 0.0f;
            h->trace = 0.0f;
            h->trace_c = 0.0f;
            for (i = 0; i < N; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
                h->sy -= h->vhead[i];
                h->vv += h->vhead[i] * h->vhead[i];
            }
        }
        for (i = 0; i < N; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
            const float b = h->tapf[i * WAKE_HPA_MAX_LEVEL + l];
            sl += b;
            cl += b * h->wsum[i];
            bl += b * h->cxy[i];
        }
        h->rowsum[l] = sl;
        h->colsum[l] = cl;
        h->colall[l] = cl + fr * mu * sl;
        h->rhs[l] = centred ? bl - cl * (h->sy / fr) : bl + mu * cl + mu * h->sy * sl + fr * mu * mu * sl;
    }
    /* one entry G[l][k], k <= l, per piece */
    for (i = 0; i < N; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
        g += h->tapf[i * WAKE_HPA_MAX_LEVEL + l] * h->bank_rxx[i * WAKE_HPA_MAX_LEVEL + k];
    }
    full = g + (mu * (h->colsum[l] * h->rowsum[k] + h->rowsum[l] * h->colsum[k]) +
                fr * mu * mu * h->rowsum[l] * h->rowsum[k]);
    /* the centred Gram (wake.hpa.fit.ridge_scale_of): A less its column means is A_c less its own, 1'A_c = c,
       so G_c = B Rxx B' - c c' / rows, with no mean term to cancel */
    g = centred ? g - h->colsum[l] * (h->colsum[k] / fr) : full;
    h->gram[l * J + k] = g;
    h->gram[k * J + l] = g;
    if (k < l) {
        h->t = (uint16_t)(k + 1u);
        return;
    }
    h->trace += full;
    h->trace_c += g;
    h->t = 0;
    h->d = (uint16_t)(l + 1u);
    if (h->d < J) {
        return;
    }
    {
        const float fn = (float)h->n, slope = h->slope;
        const float sum_sq = h->r[0] / (fn * fn);             /* sum x_c^2 */
        const float var = sum_sq / fn;
        const float ramp_sq = fn * (fn * fn - 1.0f) / 12.0f;  /* sum r^2 */
        /* sum x_c r = T - (n-1) S / 2, exact as 2T - (n-1) S */
        const float x_ramp = 0.5f * int64_to_float(2 * h->tsum - (int64_t)(h->n - 1u) * h->sum);
        const float line_sq = slope * slope * ramp_sq;
        const float yc = (h->power + 2.0f * slope * h->cross) * (2.0f / fn) + line_sq - h->vv;   /* y_c'y_c */
        h->yy = yc + 2.0f * mu * h->sy + fr * mu * mu;
        h->yc2 = yc - h->sy * (h->sy / fr);
        h->noise = max_f((sum_sq - 2.0f * slope * x_ramp + line_sq - h->power * (2.0f / fn)) / fn, 1e-6f * var);
        /* the ridge's scale (wake.hpa.fit.ridge_scale_of): trace(G) / J, or the centred Gram's trace floored at
           1e-6 trace(G) (an offset with little or no motion), over J */
        h->scale = (centred ? max_f(h->trace_c, 1e-6f * h->trace) : h->trace) / (float)J;
        h->factor = h->cfg.ridge;
        h->attempts = 0;
        h->phase = STEP_SOLVE;
    }
}

/**
 * e_L^2 = (w'Gw - 2 w'b + y'y) / rows, at least 0; with the centred Gram (WAKE_HPA_RIDGE_CENTRED)
 * (w'G_c w - 2 w'b_c + y_c'y_c - sy^2 / rows + (z'w - 1'y)^2 / rows) / rows, z'w - 1'y = (c'w - sy) + rows mu (s'w - 1).
 */
static float fit_mse(const wake_hpa_t *h, const float *w)
{
    const unsigned J = h->cfg.level;
    const int centred = h->cfg.ridge_scale == WAKE_HPA_RIDGE_CENTRED;
    float q = centred ? h->yc2 : h->yy;
    unsigned l, k;
    for (l = 0; l < J; ++l) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        float gw = 0.0f;
        for (k = 0; k < J; ++k) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            gw += h->gram[l * J + k] * w[k];
        }
        q += w[l] * (gw - 2.0f * h->rhs[l]);
    }
    if (centred) {
        float cw = -h->sy, sw = -1.0f, off;
        for (l = 0; l < J; ++l) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            cw += h->colsum[l] * w[l];
            sw += h->rowsum[l] * w[l];
        }
        off = cw + (float)h->rows * h->mean * sw;
        q += off * (off / (float)h->rows);
    }
    return max_f(q / (float)h->rows, 0.0f);
}


/**
 * One ridge attempt (wake.hpa.fit.fit_weights: the ridge rises tenfold until |w| <= 32); with
 * WAKE_HPA_RIDGE_CENTRED in two pieces (h->t 0: the factorisation and the centred solve; 1: the rank one), so
 * that a slice holds no more than one attempt of the default's.
 */
void wake_hpa_step_solve(wake_hpa_t *h)
{
    const unsigned J = h->cfg.level;
    const int centred = h->cfg.ridge_scale == WAKE_HPA_RIDGE_CENTRED;
    float *w = h->trial;
    unsigned j;
    int solved;
    if (!(h->scale >= SOLVE_MIN_SCALE) || !is_finite(h->scale)) {
        for (j = 0; j < J; ++j) {
            w[j] = 0.0f;
        }
        wake_hpa_finish_fit(h, w, h->noise, max_f(h->yy / (float)h->rows, 0.0f), h->cfg.ridge, 0u);
        return;
    }
    if (centred && h->t != 0u) {
        h->t = 0;
        solved = wake_hpa_solve_rank_one(h, h->factor, w);
    } else {
        solved = wake_hpa_solve_ridge(h, h->factor, w);
        if (solved && centred) {
            h->t = 1;   /* the rank one in the next piece */
            return;
        }
    }
    if (solved) {
        wake_hpa_finish_fit(h, w, h->noise, fit_mse(h, w), h->factor,
               h->factor > h->cfg.ridge ? (uint16_t)WAKE_HPA_NOTE_REGULARISED : (uint16_t)0u);
        return;
    }
    h->attempts = (uint16_t)(h->attempts + 1u);
    h->factor = max_f(h->factor * 10.0f, RIDGE_FLOOR);
    if (h->attempts >= WAKE_HPA_RIDGE_STEPS) {
        /* a ridge of 1e7 trace(G) still fails: zero weights, never NaN */
        for (j = 0; j < J; ++j) {
            w[j] = 0.0f;
        }
        wake_hpa_finish_fit(h, w, h->noise, max_f(h->yy / (float)h->rows, 0.0f), h->factor,
               (uint16_t)(WAKE_HPA_NOTE_REGULARISED | WAKE_HPA_NOTE_CLIPPED));
    }
}

