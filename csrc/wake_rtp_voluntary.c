/**
 * @file wake_rtp_voluntary.c
 * @brief The RTP's voluntary motion ahead (issue 32): w_h, its restart and its output, on the instance the RTP
 * embeds (wake_voluntary_ahead.h, wake_rtp_t::voluntary_ahead).
 *
 * Its per-sample step (voluntary_ahead_step) is part of the step's flow (internal/wake_rtp_sample.h).
 * The float twin is wake/rtp/reference.py (ReferenceRTP.last_voluntary_ahead).
 *
 * Compiled in every build: the instance's entry (wake_voluntary_ahead_output) reads any instance; the RTP's
 * entries reach the embedded one through wake_rtpi_voluntary, which a build without
 * WAKE_RTP_VOLUNTARY_AHEAD answers with none (they return WAKE_RTP_E_FEATURE), and the step's hooks are the
 * no-ops of internal/wake_rtp_internal.h there (the step calls none of this file).  A firmware that does
 * not call the entries does not link them.
 */
#include "internal/wake_rtp_sample.h"

#include <string.h>

/** v_h(n) of instance @p v into @p output, or WAKE_RTP_E_NULL for a NULL pointer. */
static WAKE_RTP_ALWAYS_INLINE wake_rtp_status_t output_of(const wake_voluntary_ahead_t *v, wake_q23_t *output)
{
    wake_rtp_status_t st = WAKE_RTP_E_NULL;
    if ((v != NULL) && (output != NULL)) {
        *output = v->output;
        st = WAKE_RTP_OK;
    }
    return st;
}

/* the instance's own entry (a firmware that does not call it drops it at link time) */
wake_rtp_status_t wake_voluntary_ahead_output(const wake_voluntary_ahead_t *v, wake_q23_t *output)
{
    return output_of(v, output);
}

/**
 * FIR taps h_i = sum_j B_ji w_j of weights @p w: exact in int64 (Q39), rounded once to Q(FIR), as restart
 * builds h = B'w (restart keeps its own loop so that the default build's code does not move, issue 34).
 */
static inline void fir_from_weights(const wake_rtp_t *s, const wake_q24_t *w, wake_fir_t *fir, uint32_t *ev)
{
    unsigned i, j, J = s->level, N = s->n_taps;
    for (i = 0; i < N; ++i) {
        int64_t acc = 0;
        for (j = 0; j < J; ++j) {
            acc += (int64_t)s->taps[j * N + i] * w[j];
        }
        fir[i] = fir_tap(narrow_saturate(shift_right_round(acc, 15u + WAKE_RTP_WEIGHT_FRAC - WAKE_RTP_FIR_FRAC), ev));
    }
}

/**
 * The restart of the voluntary motion ahead, for w_h and the current w, d_s (docs/studies/design.md,
 * "Voluntary motion at n + h"):  d = d_s + ((z - z_s) / |w|^2) w  since the last restart, so
 *
 *   w_h' d = w_h' d_s + k (z - z_s),    k = w_h' w / |w|^2
 *
 * and the FIR taps h_h = B' w_h.  Runs in every restart and in wake_rtp_set_voluntary_ahead.
 */
WAKE_RTP_COLD void wake_rtpi_voluntary_restart_on(wake_rtp_t *s, wake_voluntary_ahead_t *v)
{
    const unsigned J = s->level;
    fir_from_weights(s, v->weights, v->fir, &v->saturations);
#if WAKE_RTP_KALMAN
    {
        uint64_t omega = weight_norm2(s->weights, J);
        int64_t dot = 0;
        unsigned j;
        /* z_s = w' d_s and w_h' d_s                                                     Q23 */
        v->z_start = wake_rtpi_weighted_sum(s->weights, s->correction, J);
        v->start = wake_rtpi_weighted_sum(v->weights, s->correction, J);
        /* w_h' w: J products Q48 < 2^60, floor-shifted by 3 (Q45, |.| < 2^60) */
        for (j = 0; j < J; ++j) {
            dot += shift_right_floor(multiply_wide(v->weights[j], s->weights[j]), 3u);
        }
        /* k = w_h' w / |w|^2: Q45 / Q24 with 3 more fraction bits = Q24; w = 0 observes nothing (d = d_s) */
        v->gain = (omega == 0u) ? 0 : narrow_saturate(divide_wide(dot, omega, 3u, &v->saturations),
                                                          &v->saturations);
    }
#else
    /* no Kalman: d = 0 (init and load_state see to it) and z never moves */
    (void)J;
    v->z_start = 0;
    v->start = 0;
    v->gain = 0;
#endif
}

/**
 * The voluntary motion ahead after the prediction of a step (ReferenceRTP._predict), from the window and
 * z of that prediction:
 *
 *   v_h(n) = w_h' (a + d) = h_h' window + w_h' d_s + k (z - z_s)      (y(n) while no w_h is installed)
 *
 * h_h' window exact in int64 (< 2^47, as y's), rounded once to Q23; z - z_s clamped to +-2^41, times k (Q24)
 * from two 32 x 32 -> 64-bit products, rounded once to Q23; the sum (< 2^49) narrowed once to int32 with
 * saturation, counted in the instance's saturations.  No data-dependent branch: its set is configuration.
 */
void wake_rtpi_voluntary_step_on(const wake_rtp_t *s, wake_voluntary_ahead_t *v)
{
    uint32_t ev = 0u;
    if (v->set == 0u) {
        v->output = s->last_output;                                   /* the one-step prediction held */
        return;
    }
    {
        const int64_t fir = shift_right_round(fir_window(v->fir, s->ring + s->head, s->n_taps),
                                              FIR_TO_SIGNAL_SHIFT);                       /* Q23, < 2^40 */
        int64_t along = 0;
#if WAKE_RTP_KALMAN
        /* w_h' (d - d_s) = k (z - z_s): Q24 x Q23 -> Q23, |.| < 2^49.  z and z_s are read clamped to +-2^41
         * (what they hold unless the state was corrupted), so that the difference cannot overflow */
        const int64_t moved = clamp_symmetric(s->z, WAKE_BOUND_RTP_VOLUNTARY_Z_BITS, &ev)
                              - clamp_symmetric(v->z_start, WAKE_BOUND_RTP_VOLUNTARY_Z_BITS, &ev);
        along = multiply_wide_by32(moved, v->gain, 24u);
        /* w_h' d_s read within +-2^41 as well: the sum below stays < 2^50 */
        along += clamp_symmetric(v->start, WAKE_BOUND_RTP_VOLUNTARY_Z_BITS, &ev);
#else
        (void)ev;   /* no Kalman: d = d_s = 0 */
#endif
        v->output = narrow_saturate(fir + along, &ev);
    }
    count_events(&v->saturations, ev);
}

int wake_rtpi_voluntary_consistent_on(const wake_rtp_t *s, const wake_voluntary_ahead_t *v)
{
    return weights_in_range(v->weights, s->level) && (v->set <= 1u);
}

void wake_rtpi_voluntary_reset_on(wake_voluntary_ahead_t *v)
{
    v->output = 0;                                              /* w_h stays */
    v->saturations = 0u;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_set_voluntary_ahead(wake_rtp_t *s, const wake_q24_t *weights_ahead)
{
    wake_voluntary_ahead_t *v;
    wake_rtp_status_t st = wake_rtpi_check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    v = wake_rtpi_voluntary(s);
    st = wake_rtpi_feature(v);                                      /* the instance may hold none */
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (weights_ahead == NULL) {
        return WAKE_RTP_E_NULL;
    }
    if (!weights_in_range(weights_ahead, s->level)) {
        return WAKE_RTP_E_WEIGHTS;
    }
    memcpy(v->weights, weights_ahead, (size_t)s->level * sizeof(wake_q24_t));
    v->set = 1u;
    wake_rtpi_voluntary_restart(s);                                 /* d_s and z_s are the last restart's */
    return WAKE_RTP_OK;
}

wake_rtp_status_t wake_rtp_voluntary_ahead_output(const wake_rtp_t *s, wake_q23_t *output)
{
    wake_rtp_status_t st = wake_rtpi_check_structure(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    st = wake_rtpi_feature(wake_rtpi_voluntary_of(s));
    if (st != WAKE_RTP_OK) {
        return st;
    }
    return output_of(wake_rtpi_voluntary_of(s), output);
}
