/**
 * @file wake_rtp_state.c
 * @brief The RTP's configuration and state: init, reset, weights, state load and save.
 *
 * The covariance form (docs/studies/fixed_point.md): P and d of the literal recursion are formed from the
 * restart (lambda, d_s) and the per-sample scalars s and z here only, never per sample.  Every function of
 * this file runs once per HPA, reset or state load.
 */
#include "internal/wake_rtp_internal.h"

#include <string.h>


/* ---------------------------------------------------------------------- */
/* Validation                                                              */
/* ---------------------------------------------------------------------- */


/* wake_rtpi_check_structure plus the weights' range and the variance's sign (every function but the per-sample ones). */
wake_rtp_status_t wake_rtpi_check_instance(const wake_rtp_t *s)
{
    wake_rtp_status_t st = wake_rtpi_check_structure(s);
    if (st == WAKE_RTP_OK && (!weights_in_range(s->weights, s->level) || s->variance < 0)) {
        return WAKE_RTP_E_CORRUPT;
    }
    if (st == WAKE_RTP_OK && !wake_rtpi_ahead_consistent(s)) {
        return WAKE_RTP_E_CORRUPT;
    }
    if (st == WAKE_RTP_OK && !wake_rtpi_voluntary_consistent(s)) {
        return WAKE_RTP_E_CORRUPT;
    }
    return st;
}

WAKE_RTP_COLD static wake_rtp_status_t check_weights(const wake_q24_t *weights, unsigned level, wake_cov_t r, wake_cov_t q)
{
    if (weights == NULL) {
        return WAKE_RTP_E_NULL;
    }
    if (!weights_in_range(weights, level)) {
        return WAKE_RTP_E_WEIGHTS;
    }
    if (r <= 0 || q < 0) {
        return WAKE_RTP_E_NOISE;
    }
    if (!WAKE_RTP_KALMAN && q != 0) {
        return WAKE_RTP_E_NO_KALMAN;
    }
    return WAKE_RTP_OK;
}
/* ---------------------------------------------------------------------- */
/* The covariance form: P and d from a few scalars                         */
/* ---------------------------------------------------------------------- */

#if WAKE_RTP_KALMAN /* the covariance code: left out of WAKE_RTP_KALMAN 0 builds */
/** w'x for x in Q23 (d) or Q(P) (a row of P): sum of J products Q(f + 24) rounded once to Q(f); |.| < 2^41. */
int64_t wake_rtpi_weighted_sum(const wake_q24_t *w, const int32_t *x, unsigned J)
{
    unsigned j;
    int64_t acc = 0;
    for (j = 0; j < J; ++j) {
        acc += shift_right_floor(multiply_wide(x[j], w[j]), 3u);       /* 8 terms < 2^60 each: < 2^63 */
    }
    return shift_right_round(acc, 21u);
}

/** q |w|^2 or lambda |w|^2 for a Q(P) value c and |w|^2 in Q24 (< 2^40): Q(P) in int64, |.| < 2^47. */
static WAKE_RTP_OUTLINE_AT_OS int64_t scale_by_norm(wake_cov_t c, uint64_t omega)
{
    /* c |w|^2 = c (hi + lo / 2^24) with |w|^2 = hi 2^24 + lo: hi < 2^16, lo < 2^24 */
    return (int64_t)c * (int64_t)(omega >> 24) + shift_right_round((int64_t)c * (int64_t)(omega & 0xFFFFFFu), 24u);
}


/** Lambda = variance + steps q: the diagonal of P now, before the measurements along w took their share. */
static WAKE_RTP_OUTLINE_AT_OS wake_cov_t grown_variance(const wake_rtp_t *s, uint32_t *events)
{
    return narrow_saturate((int64_t)s->variance + (int64_t)s->steps * s->q, events);   /* < 2^63 */
}

/**
 * P and d of the literal recursion (docs/studies/fixed_point.md): since the last restart
 * (P = lambda I, d = d_s) every u = P w was parallel to w, so
 *
 *   d = d_s + ((z - z_s) / |w|^2) w
 *   P = Lambda I - c w w',   Lambda = lambda + steps q,   c = (Lambda - s / |w|^2) / |w|^2
 *
 * @p P may be NULL (set_weights needs d only).  With w = 0 nothing was observed:
 * d = d_s and P = Lambda I.
 */
WAKE_RTP_COLD static void materialise(const wake_rtp_t *s, wake_q23_t *d, wake_cov_t *P, uint32_t *events)
{
    /* The coefficients carry XF extra fraction bits: they are multiplied by
     * weights up to 64, whose products w_i w_j would otherwise amplify their
     * rounding to many LSB. */
    enum { XF = 16 };
    unsigned i, j, J = s->level;
    const wake_q24_t *w = s->weights;
    uint64_t omega = weight_norm2(w, J);
    wake_cov_t lambda = grown_variance(s, events);
    int64_t c_z = 0, c_ww = 0;                             /* Q(23 + XF), Q(P + XF) */
    if (omega != 0u) {
        /* c_z = (z - z_s) / |w|^2, z_s = w'd_s as the restart computed it   (|w|^2 in Q24) */
        c_z = divide_wide(s->z - wake_rtpi_weighted_sum(w, s->correction, J), omega, 24 + XF, events);
        if (P != NULL) {
            /* c = (Lambda - s / |w|^2) / |w|^2 */
            c_ww = (int64_t)lambda * (INT64_C(1) << XF) - divide_wide(s->s, omega, 24 + XF, events);
            c_ww = divide_wide(c_ww, omega, 24, events);
        }
    }
    for (i = 0; i < J; ++i) {
        /* d_i = d_s,i + c_z w_i                                                    Q23 */
        int64_t t = shift_right_round(multiply_wide_by32(c_z, w[i], 24u), XF);
        d[i] = narrow_saturate((int64_t)s->correction[i] + t, events);
        if (P != NULL) {
            /* P_ij = Lambda d_ij - (c w_i) w_j                                       Q(P) */
            int64_t row = clamp_cov_wide(multiply_wide_by32(c_ww, w[i], 24u), events);
            for (j = i; j < J; ++j) {                      /* upper triangle, mirrored */
                int64_t p = (i == j ? (int64_t)lambda : 0)
                            - shift_right_round(multiply_wide_by32(row, w[j], 24u), XF);
                P[i * J + j] = narrow_saturate(p, events);
                /* P is PSD, so P_ii >= 0; with |w| below about 0.05, |w|^2 in Q24 has few bits and the
                 * rounding of c can leave P_ii a few LSB below 0, which load_state would refuse */
                if ((i == j) && (P[i * J + j] < 0)) {
                    P[i * J + j] = 0;
                }
                P[j * J + i] = P[i * J + j];
            }
        }
    }
}

/**
 * The variance the filter holds along w: w'Pw / |w|^2, saturated to the
 * covariance format; @p unobserved when w = 0, which observes nothing.  A
 * weight change restarts P at this variance in every direction.
 */
WAKE_RTP_COLD static wake_cov_t observed_variance(const wake_rtp_t *s, int64_t w_p_w, wake_cov_t unobserved,
                                                  uint32_t *events)
{
    uint64_t omega = weight_norm2(s->weights, s->level);
    if (omega == 0u) {
        return unobserved;
    }
    return narrow_saturate(divide_wide(w_p_w < 0 ? 0 : w_p_w, omega, 24, events), events);
}
#endif /* WAKE_RTP_KALMAN */

/**
 * Restart the covariance form for the current weights from d and P = lambda I:
 * d_s = d,  s = lambda |w|^2,  z = w'd_s,  steps = 0.  Also rebuilds the
 * FIR taps h = B'w.  @p d may be the struct's own snapshot.
 */
WAKE_RTP_COLD static void restart(wake_rtp_t *s, const wake_q23_t *d, wake_cov_t lambda)
{
    unsigned i, j, J = s->level, N = s->n_taps;
    const wake_q24_t *w = s->weights;
    uint32_t *ev = &s->saturations;
    if (d != s->correction) {
        memcpy(s->correction, d, (size_t)J * sizeof(wake_q23_t));
    }
    s->variance = lambda;
    s->steps = 0u;
#if WAKE_RTP_KALMAN
    {
        uint64_t omega = weight_norm2(w, J);
        s->s = scale_by_norm(lambda, omega);                              /* w' (lambda I) w */
        s->q_omega = scale_by_norm(s->q, omega);
        s->z = wake_rtpi_weighted_sum(w, s->correction, J);                        /* z_s, recomputed by materialise */
    }
#else
    /* no Kalman: d = 0 and lambda = 0 (init and load_state see to it), so s = z = 0 */
    s->s = 0;
    s->q_omega = 0;
    s->z = 0;
#endif
    /* h_i = sum_j B_ji w_j: exact in int64 (Q39), rounded once to Q(FIR) */
    for (i = 0; i < N; ++i) {
        int64_t acc = 0;
        for (j = 0; j < J; ++j) {
            acc += (int64_t)s->taps[j * N + i] * w[j];
        }
        s->fir[i] = fir_tap(narrow_saturate(shift_right_round(acc, 15u + WAKE_RTP_WEIGHT_FRAC - WAKE_RTP_FIR_FRAC),
                                            ev));
    }
    s->inert = (s->q == 0 && s->s == 0) ? 1u : 0u;
    wake_rtpi_voluntary_restart(s);
}

/* ---------------------------------------------------------------------- */
/* Configuration                                                           */
/* ---------------------------------------------------------------------- */

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_init(wake_rtp_t *s, int level, const wake_q15_t *taps,
                                const wake_q24_t *weights, wake_cov_t r, wake_cov_t q, wake_cov_t p0)
{
    wake_rtp_status_t st;
    unsigned j, i, n;
    if (s == NULL) {
        return WAKE_RTP_E_NULL;
    }
    s->magic = 0u;
    if (taps == NULL || weights == NULL) {
        return WAKE_RTP_E_NULL;
    }
    if (level < 1 || level > WAKE_RTP_MAX_LEVEL) {
        return WAKE_RTP_E_LEVEL;
    }
    n = 1u << (unsigned)level;
    for (j = 0; j < (unsigned)level; ++j) {
        /* sum of |taps| <= 65535 (Q15) per row */
        int32_t row_abs = 0;
        for (i = 0; i < n; ++i) {
            int32_t t = taps[j * n + i];
            row_abs += (t < 0) ? -t : t;     /* at most 256 * 32768 = 2^23: no overflow */
        }
        if (row_abs > WAKE_RTP_TAP_ROW_ABS_MAX) {
            return WAKE_RTP_E_TAPS;
        }
    }
    st = check_weights(weights, (unsigned)level, r, q);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (p0 < 0) {
        return WAKE_RTP_E_NOISE;
    }
    if (!WAKE_RTP_KALMAN && p0 != 0) {
        return WAKE_RTP_E_NO_KALMAN;
    }
    memset(s, 0, sizeof(*s));
    s->level = (uint16_t)level;
    s->n_taps = (uint16_t)n;
    s->taps = taps;
    memcpy(s->weights, weights, (size_t)level * sizeof(wake_q24_t));
    s->r = r;
    s->q = q;
    s->p0 = p0;
    s->inert = (q == 0) ? 1u : 0u;   /* consistent before reset's check (s = 0); restart sets it */
    wake_rtpi_ahead_init(s);
    s->magic = WAKE_RTP_MAGIC;
    return wake_rtp_reset(s);
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_set_weights(wake_rtp_t *s, const wake_q24_t *weights, wake_cov_t r, wake_cov_t q)
{
    wake_q23_t d[WAKE_RTP_MAX_LEVEL];
    wake_cov_t lambda = 0;
    wake_rtp_status_t st = wake_rtpi_check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    st = check_weights(weights, s->level, r, q);
    if (st != WAKE_RTP_OK) {
        return st;
    }
#if WAKE_RTP_KALMAN
    /* d under the old weights; P restarts as (w'Pw / |w|^2) I, its variance along the old w */
    materialise(s, d, NULL, &s->saturations);
    lambda = observed_variance(s, s->s, grown_variance(s, &s->saturations), &s->saturations);
#else
    memset(d, 0, sizeof(d));                                    /* d and P stay 0 */
#endif
    memcpy(s->weights, weights, (size_t)s->level * sizeof(wake_q24_t));
    s->r = r;
    s->q = q;
    restart(s, d, lambda);
    wake_rtpi_split_refresh(s);                                 /* a prepared step stays prepared */
    return WAKE_RTP_OK;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_reset(wake_rtp_t *s)
{
    wake_rtp_status_t st = wake_rtpi_check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    memset(s->ring, 0, sizeof(s->ring));
    memset(s->correction, 0, sizeof(s->correction));
    s->head = 0u;
    s->primed = 0u;
    s->last_output = 0;
    s->saturations = 0u;
    wake_rtpi_ahead_reset(s);                                   /* its coefficients and ramp stay */
    wake_rtpi_voluntary_reset(s);                               /* w_h stays */
    restart(s, s->correction, s->p0);                           /* d = 0, P(0) = p0 I */
    wake_rtpi_split_refresh(s);                                 /* a prepared step stays prepared */
    return WAKE_RTP_OK;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_get_state(const wake_rtp_t *s, wake_q23_t *correction, wake_cov_t *covariance)
{
    wake_rtp_status_t st = wake_rtpi_check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (correction == NULL || covariance == NULL) {
        return WAKE_RTP_E_NULL;
    }
#if WAKE_RTP_KALMAN
    {
        uint32_t ignored = 0u;
        materialise(s, correction, covariance, &ignored);
    }
#else
    memset(correction, 0, (size_t)s->level * sizeof(wake_q23_t));
    memset(covariance, 0, (size_t)s->level * s->level * sizeof(wake_cov_t));
#endif
    return WAKE_RTP_OK;
}


WAKE_RTP_COLD wake_rtp_status_t wake_rtp_load_state(wake_rtp_t *s, const wake_q15_t *window,
                                      const wake_q23_t *correction, const wake_cov_t *covariance,
                                      wake_q23_t last_output)
{
    unsigned i, J;
    wake_cov_t lambda = 0, top = 0;
    wake_rtp_status_t st = wake_rtpi_check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (window == NULL || correction == NULL || covariance == NULL) {
        return WAKE_RTP_E_NULL;
    }
    J = s->level;
    for (i = 0; i < J; ++i) {
        const wake_cov_t p_ii = covariance[i * J + i];
        if (p_ii < 0) {
            return WAKE_RTP_E_STATE;
        }
        top = (p_ii > top) ? p_ii : top;
    }
#if WAKE_RTP_KALMAN
    {
        /* P restarts as (w'Pw / |w|^2) I: the only part of P the recursion uses until the next
         * weight change, where it restarts that way anyway.  w = 0 observes nothing: the largest P_ii. */
        int64_t w_p_w = 0;
        for (i = 0; i < J; ++i) {
            /* w'Pw = sum_i (P w)_i w_i, Q(P): |(P w)_i| < 2^41, each term < 2^50 (J <= 8 terms) */
            w_p_w += multiply_wide_by32(wake_rtpi_weighted_sum(s->weights, covariance + i * J, J), s->weights[i], 24u);
        }
        lambda = observed_variance(s, w_p_w, top, &s->saturations);
    }
#else
    for (i = 0; i < J * J; ++i) {
        if (covariance[i] != 0 || (i < J && correction[i] != 0)) {
            return WAKE_RTP_E_NO_KALMAN;
        }
    }
#endif
    memcpy(s->ring, window, (size_t)s->n_taps * sizeof(wake_q15_t));
    memcpy(s->ring + s->n_taps, window, (size_t)s->n_taps * sizeof(wake_q15_t));
    s->head = 0u;
    restart(s, correction, lambda);
    s->last_output = last_output;
    s->primed = 1u;
    wake_rtpi_split_refresh(s);                                 /* a prepared step stays prepared */
    return WAKE_RTP_OK;
}

