/**
 * @file wake_hpa_pieces.c
 * @brief The HPA's slice cost model: what each piece of work costs, in Cortex-M4F instructions at -O2 (the
 *        constants: internal/wake_hpa_costs.h, written by `python -m wake.firmware.hpa_cost --calibrate --write`),
 *        and the loop that runs pieces until a budget is spent.
 *
 * A slice spends at most WAKE_HPA_SLICE_BUDGET on pieces of work (each charged COST_PIECE for its set-up plus its
 * items) and starts an indivisible step only if it fits in what is left, or is the slice's first piece.  What a
 * slice costs beyond its budget is its fixed entry cost (the instance check, about 250).  docs/studies/hpa_c.md.
 */
#include "internal/wake_hpa_internal.h"

/**
 * Cost of the next indivisible step, or of one item of a loop step (without COST_PIECE).  The contract is what
 * run_pieces' termination proof assumes (docs/studies/verification.md, "Termination"): Eva shows it in the default
 * configuration on every phase, from any 16-bit counter t (the dispatch entries); by reading, in any
 * configuration wake_hpa.h and config_ok admit: at least COST_LAG, at most Levinson's 80 + 12 (t + 1) +
 * 2 WAKE_HPA_MAX_ORDER < 10^6 for any t (t < p <= 255 in a run: 3,662), the cut-off's 400 + 26 cut_hi <= 13,660 (cut_hi <=
 * WAKE_HPA_MAX_PSD_BINS - 2), the Gram entry's 160 + 28 2^J <= 7,328, every other below 7,000.
 */
/*@ requires \valid_read(h);
    assigns \nothing;
    ensures 1 <= \result <= 1000000;
*/
static int32_t piece_cost(const wake_hpa_t *h)
{
    const int32_t J = (int32_t)h->cfg.level, N = (int32_t)1 << J;
    switch (h->phase) {
    case STEP_LAG_END:
        return COST_LAG_END;
    case STEP_LEVINSON:
        /* order t + 1 (the first piece also clears a[]) */
        return COST_LEVINSON_BASE + COST_LEVINSON_PER_ORDER * ((int32_t)h->t + 1) + (h->t == 0u ? COST_LEVINSON_CLEAR_PER_ORDER * WAKE_HPA_MAX_ORDER : 0);
    case STEP_CUTOFF:
        /* the valley and left searches, the shallow minimum, rule floor's edge walk */
        return COST_CUTOFF_BASE + COST_CUTOFF_PER_BIN * (int32_t)h->cut_hi + COST_CUTOFF_PER_SHALLOW * (int32_t)h->cut_shallow;
    case STEP_BINS:
        /* the count stops at f_d <= cutoff_high: at most cutoff_high n / fs bins */
        return COST_BINS_BASE + COST_BINS_PER_BIN * (int32_t)(h->cfg.cutoff_high * ((float)h->n / h->cfg.fs));
    case STEP_BIN_START:
        return COST_BIN_START;
    case STEP_GRAM:
        /* one entry; a row's first also sums the row, and the first row the targets */
        return COST_GRAM_BASE + COST_GRAM_PER_TAP * N + (h->t == 0u ? COST_GRAM_ROW_PER_TAP * N : 0) + (h->t == 0u && h->d == 0u ? COST_GRAM_TARGETS_PER_TAP * N : 0) +
               (h->t == h->d && h->d + 1u == h->cfg.level ? COST_GRAM_LAST : 0);
    case STEP_SOLVE:
        /* the factorisation and substitutions, plus the bounds of the guards (18 doublings) and the guards; with
           WAKE_HPA_RIDGE_CENTRED the rank one is a piece of its own (h->t 1) */
        return h->t != 0u ? COST_SOLVE_RANK_ONE : COST_SOLVE_CUBIC * J * J * J + COST_SOLVE_SQUARE * J * J + COST_SOLVE_BASE;
    case STEP_AHEAD_START:
        return COST_AHEAD_TAP;
    case STEP_AHEAD_SOLVE:
        /* a row of G with up to 14 edge products per entry (the last with the held-out sums from b and G when
           every row is held out); a column: up to 7 x 8 products; the substitution, gain and goal */
        if (h->d == AHEAD_SOLVE_LAST) {
            return COST_AHEAD_SOLVE_LAST;
        }
        if (h->d < WAKE_HPA_AHEAD_TAPS) {
            return h->d + 1u == WAKE_HPA_AHEAD_TAPS && hpa_ahead_all_held(h) ? COST_AHEAD_SOLVE_ROW_HELD : COST_AHEAD_SOLVE_ROW;
        }
        return COST_AHEAD_SOLVE_COLUMN;
    case STEP_AHEAD_PASS:
        return COST_AHEAD_CHUNK + cost_ahead(h, 1u);
    case STEP_SUMS:
        return COST_SUM;
    case STEP_LAGS:
        return COST_LAG;
    case STEP_DIAG:
        return COST_DIAG;
    case STEP_PSD:
        return cost_psd_bin(h);
    case STEP_DFT:
        return h->pair == 2u ? COST_DFT2 : COST_DFT1;
    case STEP_RAMP:
        return COST_RAMP;
    default: /* STEP_BIN_END */
        return COST_SLIDE;
    }
}

/** Pieces of work until @p budget is spent; the next piece only if it fits (or comes first). */
void wake_hpa_run_pieces(wake_hpa_t *h, int32_t budget)
{
    int32_t left = budget;
    int first = 1;
    /* termination (WP; docs/studies/verification.md, "Termination"): a piece after the first runs only if need <= left,
       need >= 1 + COST_PIECE, and every piece lowers left by what run_step spent (> 0) plus COST_PIECE */
    /*@ loop invariant first == 0 || first == 1;
        loop invariant first == 1 ==> left == budget;
        loop invariant left <= budget;
        loop invariant STEP_IDLE <= h->phase <= (WAKE_HPA_USES_AHEAD ? STEP_AHEAD_SOLVE : STEP_SOLVE);
        loop invariant h->d <= h->lags && h->pair <= 2;
        loop assigns left, first, *h;
        loop variant left;
    */
    while (h->phase != STEP_IDLE) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_PIECE */
        const int32_t need = piece_cost(h) + COST_PIECE;
        if (!first && need > left) {
            break;
        }
        left -= wake_hpa_run_step(h, left - COST_PIECE, need - COST_PIECE) + COST_PIECE;
        first = 0;
    }
}

