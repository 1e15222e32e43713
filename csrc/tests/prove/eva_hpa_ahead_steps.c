/**
 * @file eva_hpa_ahead_steps.c
 * @brief Frama-C Eva entries for the tremor-ahead steps of one HPA run (csrc/wake_hpa*.c built with
 *        WAKE_HPA_AHEAD 1), each from a state whose fields are ranged as the step's precondition, each
 *        checking (`//@ assert`) the postcondition the next step assumes (docs/studies/verification.md, "The
 *        tremor-ahead build").
 *
 * As tests/prove/eva_hpa_steps.c (which is the default build's: its solve ends in STEP_IDLE, here in
 * STEP_AHEAD_START), this file reaches the steps through csrc/internal/wake_hpa_internal.h (it is only ever
 * given to Frama-C) and starts every entry from an instance wake_hpa_init accepted with the default configuration
 * (J = 5, p = 17, L = 500, horizon 1) and any filter bank, and a run begun on a window of any int16
 * samples of each length the default schedule starts (100 .. 500, one Eva state each).  eva_check.py
 * adds WAKE_HPA_AHEAD 1 (and WAKE_RTP_AHEAD 1, which it needs).
 */
#include <float.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include "__fc_builtin.h"
#include "internal/wake_hpa_internal.h"

#if !WAKE_HPA_AHEAD
#error "eva_hpa_ahead_steps.c analyses the tremor-ahead build: -DWAKE_HPA_AHEAD=1"
#endif

/* ---- the ranges: each is a postcondition of one step and a precondition of the next ---------------- */
/** the default configuration's 2^J and its horizon */
#define N_TAPS 32u
#define HORIZON 1u
/** |w| <= 32 (step_solve's postcondition, wake_hpa_init's start weights) */
#define W_MAX 32.0f
/**
 * A tap of the estimate's FIR w'B in Q20: |sum_l w_l B_li| <= 5 x 32 x 1 = 160, so |tap| <= 160 2^20 < 2^28
 * (STEP_AHEAD_START's postcondition)
 */
#define FIR_MAX 268435456
/** |mean| < 2^18, |slope| < 2^11 (STEP_SUMS's postcondition) */
#define MEAN_MAX 0x1p18f
#define SLOPE_MAX 0x1p11f
/** |X'_m| <= 2^38 (STEP_BIN_START's postcondition) */
#define XQ_MAX 0x1p38f
/**
 * The pass's sums (STEP_AHEAD_PASS's invariant between chunks and its postcondition): |y(t)| <= 2^15 + 32 FIR_MAX
 * 2^15 / 2^20 < 2^29 in the ring and the head; the lag sums, the right-hand side and the held-out sums within
 * envelopes, not their tight bounds (those are 500 y y < 2^67, 500 y T < 2^88 and <T, P>, <P, P> < 2^100 with T,
 * the truth, within 2^16 + 2^20 + 30 (2/n) 2 |X'| < 2^40) but invariants: each term a row adds is below half an ulp
 * of its envelope, so float addition keeps the sum inside.  The terms' bounds are what intervals give within a
 * block of the pass: y y <= 2^58 (envelope 2^83), y T <= 2^29 2^58.1 (T within a block: the oscillators grow from
 * their clamp bounds to |v| < 2^53.1 over AHEAD_BLOCK samples, 30 bins of them; envelope 2^112), T P <= 2^58.1 2^35
 * and P P <= 2^70 (P = c_prev . u, |c_prev| <= 8; envelope 2^118)
 */
#define Y_MAX 0x1p29f
#define LAG_MAX 0x1p83f
#define RHS_MAX 0x1p112f
#define HELD_MAX 0x1p118f
/** The oscillators' clamp bounds (AHEAD_V_MAX, AHEAD_E_MAX in internal/wake_bounds.h): the pass's invariant between blocks */
#define OSC_V_MAX 0x1p35f
#define OSC_E_MAX 0x1p36f
/** the predictor's clip (wake.ahead.COEFFICIENT_LIMIT) */
#define C_MAX 8.0f

static wake_q15_t taps[WAKE_HPA_MAX_LEVEL * WAKE_HPA_MAX_TAPS];
static wake_q15_t window[WAKE_HPA_MAX_WINDOW];
static float weights[WAKE_HPA_MAX_LEVEL];
static wake_hpa_config_t cfg;
static wake_hpa_t hpa;

static float anyf(float lo, float hi)
{
    return Frama_C_float_interval(lo, hi);
}

/** The default configuration, any filter bank (init takes any Q15 taps), weights init accepts. */
static int initialised(void)
{
    unsigned j;
    (void)wake_hpa_default_config(&cfg);
    Frama_C_make_unknown((char *)taps, sizeof taps);
    for (j = 0; j < WAKE_HPA_MAX_LEVEL; ++j) {
        weights[j] = anyf(-W_MAX, W_MAX);
    }
    Frama_C_make_unknown((char *)window, sizeof window);
    return wake_hpa_init(&hpa, &cfg, taps, weights) == WAKE_HPA_OK;
}

/** A run begun on a window of any int16 samples of each length of the default schedule (one Eva state each). */
static void begun(void)
{
    wake_hpa_begin(&hpa, window, (uint16_t)(100 * Frama_C_interval_split(1, 5)), Frama_C_unsigned_int_interval(0u, UINT32_MAX));
}

/**
 * What an earlier run left for this one (any of it): whether a predictor was kept, its index, the predictor
 * within +-8 (ahead_keep of a clipped predictor, or of zeros).
 */
static void any_previous(void)
{
    unsigned i;
    hpa.ahead.has_prev = (uint16_t)Frama_C_interval(0, 1);
    hpa.ahead.prev_index = Frama_C_unsigned_int_interval(0u, UINT32_MAX);
    for (i = 0; i < WAKE_HPA_AHEAD_TAPS; ++i) {
        hpa.ahead.prev[i] = anyf(-C_MAX, C_MAX);
    }
}

/**
 * STEP_SUMS in this build (its whole pass in one piece), from a run just begun and anything an earlier run kept:
 * besides the sums (eva_hpa_steps.c's eva_step_sums) and the count of samples at full scale (Eva does not bound it
 * by n: the count's xor, see step_sums, is beyond intervals; the solve takes it of any value), a silent window
 * published at once with the kept predictor (within +-8, zero before the first) and the goal 0.
 */
void eva_step_sums_ahead(void)
{
    if (!initialised()) {
        return;
    }
    begun();
    any_previous();
    (void)wake_hpa_step_sums(&hpa, INT32_MAX / 2);
    /*@ assert hpa.phase == STEP_LAGS || hpa.phase == STEP_IDLE; */
    if (hpa.phase == STEP_IDLE) {
        /*@ assert hpa.ready == 1 && hpa.result.flag == WAKE_HPA_SILENT && hpa.result.ahead_goal == 0.0; */
        /*@ assert \forall integer i; 0 <= i < WAKE_HPA_AHEAD_TAPS ==>
                   -8.0 <= hpa.result.ahead[i] <= 8.0 && -8.0 <= hpa.ahead.prev[i] <= 8.0; */
    }
}

/** The ahead step's state at the start of the pass (STEP_AHEAD_START's postcondition). */
static void post_ahead_start(void)
{
    /*@ assert hpa.phase == STEP_AHEAD_PASS && hpa.t == N_TAPS && hpa.ahead.pos == WAKE_HPA_AHEAD_RING - 1; */
    /*@ assert \forall integer i; 0 <= i < N_TAPS ==> -FIR_MAX <= hpa.ahead.fir[i] <= FIR_MAX; */
    /*@ assert \forall integer i; 0 <= i < WAKE_HPA_AHEAD_RING ==> hpa.ahead.ring[i] == 0.0; */
    /*@ assert \forall integer i; 0 <= i < WAKE_HPA_AHEAD_TAPS ==>
               hpa.ahead.lag[i] == 0.0 && hpa.ahead.rhs[i] == 0.0; */
    /*@ assert hpa.ahead.tp == 0.0 && hpa.ahead.pp == 0.0; */
    /* the held-out targets start after the first row's history, 2^J + 7 + h, or there are none (n) */
    /*@ assert N_TAPS + WAKE_HPA_AHEAD_TAPS - 1 + HORIZON <= hpa.ahead.held <= hpa.n; */
}

/**
 * STEP_AHEAD_START (the estimate's FIR w'B from the weights installed, then the clearing), its whole loop in
 * one piece as wake_hpa_run gives it, from the weights step_solve installs (within +-32), any filter bank,
 * any sample index and anything an earlier run kept.
 */
void eva_step_ahead_start(void)
{
    unsigned j;
    if (!initialised()) {
        return;
    }
    begun();
    for (j = 0; j < WAKE_HPA_MAX_LEVEL; ++j) {
        hpa.weights[j] = anyf(-W_MAX, W_MAX);
    }
    any_previous();
    /* the step reads the index only through index - ahead_prev_index (samples since the previous HPA, modulo
       2^32): with the index at UINT32_MAX and any previous index that difference takes every value, and Eva
       sees it without a wrap-around */
    hpa.index = UINT32_MAX;
    hpa.t = 0;
    hpa.d = 0;
    hpa.phase = STEP_AHEAD_START;
    (void)wake_hpa_step_ahead_start(&hpa, &hpa.ahead, INT32_MAX / 2);
    post_ahead_start();
}

/**
 * A chunk of STEP_AHEAD_PASS as a sliced run gives it (and the whole pass, a chunk from t = 2^J with a budget that
 * holds it): from any sample t of the pass (an interval over [2^J, n), not split) with everything the pass carries
 * from one chunk to the next anywhere within its invariant, and any budget in [1, INT32_MAX / 2].  The invariant:
 * the low bins' oscillators within their clamp bounds (v within 2^35, e within 2^36, lambda in [-4, 0]; every bin
 * count of the cut-off range, m <= 6 n / 100), the estimates y in the ring and the head within Y_MAX, the lag sums,
 * the right-hand side and the held-out sums within their envelopes; besides, the FIR as STEP_AHEAD_START leaves it,
 * the mean and the slope as STEP_SUMS does, any previous predictor, any held-out start, any ring position (the pass
 * reads its ring position from t).  STEP_AHEAD_START's postcondition (t = 2^J, the ring and the sums zero) and the
 * oscillators as STEP_BIN_START leaves them (v(N) = (2/n) Re Z, v(N) - v(N-1) = (2/n) Re(Z (1 - e^{-jw})), |Z| =
 * |X'_m| <= 2^38: within 2^32.4 and 2^33.4 for n >= 100) lie inside it, so the whole pass is a chain of such chunks.
 * Postcondition: the invariant, and either the pass's next sample 2^J < t < n, or STEP_AHEAD_SOLVE with its ring
 * position that of the pass's end (the solve's precondition); what the chunk spent positive.
 */
void eva_step_ahead_pass_chunk(void)
{
    unsigned i;
    int32_t r;
    if (!initialised()) {
        return;
    }
    begun();
    hpa.mean = anyf(-MEAN_MAX, MEAN_MAX);
    hpa.slope = anyf(-SLOPE_MAX, SLOPE_MAX);
    hpa.bins = (uint16_t)Frama_C_interval(0, (int)(6u * hpa.n / 100u));
    /* the default configuration's gate cut-off is 0, so STEP_BINS leaves no gate bins above the fit's */
    hpa.gate_extra = 0u;
    for (i = 0; i < WAKE_HPA_MAX_BINS; ++i) {
        hpa.ahead.bin_osc[3u * i] = anyf(-OSC_V_MAX, OSC_V_MAX);
        hpa.ahead.bin_osc[3u * i + 1u] = anyf(-OSC_E_MAX, OSC_E_MAX);
        hpa.ahead.bin_osc[3u * i + 2u] = anyf(-4.0f, 0.0f);
    }
    for (i = 0; i < N_TAPS; ++i) {
        hpa.ahead.fir[i] = Frama_C_interval(-FIR_MAX, FIR_MAX);
    }
    any_previous();
    for (i = 0; i < WAKE_HPA_AHEAD_RING; ++i) {
        hpa.ahead.ring[i] = anyf(-Y_MAX, Y_MAX);
    }
    for (i = 0; i < WAKE_HPA_AHEAD_TAPS; ++i) {
        hpa.ahead.head[i] = anyf(-Y_MAX, Y_MAX);
        hpa.ahead.lag[i] = anyf(-LAG_MAX, LAG_MAX);
        hpa.ahead.rhs[i] = anyf(-RHS_MAX, RHS_MAX);
    }
    hpa.ahead.tp = anyf(-HELD_MAX, HELD_MAX);
    hpa.ahead.pp = anyf(-HELD_MAX, HELD_MAX);
    hpa.ahead.pos = (uint16_t)Frama_C_interval(0, WAKE_HPA_AHEAD_RING - 1);
    hpa.ahead.held = (uint16_t)Frama_C_interval(N_TAPS + WAKE_HPA_AHEAD_TAPS - 1u + HORIZON, hpa.n);
    hpa.t = (uint16_t)Frama_C_unsigned_int_interval(N_TAPS, hpa.n - 1u);
    hpa.phase = STEP_AHEAD_PASS;
    r = wake_hpa_step_ahead_pass(&hpa, &hpa.ahead, Frama_C_int_interval(1, INT32_MAX / 2));
    /*@ assert hpa.phase == STEP_AHEAD_PASS || hpa.phase == STEP_AHEAD_SOLVE; */
    /*@ assert hpa.ahead.pos < WAKE_HPA_AHEAD_RING; */
    /*@ assert hpa.phase == STEP_AHEAD_PASS ==> N_TAPS <= hpa.t; */
    /*@ assert hpa.phase == STEP_AHEAD_PASS ==> hpa.t < hpa.n; */
    /*@ assert hpa.phase == STEP_AHEAD_SOLVE ==> hpa.t == 0 && hpa.d == 0; */
    /*@ assert hpa.phase == STEP_AHEAD_SOLVE ==>
               hpa.ahead.pos == (WAKE_HPA_AHEAD_RING - 1 + hpa.n - N_TAPS) % WAKE_HPA_AHEAD_RING; */
    /*@ assert \forall integer i; 0 <= i < WAKE_HPA_MAX_BINS ==>
               -OSC_V_MAX <= hpa.ahead.bin_osc[3 * i] <= OSC_V_MAX && -OSC_E_MAX <= hpa.ahead.bin_osc[3 * i + 1] <= OSC_E_MAX &&
               -4.0 <= hpa.ahead.bin_osc[3 * i + 2] <= 0.0; */
    /*@ assert \forall integer i; 0 <= i < WAKE_HPA_AHEAD_RING ==> -Y_MAX <= hpa.ahead.ring[i] <= Y_MAX; */
    /*@ assert \forall integer i; 0 <= i < WAKE_HPA_AHEAD_TAPS ==> -Y_MAX <= hpa.ahead.head[i] <= Y_MAX; */
    /*@ assert \forall integer i; 0 <= i < WAKE_HPA_AHEAD_TAPS ==> -LAG_MAX <= hpa.ahead.lag[i] <= LAG_MAX; */
    /*@ assert \forall integer i; 0 <= i < WAKE_HPA_AHEAD_TAPS ==> -RHS_MAX <= hpa.ahead.rhs[i] <= RHS_MAX; */
    /*@ assert -HELD_MAX <= hpa.ahead.tp <= HELD_MAX && -HELD_MAX <= hpa.ahead.pp <= HELD_MAX; */
    /*@ assert r > 0; */
}

/**
 * The solve's last piece (the predictor, the held-out gain, the goal, publish) for each cut-off flag, and a full-scale
 * count (any value: at most n in fact) of at most n / 5 or above it (the gate shuts), one Eva state each, with the
 * notes install wrote (the bits below the full-scale note).  A function of its own: its states are joined on return.
 */
static void last_piece(void)
{
    hpa.ahead.rail = (uint16_t)(Frama_C_interval_split(0, 1) ? Frama_C_interval(0, hpa.n / WAKE_HPA_GLITCH_DIVISOR)
                                                               : Frama_C_interval(hpa.n / WAKE_HPA_GLITCH_DIVISOR + 1,
                                                                                  UINT16_MAX));
    hpa.flag = (uint16_t)Frama_C_interval_split(WAKE_HPA_VALLEY, WAKE_HPA_FLOOR_VALLEY);
    hpa.result.notes = (uint16_t)Frama_C_interval(0, WAKE_HPA_NOTE_FULL_SCALE - 1);
    wake_hpa_step_ahead_solve(&hpa, &hpa.ahead);
    /*@ assert (hpa.flag == WAKE_HPA_NO_TREMOR_PEAK || hpa.flag == WAKE_HPA_SILENT ||
                (hpa.result.notes & WAKE_HPA_NOTE_FULL_SCALE) != 0) ==> hpa.result.ahead_goal == 0.0; */
}

/**
 * STEP_AHEAD_SOLVE, its 17 pieces in order (d = 0 .. 7 a row of G, 8 .. 15 a column of L D L', 16 the predictor,
 * the held-out gain, the goal and the result published; the driver's loop, unrolled), from the pass's sums within
 * their envelopes and its ring position (STEP_AHEAD_PASS's postcondition), any held-out start, any previous
 * predictor within +-8, and for the last piece any cut-off flag and full-scale count (last_piece).  The solve tests
 * what it divides by and clips what it produces (a pivot not positive and finite: no fit; a coefficient above 8,
 * below -8 or not finite: 8, -8 or 0; a gain above 1, below 0 or NaN: 1 or 0), so an infinity on the way is not an
 * error there: the entry runs with -warn-special-float none, as the conversions of a result do (docs/studies/verification.md,
 * "The tremor-ahead build": without it, 13 alarms at those intermediates).  Postcondition: what publish writes, the
 * predictor within +-8 (also kept as the one the next run scores) and the goal in [0, 1], 0 without a tremor peak,
 * for a silent window or at full scale; the run idle with its result ready.
 */
void eva_step_ahead_solve(void)
{
    unsigned i;
    if (!initialised()) {
        return;
    }
    begun();
    any_previous();
    for (i = 0; i < WAKE_HPA_AHEAD_RING; ++i) {
        hpa.ahead.ring[i] = anyf(-Y_MAX, Y_MAX);
    }
    for (i = 0; i < WAKE_HPA_AHEAD_TAPS; ++i) {
        hpa.ahead.head[i] = anyf(-Y_MAX, Y_MAX);
        hpa.ahead.lag[i] = anyf(-LAG_MAX, LAG_MAX);
        hpa.ahead.rhs[i] = anyf(-RHS_MAX, RHS_MAX);
    }
    hpa.ahead.tp = anyf(-HELD_MAX, HELD_MAX);
    hpa.ahead.pp = anyf(-HELD_MAX, HELD_MAX);
    /* the pass starts at the ring's last index and moves on by one per sample t = N .. n-1 */
    hpa.ahead.pos = (uint16_t)((WAKE_HPA_AHEAD_RING - 1u + hpa.n - N_TAPS) % WAKE_HPA_AHEAD_RING);
    hpa.ahead.held = (uint16_t)Frama_C_interval(N_TAPS + WAKE_HPA_AHEAD_TAPS - 1u + HORIZON, hpa.n);
    hpa.d = 0;
    hpa.phase = STEP_AHEAD_SOLVE;
    /* the pieces before the last read neither the flag nor the full-scale count: those are split for the last */
    /*@ loop unroll 16; */
    while (hpa.d < AHEAD_SOLVE_LAST) {
        wake_hpa_step_ahead_solve(&hpa, &hpa.ahead);
    }
    /*@ assert hpa.phase == STEP_AHEAD_SOLVE && hpa.d == AHEAD_SOLVE_LAST; */
    last_piece();
    /*@ assert hpa.phase == STEP_IDLE && hpa.ready == 1; */
    /*@ assert \forall integer i; 0 <= i < WAKE_HPA_AHEAD_TAPS ==>
               -8.0 <= hpa.result.ahead[i] <= 8.0 && -8.0 <= hpa.ahead.prev[i] <= 8.0; */
    /*@ assert 0.0 <= hpa.result.ahead_goal <= 1.0; */
}
