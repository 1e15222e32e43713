/**
 * @file wake_rtp_block.c
 * @brief The RTP's block entries: wake_rtp_run (a block of predictions, what a firmware's batch caller
 * uses) and wake_rtp_run_outputs (every per-sample output, the host's).
 *
 * Each is n calls of the step (wake_rtp.c) with the reads of its outputs: the same result, state and cost
 * per sample.
 */
#include "internal/wake_rtp_internal.h"

wake_rtp_status_t wake_rtp_run(wake_rtp_t *s, const wake_q15_t *in, wake_q15_t *out, size_t n)
{
    size_t k;
    wake_rtp_status_t st = wake_rtpi_check_structure(s);
    if (st != WAKE_RTP_OK || n == 0u) {
        return st;
    }
    if (in == NULL || out == NULL) {
        return WAKE_RTP_E_NULL;
    }
    for (k = 0; k < n; ++k) {
        (void)wake_rtp_step(s, in[k], &out[k]);          /* cannot fail: s and out were checked */
    }
    return WAKE_RTP_OK;
}

/* the host's block entry (wake_rtp.h): a firmware that does not call it does not link it */
wake_rtp_status_t wake_rtp_run_outputs(wake_rtp_t *s, const wake_q15_t *in, const uint8_t *missing, size_t n,
                                       wake_q15_t *voluntary, wake_q23_t *tremor_ahead, wake_ratio_t *gate,
                                       wake_q23_t *command, wake_q23_t *voluntary_ahead)
{
    size_t k;
    size_t count = 0u;                                    /* the samples stepped: none unless every check passed */
    wake_rtp_status_t st = wake_rtpi_check_structure(s);
    if ((st == WAKE_RTP_OK) && (n > 0u)) {
        if (in == NULL) {
            st = WAKE_RTP_E_NULL;
        } else {
            count = n;
        }
    }
    for (k = 0u; k < count; ++k) {
        wake_q15_t y = 0;
        wake_q23_t predicted;
        wake_ratio_t gated;
        wake_q23_t commanded;
        int measured = 1;
        if ((missing != NULL) && (missing[k] != 0u)) {
            measured = 0;
        }
        if (measured != 0) {
            (void)wake_rtp_step(s, in[k], &y);           /* cannot fail: s and &y were checked */
        } else {
            (void)wake_rtp_step_missing(s, &y);
        }
        if (voluntary != NULL) {
            voluntary[k] = y;
        }
        wake_rtpi_ahead_outputs(s, &predicted, &gated, &commanded);
        if (tremor_ahead != NULL) {
            tremor_ahead[k] = predicted;
        }
        if (gate != NULL) {
            gate[k] = gated;
        }
        if (command != NULL) {
            command[k] = commanded;
        }
        if (voluntary_ahead != NULL) {
            voluntary_ahead[k] = wake_rtpi_voluntary_output(s);
        }
    }
    return st;
}
