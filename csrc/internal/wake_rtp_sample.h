/**
 * @file wake_rtp_sample.h
 * @brief The RTP's per-sample pieces and their control flow, written once: the window and the bank's FIR,
 * the Kalman update along w, the one-step prediction, the tremor ahead's and the voluntary ahead's step, and
 * the parts a prepared step (wake_rtp_split.c) computes apart.
 *
 * Included by the modules of the per-sample path: the two that schedule a sample, wake_rtp.c (the step,
 * @p prepared 0) and wake_rtp_split.c (the finish of a prepared step, @p prepared 1), and the two whose step
 * the flow calls (wake_rtp_ahead.c, wake_rtp_voluntary.c).  Every function defined here is `static inline`:
 * each module compiles the cases it calls, and the parts inlined into the flow (WAKE_RTP_ALWAYS_INLINE) are
 * instantiated for a constant @p prepared.  The out-of-line parts are declared here and defined once, in
 * the module named beside each.
 *
 * Loops of the per-sample path carry a `wcet-loop:` annotation with their largest trip count (N = 2^J);
 * `wake profile` reads it to bound the worst-case execution time from the compiled image.
 */
#ifndef WAKE_RTP_SAMPLE_H
#define WAKE_RTP_SAMPLE_H

#include "wake_bounds.h"
#include "wake_rtp_internal.h"

/* ---------------------------------------------------------------------- */
/* The out-of-line parts of a sample, each defined once                    */
/* ---------------------------------------------------------------------- */

/* Kept out of line so that `wake profile` can bound the step with and without them (the Kalman update is
 * skipped while inert; the window fill runs on the first sample only). */

/** The first sample fills the whole window (both copies); runs once per stream (wake_rtp.c). */
void wake_rtpi_prime_window(wake_rtp_t *s, wake_q15_t sample);
#if WAKE_RTP_KALMAN
/** Kalman measurement and time update along w for the innovation e (Q23); returns its saturations (wake_rtp.c). */
uint32_t wake_rtpi_kalman_update(wake_rtp_t *s, wake_q23_t e);
/** A sample without a measurement update: P = P + q I only (wake_rtp.c). */
void wake_rtpi_time_update(wake_rtp_t *s, uint32_t *events);
#endif
/** The RTP's tremor ahead fed the tremor estimate e(n) in Q23: wake_ahead_step on the embedded instance, nothing
 * in a build without it (wake_rtp_ahead.c). */
void wake_rtpi_ahead_step(wake_rtp_t *s, wake_q23_t tremor);
/** The voluntary motion ahead @p v after the prediction of a step of @p s (wake_rtp_voluntary.c). */
void wake_rtpi_voluntary_step_on(const wake_rtp_t *s, wake_voluntary_ahead_t *v);


/* ---------------------------------------------------------------------- */
/* Per-sample recursion                                                    */
/* ---------------------------------------------------------------------- */


/** The newest sample into a primed ring (stored twice). */
static inline void ring_store(wake_rtp_t *s, wake_q15_t sample)
{
    s->ring[s->head] = sample;
    s->ring[s->head + s->n_taps] = sample;
    s->head = (uint16_t)((s->head + 1u) & (s->n_taps - 1u));
}

/** buffer <- newest sample (the ring holds each sample twice). */
static inline void push(wake_rtp_t *s, wake_q15_t sample)
{
    if (!s->primed) {
        wake_rtpi_prime_window(s, sample);
    }
    ring_store(s, sample);
}

/**
 * h' window for n = 2^J >= 2 taps.  |h_i| < 2^31, |window_i| <= 2^15, so
 * every partial sum stays below 2^52 (N <= 256): exact in int64.
 */
static inline int64_t fir_window(const wake_fir_t *h, const wake_q15_t *x, unsigned n)
{
#if WAKE_RTP_SPLIT_FIR
    /* No 32 x 32 -> 64-bit multiply (Cortex-M0+): with h = hi 2^16 + mid 2^8 + lo
     * (wake_fir_t parts), every product is one 32-bit MULS and every sum stays in
     * 32 bits, so the loop has no 64-bit add (gcc keeps it in r0-r7: 16
     * instructions per tap against 31 for a 64-bit accumulator):
     *   sum mid x, sum lo x: |.| < n 2^8 2^15 <= 2^29 (n <= 64), int32;
     *   sum hi x: |.| < (sum |h| / 2^16 + n) 2^15 < 2^31 for J <= 6 (sum |h| < 2^32,
     *   see WAKE_RTP_FIR_FRAC), summed as sum (hi + 2^15) x - 2^15 sum x in uint32
     *   (exact mod 2^32) and read back as int32.
     * The result equals the 64-bit sum exactly. */
    const wake_fir_t *end = h + n;
    uint32_t acc_hi = 0u, hi_sum;
    int32_t acc_mid = 0, acc_lo = 0, acc_x = 0;
    do {
        const int32_t xi = *x++;
        acc_x += xi;
        acc_hi += (uint32_t)h->parts.biased_hi * (uint32_t)xi;           /* (hi + 2^15) x mod 2^32 */
        acc_mid += (int32_t)h->parts.mid * xi;
        acc_lo += (int32_t)h->parts.lo * xi;
        ++h;
    } while (h != end);                                                   /* wcet-loop: N */
    hi_sum = acc_hi - ((uint32_t)acc_x << 15);                            /* sum hi x mod 2^32 */
    return ((int64_t)hi_sum - (int64_t)(hi_sum >> 31) * 4294967296) * 65536 + (int64_t)acc_mid * 256 + acc_lo;
#elif defined(__OPTIMIZE_SIZE__)
    int64_t acc = 0;
    unsigned i;
    for (i = 0; i < n; ++i) {                                             /* wcet-loop: N */
        acc += (int64_t)h[i].value * x[i];
    }
    return acc;
#else
    int64_t acc0 = 0, acc1 = 0;
    unsigned i = 0;
    if (n == 2u) {
        return (int64_t)h[0].value * x[0] + (int64_t)h[1].value * x[1];
    }
    for (; i < n; i += 4u) {                                              /* wcet-loop: N / 4 */
        acc0 += (int64_t)h[i].value * x[i];
        acc1 += (int64_t)h[i + 1u].value * x[i + 1u];
        acc0 += (int64_t)h[i + 2u].value * x[i + 2u];
        acc1 += (int64_t)h[i + 3u].value * x[i + 3u];
    }
    return acc0 + acc1;
#endif
}

/** e = m(n) - y(n-1), Q23, saturated. */
static inline wake_q23_t innovation(const wake_rtp_t *s, wake_q15_t sample, uint32_t *events)
{
    return narrow_saturate((int64_t)sample * (INT64_C(1) << SIGNAL_GUARD_BITS) - s->last_output, events);
}

#if WAKE_RTP_KALMAN
/** The Kalman gain along w: rho = s / S and tau = R / S (Q30), and s clamped to [0, 2^50]. */
typedef struct {
    int64_t s_pos;
    wake_ratio_t rho, tau;
} kalman_gain_t;

/**
 * The part of the Kalman measurement update that does not need the innovation: the gain.
 * Adds its saturations to *events.  Constant time: one reciprocal, one 32 x 32 -> 64-bit product.
 */
static inline kalman_gain_t kalman_gain(const wake_rtp_t *s, uint32_t *events)
{
    kalman_gain_t g;
    /* s in [0, 2^50] unless the state was corrupted: an s outside is counted and clamped to it */
    const int64_t s_in = clamp_cov_wide(s->s, events);
    const int64_t s_pos = (s_in < 0) ? 0 : s_in;
    /* S = s + R: in [1, 2^51) (R >= 1) */
    const uint64_t S = (uint64_t)s_pos + (uint64_t)s->r;
    /* S 2^up has its top bit at 62; mant = S 2^(up - 32) in [2^30, 2^31) and
     * s_norm = floor(s 2^(up - 32)) <= mant, both by the same shift, so the
     * exponent cancels in s / S.  1/mant = recip 2^-61.             up in 12..62 */
    const unsigned up = 63u - bit_length64(S);
    const uint32_t recip = wake_rtp_reciprocal((uint32_t)((S << up) >> 32));
    const uint32_t s_norm = (uint32_t)(((uint64_t)s_pos << up) >> 32);
    *events += (uint32_t)(s_in < 0);
    /* rho = s / S = s_norm recip / 2^31                                  Q30 */
    g.rho = narrow_saturate(shift_right_round((int64_t)multiply_wide_unsigned(s_norm, recip >> 1), 30u), events);   /* < 2^62 */
    /* tau = R / S = 1 - rho                                                Q30 */
    g.tau = narrow_saturate((int64_t)RATIO_ONE - g.rho, events);
    g.s_pos = s_pos;
    return g;
}

#if WAKE_RTP_NO_LONG_MULTIPLY
/* Without the long multiply the gain's 64-bit products are long code: the step's update and the split step's
 * prepare share one out-of-line copy (wake_rtp_split.c), as one translation unit compiled them before. */
kalman_gain_t wake_rtpi_kalman_gain(const wake_rtp_t *s, uint32_t *events);
#endif

/** The gain of a step's update or a split step's prepare: kalman_gain, or its shared copy. */
static inline kalman_gain_t gain_of(const wake_rtp_t *s, uint32_t *events)
{
#if WAKE_RTP_SPLIT && WAKE_RTP_NO_LONG_MULTIPLY
    return wake_rtpi_kalman_gain(s, events);
#else
    return kalman_gain(s, events);
#endif
}

/** P = P - u u'/S + q I, seen along w:  s = w'Pw = tau s + q |w|^2 (Q(P)), clamped to +-2^50. */
static inline int64_t kalman_covariance(const wake_rtp_t *s, const kalman_gain_t *g, uint32_t *events)
{
    return clamp_cov_wide(multiply_wide_by32(g->s_pos, g->tau, 30u) + s->q_omega, events);
}

/** d = d + u e / S with u = P w = (s / |w|^2) w:  z = w'd gains rho e (Q23), clamped to +-2^40. */
static inline int64_t kalman_corrected(const wake_rtp_t *s, wake_ratio_t rho, wake_q23_t e, uint32_t *events)
{
    return clamp_wide(s->z + shift_right_round(multiply_wide(rho, e), 30u), events);
}

#endif

/** y(n) = acc + z for acc = h' window (Q(FIR + 15), |.| < 2^62), rounded to Q23 (stored) and to Q15 (returned). */
static inline wake_q15_t step_output(wake_rtp_t *s, int64_t acc, uint32_t *events)
{
    /* y(n) = h' window + w'd:  Q(FIR + 15) -> Q23, rounded once; |.| < 2^48 */
    wake_q23_t y = narrow_saturate(shift_right_round(acc, FIR_TO_SIGNAL_SHIFT) + s->z, events);
    s->last_output = y;
    return narrow_saturate16((int32_t)shift_right_round(y, SIGNAL_GUARD_BITS), events);
}

/** a = h' window + z = w'(B window + d), rounded to Q23 (stored as y(n)) and to Q15 (returned). */
static inline wake_q15_t predict(wake_rtp_t *s, uint32_t *events)
{
    const wake_q15_t *window = s->ring + s->head;     /* contiguous: each sample is stored twice */
    return step_output(s, fir_window(s->fir, window, s->n_taps), events);
}

#if WAKE_RTP_KALMAN
/** s after a time update only: s gains q|w|^2 (steps counts the q I), clamped to +-2^50. */
static inline int64_t time_updated(const wake_rtp_t *s, uint32_t *events)
{
    return clamp_cov_wide(s->s + s->q_omega, events);
}

#endif

/** The time update of a sample without a measurement update, unless the Kalman is inert. */
static inline void time_update_only(wake_rtp_t *s, uint32_t *events)
{
#if WAKE_RTP_KALMAN
    if (!s->inert) {
        wake_rtpi_time_update(s, events);
    }
#else
    (void)s;
    (void)events;
#endif
}

/* ---------------------------------------------------------------------- */
/* The tremor ahead's per-sample pieces (wake_ahead_t; wake_rtp_ahead.c)   */
/* ---------------------------------------------------------------------- */

/**
 * P = c . line, newest estimate first: Q27 x Q15 products, exact in int64.
 * |c_i| < 2^31 and |e_i| <= 2^15 (any value of the struct): |P| < 2^49.
 */
static WAKE_RTP_ALWAYS_INLINE int64_t ahead_dot(const int32_t *c, const wake_q15_t *line)
{
#if WAKE_RTP_NO_LONG_MULTIPLY
    /* c = hi 2^16 + lo, lo in [0, 2^16): hi e and lo e are single 32-bit products (|.| < 2^31),
     * summed in int64 so that 8 of them cannot overflow: no __aeabi_lmul on the Cortex-M0+ */
    int64_t acc_hi = 0, acc_lo = 0;
    unsigned i;
    for (i = 0; i < (unsigned)WAKE_RTP_AHEAD_TAPS; ++i) {                /* wcet-loop: 8 */
        const int32_t e = line[i];
        acc_hi += (int32_t)shift_right_floor(c[i], 16u) * e;
        acc_lo += (int32_t)((uint32_t)c[i] & 0xFFFFu) * e;
    }
    return acc_hi * 65536 + acc_lo;
#else
    /* written out: eight multiply-accumulates, no loop overhead (a quarter of the ahead's cost) */
    int64_t acc0 = (int64_t)c[0] * line[0], acc1 = (int64_t)c[1] * line[1];
    acc0 += (int64_t)c[2] * line[2];
    acc1 += (int64_t)c[3] * line[3];
    acc0 += (int64_t)c[4] * line[4];
    acc1 += (int64_t)c[5] * line[5];
    acc0 += (int64_t)c[6] * line[6];
    acc1 += (int64_t)c[7] * line[7];
    return acc0 + acc1;
#endif
}

/** Index of the slot the next estimate takes (the oldest one's), 0..7: the line runs newest first. */
static WAKE_RTP_ALWAYS_INLINE unsigned ahead_next_head(const wake_ahead_t *a)
{
    return (a->head + (unsigned)WAKE_RTP_AHEAD_TAPS - 1u) & ((unsigned)WAKE_RTP_AHEAD_TAPS - 1u);
}

/** e(n) from the tremor estimate in Q23: Q15 of FS, saturated (counted in *events). */
static WAKE_RTP_ALWAYS_INLINE wake_q15_t ahead_estimate(wake_q23_t tremor, uint32_t *events)
{
    /* round(t / 2^8) = floor((floor(t / 2) + 2^6) / 2^7) in 32 bits (no overflow: |floor(t / 2)| <= 2^30),
     * |.| < 2^24 before the saturation */
    const int32_t half = shift_right_floor32(tremor, 1u);
    return narrow_saturate16(shift_right_floor32(half + (INT32_C(1) << (SIGNAL_GUARD_BITS - 2)),
                                                 SIGNAL_GUARD_BITS - 1u), events);
}

/** line <- e(n) at @p head (stored twice), which becomes the newest. */
static WAKE_RTP_ALWAYS_INLINE void ahead_line_store(wake_ahead_t *a, unsigned head, wake_q15_t e)
{
    a->line[head] = e;
    a->line[head + (unsigned)WAKE_RTP_AHEAD_TAPS] = e;
    a->head = (uint16_t)head;
}

/**
 * g(n) = g(n-1) + (goal - g(n-1)) alpha for the goal @p goal_field (the struct's, or 0 for a missing sample).
 *
 * With goal, g in [0, 2^30] and alpha in (0, 2^30] (what every setter checks) the new g lies between g
 * and goal: |round((goal - g) alpha / 2^30)| <= |goal - g|, so g never leaves [0, 1] and nothing can
 * saturate.  A corrupted value must still be safe: g, goal and alpha are read through a 31-bit mask (one
 * AND each), so goal - g fits int32, the product < 2^62, and the sum (< 2^32) is returned through the
 * same mask (defined; no branch).
 */
static WAKE_RTP_ALWAYS_INLINE int32_t ahead_gate_next(const wake_ahead_t *a, wake_ratio_t goal_field)
{
    const int32_t gate = (int32_t)((uint32_t)a->gate & UINT32_C(0x7FFFFFFF));
    const int32_t goal = (int32_t)((uint32_t)goal_field & UINT32_C(0x7FFFFFFF));
    const int32_t diff = goal - gate;
    return (int32_t)((uint32_t)(gate + shift_right_round(multiply_wide(diff, (int32_t)((uint32_t)a->ramp
                                                                                       & UINT32_C(0x7FFFFFFF))),
                                                          WAKE_RTP_GATE_FRAC)) & UINT32_C(0x7FFFFFFF));
}

/** P(n) from the dot product c . line, Q42 (|.| < 2^50): rounded to Q23, |.| < 2^31 fits int32. */
static WAKE_RTP_ALWAYS_INLINE wake_q23_t ahead_predicted(int64_t dot)
{
    return (int32_t)shift_right_round(dot, WAKE_RTP_AHEAD_COEF_FRAC + WAKE_RTP_SAMPLE_FRAC - WAKE_RTP_STATE_FRAC);
}

/** Store P(n), the gate g(n) (31 bits) and the command g P. */
static WAKE_RTP_ALWAYS_INLINE void ahead_output(wake_ahead_t *a, wake_q23_t predicted, int32_t gate)
{
    a->gate = gate;
    a->predicted = predicted;
    /* command = g P: Q53, |.| < 2^62; rounded to Q23 (<= |P| for g <= 1; < 2^31 for the 31-bit g) */
    a->command = (int32_t)shift_right_round(multiply_wide(gate, predicted), WAKE_RTP_GATE_FRAC);
}

/** v clamped to +-2^bits (1 <= bits <= 62), not counted: it only guards a corrupted prepared sum. */
static inline int64_t clamp_quiet(int64_t v, unsigned bits)
{
    const int64_t top = INT64_C(1) << bits;
    return (v > top) ? top : (v < -top) ? -top : v;
}

/** The tremor ahead's part of a prepare: the slot the next estimate takes holds the oldest one, which it
 * drops: c . line from there, less c_0 times it, is the sum of the seven products that stay (exact,
 * |.| < 2^49); the gate towards the goal (a missing sample's finish computes its own). */
static inline void ahead_prepare(const wake_ahead_t *a, wake_ahead_prepared_t *p)
{
    const unsigned head = ahead_next_head(a);
    p->dot = ahead_dot(a->coef, &a->line[head]) - multiply_wide(a->coef[0], a->line[head]);
    p->gate = ahead_gate_next(a, a->goal);
}



/** One more sample since the restart (sticks at UINT32_MAX): P gains q I per sample. */
static inline void count_step(wake_rtp_t *s)
{
    s->steps += (uint32_t)(s->steps != UINT32_MAX);
}

/** The last prediction y(n-1) rounded to Q15 (not yet saturated): it stands in for a missing sample. */
static inline int32_t stand_in(const wake_rtp_t *s)
{
    return (int32_t)shift_right_round(s->last_output, SIGNAL_GUARD_BITS);
}

/* ---------------------------------------------------------------------- */
/* The split step (wake_rtp_split.c): the parts of a step that prepare    */
/* computes without the sample into the instance's wake_rtp_split_t, and  */
/* what finish adds to them (only a prepared step, @p prepared 1, runs    */
/* them, and only on an instance that holds one: wake_rtpi_split)         */
/* ---------------------------------------------------------------------- */

/** h x exactly, for one FIR tap (either representation, see wake_fir_t) and a Q15 sample: |.| < 2^46. */
static inline int64_t fir_product(wake_fir_t h, int32_t x)
{
#if WAKE_RTP_SPLIT_FIR
    /* h = (biased_hi - 2^15) 2^16 + mid 2^8 + lo: three 32-bit products (|.| < 2^31), no 64-bit multiply */
    const int32_t p_hi = ((int32_t)h.parts.biased_hi - 32768) * x;
    const int32_t p_mid = (int32_t)h.parts.mid * x;
    const int32_t p_lo = (int32_t)h.parts.lo * x;
    return ((int64_t)p_hi * 65536) + ((int64_t)p_mid * 256) + (int64_t)p_lo;
#else
    return (int64_t)h.value * x;
#endif
}

/** The sum of the N taps h, exact in int64: |.| < 2^39 (|h_i| < 2^31, N <= 256). */
static inline int64_t fir_sum(const wake_fir_t *h, unsigned n)
{
    unsigned i;
#if WAKE_RTP_SPLIT_FIR
    /* h = (biased_hi - 2^15) 2^16 + mid 2^8 + lo: each part summed in 32 bits (n <= 64: < 2^22) */
    uint32_t hi = 0u;
    uint32_t mid = 0u;
    uint32_t lo = 0u;
    for (i = 0; i < n; ++i) {                                             /* wcet-loop: N */
        hi += h[i].parts.biased_hi;
        mid += h[i].parts.mid;
        lo += h[i].parts.lo;
    }
    return (((int64_t)hi - ((int64_t)n * 32768)) * 65536) + ((int64_t)mid * 256) + (int64_t)lo;
#else
    int64_t acc = 0;
    for (i = 0; i < n; ++i) {                                             /* wcet-loop: N */
        acc += h[i].value;
    }
    return acc;
#endif
}

/**
 * a x exactly, for |a| <= 2^39 and a Q15 sample x: a = hi 2^24 + mid 2^12 + lo with mid, lo in
 * [0, 2^12), so every product is one 32-bit multiply (|hi x| <= 2^30, |mid x|, |lo x| < 2^27); |.| < 2^55.
 */
static inline int64_t times_sample(int64_t a, int32_t x)
{
    const int64_t hi = shift_right_floor(a, 24u);
    const int64_t rest = a - (hi * 16777216);                             /* [0, 2^24) */
    const uint32_t bits = (uint32_t)rest;
    const uint32_t mid_bits = (bits >> 12) & 0xFFFu;                     /* the mask keeps it visibly < 2^12 */
    const uint32_t lo_bits = bits & 0xFFFu;
    const int32_t p_hi = (int32_t)hi * x;                                 /* |.| <= 2^30 */
    const int32_t p_mid = (int32_t)mid_bits * x;                          /* |.| < 2^27 */
    const int32_t p_lo = (int32_t)lo_bits * x;
    return ((int64_t)p_hi * 16777216) + ((int64_t)p_mid * 4096) + (int64_t)p_lo;
}


/** The feature instances' part of a prepare into @p p (the tremor ahead's, when the instance holds one). */
static inline void features_prepare(wake_rtp_t *s, wake_rtp_split_t *p)
{
#if WAKE_RTP_AHEAD
    ahead_prepare(&s->ahead, &p->ahead);
#else
    (void)s;
    (void)p;
#endif
}

/** The sample into a prepared window: h' window from the prepared sum (the first sample fills the window). */
static WAKE_RTP_ALWAYS_INLINE int64_t take_prepared(wake_rtp_t *s, wake_q15_t sample)
{
    const wake_rtp_split_t *const p = wake_rtpi_split_of(s);
    int64_t acc;
    if (s->primed != 0u) {
        ring_store(s, sample);
        /* h' window = prepared + h_{N-1} m(n), exact (the prepared sum clamped to its range, |.| < 2^52) */
        acc = clamp_quiet(p->fir, WAKE_BOUND_RTP_PREPARED_FIR_BITS) + fir_product(s->fir[s->n_taps - 1u], sample);
    } else {
        /* the first sample fills the window with itself: h' window = (sum of h) m(n), exact (the prepared
         * sum clamped to its range, |.| <= 2^39) */
        wake_rtpi_prime_window(s, sample);
        ring_store(s, sample);
        acc = times_sample(clamp_quiet(p->fir, WAKE_BOUND_RTP_PREPARED_TAP_SUM_BITS), sample);
    }
    return acc;
}

#if WAKE_RTP_KALMAN
/** The measurement update with the prepared gain and covariance; returns its saturations. */
static WAKE_RTP_ALWAYS_INLINE uint32_t kalman_finish(wake_rtp_t *s, wake_q23_t e)
{
    const wake_rtp_split_t *const p = wake_rtpi_split_of(s);
    uint32_t ev = 0u;
    s->z = kalman_corrected(s, p->rho, e, &ev);
    s->s = clamp_cov_wide(p->s, &ev);   /* within +-2^50 already, unless corrupted */
    return ev + p->events;
}
#endif

/* The per-sample control flow is written once (sample_flow, sample_admitted): @p prepared 0 makes the whole
 * step (wake_rtp_step), 1 finishes what wake_rtp_prepare computed (WAKE_RTP_SPLIT builds).  Every caller
 * passes a constant and the functions below are always inlined (WAKE_RTP_ALWAYS_INLINE), so each caller
 * compiles to its own path only: the helpers that follow pick the one of the two versions of each part. */

/** The sample into the window: a step's push (its FIR is predict's), or a prepared step's FIR sum. */
static WAKE_RTP_ALWAYS_INLINE int64_t take_sample(wake_rtp_t *s, wake_q15_t sample, int prepared)
{
    int64_t acc = 0;
    if (prepared != 0) {
        acc = take_prepared(s, sample);
    } else {
        push(s, sample);
    }
    return acc;
}

#if WAKE_RTP_KALMAN
/** The Kalman measurement update of a live instance for the innovation e; returns its saturations. */
static WAKE_RTP_ALWAYS_INLINE uint32_t kalman_measured(wake_rtp_t *s, wake_q23_t e, int prepared)
{
    uint32_t ev;
    if (prepared != 0) {
        ev = kalman_finish(s, e);
    } else {
        ev = wake_rtpi_kalman_update(s, e);
    }
    return ev;
}
#endif

/** The time update of a sample without a measurement update; a prepared step's inline (s has not changed
 * since the prepare). */
static WAKE_RTP_ALWAYS_INLINE void time_update_of_sample(wake_rtp_t *s, uint32_t *events, int prepared)
{
#if WAKE_RTP_KALMAN
    if (prepared != 0) {
        if (!s->inert) {
            s->s = time_updated(s, events);
        }
    } else {
        time_update_only(s, events);
    }
#else
    (void)prepared;
    time_update_only(s, events);
#endif
}

/** y(n): the FIR over the window (a step) or the prepared sum @p acc (a prepared step), plus z. */
static WAKE_RTP_ALWAYS_INLINE wake_q15_t sample_output(wake_rtp_t *s, int64_t acc, int prepared, uint32_t *events)
{
    return (prepared != 0) ? step_output(s, acc, events) : predict(s, events);
}

#if WAKE_RTP_AHEAD
/** The tremor ahead of the sample, e(n) = @p tremor: a step's, or a prepared step's with the prepared gate
 * (a missing sample's goal is 0: its gate is computed here). */
static WAKE_RTP_ALWAYS_INLINE void ahead_of_sample(wake_rtp_t *s, wake_q23_t tremor, int measured, int prepared)
{
    if (prepared != 0) {
        const wake_rtp_split_t *const p = wake_rtpi_split_of(s);
        wake_ahead_finish(&s->ahead, &p->ahead, tremor,
                          (measured != 0) ? p->ahead.gate : ahead_gate_next(&s->ahead, 0));
    } else {
        wake_rtpi_ahead_step(s, tremor);
    }
}
#endif

/**
 * One sample of a checked instance, with @p ev events counted before it.
 * @p measured 0: a missing sample of a primed stream, @p sample the stand-in
 * sample_admitted computed.  @p prepared: see above.
 */
static WAKE_RTP_ALWAYS_INLINE wake_q15_t sample_flow(wake_rtp_t *s, wake_q15_t sample, int measured, uint32_t ev,
                                                     int prepared)
{
    wake_q15_t y;
    int64_t acc;
#if WAKE_RTP_AHEAD
    wake_q23_t tremor = 0;                 /* e(n): 0 for the first sample and a missing one */
#endif
    if (!s->primed || !measured) {
        /* No measurement update, only the time update P = P + q I: a missing sample has no
         * innovation, and neither has the first sample of a stream (no prediction preceded it;
         * e would be 0 by construction: the window is primed with it).  It also keeps the
         * priming off the Kalman update's path: the step's static bound is the longer of the
         * two, not their sum.  (A prepared step takes its sample after the update, as below.) */
        acc = (prepared != 0) ? 0 : take_sample(s, sample, prepared);
        time_update_of_sample(s, &ev, prepared);
    } else {
        const wake_q23_t e = innovation(s, sample, &ev); /* its saturation is counted even when inert */
#if WAKE_RTP_AHEAD
        tremor = e;                                       /* the tremor estimate m(n) - y(n-1) */
#endif
        acc = (prepared != 0) ? 0 : take_sample(s, sample, prepared);
#if WAKE_RTP_KALMAN
        if (!s->inert) {
            ev += kalman_measured(s, e, prepared);
        }
#else
        (void)e;
#endif
    }
    if (prepared != 0) {
        acc = take_sample(s, sample, prepared);           /* the update reads nothing the sample changes */
    }
    count_step(s);
    y = sample_output(s, acc, prepared, &ev);
    count_events(&s->saturations, ev);
#if WAKE_RTP_VOLUNTARY_AHEAD
    wake_rtpi_voluntary_step_on(s, &s->voluntary_ahead);   /* not with WAKE_RTP_SPLIT (wake_rtp.h) */
#endif
#if WAKE_RTP_AHEAD
    ahead_of_sample(s, tremor, measured, prepared);
#endif
    return y;
}

/** 1 when a prepared step (@p prepared) finds no prepare since the last step. */
static WAKE_RTP_ALWAYS_INLINE int unprepared(const wake_rtp_t *s, int prepared)
{
    const wake_rtp_split_t *const p = wake_rtpi_split_of(s);
    return ((prepared != 0) && ((p == NULL) || (p->ready != 1u))) ? 1 : 0;
}

/**
 * The checks of wake_rtp_step (@p measured 1) and wake_rtp_step_missing (0), or with @p prepared of
 * wake_rtp_finish and wake_rtp_finish_missing, and a missing sample's stand-in.  Returns 1 when the caller
 * runs sample_flow on *@p sample (the sample or its stand-in) with the *@p ev events counted so far; 0 when
 * the call is over, with its status in *@p st.
 */
static WAKE_RTP_ALWAYS_INLINE int sample_admitted(wake_rtp_t *s, wake_q15_t *sample, int measured,
                                                  wake_q15_t *prediction, int prepared, uint32_t *ev,
                                                  wake_rtp_status_t *st)
{
    *st = wake_rtpi_check_structure(s);
    if (*st != WAKE_RTP_OK) {
        return 0;
    }
    if ((prediction == NULL) || unprepared(s, prepared)) {
        if (prediction == NULL) {                  /* nothing changes */
            *st = WAKE_RTP_E_NULL;
        } else if (wake_rtpi_split_of(s) == NULL) {
            *st = WAKE_RTP_E_FEATURE;
        } else {
            *st = WAKE_RTP_E_UNPREPARED;
        }
        return 0;
    }
    wake_rtpi_split_forget(s);                     /* the step changes what a prepare read */
    if (!measured) {
#if WAKE_RTP_AHEAD
        ahead_shut(&s->ahead);                     /* the held-out gain needs a window's worth of samples again */
#endif
        if (!s->primed) {
            *prediction = 0;                       /* a missing sample before the first: nothing to predict from */
#if WAKE_RTP_AHEAD
            ahead_of_sample(s, 0, measured, prepared);   /* the tremor ahead still takes its estimate 0 */
#endif
            return 0;
        }
        *sample = narrow_saturate16(stand_in(s), ev);
    }
    return 1;
}

#endif /* WAKE_RTP_SAMPLE_H */
