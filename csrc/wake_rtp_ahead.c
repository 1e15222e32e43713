/**
 * @file wake_rtp_ahead.c
 * @brief The tremor ahead (issue 32, wake_ahead.h): the predictor's coefficients, the gate's goal and ramp,
 * its step fed the core's tremor estimate, its outputs and its state; and the RTP's functions that forward to
 * the instance it embeds.
 *
 * Compiled in every configuration: a firmware that calls none of it drops it at link time.  The per-sample
 * pieces are internal/wake_rtp_sample.h's, shared with the split step's prepare; the float twin is
 * wake/ahead.py (AheadStep).
 */
#include "internal/wake_rtp_sample.h"

#include <string.h>

/* ---------------------------------------------------------------------- */
/* The instance (wake_ahead.h)                                             */
/* ---------------------------------------------------------------------- */

/**
 * The tremor ahead of one sample (wake.ahead.AheadStep.step), @p tremor the estimate e(n) in Q23:
 *
 *   line  <- e(n), rounded to Q15 of FS (saturated)         newest first
 *   P(n)   = c . line                                       Q27 x Q15, exact, rounded once to Q23
 *   g(n)   = g(n-1) + (goal - g(n-1)) alpha                 Q30 x Q30, rounded once to Q30
 *   cmd(n) = g(n) P(n)                                      Q30 x Q23, rounded once to Q23
 *
 * Every narrowing saturates and is counted in saturations; any value of the fields is safe (the next index is
 * taken modulo 8).
 */
static WAKE_RTP_ALWAYS_INLINE void ahead_step(wake_ahead_t *a, wake_q23_t tremor)
{
    uint32_t ev = 0u;
    const unsigned head = ahead_next_head(a);
    const wake_q15_t e = ahead_estimate(tremor, &ev);
    ahead_line_store(a, head, e);
    /* P = c . line, |P| <= 64 FS for |c| <= 8 */
    const wake_q23_t predicted = ahead_predicted(ahead_dot(a->coef, &a->line[head]));
    ahead_output(a, predicted, ahead_gate_next(a, a->goal));
    count_events(&a->saturations, ev);
}

void wake_ahead_step(wake_ahead_t *a, wake_q23_t tremor)
{
    ahead_step(a, tremor);
}

/* The per-sample flow's hook (internal/wake_rtp_sample.h): the step on the RTP's embedded instance, one call from
 * the core's step as before the instance existed (its frame and cost are the step's). */
void wake_rtpi_ahead_step(wake_rtp_t *s, wake_q23_t tremor)
{
    wake_ahead_t *a = wake_rtpi_ahead(s);
    if (a != NULL) {
        ahead_step(a, tremor);
    }
}

void wake_ahead_step_missing(wake_ahead_t *a)
{
    ahead_shut(a);
    ahead_step(a, 0);
}

void wake_ahead_prepare(const wake_ahead_t *a, wake_ahead_prepared_t *prepared)
{
    ahead_prepare(a, prepared);
}

/** wake_ahead_step with the older seven products prepared and the gate @p gate. */
void wake_ahead_finish(wake_ahead_t *a, const wake_ahead_prepared_t *prepared, wake_q23_t tremor,
                       wake_ratio_t gate)
{
    uint32_t ev = 0u;
    const unsigned head = ahead_next_head(a);
    const wake_q15_t e = ahead_estimate(tremor, &ev);
    /* P = prepared + c_0 e(n): Q42, the prepared sum clamped to its range so that a corrupted one cannot
     * overflow; the gate read through the 31-bit mask of ahead_gate_next */
    const int64_t dot = clamp_quiet(prepared->dot, WAKE_BOUND_RTP_PREPARED_AHEAD_BITS)
                        + multiply_wide(a->coef[0], e);
    ahead_line_store(a, head, e);
    ahead_output(a, ahead_predicted(dot), (int32_t)((uint32_t)gate & UINT32_C(0x7FFFFFFF)));
    count_events(&a->saturations, ev);
}

WAKE_RTP_COLD wake_rtp_status_t wake_ahead_init(wake_ahead_t *a)
{
    wake_rtp_status_t st = WAKE_RTP_E_NULL;
    if (a != NULL) {
        ahead_init(a);
        st = WAKE_RTP_OK;
    }
    return st;
}

WAKE_RTP_COLD wake_rtp_status_t wake_ahead_reset(wake_ahead_t *a)
{
    wake_rtp_status_t st = WAKE_RTP_E_NULL;
    if (a != NULL) {
        ahead_reset(a);
        st = WAKE_RTP_OK;
    }
    return st;
}

WAKE_RTP_COLD wake_rtp_status_t wake_ahead_check(const wake_ahead_t *a)
{
    wake_rtp_status_t st = WAKE_RTP_E_NULL;
    if (a != NULL) {
        st = (ahead_consistent(a) && (a->head < (unsigned)WAKE_RTP_AHEAD_TAPS)) ? WAKE_RTP_OK : WAKE_RTP_E_CORRUPT;
    }
    return st;
}

/* The setters and readers, each written once: the instance's functions below and the RTP's (which pass its
 * embedded instance, or NULL in a build without it) inline the same code. */

static WAKE_RTP_ALWAYS_INLINE wake_rtp_status_t set_model(wake_ahead_t *a, const int32_t *coefficients,
                                                          wake_ratio_t goal)
{
    if ((a == NULL) || (coefficients == NULL)) {
        return WAKE_RTP_E_NULL;
    }
    if (!ahead_coefficients_in_range(coefficients) || !gate_in_range(goal, 0)) {
        return WAKE_RTP_E_AHEAD;
    }
    memcpy(a->coef, coefficients, sizeof(a->coef));
    a->goal = goal;
    return WAKE_RTP_OK;
}

static WAKE_RTP_ALWAYS_INLINE wake_rtp_status_t set_ramp(wake_ahead_t *a, wake_ratio_t ramp)
{
    if (a == NULL) {
        return WAKE_RTP_E_NULL;
    }
    if (!gate_in_range(ramp, 1)) {
        return WAKE_RTP_E_AHEAD;
    }
    a->ramp = ramp;
    return WAKE_RTP_OK;
}

static WAKE_RTP_ALWAYS_INLINE wake_rtp_status_t load(wake_ahead_t *a, const wake_q15_t *line, wake_ratio_t gate)
{
    unsigned i;
    if ((a == NULL) || (line == NULL)) {
        return WAKE_RTP_E_NULL;
    }
    if (!gate_in_range(gate, 0)) {
        return WAKE_RTP_E_AHEAD;
    }
    for (i = 0; i < (unsigned)WAKE_RTP_AHEAD_TAPS; ++i) {
        a->line[i] = line[i];
        a->line[i + (unsigned)WAKE_RTP_AHEAD_TAPS] = line[i];
    }
    a->head = 0u;
    a->gate = gate;
    return WAKE_RTP_OK;
}

static WAKE_RTP_ALWAYS_INLINE wake_rtp_status_t history(const wake_ahead_t *a, wake_q15_t *line)
{
    unsigned i;
    if ((a == NULL) || (line == NULL)) {
        return WAKE_RTP_E_NULL;
    }
    if (a->head >= (unsigned)WAKE_RTP_AHEAD_TAPS) {
        return WAKE_RTP_E_CORRUPT;
    }
    for (i = 0; i < (unsigned)WAKE_RTP_AHEAD_TAPS; ++i) {
        line[i] = a->line[a->head + i];
    }
    return WAKE_RTP_OK;
}

static WAKE_RTP_ALWAYS_INLINE wake_rtp_status_t output(const wake_ahead_t *a, wake_q23_t *predicted,
                                                       wake_ratio_t *gate, wake_q23_t *command)
{
    if (a == NULL) {
        return WAKE_RTP_E_NULL;
    }
    if (predicted != NULL) {
        *predicted = a->predicted;
    }
    if (gate != NULL) {
        *gate = a->gate;
    }
    if (command != NULL) {
        *command = a->command;
    }
    return WAKE_RTP_OK;
}

WAKE_RTP_COLD wake_rtp_status_t wake_ahead_set_model(wake_ahead_t *a, const int32_t *coefficients, wake_ratio_t goal)
{
    return set_model(a, coefficients, goal);
}

WAKE_RTP_COLD wake_rtp_status_t wake_ahead_set_ramp(wake_ahead_t *a, wake_ratio_t ramp)
{
    return set_ramp(a, ramp);
}

WAKE_RTP_COLD wake_rtp_status_t wake_ahead_load(wake_ahead_t *a, const wake_q15_t *line, wake_ratio_t gate)
{
    return load(a, line, gate);
}

WAKE_RTP_COLD wake_rtp_status_t wake_ahead_history(const wake_ahead_t *a, wake_q15_t *line)
{
    return history(a, line);
}

wake_rtp_status_t wake_ahead_output(const wake_ahead_t *a, wake_q23_t *predicted, wake_ratio_t *gate,
                                    wake_q23_t *command)
{
    return output(a, predicted, gate, command);
}

/* ---------------------------------------------------------------------- */
/* The RTP's tremor ahead (wake_rtp.h): the RTP instance checked, then the same code on its embedded one */
/* ---------------------------------------------------------------------- */

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_set_ahead(wake_rtp_t *s, const int32_t *coefficients, wake_ratio_t goal)
{
    wake_rtp_status_t st = wake_rtpi_check_instance(s);
    if (st == WAKE_RTP_OK) {
        st = wake_rtpi_feature(wake_rtpi_ahead(s));
    }
    if (st == WAKE_RTP_OK) {
        st = set_model(wake_rtpi_ahead(s), coefficients, goal);
    }
    if (st == WAKE_RTP_OK) {
        wake_rtpi_split_refresh(s);                             /* a prepared step stays prepared */
    }
    return st;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_set_ahead_ramp(wake_rtp_t *s, wake_ratio_t ramp)
{
    wake_rtp_status_t st = wake_rtpi_check_instance(s);
    if (st == WAKE_RTP_OK) {
        st = wake_rtpi_feature(wake_rtpi_ahead(s));
    }
    if (st == WAKE_RTP_OK) {
        st = set_ramp(wake_rtpi_ahead(s), ramp);
    }
    if (st == WAKE_RTP_OK) {
        wake_rtpi_split_refresh(s);                             /* a prepared step stays prepared */
    }
    return st;
}

wake_rtp_status_t wake_rtp_ahead_output(const wake_rtp_t *s, wake_q23_t *predicted, wake_ratio_t *gate,
                                        wake_q23_t *command)
{
    wake_rtp_status_t st = wake_rtpi_check_structure(s);
    if (st == WAKE_RTP_OK) {
        st = wake_rtpi_feature(wake_rtpi_ahead_of(s));
    }
    if (st == WAKE_RTP_OK) {
        st = output(wake_rtpi_ahead_of(s), predicted, gate, command);
    }
    return st;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_load_ahead_state(wake_rtp_t *s, const wake_q15_t *line, wake_ratio_t gate)
{
    wake_rtp_status_t st = wake_rtpi_check_instance(s);
    if (st == WAKE_RTP_OK) {
        st = wake_rtpi_feature(wake_rtpi_ahead(s));
    }
    if (st == WAKE_RTP_OK) {
        st = load(wake_rtpi_ahead(s), line, gate);
    }
    if (st == WAKE_RTP_OK) {
        wake_rtpi_split_refresh(s);                             /* a prepared step stays prepared */
    }
    return st;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_get_ahead_state(const wake_rtp_t *s, wake_q15_t *line)
{
    wake_rtp_status_t st = wake_rtpi_check_instance(s);
    if (st == WAKE_RTP_OK) {
        st = wake_rtpi_feature(wake_rtpi_ahead_of(s));
    }
    if (st == WAKE_RTP_OK) {
        st = history(wake_rtpi_ahead_of(s), line);
    }
    return st;
}
