/**
 * @file wake_rtp.c
 * @brief The core step of the fixed-point WAKE RTP: bank + Kalman + one-step prediction, in constant time.
 *
 * The per-sample path (wake_rtp_step) is the 2^J-tap FIR y = h' window plus
 * a scalar Kalman recursion along w; the J x J covariance P and the
 * correction d of the literal recursion (wake/rtp/reference.py, which
 * restarts P as (w'Pw / |w|^2) I at a weight change) are formed from the
 * restart and a few scalars only in set_weights and get_state
 * (wake_rtp_state.c).  docs/studies/fixed_point.md derives the form and
 * bounds its error.  The per-sample pieces and their control flow are
 * internal/wake_rtp_sample.h's, shared with the split step (wake_rtp_split.c).
 *
 * Conventions: no signed overflow, no left shift of a negative value, no
 * float, no division instruction.  Right shifts of negative values go
 * through shift_right_floor(), written with non-negative operands only, so
 * the code does not rely on the implementation-defined behaviour of `>>` on
 * negative numbers (compilers still emit one arithmetic shift).
 */
#include "internal/wake_rtp_sample.h"

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

/* The structural fields: what wake_rtp_step indexes with or branches on (every entry checks them). */
wake_rtp_status_t wake_rtpi_check_structure(const wake_rtp_t *s)
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
    if (!wake_rtpi_ahead_structure_ok(s)) {
        return WAKE_RTP_E_CORRUPT;
    }
    return WAKE_RTP_OK;
}

/**
 * The first sample fills the whole window (both copies); runs once per stream.
 * Two samples per aligned 32-bit store (the ring is 4-byte aligned and 2N is
 * a multiple of 4 samples for J >= 1), four stores per iteration.
 */
WAKE_RTP_NOINLINE void wake_rtpi_prime_window(wake_rtp_t *s, wake_q15_t sample)
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

#if WAKE_RTP_KALMAN
/**
 * Kalman measurement and time update along w, for the innovation e (Q23).
 * Constant time: one reciprocal, four 32 x 32 -> 64-bit products.
 */
WAKE_RTP_NOINLINE uint32_t wake_rtpi_kalman_update(wake_rtp_t *s, wake_q23_t e)
{
    uint32_t ev = 0u;
    const kalman_gain_t g = gain_of(s, &ev);
    s->z = kalman_corrected(s, g.rho, e, &ev);
    s->s = kalman_covariance(s, &g, &ev);
    return ev;
}

/** A sample without a measurement update (the first of a stream, or a missing one): P = P + q I only.
 * Kept out of line, like wake_rtpi_kalman_update, so that `wake profile` bounds the inert step without it. */
WAKE_RTP_NOINLINE void wake_rtpi_time_update(wake_rtp_t *s, uint32_t *events)
{
    s->s = time_updated(s, events);
}
#endif

/** sample_flow of a whole step. */
static wake_q15_t step_validated(wake_rtp_t *s, wake_q15_t sample, int measured, uint32_t ev)
{
    return sample_flow(s, sample, measured, ev, 0);
}

/** wake_rtp_step (@p measured 1) and wake_rtp_step_missing (0): the checks, then the step. */
static WAKE_RTP_OUTLINE_AT_OS wake_rtp_status_t step_checked(wake_rtp_t *s, wake_q15_t sample, int measured,
                                                             wake_q15_t *prediction)
{
    uint32_t ev = 0u;
    wake_rtp_status_t st = WAKE_RTP_OK;
    if (sample_admitted(s, &sample, measured, prediction, 0, &ev, &st) != 0) {
        *prediction = step_validated(s, sample, measured, ev);
    }
    return st;
}

wake_rtp_status_t wake_rtp_step(wake_rtp_t *s, wake_q15_t sample, wake_q15_t *prediction)
{
    return step_checked(s, sample, 1, prediction);
}

wake_rtp_status_t wake_rtp_step_missing(wake_rtp_t *s, wake_q15_t *prediction)
{
    return step_checked(s, 0, 0, prediction);
}
