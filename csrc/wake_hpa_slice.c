/**
 * @file wake_hpa_slice.c
 * @brief The HPA's slice dispatch: which function runs the step a run is in (run_step), and the entries that run
 *        pieces of a run, wake_hpa_slice (one budget, wake_hpa_pieces.c) and wake_hpa_run (to the end).
 */
#include "internal/wake_hpa_internal.h"

/** Run the current step within @p budget (@p fixed: an indivisible step's piece_cost); returns what it spent. */
int32_t wake_hpa_run_step(wake_hpa_t *h, int32_t budget, int32_t fixed)
{
    switch (h->phase) {
    case STEP_SUMS:
        return wake_hpa_step_sums(h, budget);
    case STEP_LAGS:
        return wake_hpa_step_lags(h, budget);
    case STEP_DIAG:
        return wake_hpa_step_diag(h, budget);
    case STEP_PSD:
        return wake_hpa_step_psd(h, budget);
    case STEP_DFT:
        return wake_hpa_step_dft(h, budget);
    case STEP_BIN_END:
        return wake_hpa_step_bin_end(h, budget);
    case STEP_RAMP:
        return wake_hpa_step_ramp(h, budget);
    case STEP_AHEAD_PASS:
        return hpa_ahead_run_pass(h, budget);
    case STEP_AHEAD_START:
        return hpa_ahead_run_start(h, budget);
    case STEP_AHEAD_SOLVE:
        hpa_ahead_run_solve(h);
        break;
    case STEP_LAG_END:
        wake_hpa_step_lag_end(h);
        break;
    case STEP_LEVINSON:
        wake_hpa_step_levinson(h);
        break;
    case STEP_CUTOFF:
        wake_hpa_step_cutoff(h);
        break;
    case STEP_BINS:
        wake_hpa_step_bins(h);
        break;
    case STEP_BIN_START:
        wake_hpa_step_bin_start(h);
        break;
    case STEP_GRAM:
        wake_hpa_step_gram(h);
        break;
    case STEP_SOLVE:
        wake_hpa_step_solve(h);
        break;
    default:
        break;
    }
    return fixed;
}

wake_hpa_status_t wake_hpa_slice(wake_hpa_t *h)
{
    wake_hpa_status_t st = wake_hpa_check_instance(h);
    if (st != WAKE_HPA_OK) {
        return st;
    }
    if (h->phase == STEP_IDLE) {
        return WAKE_HPA_OK;
    }
    wake_hpa_run_pieces(h, WAKE_HPA_SLICE_BUDGET);
    return h->phase == STEP_IDLE ? WAKE_HPA_DONE : WAKE_HPA_RUNNING;
}

wake_hpa_status_t wake_hpa_run(wake_hpa_t *h)
{
    /* no time limit: every loop step runs to its end in one piece (the same arithmetic as slices).  One call of
       run_pieces: its budget is far above what a whole run spends (docs/studies/verification.md, "Termination"), and its
       loop ends (WP), so this call ends too */
    wake_hpa_status_t st = wake_hpa_check_instance(h);
    if (st != WAKE_HPA_OK) {
        return st;
    }
    if (h->phase == STEP_IDLE) {
        return WAKE_HPA_OK;
    }
    wake_hpa_run_pieces(h, INT32_MAX / 2);
    return (h->phase == STEP_IDLE) ? WAKE_HPA_DONE : WAKE_HPA_RUNNING;
}

