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
    float g = 0.0f;
    unsigned i;
    if (k == 0u) {
        /* row l's first piece: s_l, c_l = (B wsum)_l, (B Cxy)_l */
        float sl = 0.0f, cl = 0.0f, bl = 0.0f;
        if (l == 0u) {
            h->sy = 0.0f;
            h->vv = 0.0f;
            h->trace = 0.0f;
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
        h->rhs[l] = bl + mu * cl + mu * h->sy * sl + fr * mu * mu * sl;
    }
    /* one entry G[l][k], k <= l, per piece */
    for (i = 0; i < N; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
        g += h->tapf[i * WAKE_HPA_MAX_LEVEL + l] * h->bank_rxx[i * WAKE_HPA_MAX_LEVEL + k];
    }
    g += mu * (h->colsum[l] * h->rowsum[k] + h->rowsum[l] * h->colsum[k]) +
         fr * mu * mu * h->rowsum[l] * h->rowsum[k];
    h->gram[l * J + k] = g;
    h->gram[k * J + l] = g;
    if (k < l) {
        h->t = (uint16_t)(k + 1u);
        return;
    }
    h->trace += g;
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
        h->yy = (h->power + 2.0f * slope * h->cross) * (2.0f / fn) + line_sq - h->vv + 2.0f * mu * h->sy +
                fr * mu * mu;
        h->noise = max_f((sum_sq - 2.0f * slope * x_ramp + line_sq - h->power * (2.0f / fn)) / fn, 1e-6f * var);
        h->scale = h->trace / (float)J;
        h->factor = h->cfg.ridge;
        h->attempts = 0;
        h->phase = STEP_SOLVE;
    }
}

/** e_L^2 = (w'Gw - 2 w'b + y'y) / rows, at least 0. */
static float fit_mse(const wake_hpa_t *h, const float *w)
{
    const unsigned J = h->cfg.level;
    float q = h->yy;
    unsigned l, k;
    for (l = 0; l < J; ++l) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        float gw = 0.0f;
        for (k = 0; k < J; ++k) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            gw += h->gram[l * J + k] * w[k];
        }
        q += w[l] * (gw - 2.0f * h->rhs[l]);
    }
    return max_f(q / (float)h->rows, 0.0f);
}


/** One ridge attempt (wake.hpa.fit.fit_weights: the ridge rises tenfold until |w| <= 32). */
void wake_hpa_step_solve(wake_hpa_t *h)
{
    const unsigned J = h->cfg.level;
    float *w = h->trial;
    unsigned j;
    if (!(h->scale >= SOLVE_MIN_SCALE) || !is_finite(h->scale)) {
        for (j = 0; j < J; ++j) {
            w[j] = 0.0f;
        }
        wake_hpa_finish_fit(h, w, h->noise, max_f(h->yy / (float)h->rows, 0.0f), h->cfg.ridge, 0u);
        return;
    }
    if (wake_hpa_solve_ridge(h, h->factor, w)) {
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

