/**
 * @file wake_hpa_internal.h
 * @brief What the HPA's source files share, and what the tests, the fuzz harnesses and the proofs reach
 *        beyond the public API (wake_hpa.h).  Not part of the API: names and signatures may change.
 *
 * The HPA is split by concern (docs/reference/architecture.md, "The C HPA's files"):
 *
 *   wake_hpa.c           configuration, instance check, feeding, results, conversion to the RTP's formats
 *   wake_hpa_spectrum.c  the sums, lag sums and Rxx B', Levinson-Durbin, the AR spectrum and the cut-off
 *   wake_hpa_dft.c       the voluntary truth's DFT bins: the passes, the bins' slides, the end-point line's ramp
 *   wake_hpa_fit.c       the normal equations and the ridge schedule
 *   wake_hpa_solve.c     the ridge solve by L D L' and its guards
 *   wake_hpa_ahead.c     the tremor-ahead fit, on its own state (wake_hpa_ahead_t)
 *   wake_hpa_pieces.c    the slice cost model (its constants: wake_hpa_costs.h, generated) and the pieces' loop
 *   wake_hpa_slice.c     the slice dispatch: the step a run is in, wake_hpa_slice, wake_hpa_run
 *
 * The tremor-ahead fit is used or not by the instance's configuration (WAKE_HPA_AHEAD, wake_hpa.h): its hooks
 * below call wake_hpa_ahead.c when the instance holds the fit's state, and do nothing otherwise; no source file
 * tests the switch.
 */
#ifndef WAKE_HPA_INTERNAL_H
#define WAKE_HPA_INTERNAL_H

#include "../wake_hpa.h"
#include "wake_bounds.h"
#include "wake_hpa_costs.h"

#include <string.h>

#if WAKE_HPA_HORIZON != 1u
#error "the normal equations (step_bin_end, step_ramp, step_gram) are written for WAKE_HPA_HORIZON 1"
#endif
#if WAKE_HPA_AHEAD && !WAKE_RTP_AHEAD
#error "WAKE_HPA_AHEAD fits the predictor the RTP runs: it needs WAKE_RTP_AHEAD"
#endif
#if WAKE_HPA_AHEAD && WAKE_HPA_AHEAD_TAPS != WAKE_RTP_AHEAD_TAPS
#error "the HPA fits the predictor the RTP runs: WAKE_HPA_AHEAD_TAPS must equal WAKE_RTP_AHEAD_TAPS"
#endif
#if WAKE_HPA_MAX_WARMUP != 8
#error "seal_of() hashes eight warm-up points"
#endif

/** The steps of a run (wake_hpa_t::phase; wake.firmware.hpa_cost.STEP_NAMES lists them in this order). */
enum {
    STEP_IDLE = 0,
    STEP_SUMS,
    STEP_LAGS,
    STEP_LAG_END,
    STEP_DIAG,
    STEP_LEVINSON,
    STEP_PSD,
    STEP_CUTOFF,
    STEP_BINS,
    STEP_DFT,
    STEP_BIN_START,
    STEP_BIN_END,
    STEP_RAMP,
    STEP_GRAM,
    STEP_SOLVE,
    STEP_AHEAD_START,
    STEP_AHEAD_PASS,
    STEP_AHEAD_SOLVE
};

#define NO_PEAK 0xFFFFu

/** The last piece of the tremor-ahead solve (0..7 assemble G's rows, 8..15 factor its columns, 16 substitutes). */
#define AHEAD_SOLVE_LAST (2u * WAKE_HPA_AHEAD_TAPS)

/* ---- small helpers ------------------------------------------------------------------------------------------- */

static inline int is_finite(float v)
{
    /* NaN fails v == v; +-inf fails the range test. */
    return v == v && v <= 3.4028234e38f && v >= -3.4028234e38f;
}

static inline float max_f(float a, float b) { return a > b ? a : b; }

/** A counter that sticks at UINT32_MAX instead of wrapping. */
static inline void count_up(uint32_t *c)
{
    *c = *c == UINT32_MAX ? *c : *c + 1u;
}
static inline float abs_f(float a) { return a < 0.0f ? -a : a; }

/** v within [-top, top] by plain comparisons (a NaN passes unchanged). */
static inline float clamp_abs(float v, float top)
{
    return (v > top) ? top : ((v < -top) ? -top : v);
}

/** min(t + step, limit): where one slice of an inner loop stops. */
static inline unsigned chunk_end(unsigned t, unsigned step, unsigned limit)
{
    const unsigned end = t + step;   /* named once (wake_bounds.h, "analyser shapes") */
    return (end < limit) ? end : limit;
}

/** The items of a slice of an inner loop from t < limit, at most step (chunk_end(t, step, limit) - t, written
 *  from limit - t: wake_bounds.h, "analyser shapes"). */
static inline unsigned chunk_count(unsigned t, unsigned step, unsigned limit)
{
    const unsigned rest = limit - t;
    return (step < rest) ? step : rest;
}

/** Items of cost @p cost that @p budget buys, at least one. */
static inline unsigned items(int32_t budget, int32_t cost)
{
    return budget > cost ? (unsigned)(budget / cost) : 1u;
}

/** A Q15 tap as a float (exact: q / 2^15). */
static inline float q15_to_float(wake_q15_t q)
{
    return (float)q * (1.0f / 32768.0f);
}

/**
 * An int64 as a float without libgcc's __aeabi_l2f (about 30 instructions
 * on a Cortex-M4F): |z| split in two uint32 halves, each converted by the
 * FPU.  Two roundings instead of one (error within 1 ulp of the exact
 * value), the same on every IEEE machine.
 */
static inline float int64_to_float(int64_t z)
{
    const uint64_t m = z < 0 ? (uint64_t)0 - (uint64_t)z : (uint64_t)z;
    const float f = (float)(uint32_t)(m >> 32) * 4294967296.0f + (float)(uint32_t)m;
    return z < 0 ? -f : f;
}

/** Frequency of AR-spectrum bin k, Hz. */
static inline float psd_freq(const wake_hpa_t *h, unsigned k)
{
    return (float)k * (h->cfg.fs / (float)WAKE_HPA_PSD_GRID);
}

/**
 * The spectrum step's items t = 0 .. psd_last: the PSD bins 0 .. psd_hi + 1 in order (the tremor peak's
 * local-maximum test needs the right neighbour), then, for rule floor, the noise floor's bins: fs/2 and
 * every WAKE_HPA_FLOOR_STRIDE-th bin below it, down to floor_lo (wake.hpa.cutoff.FLOOR_STRIDE).
 */
static inline unsigned psd_last(const wake_hpa_t *h)
{
    const unsigned top = WAKE_HPA_PSD_GRID / 2u;
    if (h->cfg.rule != WAKE_HPA_RULE_FLOOR || h->floor_lo > top) {
        return h->psd_hi + 1u;
    }
    return h->psd_hi + 1u + (top - h->floor_lo) / WAKE_HPA_FLOOR_STRIDE + 1u;
}

/** Weights finite and within WAKE_HPA_WEIGHT_LIMIT (NaN fails both tests; tested on w[j] itself:
 *  wake_bounds.h, "analyser shapes"). */
static inline int weights_ok(const float *w, unsigned J)
{
    unsigned j;
    for (j = 0; j < J; ++j) {
        if (!((w[j] <= (float)WAKE_HPA_WEIGHT_LIMIT) && (w[j] >= -(float)WAKE_HPA_WEIGHT_LIMIT))) {
            return 0;
        }
    }
    return 1;
}

/* ---- the slice cost model (the constants: wake_hpa_costs.h, generated) ---------------------------------------- */

/** One bin of the AR spectrum (Clenshaw over p coefficients). */
static inline int32_t cost_psd_bin(const wake_hpa_t *h)
{
    return COST_PSD_BIN_BASE + COST_PSD_BIN_PER_ORDER * (int32_t)h->order;
}

/** The DFT passes' last bin: the fit's bins, then the gate's above them. */
static inline unsigned hpa_dft_bins(const wake_hpa_t *h)
{
    return (unsigned)h->bins + h->gate_extra;
}

/**
 * One sample of the tremor-ahead pass in a chunk of @p k samples: the 2^J-tap FIR (two samples a turn), the
 * row, and the bins' oscillators, each run over the samples of a chunk (about 5 + 4 r instructions per bin
 * for r samples, so short runs pay more per sample); a chunk of 1..3 also pays an odd sample's FIR alone.
 */
static inline int32_t cost_ahead(const wake_hpa_t *h, unsigned k)
{
    const int32_t N = (int32_t)1 << h->cfg.level;
    return k % 4u == 0u ? COST_AHEAD_BASE + COST_AHEAD4_PER_TAP * N + COST_AHEAD4_PER_BIN * (int32_t)hpa_dft_bins(h) : COST_AHEAD_BASE + COST_AHEAD1_PER_TAP * N + COST_AHEAD1_PER_BIN * (int32_t)hpa_dft_bins(h);
}

/** One sample of the sums pass; with the tremor ahead also its full-scale count. */
#define COST_SUM (WAKE_HPA_USES_AHEAD ? COST_SUM_AHEAD : COST_SUM_PLAIN)
/** One entry of a diagonal of Rxx into Rxx B' (the tap loops run WAKE_HPA_MAX_LEVEL times). */
#define COST_DIAG (COST_DIAG_BASE + COST_DIAG_PER_LEVEL * WAKE_HPA_MAX_LEVEL)
/** One tap of the tremor ahead's estimate FIR w'B (J products). */
#define COST_AHEAD_TAP (COST_AHEAD_TAP_BASE + COST_AHEAD_TAP_PER_LEVEL * WAKE_HPA_MAX_LEVEL)

/* ---- wake_hpa.c: the instance, the results ------------------------------------------------------------------- */

wake_hpa_status_t wake_hpa_check_instance(const wake_hpa_t *h);
/** A run started on @p window (n samples, the index of its last). */
void wake_hpa_begin(wake_hpa_t *h, const wake_q15_t *window, uint16_t n, uint32_t index);
/** A run that ends without a fit (a constant window): its weights, published at once. */
void wake_hpa_finish(wake_hpa_t *h, const float *w, float r, float mse, float ridge, uint16_t notes);
/** A run that ends with a fit: its weights installed, then the tremor ahead (if used), then published. */
void wake_hpa_finish_fit(wake_hpa_t *h, const float *w, float r, float mse, float ridge, uint16_t notes);
/** The run's result ready: the tremor ahead's predictor and goal beside the installed weights. */
void wake_hpa_publish(wake_hpa_t *h);
/** round(v) as int32, v clamped to [lo, hi] first (no undefined conversion). */
int32_t wake_hpa_round_clamp(float v, float lo, float hi);

/* ---- wake_hpa_spectrum.c ------------------------------------------------------------------------------------- */

/** cos and sin of pi num / den for 0 <= num <= den (an angle in [0, pi]). */
void wake_hpa_unit_phasor(uint32_t num, uint32_t den, float *c, float *s);
int32_t wake_hpa_step_sums(wake_hpa_t *h, int32_t budget);
int32_t wake_hpa_step_lags(wake_hpa_t *h, int32_t budget);
void wake_hpa_step_lag_end(wake_hpa_t *h);
int32_t wake_hpa_step_diag(wake_hpa_t *h, int32_t budget);
void wake_hpa_step_levinson(wake_hpa_t *h);
int32_t wake_hpa_step_psd(wake_hpa_t *h, int32_t budget);
void wake_hpa_step_cutoff(wake_hpa_t *h);

/**
 * The smallest prediction error Levinson-Durbin divides by: r is n^2 times the window's centred
 * autocorrelation in LSB^2, so err < 1 is a window predicted to far below one LSB (the recursion stops
 * there, as at err <= 0).  It bounds |k| before the clamp by |acc| < 2^88 (docs/studies/verification.md).
 */
#define LEVINSON_MIN_ERR 1.0f

/* ---- wake_hpa_dft.c ------------------------------------------------------------------------------------------ */

void wake_hpa_step_bins(wake_hpa_t *h);
/** Set up a DFT pass over bins m and m + 1 (or m alone if it is the last). */
void wake_hpa_start_pass(wake_hpa_t *h);
int32_t wake_hpa_step_dft(wake_hpa_t *h, int32_t budget);
void wake_hpa_step_bin_start(wake_hpa_t *h);
int32_t wake_hpa_step_bin_end(wake_hpa_t *h, int32_t budget);
int32_t wake_hpa_step_ramp(wake_hpa_t *h, int32_t budget);

/* ---- wake_hpa_fit.c, wake_hpa_solve.c ------------------------------------------------------------------------------------------ */

/**
 * The smallest mean diagonal trace(G) / J of a system the solve takes (LSB^2): below it the regressors are
 * zero to far below one LSB and the fit gives zero weights, as at trace(G) <= 0.  It keeps the ridge
 * factor scale (>= 1e-6 2^-80 at the default ridge) a normal float, so the pivot floor below is one.
 */
#define SOLVE_MIN_SCALE 8.2718061e-25f /* 2^-80 */
/** The smallest ridge factor once the ridge has risen (and the one the bounds of a ridge below it assume). */
#define RIDGE_FLOOR 1e-9f
/** A pivot d_j below PIVOT_FLOOR lambda refuses the attempt (d_j >= lambda when G is positive semi-definite). */
#define PIVOT_FLOOR 0.5f
/** Doublings of the bound on |L_ij| from 1 (solve_bounds): 2^18 squared is above 2^36 > 4 (2 J + f) / f. */
#define LMAX_DOUBLINGS 18u

void wake_hpa_step_gram(wake_hpa_t *h);
void wake_hpa_step_solve(wake_hpa_t *h);
/** (G + factor scale I) w = b by L D L'; 0 (the ridge rises) if a guard of the solve is not kept
 *  (WAKE_HPA_RIDGE_CENTRED: the centred solve, the attempt's first piece). */
int wake_hpa_solve_ridge(wake_hpa_t *h, float factor, float *w);
/** WAKE_HPA_RIDGE_CENTRED: the attempt's second piece, the rank one added to the centred solve in @p w. */
int wake_hpa_solve_rank_one(wake_hpa_t *h, float factor, float *w);

/* ---- wake_hpa_slice.c, wake_hpa_pieces.c ---------------------------------------------------------------------- */

/** One piece of the step the run is in, within @p budget (@p fixed: an indivisible step's cost); what it spent. */
int32_t wake_hpa_run_step(wake_hpa_t *h, int32_t budget, int32_t fixed);
/** Pieces of work until @p budget is spent; the next piece only if it fits (or comes first). */
void wake_hpa_run_pieces(wake_hpa_t *h, int32_t budget);

/* ---- wake_hpa_ahead.c: the tremor-ahead fit on its own state ------------------------------------------------- */

/** Keep @p c as the predictor of this run and the one the next run scores; @p goal the gate's goal. */
void wake_hpa_ahead_keep(const wake_hpa_t *h, wake_hpa_ahead_t *a, const float *c, float goal);
/** The previous HPA's predictor @p c (checked by the caller) and its @p index, for the next run to score. */
void wake_hpa_ahead_set_previous(wake_hpa_ahead_t *a, const float *c, uint32_t index);
/** A constant window: the gate shuts (goal 0), the previous predictor stays. */
void wake_hpa_ahead_silent(const wake_hpa_t *h, wake_hpa_ahead_t *a);
/** The predictor and goal into the run's result (the gate shut when the window is at full scale too often). */
void wake_hpa_ahead_publish(wake_hpa_t *h, wake_hpa_ahead_t *a);
/** Bin b of the DFT pass just started (X'_m in h->xr, h->xi): its oscillator for the tremor truth. */
void wake_hpa_ahead_bin(const wake_hpa_t *h, wake_hpa_ahead_t *a, unsigned b, unsigned m, float sw);
/** 1 when the fit's counters are out of their ranges in @p h's phase. */
int wake_hpa_ahead_corrupt(const wake_hpa_t *h, const wake_hpa_ahead_t *a);
int32_t wake_hpa_step_ahead_start(wake_hpa_t *h, wake_hpa_ahead_t *a, int32_t budget);
int32_t wake_hpa_step_ahead_pass(wake_hpa_t *h, wake_hpa_ahead_t *a, int32_t budget);
void wake_hpa_step_ahead_solve(wake_hpa_t *h, wake_hpa_ahead_t *a);
/** Every row of the fit is a held-out target (an HPA every L samples). */
int wake_hpa_ahead_all_held(const wake_hpa_t *h, const wake_hpa_ahead_t *a);

/* ---- the tremor-ahead fit's hooks: the instance's configuration decides, here only ---------------------------- */

#if WAKE_HPA_AHEAD
/** The instance holds the tremor-ahead fit's state. */
#define WAKE_HPA_USES_AHEAD 1
static inline void hpa_ahead_begin(wake_hpa_t *h) { h->ahead.rail = 0; }
/** 1 for a sample at full scale (INT16_MAX or INT16_MIN: clipped, or on the rail; wake.ahead.installed_goal's
 *  glitch count): u ^ (all ones when v < 0) is |v| for v >= 0 and |v| - 1 for v < 0, in 0..32767, and 32767
 *  only there; + 1 reaches 2^15. */
static inline unsigned hpa_ahead_rail(wake_q15_t v)
{
    const uint32_t u = (uint32_t)(int32_t)v;
    return ((u ^ (0u - (u >> 31))) + 1u) >> 15;
}
/** The samples at full scale counted so far in the sums pass, and their count after a chunk. */
static inline unsigned hpa_ahead_rail_so_far(const wake_hpa_t *h) { return h->ahead.rail; }
static inline void hpa_ahead_sums(wake_hpa_t *h, unsigned rail)
{
    h->ahead.rail = (uint16_t)rail;   /* <= n */
}
static inline void hpa_ahead_silent(wake_hpa_t *h) { wake_hpa_ahead_silent(h, &h->ahead); }
/** The previous HPA's predictor given to an idle instance (wake_hpa_set_previous_ahead): 1, done. */
static inline int hpa_ahead_set_previous(wake_hpa_t *h, const float *c, uint32_t index)
{
    wake_hpa_ahead_set_previous(&h->ahead, c, index);
    return 1;
}
/** The gate's truth reaches up to this frequency, Hz (0: f_d alone). */
static inline float hpa_ahead_gate_cutoff(const wake_hpa_t *h) { return h->cfg.gate_cutoff; }
static inline void hpa_ahead_install(wake_hpa_t *h)
{
    /* the result is rewritten from here to publish(), with the tremor ahead's steps (many slices) in between:
       an earlier result not taken yet is superseded now, so that take and apply never hand out this run's
       weights with the earlier run's predictor and goal */
    h->ready = 0;
}
/** After the weights: the fit's first step (1), or nothing to do (0). */
static inline int hpa_ahead_after_fit(wake_hpa_t *h)
{
    h->t = 0;
    h->d = 0;
    h->phase = STEP_AHEAD_START;
    return 1;
}
static inline void hpa_ahead_publish(wake_hpa_t *h) { wake_hpa_ahead_publish(h, &h->ahead); }
static inline void hpa_ahead_bin(wake_hpa_t *h, unsigned b, unsigned m, float sw)
{
    wake_hpa_ahead_bin(h, &h->ahead, b, m, sw);
}
static inline int hpa_ahead_corrupt(const wake_hpa_t *h) { return wake_hpa_ahead_corrupt(h, &h->ahead); }
static inline int32_t hpa_ahead_run_start(wake_hpa_t *h, int32_t budget)
{
    return wake_hpa_step_ahead_start(h, &h->ahead, budget);
}
static inline int32_t hpa_ahead_run_pass(wake_hpa_t *h, int32_t budget)
{
    return wake_hpa_step_ahead_pass(h, &h->ahead, budget);
}
static inline void hpa_ahead_run_solve(wake_hpa_t *h) { wake_hpa_step_ahead_solve(h, &h->ahead); }
static inline int hpa_ahead_all_held(const wake_hpa_t *h) { return wake_hpa_ahead_all_held(h, &h->ahead); }
/** The predictor and goal of the result into the RTP's tremor ahead. */
static inline int hpa_ahead_apply(const wake_hpa_t *h, wake_rtp_t *rtp)
{
    int32_t c[WAKE_HPA_AHEAD_TAPS];
    wake_ratio_t goal;
    (void)wake_hpa_ahead_to_rtp(&h->result, c, &goal);
    return wake_rtp_set_ahead(rtp, c, goal) == WAKE_RTP_OK;
}
#else
#define WAKE_HPA_USES_AHEAD 0
static inline void hpa_ahead_begin(wake_hpa_t *h) { (void)h; }
static inline unsigned hpa_ahead_rail(wake_q15_t v)
{
    (void)v;
    return 0u;
}
static inline unsigned hpa_ahead_rail_so_far(const wake_hpa_t *h)
{
    (void)h;
    return 0u;
}
static inline void hpa_ahead_sums(wake_hpa_t *h, unsigned rail)
{
    (void)h;
    (void)rail;
}
static inline void hpa_ahead_silent(wake_hpa_t *h) { (void)h; }
/** Without the fit's state there is no predictor to give: refused. */
static inline int hpa_ahead_set_previous(wake_hpa_t *h, const float *c, uint32_t index)
{
    (void)h;
    (void)c;
    (void)index;
    return 0;
}
/** Without the tremor ahead there is no gate: the truth's bins stop at f_d. */
static inline float hpa_ahead_gate_cutoff(const wake_hpa_t *h)
{
    (void)h;
    return 0.0f;
}
static inline void hpa_ahead_install(wake_hpa_t *h) { (void)h; }
static inline int hpa_ahead_after_fit(wake_hpa_t *h)
{
    (void)h;
    return 0;
}
static inline void hpa_ahead_publish(wake_hpa_t *h)
{
    unsigned j;
    for (j = 0; j < WAKE_HPA_AHEAD_TAPS; ++j) {
        h->result.ahead[j] = 0.0f;
    }
    h->result.ahead_goal = 0.0f;
}
static inline void hpa_ahead_bin(wake_hpa_t *h, unsigned b, unsigned m, float sw)
{
    (void)h;
    (void)b;
    (void)m;
    (void)sw;
}
/** Without the fit's state no run reaches its steps. */
static inline int hpa_ahead_corrupt(const wake_hpa_t *h) { return h->phase > STEP_SOLVE; }
static inline int32_t hpa_ahead_run_start(wake_hpa_t *h, int32_t budget)
{
    (void)h;
    return budget;
}
static inline int32_t hpa_ahead_run_pass(wake_hpa_t *h, int32_t budget)
{
    (void)h;
    return budget;
}
static inline void hpa_ahead_run_solve(wake_hpa_t *h) { (void)h; }
static inline int hpa_ahead_all_held(const wake_hpa_t *h)
{
    (void)h;
    return 0;
}
static inline int hpa_ahead_apply(const wake_hpa_t *h, wake_rtp_t *rtp)
{
    (void)h;
    (void)rtp;
    return 1;
}
#endif

#endif /* WAKE_HPA_INTERNAL_H */
