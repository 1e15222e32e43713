/**
 * @file wake_rtp_ahead.c
 * @brief The RTP's tremor ahead (issue 32): the predictor's coefficients, the gate's goal and ramp, its
 * outputs and its state.
 *
 * Its per-sample step (ahead_step, fed by the core step's tremor estimate e(n) = m(n) - y(n-1)) is part of
 * the step's flow (internal/wake_rtp_sample.h); the float twin is wake/ahead.py (AheadStep).
 */
#include "internal/wake_rtp_internal.h"

#include <string.h>

#if WAKE_RTP_AHEAD
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
