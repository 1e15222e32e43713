/**
 * @file wake_rtp.c
 * @brief Fixed-point WAKE real-time prediction in constant time.
 *
 * The per-sample path (wake_rtp_step) is the 2^J-tap FIR y = h' window plus
 * a scalar Kalman recursion along w; the J x J covariance P and the
 * correction d of the literal recursion (wake/rtp/reference.py, which
 * restarts P as (w'Pw / |w|^2) I at a weight change) are formed from the
 * restart and a few scalars only in set_weights and get_state.
 * docs/studies/fixed_point.md derives the form and bounds its error.
 *
 * Conventions: no signed overflow, no left shift of a negative value, no
 * float, no division instruction.  Right shifts of negative values go
 * through shift_right_floor(), written with non-negative operands only, so
 * the code does not rely on the implementation-defined behaviour of `>>` on
 * negative numbers (compilers still emit one arithmetic shift).
 *
 * Loops of the per-sample path carry a `wcet-loop:` annotation with their
 * largest trip count (N = 2^J); `wake profile` reads it to bound the
 * worst-case execution time from the compiled image.
 */
#include "wake_rtp.h"
#include "wake_fixed.h"

#include <string.h>

/* The FIR reads its taps split in parts (wake_fir_t) where that avoids 64-bit
 * sums; its 32-bit sums hold up to 64 taps. */
#if WAKE_RTP_NO_LONG_MULTIPLY && WAKE_RTP_MAX_LEVEL <= 6
#define WAKE_RTP_SPLIT_FIR 1
#else
#define WAKE_RTP_SPLIT_FIR 0
#endif

/* Functions kept out of line so that `wake profile` can bound the step with
 * and without them (the Kalman update is skipped while inert; the window fill
 * runs on the first sample only). */
#if defined(__GNUC__)
#define WAKE_RTP_NOINLINE __attribute__((noinline))
#else
#define WAKE_RTP_NOINLINE
#endif

/* Functions that run once per HPA, reset or state load, never per sample.
 * clang optimises them for size: at -O2 it unrolls their loops over the J
 * levels into about twice gcc's code (bench/clang_cost.py); gcc builds them
 * as the rest.  The per-sample path is not marked. */
#if defined(__clang__)
#define WAKE_RTP_COLD __attribute__((minsize))
#else
#define WAKE_RTP_COLD
#endif

/* The ring is 4-byte aligned inside the struct (prime_window stores words). */
typedef char wake_rtp_ring_is_aligned[(offsetof(wake_rtp_t, ring) % 4u == 0u) ? 1 : -1];

#define P_FRAC WAKE_RTP_P_FRAC
#define RATIO_ONE (INT32_C(1) << WAKE_RTP_RATIO_FRAC)
/* Q15 sample -> Q23 signal: 8 guard bits */
#define SIGNAL_GUARD_BITS (WAKE_RTP_STATE_FRAC - WAKE_RTP_SAMPLE_FRAC)
/* Q(FIR) x Q15 -> Q23 */
#define FIR_TO_SIGNAL_SHIFT (WAKE_RTP_FIR_FRAC + WAKE_RTP_SAMPLE_FRAC - WAKE_RTP_STATE_FRAC)

#if WAKE_RTP_KALMAN /* the ranges of the Kalman's scalars */
/** v clamped to +-2^40 (the range of z = w'd); adds 1 to *events when it clamps. */
static inline int64_t clamp_wide(int64_t v, uint32_t *events)
{
    return clamp_symmetric(v, 40u, events);
}

/** v clamped to +-2^50 (the range of s); adds 1 to *events when it clamps. */
WAKE_RTP_INLINE_UNLESS_OS int64_t clamp_cov_wide(int64_t v, uint32_t *events)
{
    return clamp_symmetric(v, 50u, events);
}

#endif

uint32_t wake_rtp_reciprocal(uint32_t x)
{
    /* x in [2^30, 2^31) is X = x / 2^31 in [0.5, 1); the result is 1/X in Q30.
     * The first steps need few bits, so they run on the top 16 bits of x with
     * 32-bit products (one MULS each on a Cortex-M0+); only the last two need
     * 32 x 32 -> 64-bit ones.
     * Start: r0 = 48/17 - 32/17 X (max relative error 1/17), r in Q15.
     * Two steps r <- r (2 - X r) in 32 bits: 1/17 -> 3.5e-3 -> 1.2e-5, plus
     * the truncation of X and r to 16 bits (< 2^-14 in all).
     * Two steps in 64 bits, r in Q30: -> 1e-8 -> rounding.
     * The result is within 2^-29 relative of 2^61 / x (csrc/tests). */
    const uint32_t x16 = x >> 15;                                        /* X, Q16, in [2^15, 2^16) */
    /* 48/17 in Q15 = 92521.4, 32/17 in Q16 = 123362.6: r0 = 92521 - (32/17 X), Q15 */
    uint32_t r = UINT32_C(92521) - ((UINT32_C(123363) * (x16 >> 1)) >> 16);  /* 123363 x16/2 < 2^32 */
    uint64_t xr;
    uint32_t two_minus;
    /* X r in Q31 = x16 r (Q16 x Q15) is about 2^31 (< 1.07 2^31 from the start on):
     * 2 - X r in Q31 is 2^32 - X r, as a uint32 (mod 2^32); in Q15 it is that / 2^16. */
    r = (r * ((UINT32_C(0) - x16 * r) >> 16)) >> 15;                    /* step 1; r <= 2^16.1: < 2^32 */
    r = (r * ((UINT32_C(0) - x16 * r) >> 16)) >> 15;                    /* step 2 */
    r <<= 15;                                                             /* Q15 -> Q30 */
    xr = multiply_wide_unsigned(x, r) >> 31;                              /* X r, Q30, about 2^30 */
    two_minus = (uint32_t)((UINT64_C(1) << 31) - xr);                    /* 2 - X r, Q30, < 2^31 */
    r = (uint32_t)(multiply_wide_unsigned(r, two_minus) >> 30);          /* step 3 */
    xr = multiply_wide_unsigned(x, r) >> 31;
    two_minus = (uint32_t)((UINT64_C(1) << 31) - xr);
    r = (uint32_t)(multiply_wide_unsigned(r, two_minus) >> 30);          /* step 4 */
    return r;
}

#if WAKE_RTP_KALMAN
/**
 * round(a 2^frac / x) clamped to +-2^50, for |a| < 2^62, 1 <= x < 2^62 and
 * frac <= 40: restoring long division, one quotient bit per turn.  Exact
 * (one rounding), a fixed number of turns; it runs in the restart and in
 * get_state only, never per sample.
 */
WAKE_RTP_COLD static int64_t divide_wide(int64_t a, uint64_t x, unsigned frac, uint32_t *events)
{
    const uint64_t cap = UINT64_C(1) << 52;                 /* twice 2^50 and more: clamps below */
    uint64_t mag = (uint64_t)(a < 0 ? -a : a), rem = 0, q = 0;
    unsigned k;
    /* the numerator mag 2^(frac + 1), bit by bit from the top: the 62 bits of mag, then zeros */
    for (k = 0; k < 63u + frac; ++k) {
        uint64_t take;
        rem = (rem << 1) | (mag >> 61);                                     /* < 2 x < 2^63 */
        mag = (mag << 1) & ((UINT64_C(1) << 62) - 1u);
        take = (rem >= x) ? 1u : 0u;
        rem -= x & (UINT64_C(0) - take);                                 /* no multiply */
        q = (q << 1) | take;                                                /* <= 2^53 + 1 */
        q = (q > cap) ? cap : q;
    }
    q = (q + 1u) >> 1;                                      /* one extra bit: round half up */
    return clamp_cov_wide(a < 0 ? -(int64_t)q : (int64_t)q, events);
}
#endif /* WAKE_RTP_KALMAN */

#if WAKE_RTP_SPLIT
static void split_refresh(wake_rtp_t *s);
#endif

/* ---------------------------------------------------------------------- */
/* Validation                                                              */
/* ---------------------------------------------------------------------- */

static int weights_in_range(const wake_q24_t *weights, unsigned level)
{
    unsigned j;
    for (j = 0; j < level; ++j) {
        if (weights[j] > WAKE_RTP_WEIGHT_MAX || weights[j] < -WAKE_RTP_WEIGHT_MAX) {
            return 0;
        }
    }
    return 1;
}

/** The structural fields: what wake_rtp_step indexes with or branches on. */
static wake_rtp_status_t check_structure(const wake_rtp_t *s)
{
    uint32_t live;
    if (s == NULL) {
        return WAKE_RTP_E_NULL;
    }
    if (s->magic != WAKE_RTP_MAGIC) {
        return WAKE_RTP_E_UNINIT;
    }
    /* an inert instance has q = 0 and a zero covariance; tested without a branch on inert, so
       that an inert and a live instance pay the same (the step's cost does not depend on it) */
    live = (uint32_t)(s->q != 0) | (uint32_t)(s->s != 0);
    if (s->level < 1u || s->level > (unsigned)WAKE_RTP_MAX_LEVEL
        || s->n_taps != (uint16_t)(1u << s->level) || s->head >= s->n_taps
        || s->primed > 1u || s->taps == NULL || s->r <= 0 || s->q < 0 || s->p0 < 0
        || s->inert > 1u || (s->inert & live) != 0u
        || (!WAKE_RTP_KALMAN && s->inert != 1u)) {
        return WAKE_RTP_E_CORRUPT;
    }
#if WAKE_RTP_AHEAD
    if (s->ahead_head >= (unsigned)WAKE_RTP_AHEAD_TAPS) {           /* the step indexes the line with it */
        return WAKE_RTP_E_CORRUPT;
    }
#endif
    return WAKE_RTP_OK;
}

#if WAKE_RTP_AHEAD
/** 1 when every coefficient lies within +-8 (Q27). */
static int ahead_coefficients_in_range(const int32_t *c)
{
    unsigned i;
    for (i = 0; i < (unsigned)WAKE_RTP_AHEAD_TAPS; ++i) {
        if (c[i] > WAKE_RTP_AHEAD_COEF_MAX || c[i] < -WAKE_RTP_AHEAD_COEF_MAX) {
            return 0;
        }
    }
    return 1;
}

/** 1 when v lies in [lo, 2^30] (a gate, goal or ramp in Q30). */
static int gate_in_range(wake_ratio_t v, wake_ratio_t lo)
{
    return (v >= lo && v <= WAKE_RTP_GATE_ONE) ? 1 : 0;
}

/** The ahead fields every function but the per-sample ones checks (the step indexes with ahead_head only). */
static int ahead_consistent(const wake_rtp_t *s)
{
    return ahead_coefficients_in_range(s->ahead_coef) && gate_in_range(s->ahead_goal, 0)
           && gate_in_range(s->ahead_gate, 0) && gate_in_range(s->ahead_ramp, 1);
}
#endif

/** check_structure plus the weights' range and the variance's sign (every function but the per-sample ones). */
static wake_rtp_status_t check_instance(const wake_rtp_t *s)
{
    wake_rtp_status_t st = check_structure(s);
    if (st == WAKE_RTP_OK && (!weights_in_range(s->weights, s->level) || s->variance < 0)) {
        return WAKE_RTP_E_CORRUPT;
    }
#if WAKE_RTP_AHEAD
    if (st == WAKE_RTP_OK && !ahead_consistent(s)) {
        return WAKE_RTP_E_CORRUPT;
    }
#endif
#if WAKE_RTP_VOLUNTARY_AHEAD
    if (st == WAKE_RTP_OK && (!weights_in_range(s->vol_weights, s->level) || s->vol_set > 1u)) {
        return WAKE_RTP_E_CORRUPT;
    }
#endif
    return st;
}

WAKE_RTP_COLD static wake_rtp_status_t check_weights(const wake_q24_t *weights, unsigned level, wake_cov_t r, wake_cov_t q)
{
    if (weights == NULL) {
        return WAKE_RTP_E_NULL;
    }
    if (!weights_in_range(weights, level)) {
        return WAKE_RTP_E_WEIGHTS;
    }
    if (r <= 0 || q < 0) {
        return WAKE_RTP_E_NOISE;
    }
    if (!WAKE_RTP_KALMAN && q != 0) {
        return WAKE_RTP_E_NO_KALMAN;
    }
    return WAKE_RTP_OK;
}

/* ---------------------------------------------------------------------- */
/* The covariance form: P and d from a few scalars                         */
/* ---------------------------------------------------------------------- */

#if WAKE_RTP_KALMAN /* the covariance code: left out of WAKE_RTP_KALMAN 0 builds */
/** q |w|^2 or lambda |w|^2 for a Q(P) value c and |w|^2 in Q24 (< 2^40): Q(P) in int64, |.| < 2^47. */
static WAKE_RTP_OUTLINE_AT_OS int64_t scale_by_norm(wake_cov_t c, uint64_t omega)
{
    /* c |w|^2 = c (hi + lo / 2^24) with |w|^2 = hi 2^24 + lo: hi < 2^16, lo < 2^24 */
    return (int64_t)c * (int64_t)(omega >> 24) + shift_right_round((int64_t)c * (int64_t)(omega & 0xFFFFFFu), 24u);
}

/** |w|^2 in Q24 (exact sum of Q48 squares, rounded once): < 2^40. */
static uint64_t weight_norm2(const wake_q24_t *w, unsigned J)
{
    unsigned j;
    uint64_t acc = 0;
    for (j = 0; j < J; ++j) {
        acc += (uint64_t)((int64_t)w[j] * w[j]);           /* < 2^60, J <= 8 terms */
    }
    return (acc + (UINT64_C(1) << 23)) >> 24;
}

/** w'x for x in Q23 (d) or Q(P) (a row of P): sum of J products Q(f + 24) rounded once to Q(f); |.| < 2^41. */
static int64_t weighted_sum(const wake_q24_t *w, const int32_t *x, unsigned J)
{
    unsigned j;
    int64_t acc = 0;
    for (j = 0; j < J; ++j) {
        acc += shift_right_floor(multiply_wide(x[j], w[j]), 3u);       /* 8 terms < 2^60 each: < 2^63 */
    }
    return shift_right_round(acc, 21u);
}

/** Lambda = variance + steps q: the diagonal of P now, before the measurements along w took their share. */
static WAKE_RTP_OUTLINE_AT_OS wake_cov_t grown_variance(const wake_rtp_t *s, uint32_t *events)
{
    return narrow_saturate((int64_t)s->variance + (int64_t)s->steps * s->q, events);   /* < 2^63 */
}

/**
 * P and d of the literal recursion (docs/studies/fixed_point.md): since the last restart
 * (P = lambda I, d = d_s) every u = P w was parallel to w, so
 *
 *   d = d_s + ((z - z_s) / |w|^2) w
 *   P = Lambda I - c w w',   Lambda = lambda + steps q,   c = (Lambda - s / |w|^2) / |w|^2
 *
 * @p P may be NULL (set_weights needs d only).  With w = 0 nothing was observed:
 * d = d_s and P = Lambda I.
 */
WAKE_RTP_COLD static void materialise(const wake_rtp_t *s, wake_q23_t *d, wake_cov_t *P, uint32_t *events)
{
    /* The coefficients carry XF extra fraction bits: they are multiplied by
     * weights up to 64, whose products w_i w_j would otherwise amplify their
     * rounding to many LSB. */
    enum { XF = 16 };
    unsigned i, j, J = s->level;
    const wake_q24_t *w = s->weights;
    uint64_t omega = weight_norm2(w, J);
    wake_cov_t lambda = grown_variance(s, events);
    int64_t c_z = 0, c_ww = 0;                             /* Q(23 + XF), Q(P + XF) */
    if (omega != 0u) {
        /* c_z = (z - z_s) / |w|^2, z_s = w'd_s as the restart computed it   (|w|^2 in Q24) */
        c_z = divide_wide(s->z - weighted_sum(w, s->correction, J), omega, 24 + XF, events);
        if (P != NULL) {
            /* c = (Lambda - s / |w|^2) / |w|^2 */
            c_ww = (int64_t)lambda * (INT64_C(1) << XF) - divide_wide(s->s, omega, 24 + XF, events);
            c_ww = divide_wide(c_ww, omega, 24, events);
        }
    }
    for (i = 0; i < J; ++i) {
        /* d_i = d_s,i + c_z w_i                                                    Q23 */
        int64_t t = shift_right_round(multiply_wide_by32(c_z, w[i], 24u), XF);
        d[i] = narrow_saturate((int64_t)s->correction[i] + t, events);
        if (P != NULL) {
            /* P_ij = Lambda d_ij - (c w_i) w_j                                       Q(P) */
            int64_t row = clamp_cov_wide(multiply_wide_by32(c_ww, w[i], 24u), events);
            for (j = i; j < J; ++j) {                      /* upper triangle, mirrored */
                int64_t p = (i == j ? (int64_t)lambda : 0)
                            - shift_right_round(multiply_wide_by32(row, w[j], 24u), XF);
                P[i * J + j] = narrow_saturate(p, events);
                /* P is PSD, so P_ii >= 0; with |w| below about 0.05, |w|^2 in Q24 has few bits and the
                 * rounding of c can leave P_ii a few LSB below 0, which load_state would refuse */
                if ((i == j) && (P[i * J + j] < 0)) {
                    P[i * J + j] = 0;
                }
                P[j * J + i] = P[i * J + j];
            }
        }
    }
}

/**
 * The variance the filter holds along w: w'Pw / |w|^2, saturated to the
 * covariance format; @p unobserved when w = 0, which observes nothing.  A
 * weight change restarts P at this variance in every direction.
 */
WAKE_RTP_COLD static wake_cov_t observed_variance(const wake_rtp_t *s, int64_t w_p_w, wake_cov_t unobserved,
                                                  uint32_t *events)
{
    uint64_t omega = weight_norm2(s->weights, s->level);
    if (omega == 0u) {
        return unobserved;
    }
    return narrow_saturate(divide_wide(w_p_w < 0 ? 0 : w_p_w, omega, 24, events), events);
}
#endif /* WAKE_RTP_KALMAN */

/** A tap as fir_window reads it (see wake_fir_t). */
WAKE_RTP_INLINE_UNLESS_OS wake_fir_t fir_tap(int32_t h)
{
    wake_fir_t t;
#if WAKE_RTP_SPLIT_FIR
    const uint32_t bits = (uint32_t)h;
    t.parts.biased_hi = (uint16_t)((bits >> 16) ^ 0x8000u);   /* top half, top bit flipped: floor(h/2^16) + 2^15 */
    t.parts.mid = (uint8_t)((bits >> 8) & 0xFFu);
    t.parts.lo = (uint8_t)(bits & 0xFFu);
#else
    t.value = h;
#endif
    return t;
}

#if WAKE_RTP_VOLUNTARY_AHEAD
/**
 * FIR taps h_i = sum_j B_ji w_j of weights @p w: exact in int64 (Q39), rounded once to Q(FIR), as restart
 * builds h = B'w (restart keeps its own loop so that the default build's code does not move, issue 34).
 */
static inline void fir_from_weights(const wake_rtp_t *s, const wake_q24_t *w, wake_fir_t *fir, uint32_t *ev)
{
    unsigned i, j, J = s->level, N = s->n_taps;
    for (i = 0; i < N; ++i) {
        int64_t acc = 0;
        for (j = 0; j < J; ++j) {
            acc += (int64_t)s->taps[j * N + i] * w[j];
        }
        fir[i] = fir_tap(narrow_saturate(shift_right_round(acc, 15u + WAKE_RTP_WEIGHT_FRAC - WAKE_RTP_FIR_FRAC), ev));
    }
}

/**
 * The restart of the voluntary motion ahead, for w_h and the current w, d_s (docs/studies/design.md,
 * "Voluntary motion at n + h"):  d = d_s + ((z - z_s) / |w|^2) w  since the last restart, so
 *
 *   w_h' d = w_h' d_s + k (z - z_s),    k = w_h' w / |w|^2
 *
 * and the FIR taps h_h = B' w_h.  Runs in every restart and in wake_rtp_set_voluntary_ahead.
 */
WAKE_RTP_COLD static void voluntary_ahead_restart(wake_rtp_t *s)
{
    const unsigned J = s->level;
    fir_from_weights(s, s->vol_weights, s->vol_fir, &s->vol_saturations);
#if WAKE_RTP_KALMAN
    {
        uint64_t omega = weight_norm2(s->weights, J);
        int64_t dot = 0;
        unsigned j;
        /* z_s = w' d_s and w_h' d_s                                                     Q23 */
        s->vol_z_start = weighted_sum(s->weights, s->correction, J);
        s->vol_start = weighted_sum(s->vol_weights, s->correction, J);
        /* w_h' w: J products Q48 < 2^60, floor-shifted by 3 (Q45, |.| < 2^60) */
        for (j = 0; j < J; ++j) {
            dot += shift_right_floor(multiply_wide(s->vol_weights[j], s->weights[j]), 3u);
        }
        /* k = w_h' w / |w|^2: Q45 / Q24 with 3 more fraction bits = Q24; w = 0 observes nothing (d = d_s) */
        s->vol_gain = (omega == 0u) ? 0 : narrow_saturate(divide_wide(dot, omega, 3u, &s->vol_saturations),
                                                          &s->vol_saturations);
    }
#else
    /* no Kalman: d = 0 (init and load_state see to it) and z never moves */
    (void)J;
    s->vol_z_start = 0;
    s->vol_start = 0;
    s->vol_gain = 0;
#endif
}
#endif

/**
 * Restart the covariance form for the current weights from d and P = lambda I:
 * d_s = d,  s = lambda |w|^2,  z = w'd_s,  steps = 0.  Also rebuilds the
 * FIR taps h = B'w.  @p d may be the struct's own snapshot.
 */
WAKE_RTP_COLD static void restart(wake_rtp_t *s, const wake_q23_t *d, wake_cov_t lambda)
{
    unsigned i, j, J = s->level, N = s->n_taps;
    const wake_q24_t *w = s->weights;
    uint32_t *ev = &s->saturations;
    if (d != s->correction) {
        memcpy(s->correction, d, (size_t)J * sizeof(wake_q23_t));
    }
    s->variance = lambda;
    s->steps = 0u;
#if WAKE_RTP_KALMAN
    {
        uint64_t omega = weight_norm2(w, J);
        s->s = scale_by_norm(lambda, omega);                              /* w' (lambda I) w */
        s->q_omega = scale_by_norm(s->q, omega);
        s->z = weighted_sum(w, s->correction, J);                        /* z_s, recomputed by materialise */
    }
#else
    /* no Kalman: d = 0 and lambda = 0 (init and load_state see to it), so s = z = 0 */
    s->s = 0;
    s->q_omega = 0;
    s->z = 0;
#endif
    /* h_i = sum_j B_ji w_j: exact in int64 (Q39), rounded once to Q(FIR) */
    for (i = 0; i < N; ++i) {
        int64_t acc = 0;
        for (j = 0; j < J; ++j) {
            acc += (int64_t)s->taps[j * N + i] * w[j];
        }
        s->fir[i] = fir_tap(narrow_saturate(shift_right_round(acc, 15u + WAKE_RTP_WEIGHT_FRAC - WAKE_RTP_FIR_FRAC),
                                            ev));
    }
    s->inert = (s->q == 0 && s->s == 0) ? 1u : 0u;
#if WAKE_RTP_VOLUNTARY_AHEAD
    voluntary_ahead_restart(s);
#endif
}

/* ---------------------------------------------------------------------- */
/* Configuration                                                           */
/* ---------------------------------------------------------------------- */

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_init(wake_rtp_t *s, int level, const wake_q15_t *taps,
                                const wake_q24_t *weights, wake_cov_t r, wake_cov_t q, wake_cov_t p0)
{
    wake_rtp_status_t st;
    unsigned j, i, n;
    if (s == NULL) {
        return WAKE_RTP_E_NULL;
    }
    s->magic = 0u;
    if (taps == NULL || weights == NULL) {
        return WAKE_RTP_E_NULL;
    }
    if (level < 1 || level > WAKE_RTP_MAX_LEVEL) {
        return WAKE_RTP_E_LEVEL;
    }
    n = 1u << (unsigned)level;
    for (j = 0; j < (unsigned)level; ++j) {
        /* sum of |taps| <= 65535 (Q15) per row */
        int32_t row_abs = 0;
        for (i = 0; i < n; ++i) {
            int32_t t = taps[j * n + i];
            row_abs += (t < 0) ? -t : t;     /* at most 256 * 32768 = 2^23: no overflow */
        }
        if (row_abs > WAKE_RTP_TAP_ROW_ABS_MAX) {
            return WAKE_RTP_E_TAPS;
        }
    }
    st = check_weights(weights, (unsigned)level, r, q);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (p0 < 0) {
        return WAKE_RTP_E_NOISE;
    }
    if (!WAKE_RTP_KALMAN && p0 != 0) {
        return WAKE_RTP_E_NO_KALMAN;
    }
    memset(s, 0, sizeof(*s));
    s->level = (uint16_t)level;
    s->n_taps = (uint16_t)n;
    s->taps = taps;
    memcpy(s->weights, weights, (size_t)level * sizeof(wake_q24_t));
    s->r = r;
    s->q = q;
    s->p0 = p0;
    s->inert = (q == 0) ? 1u : 0u;   /* consistent before reset's check (s = 0); restart sets it */
#if WAKE_RTP_AHEAD
    s->ahead_ramp = WAKE_RTP_AHEAD_RAMP_DEFAULT;   /* coefficients, goal and gate 0 (memset) */
#endif
    s->magic = WAKE_RTP_MAGIC;
    return wake_rtp_reset(s);
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_set_weights(wake_rtp_t *s, const wake_q24_t *weights, wake_cov_t r, wake_cov_t q)
{
    wake_q23_t d[WAKE_RTP_MAX_LEVEL];
    wake_cov_t lambda = 0;
    wake_rtp_status_t st = check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    st = check_weights(weights, s->level, r, q);
    if (st != WAKE_RTP_OK) {
        return st;
    }
#if WAKE_RTP_KALMAN
    /* d under the old weights; P restarts as (w'Pw / |w|^2) I, its variance along the old w */
    materialise(s, d, NULL, &s->saturations);
    lambda = observed_variance(s, s->s, grown_variance(s, &s->saturations), &s->saturations);
#else
    memset(d, 0, sizeof(d));                                    /* d and P stay 0 */
#endif
    memcpy(s->weights, weights, (size_t)s->level * sizeof(wake_q24_t));
    s->r = r;
    s->q = q;
    restart(s, d, lambda);
#if WAKE_RTP_SPLIT
    split_refresh(s);                                           /* a prepared step stays prepared */
#endif
    return WAKE_RTP_OK;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_reset(wake_rtp_t *s)
{
    wake_rtp_status_t st = check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    memset(s->ring, 0, sizeof(s->ring));
    memset(s->correction, 0, sizeof(s->correction));
    s->head = 0u;
    s->primed = 0u;
    s->last_output = 0;
    s->saturations = 0u;
#if WAKE_RTP_AHEAD
    /* the tremor ahead forgets its samples and shuts; its coefficients and ramp stay */
    memset(s->ahead_line, 0, sizeof(s->ahead_line));
    s->ahead_head = 0u;
    s->ahead_goal = 0;
    s->ahead_gate = 0;
    s->ahead_predicted = 0;
    s->ahead_command = 0;
    s->ahead_saturations = 0u;
#endif
#if WAKE_RTP_VOLUNTARY_AHEAD
    s->vol_output = 0;                                          /* w_h stays */
    s->vol_saturations = 0u;
#endif
    restart(s, s->correction, s->p0);                           /* d = 0, P(0) = p0 I */
#if WAKE_RTP_SPLIT
    split_refresh(s);                                           /* a prepared step stays prepared */
#endif
    return WAKE_RTP_OK;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_get_state(const wake_rtp_t *s, wake_q23_t *correction, wake_cov_t *covariance)
{
    wake_rtp_status_t st = check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (correction == NULL || covariance == NULL) {
        return WAKE_RTP_E_NULL;
    }
#if WAKE_RTP_KALMAN
    {
        uint32_t ignored = 0u;
        materialise(s, correction, covariance, &ignored);
    }
#else
    memset(correction, 0, (size_t)s->level * sizeof(wake_q23_t));
    memset(covariance, 0, (size_t)s->level * s->level * sizeof(wake_cov_t));
#endif
    return WAKE_RTP_OK;
}



/* ---------------------------------------------------------------------- */
/* Per-sample recursion                                                    */
/* ---------------------------------------------------------------------- */

/**
 * The first sample fills the whole window (both copies); runs once per stream.
 * Two samples per aligned 32-bit store (the ring is 4-byte aligned and 2N is
 * a multiple of 4 samples for J >= 1), four stores per iteration.
 */
WAKE_RTP_NOINLINE static void prime_window(wake_rtp_t *s, wake_q15_t sample)
{
    unsigned i, N = s->n_taps;
#if defined(__GNUC__) && !defined(__OPTIMIZE_SIZE__)
    uint32_t pair = (uint32_t)(uint16_t)sample * UINT32_C(0x10001);
    unsigned char *ring = (unsigned char *)__builtin_assume_aligned(s->ring, 4);
    if (N == 2u) {                                /* J = 1: 2N = 4 samples, two words */
        __builtin_memcpy(ring, &pair, 4);
        __builtin_memcpy(ring + 4u, &pair, 4);
    } else {
        for (i = 0; i < 4u * N; i += 16u) {                               /* wcet-loop: N / 4 */
            __builtin_memcpy(ring + i, &pair, 4);
            __builtin_memcpy(ring + i + 4u, &pair, 4);
            __builtin_memcpy(ring + i + 8u, &pair, 4);
            __builtin_memcpy(ring + i + 12u, &pair, 4);
        }
    }
#else
    for (i = 0; i < 2u * N; ++i) {                                        /* wcet-loop: 2 * N */
        s->ring[i] = sample;
    }
#endif
    s->last_output = (int32_t)sample * (INT32_C(1) << SIGNAL_GUARD_BITS);
    s->primed = 1u;
}

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
        prime_window(s, sample);
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

/**
 * Kalman measurement and time update along w, for the innovation e (Q23).
 * Constant time: one reciprocal, four 32 x 32 -> 64-bit products.
 */
WAKE_RTP_NOINLINE static uint32_t kalman_update(wake_rtp_t *s, wake_q23_t e)
{
    uint32_t ev = 0u;
    const kalman_gain_t g = kalman_gain(s, &ev);
    s->z = kalman_corrected(s, g.rho, e, &ev);
    s->s = kalman_covariance(s, &g, &ev);
    return ev;
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

/** A sample without a measurement update (the first of a stream, or a missing one): P = P + q I only.
 * Kept out of line, like kalman_update, so that `wake profile` bounds the inert step without it. */
WAKE_RTP_NOINLINE static void time_update(wake_rtp_t *s, uint32_t *events)
{
    s->s = time_updated(s, events);
}
#endif

/** The time update of a sample without a measurement update, unless the Kalman is inert. */
static inline void time_update_only(wake_rtp_t *s, uint32_t *events)
{
#if WAKE_RTP_KALMAN
    if (!s->inert) {
        time_update(s, events);
    }
#else
    (void)s;
    (void)events;
#endif
}

#if WAKE_RTP_AHEAD
/**
 * P = c . line, newest estimate first: Q27 x Q15 products, exact in int64.
 * |c_i| < 2^31 and |e_i| <= 2^15 (any value of the struct): |P| < 2^49.
 */
static inline int64_t ahead_dot(const int32_t *c, const wake_q15_t *line)
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
static inline unsigned ahead_next_head(const wake_rtp_t *s)
{
    return (s->ahead_head + (unsigned)WAKE_RTP_AHEAD_TAPS - 1u) & ((unsigned)WAKE_RTP_AHEAD_TAPS - 1u);
}

/** e(n) from the tremor estimate in Q23: Q15 of FS, saturated (counted in *events). */
static inline wake_q15_t ahead_estimate(wake_q23_t tremor, uint32_t *events)
{
    /* round(t / 2^8) = floor((floor(t / 2) + 2^6) / 2^7) in 32 bits (no overflow: |floor(t / 2)| <= 2^30),
     * |.| < 2^24 before the saturation */
    const int32_t half = shift_right_floor32(tremor, 1u);
    return narrow_saturate16(shift_right_floor32(half + (INT32_C(1) << (SIGNAL_GUARD_BITS - 2)),
                                                 SIGNAL_GUARD_BITS - 1u), events);
}

/** line <- e(n) at @p head (stored twice), which becomes the newest. */
static inline void ahead_line_store(wake_rtp_t *s, unsigned head, wake_q15_t e)
{
    s->ahead_line[head] = e;
    s->ahead_line[head + (unsigned)WAKE_RTP_AHEAD_TAPS] = e;
    s->ahead_head = (uint16_t)head;
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
static inline int32_t ahead_gate_next(const wake_rtp_t *s, wake_ratio_t goal_field)
{
    const int32_t gate = (int32_t)((uint32_t)s->ahead_gate & UINT32_C(0x7FFFFFFF));
    const int32_t goal = (int32_t)((uint32_t)goal_field & UINT32_C(0x7FFFFFFF));
    const int32_t diff = goal - gate;
    return (int32_t)((uint32_t)(gate + shift_right_round(multiply_wide(diff, (int32_t)((uint32_t)s->ahead_ramp
                                                                                       & UINT32_C(0x7FFFFFFF))),
                                                          WAKE_RTP_GATE_FRAC)) & UINT32_C(0x7FFFFFFF));
}

/** P(n) from the dot product c . line, Q42 (|.| < 2^50): rounded to Q23, |.| < 2^31 fits int32. */
static inline wake_q23_t ahead_predicted(int64_t dot)
{
    return (int32_t)shift_right_round(dot, WAKE_RTP_AHEAD_COEF_FRAC + WAKE_RTP_SAMPLE_FRAC - WAKE_RTP_STATE_FRAC);
}

/** Store P(n), the gate g(n) (31 bits) and the command g P. */
static inline void ahead_output(wake_rtp_t *s, wake_q23_t predicted, int32_t gate)
{
    s->ahead_gate = gate;
    s->ahead_predicted = predicted;
    /* command = g P: Q53, |.| < 2^62; rounded to Q23 (<= |P| for g <= 1; < 2^31 for the 31-bit g) */
    s->ahead_command = (int32_t)shift_right_round(multiply_wide(gate, predicted), WAKE_RTP_GATE_FRAC);
}

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
static void ahead_step(wake_rtp_t *s, wake_q23_t tremor)
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
#endif

#if WAKE_RTP_VOLUNTARY_AHEAD
/**
 * The voluntary motion ahead after the prediction of a step (ReferenceRTP._predict), from the window and
 * z of that prediction:
 *
 *   v_h(n) = w_h' (a + d) = h_h' window + w_h' d_s + k (z - z_s)      (y(n) while no w_h is installed)
 *
 * h_h' window exact in int64 (< 2^47, as y's), rounded once to Q23; z - z_s clamped to +-2^41, times k (Q24)
 * from two 32 x 32 -> 64-bit products, rounded once to Q23; the sum (< 2^49) narrowed once to int32 with
 * saturation, counted in vol_saturations.  No data-dependent branch: vol_set is configuration.
 */
static void voluntary_ahead_step(wake_rtp_t *s)
{
    uint32_t ev = 0u;
    if (s->vol_set == 0u) {
        s->vol_output = s->last_output;                                   /* the one-step prediction held */
        return;
    }
    {
        const int64_t fir = shift_right_round(fir_window(s->vol_fir, s->ring + s->head, s->n_taps),
                                              FIR_TO_SIGNAL_SHIFT);                       /* Q23, < 2^40 */
        int64_t along = 0;
#if WAKE_RTP_KALMAN
        /* w_h' (d - d_s) = k (z - z_s): Q24 x Q23 -> Q23, |.| < 2^49.  z and z_s are read clamped to +-2^41
         * (what they hold unless the state was corrupted), so that the difference cannot overflow */
        const int64_t moved = clamp_symmetric(s->z, 41u, &ev) - clamp_symmetric(s->vol_z_start, 41u, &ev);
        along = multiply_wide_by32(moved, s->vol_gain, 24u);
        /* w_h' d_s read within +-2^41 as well: the sum below stays < 2^50 */
        along += clamp_symmetric(s->vol_start, 41u, &ev);
#else
        (void)ev;   /* no Kalman: d = d_s = 0 */
#endif
        s->vol_output = narrow_saturate(fir + along, &ev);
    }
    count_events(&s->vol_saturations, ev);
}
#endif

/* Functions inlined even at -Os: the parts of the per-sample control flow below, each of which one caller
 * instantiates for a constant case (a copy per case is what a hand-written copy of the flow would hold). */
#if defined(__GNUC__)
#define WAKE_RTP_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define WAKE_RTP_ALWAYS_INLINE inline
#endif

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

#if WAKE_RTP_SPLIT
/* ---------------------------------------------------------------------- */
/* The split step (WAKE_RTP_SPLIT): the parts of a step that prepare      */
/* computes without the sample, and what finish adds to them              */
/* ---------------------------------------------------------------------- */

/** v clamped to +-2^bits (1 <= bits <= 62), not counted: it only guards a corrupted prepared sum. */
static inline int64_t clamp_quiet(int64_t v, unsigned bits)
{
    const int64_t top = INT64_C(1) << bits;
    return (v > top) ? top : (v < -top) ? -top : v;
}

/** h x exactly, for one FIR tap (either representation, see wake_fir_t) and a Q15 sample: |.| < 2^46. */
static inline int64_t fir_product(wake_fir_t h, int32_t x)
{
#if WAKE_RTP_SPLIT_FIR
    /* h = (biased_hi - 2^15) 2^16 + mid 2^8 + lo: three 32-bit products (|.| < 2^31), no 64-bit multiply */
    return (int64_t)(((int32_t)h.parts.biased_hi - 32768) * x) * 65536 + (int64_t)((int32_t)h.parts.mid * x) * 256
           + (int64_t)((int32_t)h.parts.lo * x);
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

#if WAKE_RTP_AHEAD
/** ahead_step with the older seven products and the gate @p gate prepared. */
static void ahead_finish(wake_rtp_t *s, wake_q23_t tremor, wake_ratio_t gate)
{
    uint32_t ev = 0u;
    const unsigned head = ahead_next_head(s);
    const wake_q15_t e = ahead_estimate(tremor, &ev);
    /* P = prepared + c_0 e(n): Q42, the prepared sum clamped to its range so that a corrupted one cannot
     * overflow; the gate read through the 31-bit mask of ahead_gate_next */
    const int64_t dot = clamp_quiet(s->split_ahead, 49u) + multiply_wide(s->ahead_coef[0], e);
    ahead_line_store(s, head, e);
    ahead_output(s, ahead_predicted(dot), (int32_t)((uint32_t)gate & UINT32_C(0x7FFFFFFF)));
    count_events(&s->ahead_saturations, ev);
}
#endif

/** The sample into a prepared window: h' window from the prepared sum (the first sample fills the window). */
static WAKE_RTP_ALWAYS_INLINE int64_t take_prepared(wake_rtp_t *s, wake_q15_t sample)
{
    int64_t acc;
    if (s->primed != 0u) {
        ring_store(s, sample);
        /* h' window = prepared + h_{N-1} m(n), exact (the prepared sum clamped to its range, |.| < 2^52) */
        acc = clamp_quiet(s->split_fir, 52u) + fir_product(s->fir[s->n_taps - 1u], sample);
    } else {
        /* the first sample fills the window with itself: h' window = (sum of h) m(n), exact (the prepared
         * sum clamped to its range, |.| <= 2^39) */
        prime_window(s, sample);
        ring_store(s, sample);
        acc = times_sample(clamp_quiet(s->split_fir, 39u), sample);
    }
    return acc;
}

#if WAKE_RTP_KALMAN
/** The measurement update with the prepared gain and covariance; returns its saturations. */
static WAKE_RTP_ALWAYS_INLINE uint32_t kalman_finish(wake_rtp_t *s, wake_q23_t e)
{
    uint32_t ev = 0u;
    s->z = kalman_corrected(s, s->split_rho, e, &ev);
    s->s = clamp_cov_wide(s->split_s, &ev);   /* within +-2^50 already, unless corrupted */
    return ev + s->split_events;
}
#endif
#endif

/* The per-sample control flow is written once (sample_flow, sample_checked): @p prepared 0 makes the whole
 * step (wake_rtp_step), 1 finishes what wake_rtp_prepare computed (WAKE_RTP_SPLIT builds).  Every caller
 * passes a constant and the functions below are always inlined (WAKE_RTP_ALWAYS_INLINE), so each caller
 * compiles to its own path only: the helpers that follow pick the one of the two versions of each part. */

/** The sample into the window: a step's push (its FIR is predict's), or a prepared step's FIR sum. */
static WAKE_RTP_ALWAYS_INLINE int64_t take_sample(wake_rtp_t *s, wake_q15_t sample, int prepared)
{
    int64_t acc = 0;
#if WAKE_RTP_SPLIT
    if (prepared != 0) {
        acc = take_prepared(s, sample);
    } else {
        push(s, sample);
    }
#else
    (void)prepared;
    push(s, sample);
#endif
    return acc;
}

#if WAKE_RTP_KALMAN
/** The Kalman measurement update of a live instance for the innovation e; returns its saturations. */
static WAKE_RTP_ALWAYS_INLINE uint32_t kalman_measured(wake_rtp_t *s, wake_q23_t e, int prepared)
{
    uint32_t ev;
#if WAKE_RTP_SPLIT
    if (prepared != 0) {
        ev = kalman_finish(s, e);
    } else {
        ev = kalman_update(s, e);
    }
#else
    (void)prepared;
    ev = kalman_update(s, e);
#endif
    return ev;
}
#endif

/** The time update of a sample without a measurement update; a prepared step's inline (s has not changed
 * since the prepare). */
static WAKE_RTP_ALWAYS_INLINE void time_update_of_sample(wake_rtp_t *s, uint32_t *events, int prepared)
{
#if WAKE_RTP_SPLIT && WAKE_RTP_KALMAN
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
#if WAKE_RTP_SPLIT
    if (prepared != 0) {
        ahead_finish(s, tremor, (measured != 0) ? s->split_gate : ahead_gate_next(s, 0));
    } else {
        ahead_step(s, tremor);
    }
#else
    (void)prepared;
    (void)measured;
    ahead_step(s, tremor);
#endif
}
#endif

/**
 * One sample of a checked instance, with @p ev events counted before it.
 * @p measured 0: a missing sample of a primed stream, @p sample the stand-in
 * sample_checked computed.  @p prepared: see above.
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
    voluntary_ahead_step(s);               /* not with WAKE_RTP_SPLIT (wake_rtp.h) */
#endif
#if WAKE_RTP_AHEAD
    ahead_of_sample(s, tremor, measured, prepared);
#endif
    return y;
}

/** sample_flow of a whole step. */
static wake_q15_t step_validated(wake_rtp_t *s, wake_q15_t sample, int measured, uint32_t ev)
{
    return sample_flow(s, sample, measured, ev, 0);
}

#if WAKE_RTP_SPLIT
/** sample_flow of a prepared step. */
static wake_q15_t finish_validated(wake_rtp_t *s, wake_q15_t sample, int measured, uint32_t ev)
{
    return sample_flow(s, sample, measured, ev, 1);
}
#endif

/** The validated step: sample_flow of a whole step or of a prepared one. */
static WAKE_RTP_ALWAYS_INLINE wake_q15_t validated(wake_rtp_t *s, wake_q15_t sample, int measured, uint32_t ev,
                                                   int prepared)
{
    wake_q15_t y;
#if WAKE_RTP_SPLIT
    if (prepared != 0) {
        y = finish_validated(s, sample, measured, ev);
    } else {
        y = step_validated(s, sample, measured, ev);
    }
#else
    (void)prepared;
    y = step_validated(s, sample, measured, ev);
#endif
    return y;
}

/** 1 when a prepared step (@p prepared) finds no prepare since the last step. */
static WAKE_RTP_ALWAYS_INLINE int unprepared(const wake_rtp_t *s, int prepared)
{
#if WAKE_RTP_SPLIT
    return ((prepared != 0) && (s->split_ready != 1u)) ? 1 : 0;
#else
    (void)s;
    (void)prepared;
    return 0;
#endif
}

/**
 * wake_rtp_step (@p measured 1) and wake_rtp_step_missing (0), or with @p prepared wake_rtp_finish and
 * wake_rtp_finish_missing: the checks, then the step.
 */
static WAKE_RTP_ALWAYS_INLINE wake_rtp_status_t sample_checked(wake_rtp_t *s, wake_q15_t sample, int measured,
                                                               wake_q15_t *prediction, int prepared)
{
    uint32_t ev = 0u;
    wake_rtp_status_t st = check_structure(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if ((prediction == NULL) || unprepared(s, prepared)) {
        return (prediction == NULL) ? WAKE_RTP_E_NULL : WAKE_RTP_E_UNPREPARED;   /* nothing changes */
    }
#if WAKE_RTP_SPLIT
    s->split_ready = 0u;                           /* the step changes what a prepare read */
#endif
    if (!measured) {
#if WAKE_RTP_AHEAD
        s->ahead_goal = 0;                         /* the held-out gain needs a window's worth of samples again */
#endif
        if (!s->primed) {
            *prediction = 0;                       /* a missing sample before the first: nothing to predict from */
#if WAKE_RTP_AHEAD
            ahead_of_sample(s, 0, measured, prepared);   /* the tremor ahead still takes its estimate 0 */
#endif
            return WAKE_RTP_OK;
        }
        sample = narrow_saturate16(stand_in(s), &ev);
    }
    *prediction = validated(s, sample, measured, ev, prepared);
    return WAKE_RTP_OK;
}

/** wake_rtp_step (@p measured 1) and wake_rtp_step_missing (0). */
static WAKE_RTP_OUTLINE_AT_OS wake_rtp_status_t step_checked(wake_rtp_t *s, wake_q15_t sample, int measured, wake_q15_t *prediction)
{
    return sample_checked(s, sample, measured, prediction, 0);
}

wake_rtp_status_t wake_rtp_step(wake_rtp_t *s, wake_q15_t sample, wake_q15_t *prediction)
{
    return step_checked(s, sample, 1, prediction);
}

wake_rtp_status_t wake_rtp_step_missing(wake_rtp_t *s, wake_q15_t *prediction)
{
    return step_checked(s, 0, 0, prediction);
}

#if WAKE_RTP_SPLIT
/**
 * wake_rtp_prepare on a checked instance.  Everything below is what sample_flow computes before it
 * needs the sample, stored for its prepared case:
 *
 *   fir    = h' window(n) - h_{N-1} m(n)       the window after the next push, less its newest product
 *            (before the first sample: the sum of h, the first sample fills the window with itself)
 *   rho, s = the Kalman gain and (R/S) s + q|w|^2                           unless inert
 *   ahead  = c . line(n) - c_0 e(n);  gate towards the goal
 */
static void prepare_validated(wake_rtp_t *s)
{
    const unsigned N = s->n_taps;
    /* after the next push the window is ring[head + 1 .. head + N - 1] and the new sample; the ring's
     * ring[head + N] (the copy of the oldest sample, which the push drops) takes the new sample's place
     * in fir_window and its product is taken off again: exact in int64, |.| < 2^52 */
    const wake_q15_t *older = &s->ring[s->head + 1u];
    uint32_t ev = 0u;
    if (s->primed != 0u) {
        s->split_fir = fir_window(s->fir, older, N) - fir_product(s->fir[N - 1u], older[N - 1u]);
    } else {
        s->split_fir = fir_sum(s->fir, N);
    }
    s->split_rho = 0;
    s->split_s = s->s;
#if WAKE_RTP_KALMAN
    if (!s->inert) {
        const kalman_gain_t g = kalman_gain(s, &ev);
        s->split_rho = g.rho;
        s->split_s = kalman_covariance(s, &g, &ev);
    }
#endif
    s->split_events = ev;
#if WAKE_RTP_AHEAD
    {
        /* the slot the next estimate takes holds the oldest one, which it drops: c . line from there,
         * less c_0 times it, is the sum of the seven products that stay (exact, |.| < 2^49) */
        const unsigned head = ahead_next_head(s);
        s->split_ahead = ahead_dot(s->ahead_coef, &s->ahead_line[head])
                         - multiply_wide(s->ahead_coef[0], s->ahead_line[head]);
        s->split_gate = ahead_gate_next(s, s->ahead_goal);   /* a missing sample's finish computes its own */
    }
#endif
    s->split_ready = 1u;
}

/** A setter changed what a prepare read: prepare again if the instance was prepared. */
static void split_refresh(wake_rtp_t *s)
{
    if (s->split_ready != 0u) {
        prepare_validated(s);
    }
}

/** wake_rtp_finish (@p measured 1) and wake_rtp_finish_missing (0). */
static wake_rtp_status_t finish_checked(wake_rtp_t *s, wake_q15_t sample, int measured, wake_q15_t *prediction)
{
    return sample_checked(s, sample, measured, prediction, 1);
}

wake_rtp_status_t wake_rtp_prepare(wake_rtp_t *s)
{
    wake_rtp_status_t st = check_structure(s);
    if (st == WAKE_RTP_OK) {
        prepare_validated(s);
    }
    return st;
}

wake_rtp_status_t wake_rtp_finish(wake_rtp_t *s, wake_q15_t sample, wake_q15_t *prediction)
{
    return finish_checked(s, sample, 1, prediction);
}

wake_rtp_status_t wake_rtp_finish_missing(wake_rtp_t *s, wake_q15_t *prediction)
{
    return finish_checked(s, 0, 0, prediction);
}
#endif

wake_rtp_status_t wake_rtp_run(wake_rtp_t *s, const wake_q15_t *in, wake_q15_t *out, size_t n)
{
    size_t k;
    wake_rtp_status_t st = check_structure(s);
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

#if WAKE_RTP_VOLUNTARY_AHEAD
/* the host build's block entry (wake_rtp.h): firmware builds leave it out */
wake_rtp_status_t wake_rtp_run_outputs(wake_rtp_t *s, const wake_q15_t *in, const uint8_t *missing, size_t n,
                                       wake_q15_t *voluntary, wake_q23_t *tremor_ahead, wake_ratio_t *gate,
                                       wake_q23_t *command, wake_q23_t *voluntary_ahead)
{
    size_t k;
    size_t count = 0u;                                    /* the samples stepped: none unless every check passed */
    wake_rtp_status_t st = check_structure(s);
    if ((st == WAKE_RTP_OK) && (n > 0u)) {
        if (in == NULL) {
            st = WAKE_RTP_E_NULL;
        } else {
            count = n;
        }
    }
    for (k = 0u; k < count; ++k) {
        wake_q15_t y = 0;
        int measured = 1;
        if ((missing != NULL) && (missing[k] != 0u)) {
            measured = 0;
        }
        (void)step_checked(s, in[k], measured, &y);      /* cannot fail: s and &y were checked */
        if (voluntary != NULL) {
            voluntary[k] = y;
        }
#if WAKE_RTP_AHEAD
        if (tremor_ahead != NULL) {
            tremor_ahead[k] = s->ahead_predicted;
        }
        if (gate != NULL) {
            gate[k] = s->ahead_gate;
        }
        if (command != NULL) {
            command[k] = s->ahead_command;
        }
#else
        if (tremor_ahead != NULL) {
            tremor_ahead[k] = 0;
        }
        if (gate != NULL) {
            gate[k] = 0;
        }
        if (command != NULL) {
            command[k] = 0;
        }
#endif
        if (voluntary_ahead != NULL) {
            voluntary_ahead[k] = s->vol_output;
        }
    }
    return st;
}
#endif

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_load_state(wake_rtp_t *s, const wake_q15_t *window,
                                      const wake_q23_t *correction, const wake_cov_t *covariance,
                                      wake_q23_t last_output)
{
    unsigned i, J;
    wake_cov_t lambda = 0, top = 0;
    wake_rtp_status_t st = check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (window == NULL || correction == NULL || covariance == NULL) {
        return WAKE_RTP_E_NULL;
    }
    J = s->level;
    for (i = 0; i < J; ++i) {
        const wake_cov_t p_ii = covariance[i * J + i];
        if (p_ii < 0) {
            return WAKE_RTP_E_STATE;
        }
        top = (p_ii > top) ? p_ii : top;
    }
#if WAKE_RTP_KALMAN
    {
        /* P restarts as (w'Pw / |w|^2) I: the only part of P the recursion uses until the next
         * weight change, where it restarts that way anyway.  w = 0 observes nothing: the largest P_ii. */
        int64_t w_p_w = 0;
        for (i = 0; i < J; ++i) {
            /* w'Pw = sum_i (P w)_i w_i, Q(P): |(P w)_i| < 2^41, each term < 2^50 (J <= 8 terms) */
            w_p_w += multiply_wide_by32(weighted_sum(s->weights, covariance + i * J, J), s->weights[i], 24u);
        }
        lambda = observed_variance(s, w_p_w, top, &s->saturations);
    }
#else
    for (i = 0; i < J * J; ++i) {
        if (covariance[i] != 0 || (i < J && correction[i] != 0)) {
            return WAKE_RTP_E_NO_KALMAN;
        }
    }
#endif
    memcpy(s->ring, window, (size_t)s->n_taps * sizeof(wake_q15_t));
    memcpy(s->ring + s->n_taps, window, (size_t)s->n_taps * sizeof(wake_q15_t));
    s->head = 0u;
    restart(s, correction, lambda);
    s->last_output = last_output;
    s->primed = 1u;
#if WAKE_RTP_SPLIT
    split_refresh(s);                                           /* a prepared step stays prepared */
#endif
    return WAKE_RTP_OK;
}

#if WAKE_RTP_AHEAD
WAKE_RTP_COLD wake_rtp_status_t wake_rtp_set_ahead(wake_rtp_t *s, const int32_t *coefficients, wake_ratio_t goal)
{
    wake_rtp_status_t st = check_instance(s);
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
#if WAKE_RTP_SPLIT
    split_refresh(s);                                           /* a prepared step stays prepared */
#endif
    return WAKE_RTP_OK;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_set_ahead_ramp(wake_rtp_t *s, wake_ratio_t ramp)
{
    wake_rtp_status_t st = check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (!gate_in_range(ramp, 1)) {
        return WAKE_RTP_E_AHEAD;
    }
    s->ahead_ramp = ramp;
#if WAKE_RTP_SPLIT
    split_refresh(s);                                           /* a prepared step stays prepared */
#endif
    return WAKE_RTP_OK;
}

wake_rtp_status_t wake_rtp_ahead_output(const wake_rtp_t *s, wake_q23_t *predicted, wake_ratio_t *gate,
                                        wake_q23_t *command)
{
    wake_rtp_status_t st = check_structure(s);
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
    wake_rtp_status_t st = check_instance(s);
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
#if WAKE_RTP_SPLIT
    split_refresh(s);                                           /* a prepared step stays prepared */
#endif
    return WAKE_RTP_OK;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_get_ahead_state(const wake_rtp_t *s, wake_q15_t *line)
{
    unsigned i;
    wake_rtp_status_t st = check_instance(s);
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

#if WAKE_RTP_VOLUNTARY_AHEAD
WAKE_RTP_COLD wake_rtp_status_t wake_rtp_set_voluntary_ahead(wake_rtp_t *s, const wake_q24_t *weights_ahead)
{
    wake_rtp_status_t st = check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (weights_ahead == NULL) {
        return WAKE_RTP_E_NULL;
    }
    if (!weights_in_range(weights_ahead, s->level)) {
        return WAKE_RTP_E_WEIGHTS;
    }
    memcpy(s->vol_weights, weights_ahead, (size_t)s->level * sizeof(wake_q24_t));
    s->vol_set = 1u;
    voluntary_ahead_restart(s);                                 /* d_s and z_s are the last restart's */
    return WAKE_RTP_OK;
}

wake_rtp_status_t wake_rtp_voluntary_ahead_output(const wake_rtp_t *s, wake_q23_t *output)
{
    wake_rtp_status_t st = check_structure(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (output == NULL) {
        return WAKE_RTP_E_NULL;
    }
    *output = s->vol_output;
    return WAKE_RTP_OK;
}
#endif
