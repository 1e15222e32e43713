/**
 * @file eva_hpa_steps.c
 * @brief Frama-C Eva entries for the steps of one HPA run (csrc/wake_hpa*.c), each from a state whose
 *        fields are ranged as the step's precondition, each checking (`//@ assert`) the postcondition
 *        the next step assumes (make -C csrc prove; docs/studies/verification.md, "A whole HPA run").
 *
 * The steps are the HPA's internal functions: this file reaches them through csrc/internal/wake_hpa_internal.h
 * (it is only ever given to Frama-C, with the HPA's sources, never compiled into the library).  Every entry starts from an instance wake_hpa_init accepted with the
 * default configuration (J = 5, p = 17, L = 500) and any filter bank, and a run begun on a window of
 * any int16 samples of each length the default schedule starts (the warm-up windows of 100, 200, 300
 * and 400 samples and the full window of 500), then
 * ranges the fields the step reads as the steps before it guarantee.  wake_hpa_run gives every loop
 * step its whole loop in one piece (a budget of INT32_MAX / 2): the entries call the step the same way.
 * The *_chunk entries call a loop step as a sliced run does: from any index of its loop (an interval), with
 * the fields it carries between chunks within its invariant and any budget (docs/studies/verification.md, "Chunks
 * of a sliced run"): the spectrum, the DFT pass, the ramp and the diagonals of Rxx B' (eva_step_diag_chunk, from
 * any diag: the step clamps what a chunk loads to its bound) and a bin's slide (eva_step_bin_end_chunk, from any
 * Q_m and phasors: the step clamps them where a chunk loads them and its phasors every SLIDE_BLOCK rows).
 * The integer chunk entries (eva_step_sums_chunk, eva_step_lags_chunk) call an integer loop step from any index of its
 * loop with a small budget, and the dispatch entries (eva_dispatch_slice, eva_dispatch_run) run wake_hpa_slice
 * and wake_hpa_run from a run in any phase with run_step's contract instead of its body (docs/studies/verification.md,
 * "The dispatch and the integer chunks").
 */
#include <float.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include "__fc_builtin.h"
#include "internal/wake_hpa_internal.h"

/* ---- the ranges: each is a postcondition of one step and a precondition of the next ---------------- */
/** |x| <= 2^15 */
#define X_MAX 32768LL
/** the default configuration's L, 2^J and p */
#define L_MAX 500LL
#define N_TAPS 32u
/** |S|, |sum_{t < rows} x|, |P(rows + d)| <= 2^15 L */
#define SUM_MAX (X_MAX * L_MAX)
/** |T| = |sum t x(t)| <= 2^15 L (L - 1) / 2 */
#define TSUM_MAX (X_MAX * L_MAX * (L_MAX - 1LL) / 2LL)
/** |lag sum| <= 2^30 L < 2^39 */
#define ACC_MAX (1LL << 39)
/** |n^2 r(d)|, |n^2 Rxx(i, i + d)| < 2^60 */
#define R_MAX (1LL << 60)
/** |mean| < 2^18 (S / n, n >= 64), |slope| < 2^11 (2^16 / 63), |wsum| < 2^29 */
#define MEAN_MAX 0x1p18f
#define SLOPE_MAX 0x1p11f
#define WSUM_MAX 0x1p29f
/**
 * |Rxx(i, i + d) B[l][j]| = |z| / n^2 |B| < 2^49: an envelope of Rxx B' (not its tight bound) in which a term
 * is below half an ulp, so the envelope is an invariant of every lag's diagonal
 */
#define BANK_MAX 0x1p76f
#define BANK_MAX_R 75557863725914323419136.0
/** |a[i]| <= 2^m after order m of Levinson-Durbin (|k| <= 1): 2^17 after p = 17 */
#define A_MAX 0x1p17f
#define A_MAX_R 131072.0
/** |D(f_k)| = |A(e^{j theta})|^2 <= DEN_MAX (D >= 0; the intervals of re re + im im do not see the squares) */
#define DEN_MAX 0x1p100f
#define DEN_MAX_R 1267650600228229401496703205376.0

/**
 * The DFT pass's Reinsch states (STEP_DFT's postcondition, shown by eva_step_dft below): the bounds internal/wake_bounds.h
 * clamps them to every REINSCH_BLOCK samples, 2^33 for s and 2^34 for d in this build (WAKE_HPA_MAX_WINDOW <= 512).
 * The clamp never fires on a window of int16 samples (docs/reference/verification.md#bound-reinsch).
 */
#define DFT_S_MAX REINSCH_S_MAX
#define DFT_D_MAX REINSCH_D_MAX
#define DFT_S_MAX_R 8589934592.0
#define DFT_D_MAX_R 17179869184.0
/** |X'_m|, |Q_m| (re and im) of one bin from the states above */
#define XQ_MAX 0x1p38f
#define XQ_MAX_R 274877906944.0
/**
 * Envelopes, not tight bounds, of the sums over the bins: sum |X'|^2, sum Re X' conj R, Cxy and v_c(t < 2^J).
 * Each is large enough that one bin's (or the ramp's) term is below half an ulp of it, so float addition
 * keeps a sum inside: the envelope is an invariant of every bin, which the entries below check.
 */
#define POWER_MAX 0x1p104f
#define POWER_MAX_R 20282409603651670423947251286016.0
#define CXY_MAX 0x1p104f
#define CXY_MAX_R 20282409603651670423947251286016.0
#define VHEAD_MAX 0x1p60f
#define VHEAD_MAX_R 1152921504606846976.0
/**
 * The normal equations STEP_GRAM leaves, envelopes from the ones above: |G| <= 32 BANK_MAX + the mean's terms
 * (< 2^59) < 2^82, |b| <= 32 CXY_MAX + the mean's terms (< 2^89) < 2^110, |y'y| <= 32 VHEAD_MAX^2 + the bins' and
 * the line's terms (< 2^112) < 2^126, |R| <= 2 POWER_MAX / n + the line's terms < 2^100; trace(G) / J within G's.
 */
#define G_MAX 0x1p82f
#define G_MAX_R 4835703278458516698824704.0
#define B_MAX 0x1p110f
#define B_MAX_R 1298074214633706907132624082305024.0
#define YY_MAX 0x1p126f
#define YY_MAX_R 85070591730234615865843651857942052864.0
#define NOISE_MAX 0x1p100f
#define NOISE_MAX_R 1267650600228229401496703205376.0

static wake_q15_t taps[WAKE_HPA_MAX_LEVEL * WAKE_HPA_MAX_TAPS];
static wake_q15_t window[WAKE_HPA_MAX_WINDOW];
static float weights[WAKE_HPA_MAX_LEVEL];
static wake_hpa_config_t cfg;
static wake_hpa_t hpa;

static int64_t any64(int64_t lo, int64_t hi)
{
    return Frama_C_long_long_interval(lo, hi);
}

static float anyf(float lo, float hi)
{
    return Frama_C_float_interval(lo, hi);
}

/**
 * A chunk's budget, any in [1, INT32_MAX / 2], in the range q of ranges on which the chunk's length is one value:
 * q = 0 .. @p n - 1 a budget of q items at @p cost (below one item's cost for q = 0), q = n every budget of at least
 * n items (a whole loop of n items).  Intervals alone do not relate what a chunk spends, min(budget / cost, what is
 * left) items, to the budget it was given; within one range they do.  The caller splits q (one Eva state each) in
 * its own scope, where the split lasts until the assertions after the step.
 */
static int32_t budget_range(int q, unsigned n, int32_t cost)
{
    if (q == 0) {
        return Frama_C_int_interval(1, cost - 1);
    }
    if (q < (int)n) {
        return Frama_C_int_interval(q * cost, q * cost + cost - 1);
    }
    return Frama_C_int_interval(q * cost, INT32_MAX / 2);
}

/** The default configuration, any filter bank (init takes any Q15 taps), weights init accepts. */
static int initialised(void)
{
    unsigned j;
    (void)wake_hpa_default_config(&cfg);
    Frama_C_make_unknown((char *)taps, sizeof taps);
    for (j = 0; j < WAKE_HPA_MAX_LEVEL; ++j) {
        weights[j] = anyf(-(float)WAKE_HPA_WEIGHT_LIMIT, (float)WAKE_HPA_WEIGHT_LIMIT);
    }
    Frama_C_make_unknown((char *)window, sizeof window);
    return wake_hpa_init(&hpa, &cfg, taps, weights) == WAKE_HPA_OK;
}

/**
 * A run begun on a window of any int16 samples, of each length the default schedule starts: the
 * warm-up points 100 .. 400 and the full window, one Eva state each.
 */
static void begun(void)
{
    wake_hpa_begin(&hpa, window, (uint16_t)(100 * Frama_C_interval_split(1, 5)), 0u);
}

static int started(void)
{
    if (!initialised()) {
        return 0;
    }
    begun();
    return 1;
}

/** After STEP_SUMS (not silent): the exact sums, the mean and the end-point slope. */
static void any_sums(void)
{
    hpa.sum = any64(-SUM_MAX, SUM_MAX);
    hpa.prefix_rows = any64(-SUM_MAX, SUM_MAX);
    hpa.tsum = any64(-TSUM_MAX, TSUM_MAX);
    hpa.tsum_rows = any64(-TSUM_MAX, TSUM_MAX);
    hpa.mean = anyf(-MEAN_MAX, MEAN_MAX);
    hpa.slope = anyf(-SLOPE_MAX, SLOPE_MAX);
}

static void post_sums(void)
{
    /*@ assert -SUM_MAX <= hpa.sum <= SUM_MAX && -SUM_MAX <= hpa.prefix_rows <= SUM_MAX; */
    /*@ assert -TSUM_MAX <= hpa.tsum <= TSUM_MAX && -TSUM_MAX <= hpa.tsum_rows <= TSUM_MAX; */
    /*@ assert -MEAN_MAX <= hpa.mean <= MEAN_MAX && -SLOPE_MAX <= hpa.slope <= SLOPE_MAX; */
    /*@ assert -X_MAX * hpa.rows <= hpa.prefix_hi <= X_MAX * hpa.rows && hpa.prefix_lo == 0 && hpa.suffix == 0; */
}

/**
 * Lag d (STEP_LAGS, STEP_LAG_END, STEP_DIAG): the prefix sums of d samples, P(d) and the suffix, within
 * 2^15 d; P(rows + d) within 2^15 (rows + d).
 */
static void any_lag_state(unsigned d)
{
    any_sums();
    hpa.d = (uint16_t)d;
    hpa.prefix_lo = any64(-X_MAX * (int64_t)d, X_MAX * (int64_t)d);
    hpa.suffix = any64(-X_MAX * (int64_t)d, X_MAX * (int64_t)d);
    hpa.prefix_hi = any64(-X_MAX * (int64_t)(hpa.rows + d), X_MAX * (int64_t)(hpa.rows + d));
}

/** Lag d done: the prefix sums of d + 1 samples (hpa.d is d + 1 now). */
static void post_lag_state(void)
{
    /*@ assert -X_MAX * hpa.d <= hpa.prefix_lo <= X_MAX * hpa.d && -X_MAX * hpa.d <= hpa.suffix <= X_MAX * hpa.d; */
    /*@ assert -X_MAX * (hpa.rows + hpa.d) <= hpa.prefix_hi <= X_MAX * (hpa.rows + hpa.d); */
    /*@ assert hpa.phase == STEP_LAGS || hpa.phase == STEP_LEVINSON; */
    /*@ assert hpa.d <= hpa.lags; */
}

void eva_step_sums(void)
{
    if (!started()) {
        return;
    }
    (void)wake_hpa_step_sums(&hpa, INT32_MAX / 2);
    if (hpa.phase == STEP_LAGS) {
        post_sums();
    } else {
        /*@ assert hpa.phase == STEP_IDLE; */
    }
}

void eva_step_lags(void)
{
    if (!started()) {
        return;
    }
    any_lag_state((unsigned)Frama_C_interval_split(0, (int)hpa.lags - 1));
    hpa.phase = STEP_LAGS;
    (void)wake_hpa_step_lags(&hpa, INT32_MAX / 2);
    /*@ assert -ACC_MAX <= hpa.acc_head <= ACC_MAX && -ACC_MAX <= hpa.acc_tail <= ACC_MAX; */
    /*@ assert hpa.phase == STEP_LAG_END; */
}

void eva_step_lag_end(void)
{
    if (!started()) {
        return;
    }
    any_lag_state((unsigned)Frama_C_interval_split(0, (int)hpa.lags - 1));
    hpa.phase = STEP_LAG_END;
    hpa.acc_head = any64(-ACC_MAX, ACC_MAX);
    hpa.acc_tail = any64(-ACC_MAX, ACC_MAX);
    wake_hpa_step_lag_end(&hpa);
    /*@ assert -R_MAX <= hpa.diag <= R_MAX; */
    /*@ assert \forall integer i; 0 <= i <= 17 ==> -R_MAX <= hpa.r[i] <= R_MAX; */
    /*@ assert \forall integer i; 0 <= i < 32 ==> -WSUM_MAX <= hpa.wsum[i] <= WSUM_MAX; */
    /* what the dispatch's contract of run_step assumes (the phase and d) */
    /*@ assert (hpa.phase == STEP_DIAG && hpa.t == 0) || hpa.phase == STEP_LAGS || hpa.phase == STEP_LEVINSON; */
    /*@ assert hpa.d <= hpa.lags; */
}

void eva_step_diag(void)
{
    unsigned i;
    if (!initialised()) {
        return;
    }
    /* an envelope, not the tight bound: |Rxx B'| <= 2^15 2 * 2^49 after the last lag, but a d-dependent bound
       would need the d split before this loop (too many states); 2^76 absorbs each term (< 2^49, half an ulp
       of 2^76 is 2^52), so the envelope is kept exactly in float arithmetic */
    for (i = 0; i < WAKE_HPA_MAX_TAPS * WAKE_HPA_MAX_LEVEL; ++i) {
        hpa.bank_rxx[i] = anyf(-BANK_MAX, BANK_MAX);
    }
    begun();
    any_lag_state((unsigned)Frama_C_interval_split(0, (int)N_TAPS - 1));
    hpa.phase = STEP_DIAG;
    hpa.diag = any64(-R_MAX, R_MAX);
    (void)wake_hpa_step_diag(&hpa, INT32_MAX / 2);
    /*@ assert \forall integer i; 0 <= i < WAKE_HPA_MAX_TAPS * WAKE_HPA_MAX_LEVEL ==>
               -BANK_MAX_R <= hpa.bank_rxx[i] <= BANK_MAX_R; */
    post_lag_state();
}

/**
 * A chunk of lag d's diagonal (STEP_DIAG) as a sliced run gives it: from any row t < 2^J - d (an interval on either
 * side of the row from which the chunk ends the lag, one state each) of every lag d < 2^J (one Eva state each), diag
 * any int64 (wake_hpa_spectrum.c clamps it to DIAG_MAX, its bound at every row, when a chunk loads it, so no interval of it
 * need be an invariant), Rxx B' within its envelope, the prefix sums of lag d, the sums as STEP_SUMS leaves them, each
 * window length of the schedule (one state each), any budget (budget_range).  Postcondition: Rxx B' within its envelope; t < 2^J - d (STEP_DIAG) or the lag done (next_lag:
 * t = 0, the prefix sums of d + 1, STEP_LAGS or STEP_LEVINSON); 0 < r <= max(budget, cost).
 */
void eva_step_diag_chunk(void)
{
    unsigned i, d;
    int32_t budget, r;
    int q;
    if (!initialised()) {
        return;
    }
    for (i = 0; i < WAKE_HPA_MAX_TAPS * WAKE_HPA_MAX_LEVEL; ++i) {
        hpa.bank_rxx[i] = anyf(-BANK_MAX, BANK_MAX);
    }
    begun();
    d = (unsigned)Frama_C_interval_split(0, (int)N_TAPS - 1);
    any_lag_state(d);
    hpa.phase = STEP_DIAG;
    hpa.diag = any64(INT64_MIN, INT64_MAX);
    q = Frama_C_interval_split(0, (int)(N_TAPS - d));
    budget = budget_range(q, N_TAPS - d, COST_DIAG);
    {
        /* the chunk from t runs max(q, 1) rows or the rest, and ends the lag iff t >= edge: t drawn on either side
           of the edge, one state each, so that each state leaves the step (whose states are joined inside it) with
           one outcome */
        const unsigned rows_q = q == 0 ? 1u : (unsigned)q;
        const unsigned edge = rows_q >= N_TAPS - d ? 0u : N_TAPS - d - rows_q;
        if (edge > 0u && Frama_C_interval_split(0, 1) == 1) {
            hpa.t = Frama_C_unsigned_short_interval(0u, (uint16_t)(edge - 1u));
        } else {
            hpa.t = Frama_C_unsigned_short_interval((uint16_t)edge, (uint16_t)(N_TAPS - 1u - d));
        }
    }
    r = wake_hpa_step_diag(&hpa, budget);
    /*@ assert \forall integer i; 0 <= i < WAKE_HPA_MAX_TAPS * WAKE_HPA_MAX_LEVEL ==>
               -BANK_MAX_R <= hpa.bank_rxx[i] <= BANK_MAX_R; */
    if (hpa.phase == STEP_DIAG) {
        /*@ assert hpa.d == d && 0 < hpa.t < N_TAPS - d; */
    } else {
        /*@ assert hpa.d == d + 1 && hpa.t == 0; */
        post_lag_state();
    }
    /*@ assert 0 < r <= (budget > COST_DIAG ? budget : COST_DIAG); */
}

/**
 * One order of Levinson-Durbin, order m = t + 1 for each t < p (the driver's loop, unrolled: one
 * analysis per order), from r(0 .. p) as STEP_LAG_END leaves them, a prediction error of any sign within
 * R_MAX and, before order m, the coefficients |a[i]| <= 2^(m - 1) (a[0] = 1): after it |a[i]| <= 2^m and
 * the error still within R_MAX.
 */
void eva_step_levinson(void)
{
    unsigned i, t;
    if (!initialised()) {
        return;
    }
    /* the step reads no field of n but the order, p = 17 for every window of the schedule: the full one */
    wake_hpa_begin(&hpa, window, hpa.cfg.window, 0u);
    /*@ loop unroll WAKE_HPA_MAX_ORDER; */
    for (t = 0; t < hpa.order; ++t) {
        const float before = (float)(1u << (t == 0u ? 0u : t - 1u)), after = (float)(1u << t);
        for (i = 0; i <= WAKE_HPA_MAX_ORDER; ++i) {
            hpa.r[i] = anyf(-(float)R_MAX, (float)R_MAX);
            hpa.a[i] = anyf(-before, before);
        }
        hpa.a[0] = 1.0f;
        hpa.err = anyf(-(float)R_MAX, (float)R_MAX);
        /* what the previous order may have written: one state again */
        hpa.flag = WAKE_HPA_VALLEY;
        hpa.cutoff = 0.0f;
        hpa.peak = 0;
        hpa.prev1 = 0.0f;
        hpa.prev2 = 0.0f;
        hpa.den_floor = 0.0f;
        hpa.psd_end = 0;
        hpa.phase = STEP_LEVINSON;
        hpa.t = (uint16_t)t;
        wake_hpa_step_levinson(&hpa);
        /*@ assert hpa.phase == STEP_LEVINSON || hpa.phase == STEP_PSD || hpa.phase == STEP_CUTOFF; */
        /*@ assert hpa.phase == STEP_LEVINSON ==> hpa.t == t + 1; */
        /*@ assert hpa.a[0] == 1.0f; */
        /*@ assert \forall integer i; 0 <= i <= WAKE_HPA_MAX_ORDER ==> -after <= hpa.a[i] <= after; */
        /*@ assert -R_MAX <= hpa.err <= R_MAX; */
    }
}

/** D(f_k) of every bin within DEN_MAX (this run's and, for the bins it does not write, earlier runs'). */
static void any_den(void)
{
    unsigned k;
    for (k = 0; k < WAKE_HPA_MAX_PSD_BINS; ++k) {
        hpa.den[k] = anyf(-DEN_MAX, DEN_MAX);
    }
}

static void post_den(void)
{
    /*@ assert \forall integer k; 0 <= k < WAKE_HPA_MAX_PSD_BINS ==> -DEN_MAX_R <= hpa.den[k] <= DEN_MAX_R; */
    /*@ assert -DEN_MAX_R <= hpa.den_peak <= DEN_MAX_R && -DEN_MAX_R <= hpa.den_floor <= DEN_MAX_R; */
}

/** The AR polynomial Levinson-Durbin leaves (order p), the spectrum's bins and the tremor peak. */
void eva_step_psd(void)
{
    unsigned i;
    if (!started()) {
        return;
    }
    any_den();
    hpa.a[0] = 1.0f;
    for (i = 1; i <= WAKE_HPA_MAX_ORDER; ++i) {
        hpa.a[i] = anyf(-A_MAX, A_MAX);
    }
    hpa.t = 0;
    hpa.peak = NO_PEAK;
    hpa.prev1 = 0.0f;
    hpa.prev2 = 0.0f;
    hpa.den_floor = 0.0f;
    hpa.den_peak = anyf(-DEN_MAX, DEN_MAX);
    hpa.psd_end = (uint16_t)psd_last(&hpa);
    hpa.phase = STEP_PSD;
    (void)wake_hpa_step_psd(&hpa, INT32_MAX / 2);
    /*@ assert hpa.phase == STEP_CUTOFF; */
    post_den();
}

/**
 * A chunk of the spectrum as a sliced run gives it: from any item t of the pass (an interval over 0 .. psd_last, not
 * split), with every field the pass carries between chunks within the pass's invariant (D of every bin, the two
 * previous bins', the peak's and the floor's within DEN_MAX, the peak any bin), and any budget (budget_range).  The
 * step reads no field of n: the full window.  Postcondition: the invariant, t <= psd_last (0 when the pass ends,
 * STEP_CUTOFF next) and 0 < r <= max(budget, cost).
 */
void eva_step_psd_chunk(void)
{
    unsigned i;
    int32_t budget, cost, r;
    int q;
    if (!initialised()) {
        return;
    }
    wake_hpa_begin(&hpa, window, hpa.cfg.window, 0u);
    any_den();
    hpa.a[0] = 1.0f;
    for (i = 1; i <= WAKE_HPA_MAX_ORDER; ++i) {
        hpa.a[i] = anyf(-A_MAX, A_MAX);
    }
    hpa.psd_end = (uint16_t)psd_last(&hpa);
    hpa.t = Frama_C_unsigned_short_interval(0u, hpa.psd_end);
    hpa.peak = Frama_C_unsigned_short_interval(0u, UINT16_MAX);
    hpa.prev1 = anyf(-DEN_MAX, DEN_MAX);
    hpa.prev2 = anyf(-DEN_MAX, DEN_MAX);
    hpa.den_floor = anyf(-DEN_MAX, DEN_MAX);
    hpa.den_peak = anyf(-DEN_MAX, DEN_MAX);
    hpa.phase = STEP_PSD;
    cost = cost_psd_bin(&hpa);
    q = Frama_C_interval_split(0, (int)hpa.psd_end + 1);
    budget = budget_range(q, hpa.psd_end + 1u, cost);
    r = wake_hpa_step_psd(&hpa, budget);
    /*@ assert (hpa.phase == STEP_PSD && 0 < hpa.t <= hpa.psd_end) || (hpa.phase == STEP_CUTOFF && hpa.t == 0); */
    post_den();
    /*@ assert -DEN_MAX_R <= hpa.prev1 <= DEN_MAX_R && -DEN_MAX_R <= hpa.prev2 <= DEN_MAX_R; */
    /*@ assert 0 < r <= (budget > cost ? budget : cost); */
}

/** The valley rule on any spectrum STEP_PSD can leave (or a silent Levinson's default cut-off). */
void eva_step_cutoff(void)
{
    if (!started()) {
        return;
    }
    any_den();
    hpa.den_peak = anyf(-DEN_MAX, DEN_MAX);
    hpa.den_floor = anyf(-DEN_MAX, DEN_MAX);
    /* the peak is only ever taken with min(., cut_hi) or min(., cut_shallow): any value */
    hpa.peak = Frama_C_unsigned_short_interval(0u, UINT16_MAX);
    if (Frama_C_nondet(0, 1)) {
        hpa.flag = WAKE_HPA_SILENT;
        hpa.cutoff = hpa.cfg.default_cutoff;
    }
    hpa.phase = STEP_CUTOFF;
    wake_hpa_step_cutoff(&hpa);
    /*@ assert hpa.phase == STEP_BINS; */
    /*@ assert 0.0 <= hpa.cutoff <= hpa.cfg.cutoff_high; */
}

/** The DFT bins at or below the cut-off, the first pass set up. */
void eva_step_bins(void)
{
    if (!started()) {
        return;
    }
    hpa.cutoff = anyf(0.0f, hpa.cfg.cutoff_high);
    hpa.phase = STEP_BINS;
    wake_hpa_step_bins(&hpa);
    /*@ assert hpa.bins <= 6 * hpa.n / 100 && hpa.m == 1; */
    /*@ assert hpa.phase == STEP_DFT || (hpa.phase == STEP_RAMP && hpa.bins == 0); */
    /*@ assert -4.0 <= hpa.lam[0] <= 0.0 && -4.0 <= hpa.lam[1] <= 0.0; */
    /*@ assert hpa.phase == STEP_DFT ==> 1 <= hpa.pair <= 2; */
}

/** The sums over the bins and the targets, within their envelopes (earlier bins' terms). */
static void any_bin_sums(void)
{
    unsigned i;
    hpa.power = anyf(-POWER_MAX, POWER_MAX);
    hpa.cross = anyf(-POWER_MAX, POWER_MAX);
    for (i = 0; i < WAKE_HPA_MAX_TAPS; ++i) {
        hpa.cxy[i] = anyf(-CXY_MAX, CXY_MAX);
        hpa.vhead[i] = anyf(-VHEAD_MAX, VHEAD_MAX);
        hpa.wsum[i] = anyf(-WSUM_MAX, WSUM_MAX);
    }
}

static void post_bin_sums(void)
{
    /*@ assert -POWER_MAX_R <= hpa.power <= POWER_MAX_R && -POWER_MAX_R <= hpa.cross <= POWER_MAX_R; */
    /*@ assert \forall integer i; 0 <= i < WAKE_HPA_MAX_TAPS ==> -CXY_MAX_R <= hpa.cxy[i] <= CXY_MAX_R; */
    /*@ assert \forall integer i; 0 <= i < WAKE_HPA_MAX_TAPS ==> -VHEAD_MAX_R <= hpa.vhead[i] <= VHEAD_MAX_R; */
}

/** The Reinsch states of a pass in progress, and the ones kept at t = rows, within the clamp bounds. */
static void any_dft_states(void)
{
    unsigned b;
    for (b = 0; b < 2u; ++b) {
        hpa.gs[b] = anyf(-DFT_S_MAX, DFT_S_MAX);
        hpa.hs[b] = anyf(-DFT_S_MAX, DFT_S_MAX);
        hpa.gd[b] = anyf(-DFT_D_MAX, DFT_D_MAX);
        hpa.hd[b] = anyf(-DFT_D_MAX, DFT_D_MAX);
    }
}

static void post_dft_states(void)
{
    /*@ assert -DFT_S_MAX_R <= hpa.gs[0] <= DFT_S_MAX_R && -DFT_D_MAX_R <= hpa.gd[0] <= DFT_D_MAX_R; */
    /*@ assert -DFT_S_MAX_R <= hpa.gs[1] <= DFT_S_MAX_R && -DFT_D_MAX_R <= hpa.gd[1] <= DFT_D_MAX_R; */
    /*@ assert -DFT_S_MAX_R <= hpa.hs[0] <= DFT_S_MAX_R && -DFT_D_MAX_R <= hpa.hd[0] <= DFT_D_MAX_R; */
    /*@ assert -DFT_S_MAX_R <= hpa.hs[1] <= DFT_S_MAX_R && -DFT_D_MAX_R <= hpa.hd[1] <= DFT_D_MAX_R; */
}

/**
 * A DFT pass of a run begun on each window length of the schedule, the sums as STEP_SUMS guarantees them, one bin
 * or two (one Eva state each), each lambda in [-4, 0] (every bin 1 <= m < n / 2 of any configuration; the default
 * configuration's, m <= 6 n / 100, lie in [-0.15, 0]); 0 when init refuses.
 */
static int dft_pass_set(void)
{
    unsigned b;
    if (!initialised()) {
        return 0;
    }
    begun();
    any_sums();
    hpa.pair = (uint16_t)Frama_C_interval_split(1, 2);
    for (b = 0; b < 2u; ++b) {
        hpa.lam[b] = anyf(-4.0f, 0.0f);
    }
    return 1;
}

/**
 * One DFT pass (STEP_DFT) as wake_hpa_run runs it: from t = 0 with start_pass's zero states, the whole pass in
 * one piece (a budget of INT32_MAX / 2), for every window length of the schedule, one bin or two (one Eva state
 * each), each lambda in [-4, 0] (every bin 1 <= m < n / 2 of any configuration; the default configuration's,
 * m <= 6 n / 100, lie in [-0.15, 0]), the window's mean as STEP_SUMS guarantees it.  Postcondition: the states
 * STEP_BIN_START reads, s and d at the pass's end and at t = rows, within DFT_S_MAX and DFT_D_MAX.
 */
void eva_step_dft(void)
{
    unsigned b;
    if (!dft_pass_set()) {
        return;
    }
    for (b = 0; b < 2u; ++b) {
        hpa.gs[b] = 0.0f;
        hpa.hs[b] = 0.0f;
        hpa.gd[b] = 0.0f;
        hpa.hd[b] = 0.0f;
    }
    hpa.t = 0;
    hpa.phase = STEP_DFT;
    (void)wake_hpa_step_dft(&hpa, INT32_MAX / 2);
    /*@ assert hpa.phase == STEP_BIN_START && hpa.t == 0 && hpa.d == 0; */
    post_dft_states();
}

/**
 * A chunk of a DFT pass as a sliced run gives it: from any sample t of the pass (an interval over [0, n), not
 * split) with the states any within the clamp bounds (the pass's invariant: the clamps at the end of every block
 * and every run keep them there), any budget, one bin or two, each lambda in [-4, 0], the mean as STEP_SUMS
 * guarantees it.  Postcondition: the invariant, the pass's next sample t <= n (0 when the pass ends, STEP_BIN_START
 * next), and what the chunk spent within what the dispatch allows, 0 < r <= max(budget, cost).
 * The budget: any, in the ranges of budget_range (one state each).
 */
void eva_step_dft_chunk(void)
{
    int32_t budget, cost, r;
    int q;
    if (!dft_pass_set()) {
        return;
    }
    any_dft_states();
    hpa.t = (uint16_t)Frama_C_unsigned_int_interval(0u, hpa.n - 1u);
    hpa.phase = STEP_DFT;
    cost = hpa.pair == 2u ? COST_DFT2 : COST_DFT1;
    q = Frama_C_interval_split(0, (int)hpa.n);
    budget = budget_range(q, hpa.n, cost);
    r = wake_hpa_step_dft(&hpa, budget);
    /*@ assert (hpa.phase == STEP_DFT && 0 < hpa.t < hpa.n) || (hpa.phase == STEP_BIN_START && hpa.t == 0 && hpa.d == 0); */
    post_dft_states();
    /*@ assert 0 < r <= (budget > cost ? budget : cost); */
}

/**
 * One bin of a pass: its X'_m and Q_m(0) from the pass's states (STEP_BIN_START), then its slide over the
 * 2^J fit rows (STEP_BIN_END), for every bin m of the cut-off range of every window length (one Eva state
 * each: the phasors are then single values) and either bin of a pass.  Precondition: the pass's states
 * within the hand bound above, lambda of the bin, the sums over the bins within their envelopes.
 */
void eva_step_bin(void)
{
    unsigned b;
    if (!initialised()) {
        return;
    }
    any_bin_sums();
    begun();
    any_sums();
    /* m fs / n <= cutoff_high = 6 Hz: m <= 6 n / 100 */
    hpa.m = (uint16_t)Frama_C_interval_split(1, (int)(6u * hpa.n / 100u));
    hpa.bins = (uint16_t)(6u * hpa.n / 100u);
    wake_hpa_start_pass(&hpa);
    for (b = 0; b < 2u; ++b) {
        hpa.gs[b] = anyf(-DFT_S_MAX, DFT_S_MAX);
        hpa.hs[b] = anyf(-DFT_S_MAX, DFT_S_MAX);
        hpa.gd[b] = anyf(-DFT_D_MAX, DFT_D_MAX);
        hpa.hd[b] = anyf(-DFT_D_MAX, DFT_D_MAX);
    }
    hpa.d = (uint16_t)Frama_C_interval_split(0, (int)hpa.pair - 1);
    hpa.phase = STEP_BIN_START;
    wake_hpa_step_bin_start(&hpa);
    /*@ assert -XQ_MAX_R <= hpa.xr <= XQ_MAX_R && -XQ_MAX_R <= hpa.xi <= XQ_MAX_R; */
    /*@ assert -XQ_MAX_R <= hpa.qr <= XQ_MAX_R && -XQ_MAX_R <= hpa.qi <= XQ_MAX_R; */
    /*@ assert hpa.phase == STEP_BIN_END && hpa.t == 0; */
    (void)wake_hpa_step_bin_end(&hpa, INT32_MAX / 2);
    /*@ assert hpa.phase == STEP_BIN_START || hpa.phase == STEP_DFT || hpa.phase == STEP_RAMP; */
    /*@ assert -4.0 <= hpa.lam[0] <= 0.0 && -4.0 <= hpa.lam[1] <= 0.0; */
    /*@ assert 1 <= hpa.pair <= 2 && hpa.d < hpa.pair; */
    post_bin_sums();
}

/**
 * The carried state of a slide the chunk entry below starts from: wider than the bounds step_bin_end clamps it
 * to at the start of every block of rows, the first where a chunk loads it (PHASOR_MAX, SLIDE_Q_MAX = 2^36 in this
 * build), so that the clamp is what restores the invariant.  After a chunk, the state its last block of at most 4
 * rows leaves: Q_m within 2^36 + 4 2^21 < 2^37, the phasor parts within PHASOR_MAX 1.37^4 < 4 (the next chunk
 * clamps them again).
 */
#define SLIDE_PH_IN 2.0f
#define SLIDE_Q_IN 0x1p100f
#define SLIDE_Q_OUT_R 137438953472.0
#define SLIDE_PH_OUT_R 4.0
/** cos w and sin w of every bin of the default schedule, w = 2 pi m / n <= 2 pi 0.06 (m <= 6 n / 100) */
#define ROT_COS_MIN 0.9297f
#define ROT_SIN_MAX 0.3682f

/**
 * A chunk of a bin's slide (STEP_BIN_END) as a sliced run gives it: from any row t < 2^J (an interval on either side
 * of the row from which the chunk ends the slide, one state each), for every window length of the schedule (one
 * state each), any bin of the pass (m an interval: m < bins with a pass of two bins, m = bins with one; d either
 * bin of the pass, one state each), its rotation e^{j w} any in the box of the schedule's bins, X'_m within the
 * bound step_bin_start leaves (XQ_MAX), the carried Q_m and phasors any in a box wider than the clamps, the sums
 * over the bins within their envelopes, the mean as STEP_SUMS guarantees it, any budget (budget_range).
 * Postcondition: Cxy and vhead within their envelopes; STEP_BIN_END with 0 < t < 2^J, the phasors within 4 and Q_m
 * within 2^37 (finite: the next chunk clamps them where it loads them), or the slide done (next_bin: t = 0, the next
 * bin's STEP_BIN_START, the next pass's STEP_DFT or STEP_RAMP, lambda in [-4, 0], d < pair);
 * 0 < r <= max(budget, cost).
 */
void eva_step_bin_end_chunk(void)
{
    unsigned b, bins;
    int32_t budget, r;
    int q;
    if (!initialised()) {
        return;
    }
    any_bin_sums();
    begun();
    any_sums();
    bins = 6u * hpa.n / 100u;
    hpa.bins = (uint16_t)bins;
    hpa.pair = (uint16_t)Frama_C_interval_split(1, 2);
    if (hpa.pair == 2u) {
        hpa.m = Frama_C_unsigned_short_interval(1u, (uint16_t)(bins - 1u));
    } else {
        hpa.m = (uint16_t)bins;
    }
    hpa.d = (uint16_t)Frama_C_interval_split(0, (int)hpa.pair - 1);
    for (b = 0; b < 2u; ++b) {
        hpa.lam[b] = anyf(-4.0f, 0.0f);
    }
    hpa.rot[0] = anyf(ROT_COS_MIN, 1.0f);
    hpa.rot[1] = anyf(0.0f, ROT_SIN_MAX);
    hpa.xr = anyf(-XQ_MAX, XQ_MAX);
    hpa.xi = anyf(-XQ_MAX, XQ_MAX);
    hpa.qr = anyf(-SLIDE_Q_IN, SLIDE_Q_IN);
    hpa.qi = anyf(-SLIDE_Q_IN, SLIDE_Q_IN);
    for (b = 0; b < 6u; ++b) {
        hpa.ph[b] = anyf(-SLIDE_PH_IN, SLIDE_PH_IN);
    }
    hpa.phase = STEP_BIN_END;
    q = Frama_C_interval_split(0, (int)N_TAPS);
    budget = budget_range(q, N_TAPS, COST_SLIDE);
    {
        /* the chunk from t runs max(q, 1) rows or the rest, and ends the slide iff t >= edge: t drawn on either
           side of the edge, one state each, so that each state leaves the step with one outcome */
        const unsigned rows_q = q == 0 ? 1u : (unsigned)q;
        const unsigned edge = rows_q >= N_TAPS ? 0u : N_TAPS - rows_q;
        if (edge > 0u && Frama_C_interval_split(0, 1) == 1) {
            hpa.t = Frama_C_unsigned_short_interval(0u, (uint16_t)(edge - 1u));
        } else {
            hpa.t = Frama_C_unsigned_short_interval((uint16_t)edge, (uint16_t)(N_TAPS - 1u));
        }
    }
    r = wake_hpa_step_bin_end(&hpa, budget);
    post_bin_sums();
    if (hpa.phase == STEP_BIN_END) {
        /*@ assert 0 < hpa.t < N_TAPS; */
        /*@ assert -SLIDE_Q_OUT_R <= hpa.qr <= SLIDE_Q_OUT_R && -SLIDE_Q_OUT_R <= hpa.qi <= SLIDE_Q_OUT_R; */
        /*@ assert \forall integer i; 0 <= i < 6 ==> -SLIDE_PH_OUT_R <= hpa.ph[i] <= SLIDE_PH_OUT_R; */
    } else {
        /*@ assert hpa.t == 0; */
        /*@ assert hpa.phase == STEP_BIN_START || hpa.phase == STEP_DFT || hpa.phase == STEP_RAMP; */
        /*@ assert -4.0 <= hpa.lam[0] <= 0.0 && -4.0 <= hpa.lam[1] <= 0.0; */
        /*@ assert 1 <= hpa.pair <= 2 && hpa.d < hpa.pair; */
    }
    /*@ assert 0 < r <= (budget > COST_SLIDE ? budget : COST_SLIDE); */
}

/** The end-point line's ramp into the targets (STEP_RAMP). */
void eva_step_ramp(void)
{
    if (!initialised()) {
        return;
    }
    any_bin_sums();
    begun();
    any_sums();
    hpa.t = 0;
    hpa.phase = STEP_RAMP;
    (void)wake_hpa_step_ramp(&hpa, INT32_MAX / 2);
    /*@ assert hpa.phase == STEP_GRAM && hpa.d == 0 && hpa.t == 0; */
    post_bin_sums();
}

/**
 * |U(i)| = |sum_{u < rows} u x_c(i + u)| < 2^19 L^2 / 2 < 2^37 (STEP_RAMP's ramp_u between chunks; |x_c| < 2^19 with
 * the mean within MEAN_MAX): an envelope, not the tight bound, in which one row's change (|rows x_c| + |wsum| < 2^30)
 * is below half an ulp (2^35), so that float addition keeps U inside: an invariant of the slide
 */
#define RAMP_U_MAX 0x1p60f
#define RAMP_U_MAX_R 1152921504606846976.0

/**
 * A chunk of the ramp as a sliced run gives it: from any row i < 2^J (an interval, not split), U(i) within its
 * envelope (from the exact sums at i = 0), the targets' sums within theirs, any budget (budget_range).
 * Postcondition: the envelopes, i <= 2^J (0 when the ramp ends, STEP_GRAM next) and 0 < r <= max(budget, cost).
 */
void eva_step_ramp_chunk(void)
{
    int32_t budget, r;
    int q;
    if (!initialised()) {
        return;
    }
    any_bin_sums();
    begun();
    any_sums();
    hpa.ramp_u = anyf(-RAMP_U_MAX, RAMP_U_MAX);
    hpa.t = Frama_C_unsigned_short_interval(0u, N_TAPS - 1u);
    hpa.phase = STEP_RAMP;
    q = Frama_C_interval_split(0, (int)N_TAPS);
    budget = budget_range(q, N_TAPS, COST_RAMP);
    r = wake_hpa_step_ramp(&hpa, budget);
    /*@ assert (hpa.phase == STEP_RAMP && 0 < hpa.t < N_TAPS) || (hpa.phase == STEP_GRAM && hpa.t == 0 && hpa.d == 0); */
    /*@ assert -RAMP_U_MAX_R <= hpa.ramp_u <= RAMP_U_MAX_R; */
    post_bin_sums();
    /*@ assert 0 < r <= (budget > COST_RAMP ? budget : COST_RAMP); */
}

/**
 * The normal equations (STEP_GRAM), one entry G[l][k] per piece, every piece in order (the driver's loop,
 * unrolled), from Rxx B' within its envelope, the targets' sums within theirs and r(0) within R_MAX.
 * Postcondition: G, b, y'y, R and trace(G) / J finite (within the bounds below).
 */
void eva_step_gram(void)
{
    unsigned i;
    if (!initialised()) {
        return;
    }
    for (i = 0; i < WAKE_HPA_MAX_TAPS * WAKE_HPA_MAX_LEVEL; ++i) {
        hpa.bank_rxx[i] = anyf(-BANK_MAX, BANK_MAX);
    }
    any_bin_sums();
    begun();
    any_sums();
    hpa.r[0] = anyf(-(float)R_MAX, (float)R_MAX);
    hpa.d = 0;
    hpa.t = 0;
    hpa.phase = STEP_GRAM;
    /*@ loop unroll 15; */
    while (hpa.phase == STEP_GRAM) {
        wake_hpa_step_gram(&hpa);
    }
    /*@ assert hpa.phase == STEP_SOLVE && hpa.d <= hpa.lags; */
    /*@ assert \forall integer i; 0 <= i < 25 ==> \is_finite(hpa.gram[i]); */
    /*@ assert \forall integer i; 0 <= i < 5 ==> \is_finite(hpa.rhs[i]); */
    /*@ assert \is_finite(hpa.yy) && \is_finite(hpa.noise) && \is_finite(hpa.scale); */
    /*@ assert \forall integer i; 0 <= i < 25 ==> -G_MAX_R <= hpa.gram[i] <= G_MAX_R; */
    /*@ assert \forall integer i; 0 <= i < 5 ==> -B_MAX_R <= hpa.rhs[i] <= B_MAX_R; */
    /*@ assert -YY_MAX_R <= hpa.yy <= YY_MAX_R && -NOISE_MAX_R <= hpa.noise <= NOISE_MAX_R; */
    /*@ assert -G_MAX_R <= hpa.scale <= G_MAX_R && hpa.factor == hpa.cfg.ridge && hpa.attempts == 0; */
}

/** 2^e, exactly (e a single value in each Eva state). */
static float pow2f(int e)
{
    float p = 1.0f;
    int i;
    for (i = 0; i < e; ++i) {
        p *= 2.0f;
    }
    for (i = 0; i > e; --i) {
        p *= 0.5f;
    }
    return p;
}

/**
 * STEP_GRAM's postcondition: G (symmetric, as step_gram writes both triangles), b, y'y and R within their
 * envelopes, and trace(G) / J within G's (the scale is drawn by the caller, solve_attempt).  The scale is
 * split into ranges [2^8k, 2^(8k + 8)] of [2^-80, 2^82] and the range below the solve's smallest, one Eva
 * state each; they cover every scale.  Within one, a guard of the solve that compares with a bound
 * proportional to the scale (|G_ij| <= 2 J scale, d_j >= lambda / 2, |z_i| <= zlim) gives the compared
 * value an interval proportional to 2^8k, which is how intervals see the ratios the solve divides by.
 */
static void any_normal_equations(void)
{
    unsigned l, k;
    for (l = 0; l < 5u; ++l) {
        for (k = 0; k <= l; ++k) {
            const float g = anyf(-G_MAX, G_MAX);
            hpa.gram[l * 5u + k] = g;
            hpa.gram[k * 5u + l] = g;
        }
        hpa.rhs[l] = anyf(-B_MAX, B_MAX);
    }
    hpa.yy = anyf(-YY_MAX, YY_MAX);
    hpa.noise = anyf(-NOISE_MAX, NOISE_MAX);
}

/**
 * One ridge attempt (STEP_SOLVE) with the factor of attempt @p a, from STEP_GRAM's postcondition.
 * Postcondition: the attempt is refused (the ridge rises: the next attempt's factor @p next) or the run's
 * result is published with weights within +-32, a finite e_L^2 >= 0, a finite R and ridge.  A function of
 * its own so that its states are joined on return, one state per attempt entering the next.
 */
static void solve_attempt(unsigned a, float factor, float next)
{
    unsigned j;
    /* what an earlier run published (any content), in range: a refused attempt leaves it as it is */
    for (j = 0; j < WAKE_HPA_MAX_LEVEL; ++j) {
        hpa.result.weights[j] = 0.0f;
    }
    hpa.result.fit_mse = 0.0f;
    hpa.result.measurement_noise = 0.0f;
    hpa.result.ridge = 0.0f;
    any_normal_equations();
    {
        /* k = -11: a scale below the solve's smallest (zero weights); else [2^8k, 2^(8k + 8)] within G_MAX */
        const int k = Frama_C_interval_split(-11, 10);
        hpa.scale = k < -10 ? anyf(-G_MAX, SOLVE_MIN_SCALE) : anyf(pow2f(8 * k), pow2f(k < 10 ? 8 * k + 8 : 82));
    }
    hpa.factor = factor;
    hpa.attempts = (uint16_t)a;
    hpa.phase = STEP_SOLVE;
    wake_hpa_step_solve(&hpa);
    /* refused (the ridge rises: the next attempt's factor) or the result published */
    /*@ assert hpa.phase == STEP_SOLVE || hpa.phase == STEP_IDLE; */
    /*@ assert a <= hpa.attempts <= a + 1 && factor <= hpa.factor <= next; */
    /*@ assert \forall integer j; 0 <= j < WAKE_HPA_MAX_LEVEL ==>
               -32.0 <= hpa.result.weights[j] <= 32.0 && -32.0 <= hpa.weights[j] <= 32.0; */
    /*@ assert \is_finite(hpa.result.fit_mse) && hpa.result.fit_mse >= 0.0; */
    /*@ assert \is_finite(hpa.result.measurement_noise) && \is_finite(hpa.result.ridge); */
}

/**
 * Every ridge attempt of the solve, a = 0 .. WAKE_HPA_RIDGE_STEPS - 1 (the driver's loop, unrolled): the
 * factor is the a-th of ridge, then max(10 factor, RIDGE_FLOOR), as step_solve raises it.
 */
void eva_step_solve(void)
{
    unsigned a;
    float factor;
    if (!initialised()) {
        return;
    }
    /* the solve reads n only through rows (e_L^2 and R over rows >= 68) and the warm-up test of install:
       the schedule's five window lengths in one state */
    wake_hpa_begin(&hpa, window, (uint16_t)(100 * Frama_C_interval(1, 5)), 0u);
    factor = hpa.cfg.ridge;
    /*@ loop unroll WAKE_HPA_RIDGE_STEPS; */
    for (a = 0; a < WAKE_HPA_RIDGE_STEPS; ++a) {
        const float next = max_f(factor * 10.0f, RIDGE_FLOOR);
        solve_attempt(a, factor, next);
        factor = next;
    }
}

/* ---- chunks of the integer loop steps (docs/studies/verification.md, "The dispatch and the integer chunks") ------ */

/**
 * The items a chunk entry gives an integer loop step: every budget that buys 1 .. CHUNK_ITEMS of them, the
 * ranges 0 .. CHUNK_ITEMS of budget_range (a loop of CHUNK_ITEMS + 1 items, so each range buys one count).
 */
#define CHUNK_ITEMS 4

/** |sum_{u < t} u x(u)| <= 2^15 t (t - 1) / 2 */
static int64_t tsum_max(unsigned t)
{
    return X_MAX * (int64_t)t * ((int64_t)t - 1) / 2;
}

/**
 * A chunk of STEP_SUMS from any index t0 < n (one Eva state per value), with the partial sums the samples
 * before t0 can give (S and T over t < t0, P(rows) and T(rows) over t < min(t0, rows)), any smallest and largest
 * sample so far, and any budget that buys 1 .. CHUNK_ITEMS samples.  Postcondition: the budget bound, and the
 * partial sums up to the new index, or at the window's end STEP_SUMS's postcondition (or a silent window).
 */
void eva_step_sums_chunk(void)
{
    unsigned t0, m0;
    int32_t budget, r;
    if (!started()) {
        return;
    }
    t0 = (unsigned)Frama_C_interval_split(0, (int)hpa.n - 1);
    m0 = t0 < hpa.rows ? t0 : hpa.rows;
    hpa.t = (uint16_t)t0;
    hpa.sum = any64(-X_MAX * (int64_t)t0, X_MAX * (int64_t)t0);
    hpa.tsum = any64(-tsum_max(t0), tsum_max(t0));
    hpa.prefix_rows = any64(-X_MAX * (int64_t)m0, X_MAX * (int64_t)m0);
    hpa.tsum_rows = any64(-tsum_max(m0), tsum_max(m0));
    if (t0 > 0u) {
        hpa.lo = (int16_t)Frama_C_short_interval(INT16_MIN, INT16_MAX);
        hpa.hi = (int16_t)Frama_C_short_interval(INT16_MIN, INT16_MAX);
    }
    budget = budget_range(Frama_C_interval_split(0, CHUNK_ITEMS), CHUNK_ITEMS + 1u, COST_SUM);
    r = wake_hpa_step_sums(&hpa, budget);
    /*@ assert 0 < r && (r <= budget || r == COST_SUM); */
    if (hpa.phase == STEP_SUMS) {
        /*@ assert t0 < hpa.t < hpa.n; */
        /*@ assert -X_MAX * hpa.t <= hpa.sum <= X_MAX * hpa.t; */
        /*@ assert -X_MAX * hpa.t * (hpa.t - 1) / 2 <= hpa.tsum <= X_MAX * hpa.t * (hpa.t - 1) / 2; */
        /*@ assert hpa.t <= hpa.rows ==> -X_MAX * hpa.t <= hpa.prefix_rows <= X_MAX * hpa.t; */
        /*@ assert hpa.t <= hpa.rows ==>
                   -X_MAX * hpa.t * (hpa.t - 1) / 2 <= hpa.tsum_rows <= X_MAX * hpa.t * (hpa.t - 1) / 2; */
        /*@ assert -X_MAX * hpa.rows <= hpa.prefix_rows <= X_MAX * hpa.rows; */
        /*@ assert -X_MAX * hpa.rows * (hpa.rows - 1) / 2 <= hpa.tsum_rows <= X_MAX * hpa.rows * (hpa.rows - 1) / 2; */
    } else if (hpa.phase == STEP_LAGS) {
        post_sums();
    } else {
        /*@ assert hpa.phase == STEP_IDLE; */
    }
}

/** |x(t) x(t + d)| <= 2^30 */
#define PRODUCT_MAX (1LL << 30)

/**
 * A chunk of STEP_LAGS from any index t0 < n - d of any lag d < lags, with the lag sums the products before t0
 * can give (those of t < min(t0, rows) in the head, the others in the tail), the sums as STEP_SUMS leaves them, and
 * any budget that buys 1 .. CHUNK_ITEMS products.  t0 is one Eva state per value; so is d where a chunk of
 * CHUNK_ITEMS can reach the lag's end (d >= n - t0 - CHUNK_ITEMS - 1), the lags below in one state (no chunk from
 * t0 ends them).  Postcondition: the budget bound, and the lag sums up to the new index, or at the lag's end (t = n - d)
 * STEP_LAGS's postcondition.
 */
void eva_step_lags_chunk(void)
{
    unsigned t0, head, tail, d, near;
    int32_t budget, r;
    if (!started()) {
        return;
    }
    t0 = (unsigned)Frama_C_interval_split(0, (int)hpa.n - 1);
    /* d < lags and t0 < n - d */
    near = hpa.n - t0 - 1u < CHUNK_ITEMS + 1u ? 0u : hpa.n - t0 - 1u - (CHUNK_ITEMS + 1u);
    if (near >= hpa.lags) {
        d = (unsigned)Frama_C_interval(0, (int)hpa.lags - 1);
    } else if (near > 0u && Frama_C_nondet(0, 1)) {
        d = (unsigned)Frama_C_interval(0, (int)near - 1);
    } else {
        d = (unsigned)Frama_C_interval_split((int)near, (int)(hpa.n - t0 - 1u < hpa.lags - 1u ? hpa.n - t0 - 1u
                                                                                              : hpa.lags - 1u));
    }
    any_lag_state(d);
    head = t0 < hpa.rows ? t0 : hpa.rows;
    tail = t0 - head;
    hpa.t = (uint16_t)t0;
    hpa.acc_head = any64(-PRODUCT_MAX * (int64_t)head, PRODUCT_MAX * (int64_t)head);
    hpa.acc_tail = any64(-PRODUCT_MAX * (int64_t)tail, PRODUCT_MAX * (int64_t)tail);
    hpa.phase = STEP_LAGS;
    budget = budget_range(Frama_C_interval_split(0, CHUNK_ITEMS), CHUNK_ITEMS + 1u, COST_LAG);
    r = wake_hpa_step_lags(&hpa, budget);
    /*@ assert 0 < r && (r <= budget || r == COST_LAG); */
    /*@ assert t0 < hpa.t <= hpa.n - hpa.d; */
    /*@ assert hpa.t <= hpa.rows ==> -PRODUCT_MAX * hpa.t <= hpa.acc_head <= PRODUCT_MAX * hpa.t; */
    /*@ assert -PRODUCT_MAX * hpa.rows <= hpa.acc_head <= PRODUCT_MAX * hpa.rows; */
    /*@ assert hpa.t <= hpa.rows ==> hpa.acc_tail == 0; */
    /*@ assert hpa.t > hpa.rows ==>
               -PRODUCT_MAX * (hpa.t - hpa.rows) <= hpa.acc_tail <= PRODUCT_MAX * (hpa.t - hpa.rows); */
    if (hpa.phase == STEP_LAGS) {
        /*@ assert hpa.t < hpa.n - hpa.d; */
    } else {
        /*@ assert hpa.phase == STEP_LAG_END && hpa.t == hpa.n - hpa.d; */
        /*@ assert -ACC_MAX <= hpa.acc_head <= ACC_MAX && -ACC_MAX <= hpa.acc_tail <= ACC_MAX; */
    }
}

/* ---- the dispatch (docs/studies/verification.md, "The dispatch and the integer chunks") --------------------------------- */

/**
 * run_step as the dispatch sees it: one piece of the step `phase` names, from a state of a run, within @p budget
 * (@p fixed: piece_cost, the cost of an indivisible step or of one item of a loop step).  The dispatch entries below
 * use this contract instead of the body (-eva-use-spec run_step); the step entries show each clause (the list in
 * docs/studies/verification.md).  What piece_cost reads and the steps may write: the phase, and t, d, pair in the phases
 * whose cost depends on them; the configuration, the window's length and order and the PSD bins (cut_hi,
 * cut_shallow) are set by init and begin, which no step writes (assigns).
 */
/*@ requires \valid(h);
    requires STEP_SUMS <= h->phase <= STEP_SOLVE;
    requires h->d <= h->lags && h->pair <= 2;
    requires 1 <= budget <= INT32_MAX / 2;
    requires 1 <= fixed;
    assigns h->phase, h->t, h->d, h->m, h->bins, h->psd_end, h->peak, h->pair, h->flag, h->attempts, h->lo, h->hi,
            h->sum, h->prefix_rows, h->tsum, h->tsum_rows, h->prefix_lo, h->prefix_hi, h->suffix, h->acc_head,
            h->acc_tail, h->diag, h->mean, h->cutoff, h->xr, h->xi, h->qr, h->qi, h->lam[0 .. 1], h->gs[0 .. 1],
            h->gd[0 .. 1], h->hs[0 .. 1], h->hd[0 .. 1], h->rot[0 .. 1], h->ph[0 .. 5], h->power, h->cross, h->slope,
            h->ramp_u, h->prev1, h->prev2, h->err, h->den_peak, h->den_floor, h->yy, h->noise, h->scale, h->factor,
            h->gram[0 .. WAKE_HPA_MAX_LEVEL * WAKE_HPA_MAX_LEVEL - 1], h->rhs[0 .. WAKE_HPA_MAX_LEVEL - 1],
            h->chol[0 .. WAKE_HPA_MAX_LEVEL * WAKE_HPA_MAX_LEVEL - 1], h->trial[0 .. WAKE_HPA_MAX_LEVEL - 1],
            h->rowsum[0 .. WAKE_HPA_MAX_LEVEL - 1], h->colsum[0 .. WAKE_HPA_MAX_LEVEL - 1], h->sy, h->vv, h->trace,
            h->weights[0 .. WAKE_HPA_MAX_LEVEL - 1], h->r[0 .. WAKE_HPA_MAX_ORDER], h->a[0 .. WAKE_HPA_MAX_ORDER],
            h->den[0 .. WAKE_HPA_MAX_PSD_BINS - 1], h->bank_rxx[0 .. WAKE_HPA_MAX_TAPS * WAKE_HPA_MAX_LEVEL - 1],
            h->cxy[0 .. WAKE_HPA_MAX_TAPS - 1], h->wsum[0 .. WAKE_HPA_MAX_TAPS - 1],
            h->vhead[0 .. WAKE_HPA_MAX_TAPS - 1], h->result, h->ready;
    ensures STEP_IDLE <= h->phase <= STEP_SOLVE;
    ensures h->d <= h->lags && h->pair <= 2;
    ensures 0 < \result <= (budget >= fixed ? budget : fixed);
*/
int32_t wake_hpa_run_step(wake_hpa_t *h, int32_t budget, int32_t fixed);

/**
 * run_pieces as its callers use it (wake_hpa_slice: WAKE_HPA_SLICE_BUDGET, wake_hpa_run: INT32_MAX / 2), from a
 * state check_instance accepted: WP proves its loop's variant (left) from run_step's and piece_cost's contracts
 * (tests/prove/wp_check.py; docs/studies/verification.md, "Termination"), and that it ends in a state run_step's contract
 * accepts again; the dispatch entries check the preconditions at its calls.
 */
/*@ requires \valid(h);
    requires STEP_IDLE <= h->phase <= STEP_SOLVE;
    requires h->d <= h->lags && h->pair <= 2;
    requires COST_PIECE < budget <= INT32_MAX / 2;
    assigns *h;
    ensures STEP_IDLE <= h->phase <= STEP_SOLVE;
    ensures h->d <= h->lags && h->pair <= 2;
*/
void wake_hpa_run_pieces(wake_hpa_t *h, int32_t budget);

/**
 * A run in any phase: an instance init accepted (the default configuration, any bank), a run begun on a window of
 * each length of the schedule (one Eva state each), the phase any of the run's (one state each), and the fields
 * piece_cost reads within what the run gives them: the order reached t < order in STEP_LEVINSON, the entry G[d][t],
 * t <= d < J, in STEP_GRAM, one bin or two in a DFT pass; every other counter within check_instance's ranges.
 */
static int dispatching(void)
{
    if (!started()) {
        return 0;
    }
    hpa.phase = (uint16_t)Frama_C_interval_split(STEP_SUMS, STEP_SOLVE);
    hpa.m = 1;
    hpa.pair = (uint16_t)Frama_C_interval(1, 2);
    if (hpa.phase == STEP_LEVINSON) {
        hpa.t = (uint16_t)Frama_C_interval(0, (int)hpa.order - 1);
    } else if (hpa.phase == STEP_GRAM) {
        hpa.d = (uint16_t)Frama_C_interval_split(0, (int)hpa.cfg.level - 1);
        hpa.t = (uint16_t)Frama_C_interval(0, (int)hpa.d);
    }
    return 1;
}

/** The fields piece_cost reads, within the ranges above, or the run done. */
static void post_dispatch(void)
{
    /*@ assert STEP_IDLE <= hpa.phase <= STEP_SOLVE && hpa.d <= hpa.lags && hpa.pair <= 2; */
}

/** A slice (WAKE_HPA_SLICE_BUDGET) of a run in any phase: wake_hpa_slice's check, run_pieces, its budget arithmetic. */
void eva_dispatch_slice(void)
{
    wake_hpa_status_t st;
    if (!dispatching()) {
        return;
    }
    st = wake_hpa_slice(&hpa);
    /* every such state passes the instance check: the dispatch is reached in every phase */
    /*@ assert st == WAKE_HPA_DONE || st == WAKE_HPA_RUNNING; */
    post_dispatch();
}

/**
 * wake_hpa_run on a run in any phase (after slices): one wake_hpa_run_pieces(INT32_MAX / 2).  run_step's contract bounds
 * what a piece spends by the budget, not what a whole run spends, so from the contract the run may stop short
 * (running); that it never does is measured (docs/studies/verification.md, "Termination").
 */
void eva_dispatch_run(void)
{
    wake_hpa_status_t st;
    if (!dispatching()) {
        return;
    }
    st = wake_hpa_run(&hpa);
    /* one Eva state per status, kept apart from the call on (the entry's states exceed its slevel) */
    //@ split st;
    /*@ assert (st == WAKE_HPA_DONE && hpa.phase == STEP_IDLE) || (st == WAKE_HPA_RUNNING && hpa.phase != STEP_IDLE); */
    post_dispatch();
}
