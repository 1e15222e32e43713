/**
 * @file wake_rtp_ahead.c
 * @brief The RTP's tremor ahead (issue 32): the predictor's coefficients, the gate's goal and ramp, its
 * outputs and its state.
 *
 * Its per-sample step (ahead_step, fed by the core step's tremor estimate e(n) = m(n) - y(n-1)) is part of
 * the step's flow (internal/wake_rtp_sample.h); the float twin is wake/ahead.py (AheadStep).
 */
#include "internal/wake_rtp_sample.h"

#include <string.h>

#if WAKE_RTP_AHEAD
/**
 * The tremor ahead of one sample (wake.ahead.AheadStep.step), @p tremor the estimate e(n) in Q23:
 *
 *   line  <- e(n), rounded to Q15 of FS (saturated)         newest first
 *   P(n)   = c . line                                       Q27 x Q15, exact, rounded once to Q23
 *   g(n)   = g(n-1) + (goal - g(n-1)) alpha                 Q30 x Q30, rounded once to Q30
 *   cmd(n) = g(n) P(n)                                      Q30 x Q23, rounded once to Q23
 *
 * P and the command keep 8 guard bits (Q23, as y(n)): a tremor far below the full scale
 * (which has headroom for the voluntary motion) would lose a percent to a Q15 rounding.
 *
 * Every narrowing saturates and is counted in ahead_saturations; any value of the
 * ahead fields but ahead_head (checked by every step) is safe.
 */
void wake_rtpi_ahead_step(wake_rtp_t *s, wake_q23_t tremor)
{
    uint32_t ev = 0u;
    const unsigned head = ahead_next_head(s);
    const wake_q15_t e = ahead_estimate(tremor, &ev);
    ahead_line_store(s, head, e);
    /* P = c . line, |P| <= 64 FS for |c| <= 8 */
    const wake_q23_t predicted = ahead_predicted(ahead_dot(s->ahead_coef, &s->ahead_line[head]));
    ahead_output(s, predicted, ahead_gate_next(s, s->ahead_goal));
    count_events(&s->ahead_saturations, ev);
}

#if WAKE_RTP_SPLIT
/** wake_rtpi_ahead_step with the older seven products and the gate @p gate prepared. */
void wake_rtpi_ahead_finish(wake_rtp_t *s, wake_q23_t tremor, wake_ratio_t gate)
{
    uint32_t ev = 0u;
    const unsigned head = ahead_next_head(s);
    const wake_q15_t e = ahead_estimate(tremor, &ev);
    /* P = prepared + c_0 e(n): Q42, the prepared sum clamped to its range so that a corrupted one cannot
     * overflow; the gate read through the 31-bit mask of ahead_gate_next */
    const int64_t dot = clamp_quiet(s->split_ahead, WAKE_BOUND_RTP_PREPARED_AHEAD_BITS) + multiply_wide(s->ahead_coef[0], e);
    ahead_line_store(s, head, e);
    ahead_output(s, ahead_predicted(dot), (int32_t)((uint32_t)gate & UINT32_C(0x7FFFFFFF)));
    count_events(&s->ahead_saturations, ev);
}
#endif

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_set_ahead(wake_rtp_t *s, const int32_t *coefficients, wake_ratio_t goal)
{
    wake_rtp_status_t st = wake_rtpi_check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (coefficients == NULL) {
        return WAKE_RTP_E_NULL;
    }
    if (!ahead_coefficients_in_range(coefficients) || !gate_in_range(goal, 0)) {
        return WAKE_RTP_E_AHEAD;
    }
    memcpy(s->ahead_coef, coefficients, sizeof(s->ahead_coef));
    s->ahead_goal = goal;
    wake_rtpi_split_refresh(s);                                 /* a prepared step stays prepared */
    return WAKE_RTP_OK;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_set_ahead_ramp(wake_rtp_t *s, wake_ratio_t ramp)
{
    wake_rtp_status_t st = wake_rtpi_check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (!gate_in_range(ramp, 1)) {
        return WAKE_RTP_E_AHEAD;
    }
    s->ahead_ramp = ramp;
    wake_rtpi_split_refresh(s);                                 /* a prepared step stays prepared */
    return WAKE_RTP_OK;
}

wake_rtp_status_t wake_rtp_ahead_output(const wake_rtp_t *s, wake_q23_t *predicted, wake_ratio_t *gate,
                                        wake_q23_t *command)
{
    wake_rtp_status_t st = wake_rtpi_check_structure(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (predicted != NULL) {
        *predicted = s->ahead_predicted;
    }
    if (gate != NULL) {
        *gate = s->ahead_gate;
    }
    if (command != NULL) {
        *command = s->ahead_command;
    }
    return WAKE_RTP_OK;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_load_ahead_state(wake_rtp_t *s, const wake_q15_t *line, wake_ratio_t gate)
{
    unsigned i;
    wake_rtp_status_t st = wake_rtpi_check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (line == NULL) {
        return WAKE_RTP_E_NULL;
    }
    if (!gate_in_range(gate, 0)) {
        return WAKE_RTP_E_AHEAD;
    }
    for (i = 0; i < (unsigned)WAKE_RTP_AHEAD_TAPS; ++i) {
        s->ahead_line[i] = line[i];
        s->ahead_line[i + (unsigned)WAKE_RTP_AHEAD_TAPS] = line[i];
    }
    s->ahead_head = 0u;
    s->ahead_gate = gate;
    wake_rtpi_split_refresh(s);                                 /* a prepared step stays prepared */
    return WAKE_RTP_OK;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_get_ahead_state(const wake_rtp_t *s, wake_q15_t *line)
{
    unsigned i;
    wake_rtp_status_t st = wake_rtpi_check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (line == NULL) {
        return WAKE_RTP_E_NULL;
    }
    for (i = 0; i < (unsigned)WAKE_RTP_AHEAD_TAPS; ++i) {
        line[i] = s->ahead_line[s->ahead_head + i];
    }
    return WAKE_RTP_OK;
}
#endif
