/**
 * @file wake_rtp.c
 * @brief Fixed-point WAKE real-time prediction in constant time.
 *
 * The per-sample path (wake_rtp_step) is the 2^J-tap FIR y = h' window plus
 * a scalar Kalman recursion; the J x J covariance P and the correction d of
 * the literal recursion (wake/rtp/reference.py) are rebuilt from a snapshot
 * only in set_weights, reset, load_state and get_state.  docs/fixed_point.md
 * derives the form and bounds its error.
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

#include <string.h>

/* Cores without a 32 x 32 -> 64-bit multiply instruction (ARMv6-M, ARMv8-M
 * baseline): 64-bit products are assembled from 16 x 16-bit ones, so no
 * __aeabi_lmul call is made. */
#ifndef WAKE_RTP_NO_LONG_MULTIPLY /* the host tests also build it with 1, to run the Cortex-M0+ arithmetic */
#if defined(__ARM_ARCH_6M__) || defined(__ARM_ARCH_8M_BASE__)
#define WAKE_RTP_NO_LONG_MULTIPLY 1
#else
#define WAKE_RTP_NO_LONG_MULTIPLY 0
#endif
#endif

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

/* ---------------------------------------------------------------------- */
/* Integer helpers (libfixmath style: static inline, no macros).           */
/* ---------------------------------------------------------------------- */

/** Add n events to a counter that sticks at UINT32_MAX (no branch on the data). */
static inline void count_events(uint32_t *counter, uint32_t n)
{
    uint32_t sum = *counter + n;
    *counter = (sum < n) ? UINT32_MAX : sum;
}

/** floor(v / 2^sh) for 0 <= sh <= 63, without shifting a negative value. */
static inline int64_t shift_right_floor(int64_t v, unsigned sh)
{
    if (v >= 0) {
        return v >> sh;
    }
    /* v < 0: -1 - v is in [0, INT64_MAX]; floor(v/2^k) = -1 - floor((-1-v)/2^k) */
    return -1 - ((-1 - v) >> sh);
}

/** round(v / 2^sh), halves up, for 1 <= sh <= 62 and |v| <= 2^62 (cannot overflow). */
static inline int64_t shift_right_round(int64_t v, unsigned sh)
{
    return shift_right_floor(v + (INT64_C(1) << (sh - 1u)), sh);
}

/** Narrow int64 to int32, saturating; adds 1 to *events when it saturates. */
static inline int32_t narrow_saturate(int64_t v, uint32_t *events)
{
    /* v + 2^31 in [0, 2^32) exactly when v fits: one 64-bit add and a test of the top word */
    const uint32_t over = (uint32_t)(((uint64_t)v + UINT64_C(0x80000000)) >> 32) != 0u;
    *events += over;
    return over ? ((v < 0) ? INT32_MIN : INT32_MAX) : (int32_t)v;
}

/** Narrow int32 to int16, saturating; adds 1 to *events when it saturates. */
static inline int16_t narrow_saturate16(int32_t v, uint32_t *events)
{
    *events += (uint32_t)((v > INT16_MAX) | (v < INT16_MIN));
    return (int16_t)((v > INT16_MAX) ? INT16_MAX : (v < INT16_MIN) ? INT16_MIN : v);
}

/** a * b exactly, for int32 operands (a 32 x 32 -> 64-bit multiply). */
static inline int64_t multiply_wide(int32_t a, int32_t b)
{
#if WAKE_RTP_NO_LONG_MULTIPLY
    /* a = ah 2^16 + al, b = bh 2^16 + bl with al, bl in [0, 2^16): four 16 x 16-bit products */
    int32_t ah = (int32_t)shift_right_floor(a, 16u), bh = (int32_t)shift_right_floor(b, 16u);
    int32_t al = (int32_t)((uint32_t)a & 0xFFFFu), bl = (int32_t)((uint32_t)b & 0xFFFFu);
    int64_t cross = (int64_t)(ah * bl) + (int64_t)(al * bh);       /* each |.| < 2^31 */
    return (int64_t)(ah * bh) * 4294967296 + cross * 65536 + (int64_t)((uint32_t)al * (uint32_t)bl);
#else
    return (int64_t)a * b;
#endif
}

/** a * b exactly, for uint32 operands. */
static inline uint64_t multiply_wide_unsigned(uint32_t a, uint32_t b)
{
#if WAKE_RTP_NO_LONG_MULTIPLY
    uint32_t ah = a >> 16, al = a & 0xFFFFu, bh = b >> 16, bl = b & 0xFFFFu;
    uint64_t cross = (uint64_t)(ah * bl) + (uint64_t)(al * bh);
    return ((uint64_t)(ah * bh) << 32) + (cross << 16) + (uint64_t)(al * bl);
#else
    return (uint64_t)a * b;
#endif
}

/** v clamped to +-2^40 (the range of z = w'd); adds 1 to *events when it clamps. */
static inline int64_t clamp_wide(int64_t v, uint32_t *events)
{
    const int64_t top = INT64_C(1) << 40;
    *events += (uint32_t)((v > top) | (v < -top));
    return (v > top) ? top : (v < -top) ? -top : v;
}

/** v clamped to +-2^50 (the range of s, b, acc_vv); adds 1 to *events when it clamps. */
static inline int64_t clamp_cov_wide(int64_t v, uint32_t *events)
{
    const int64_t top = INT64_C(1) << 50;
    *events += (uint32_t)((v > top) | (v < -top));
    return (v > top) ? top : (v < -top) ? -top : v;
}

/**
 * round (or floor) of a b / 2^sh for |a| <= 2^50, 20 <= sh <= 31: a = hi 2^31 + lo with
 * lo in [0, 2^31), so a b = hi b 2^31 + lo b from two 32 x 32 -> 64-bit products.
 * |result| < 2^62.
 */
static inline int64_t multiply_wide_by32(int64_t a, int32_t b, unsigned sh, int round)
{
    int64_t hi = shift_right_floor(a, 31u);                                /* |hi| <= 2^19 */
    int32_t lo = (int32_t)(a - hi * (INT64_C(1) << 31));                   /* [0, 2^31) */
    int64_t low = multiply_wide(lo, b);
    return multiply_wide((int32_t)hi, b) * (INT64_C(1) << (31u - sh))
           + (round ? shift_right_round(low, sh) : shift_right_floor(low, sh));
}

/** v / 2^k (floor) for k >= 0, v 2^-k for k < 0 (the caller keeps |v 2^-k| < 2^63). */
static inline int64_t shift_by(int64_t v, int k)
{
    return (k >= 0) ? shift_right_floor(v, (unsigned)k) : v * (INT64_C(1) << (unsigned)(-k));
}

/** a + b for int32 operands, saturated (computed in int64). */
static inline int32_t add_saturate(int32_t a, int64_t b, uint32_t *events)
{
    return narrow_saturate((int64_t)a + b, events);
}

/** Number of significant bits of v (0 for v = 0), portable. */
static inline unsigned bit_length64(uint64_t v)
{
#if defined(__GNUC__) && defined(__ARM_FEATURE_CLZ)
    /* CLZ (Cortex-M3/M4/M7): no branch on the data, so the step's worst path is its usual one */
    return (v == 0u) ? 0u : 64u - (unsigned)__builtin_clzll(v);
#else
    unsigned n = 0;
    if (v >> 32) { v >>= 32; n += 32; }
    if (v >> 16) { v >>= 16; n += 16; }
    if (v >> 8) { v >>= 8; n += 8; }
    if (v >> 4) { v >>= 4; n += 4; }
    if (v >> 2) { v >>= 2; n += 2; }
    if (v >> 1) { v >>= 1; n += 1; }
    return n + (unsigned)v;
#endif
}

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
 * A positive divisor as a reciprocal: 1/x = recip 2^-(61 + exponent), with
 * x = mantissa 2^exponent, mantissa in [2^30, 2^31).
 */
typedef struct {
    uint32_t recip;
    int exponent;
} inverse_t;

/** The inverse of x, 1 <= x < 2^63 (normalisation by shifts, then Newton-Raphson). */
static inline inverse_t inverse_of(uint64_t x)
{
    inverse_t inv;
    int k = (int)bit_length64(x) - 31;
    uint32_t mant = (k >= 0) ? (uint32_t)(x >> (unsigned)k) : (uint32_t)(x << (unsigned)(-k));
    inv.recip = wake_rtp_reciprocal(mant);
    inv.exponent = k;
    return inv;
}

/**
 * round(a / x 2^frac) clamped to +-2^50, for |a| < 2^62 and the inverse of x.
 * a is first reduced to 31 significant bits (relative error <= 2^-31); then
 * a * recip < 2^62, and the shift 61 + exponent - frac is applied (left
 * shifts saturate).
 */
static int64_t divide_wide(int64_t a, inverse_t inv, int frac, uint32_t *events)
{
    uint64_t mag_a = (uint64_t)(a < 0 ? -a : a);
    int m = (int)bit_length64(mag_a) - 31;
    int64_t p, mag;
    int sh;
    if (m < 0) {
        m = 0;
    }
    p = (int64_t)multiply_wide_unsigned((uint32_t)(mag_a >> (unsigned)m), inv.recip);
    sh = 61 + inv.exponent - frac - m;
    if (p == 0 || sh > 62) {
        mag = 0;
    } else if (sh >= 1) {
        mag = shift_right_round(p, (unsigned)sh);
    } else {
        mag = (sh < -30 || (p >> (unsigned)(63 + sh)) != 0) ? INT64_MAX : p << (unsigned)(-sh);
    }
    return clamp_cov_wide(a < 0 ? -mag : mag, events);
}

/** divide_wide narrowed to int32 with saturation. */
static int32_t divide_scaled(int64_t a, inverse_t inv, int frac, uint32_t *events)
{
    return narrow_saturate(divide_wide(a, inv, frac, events), events);
}
#endif /* WAKE_RTP_KALMAN */

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
    live = (uint32_t)(s->q != 0) | (uint32_t)(s->s != 0) | (uint32_t)(s->b != 0);
    if (s->level < 1u || s->level > (unsigned)WAKE_RTP_MAX_LEVEL
        || s->n_taps != (uint16_t)(1u << s->level) || s->head >= s->n_taps
        || s->primed > 1u || s->taps == NULL || s->r <= 0 || s->q < 0 || s->p0 < 0
        || s->inert > 1u || (s->inert & live) != 0u
        || (!WAKE_RTP_KALMAN && s->inert != 1u)) {
        return WAKE_RTP_E_CORRUPT;
    }
    return WAKE_RTP_OK;
}

/** check_structure plus the weights' range (every function that multiplies by the weights). */
static wake_rtp_status_t check_instance(const wake_rtp_t *s)
{
    wake_rtp_status_t st = check_structure(s);
    if (st == WAKE_RTP_OK && !weights_in_range(s->weights, s->level)) {
        return WAKE_RTP_E_CORRUPT;
    }
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
/* Rebuild: the affine form <-> P and d                                    */
/* ---------------------------------------------------------------------- */

#if WAKE_RTP_KALMAN /* the covariance code: left out of WAKE_RTP_KALMAN 0 builds */
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

/** floor(sqrt(v)), bit by bit (rebuild only, never in the per-sample path). */
WAKE_RTP_COLD static uint32_t isqrt64(uint64_t v)
{
    uint64_t res = 0;
    uint64_t bit = (uint64_t)1 << 62;
    while (bit > v) {
        bit >>= 2;
    }
    while (bit != 0) {
        if (v >= res + bit) {
            v -= res + bit;
            res = (res >> 1) + bit;
        } else {
            res >>= 1;
        }
        bit >>= 2;
    }
    return (uint32_t)res;
}

/**
 * Keep a rebuilt P a covariance where rounding or saturation broke it:
 * P_ii >= 0 and |P_ij| <= sqrt(P_ii P_jj) (symmetric J x J, stride J).
 * Runs in the rebuild (once per weight update), never per sample.
 */
WAKE_RTP_COLD static void covariance_guard(wake_cov_t *P, unsigned J, uint32_t *events)
{
    unsigned i, j;
    for (i = 0; i < J; ++i) {
        if (P[i * J + i] < 0) {
            P[i * J + i] = 0;
            count_events(events, 1u);
        }
    }
    for (i = 0; i < J; ++i) {
        for (j = i + 1u; j < J; ++j) {
            int64_t pij = P[i * J + j];
            int64_t apij = (pij < 0) ? -pij : pij;
            int64_t bound2 = (int64_t)P[i * J + i] * P[j * J + j];            /* < 2^62 */
            if (apij * apij > bound2) {                                        /* <= 2^62 */
                int32_t b = (int32_t)isqrt64((uint64_t)bound2);               /* < 2^31 */
                P[i * J + j] = (pij < 0) ? -b : b;
                P[j * J + i] = P[i * J + j];
                count_events(events, 1u);
            }
        }
    }
}

/** What the affine form derives from the snapshot (P_s, d_s) and w; recomputed, not stored. */
typedef struct {
    int64_t s;                          /**< w' P_s w (>= 0), Q(P) */
    int64_t b;                          /**< 2^nb > max |g_i - (s/|w|^2) w_i|, or 0 */
    int64_t z;                          /**< w' d_s, Q23 */
    wake_q24_t v[WAKE_RTP_MAX_LEVEL];   /**< (g - (s/|w|^2) w) / b, |v_i| < 2 */
} snapshot_t;

/**
 * g = P_s w,  s = w'g,  v = (g - (s/|w|^2) w) / b,  z = w'd_s.  Deterministic:
 * the rebuild and every later materialisation get the same values.
 */
WAKE_RTP_COLD static void snapshot_terms(const wake_rtp_t *s, snapshot_t *out, uint32_t *ev)
{
    unsigned i, j, J = s->level;
    const wake_q24_t *w = s->weights;
    uint64_t omega = weight_norm2(w, J);
    int64_t g[WAKE_RTP_MAX_LEVEL];
    int64_t perp[WAKE_RTP_MAX_LEVEL];
    int64_t gamma = 0, zacc = 0;
    uint64_t perp_max = 0;
    wake_cov_t ratio = 0;
    unsigned nb;
    /* g = P_s w: J products < 2^61 each, in Q(P + 24) -> Q(P); |g_i| < 2^40 */
    for (i = 0; i < J; ++i) {
        int64_t acc = 0;
        for (j = 0; j < J; ++j) {
            acc += shift_right_floor(multiply_wide(s->covariance[i * J + j], w[j]), 3u);   /* 8 terms < 2^63 */
        }
        g[i] = shift_right_round(acc, 21u);
        zacc += shift_right_floor(multiply_wide(s->correction[i], w[i]), 3u);   /* 8 terms < 2^63 */
    }
    /* s = w' g                                                          Q(P), int64, < 2^50 */
    for (i = 0; i < J; ++i) {
        gamma += multiply_wide_by32(g[i], w[i], 24u, 1);
    }
    /* w'Pw of a covariance is >= 0; rounding of the rebuilt P (a few LSB per entry, times |w|^2)
     * can leave it just below 0 when the new w is nearly unobservable: take 0 there (with s >= 0
     * the recursion keeps 0 <= rho < 1, 0 < tau <= 1 and s >= 0 for ever) */
    out->s = clamp_cov_wide(gamma < 0 ? 0 : gamma, ev);
    /* v: g minus its component along w, scaled by the power of two b just above its largest entry */
    if (omega != 0u) {
        ratio = divide_scaled(out->s, inverse_of(omega), 24, ev);        /* s / |w|^2, Q(P) */
    }
    for (i = 0; i < J; ++i) {
        uint64_t mag;
        perp[i] = g[i] - shift_right_round(multiply_wide(ratio, w[i]), 24u);
        mag = (uint64_t)(perp[i] < 0 ? -perp[i] : perp[i]);
        perp_max = mag > perp_max ? mag : perp_max;
    }
    nb = bit_length64(perp_max);                                        /* b = 2^nb > max |perp_i| */
    out->b = (perp_max == 0u) ? 0 : (INT64_C(1) << nb);                   /* nb <= 42 */
    for (i = 0; i < J; ++i) {
        /* v_i = perp_i / 2^nb in Q24, |v_i| < 2 */
        int64_t vi;
        if (nb > 24u) {
            vi = shift_right_round(perp[i], nb - 24u);
        } else {
            vi = perp[i] * (INT64_C(1) << (24u - nb));
        }
        out->v[i] = (perp_max == 0u) ? 0 : narrow_saturate(vi, ev);
    }
    /* z = w' d_s                                                        Q23 */
    out->z = shift_right_round(zacc, 21u);                              /* < 2^40 */
}

/**
 * P and d of the literal recursion from the affine form (docs/fixed_point.md):
 *
 *   P = P_s + steps q I - acc_vv v v' - ((b_s - b) / |w|^2)(v w' + w v')
 *         + ((s - s_s) / |w|^4 - steps q / |w|^2) w w'
 *   d = d_s + d_dir v + ((z - z_s) / |w|^2) w
 *
 * Only the v v' coefficient needs an accumulator: P w = b v + (s/|w|^2) w
 * fixes the others.  Where rounding or saturation left P indefinite, the
 * guard restores P_ii >= 0 and |P_ij| <= sqrt(P_ii P_jj) (counted).
 */
WAKE_RTP_COLD static void materialise(const wake_rtp_t *s, wake_q23_t *d, wake_cov_t *P, uint32_t *events, uint32_t *guarded)
{
    /* The coefficients carry XF extra fraction bits: they are multiplied by
     * weights up to 64, whose products w_i w_j would otherwise amplify their
     * rounding to many LSB of P. */
    enum { XF = 16 };
    unsigned i, j, J = s->level;
    const wake_q24_t *w = s->weights, *v;
    uint64_t omega = weight_norm2(w, J);
    int64_t nq = (int64_t)s->steps * s->q;                  /* < 2^63 */
    snapshot_t snap;
    uint32_t again = 0u;                                    /* counted at the rebuild already */
    wake_cov_t grow = narrow_saturate(nq, events);
    int64_t c_vw = 0, c_ww = 0, c_z = 0;                    /* Q(P + XF), Q(P + XF), Q(23 + XF) */
    int64_t row_v[WAKE_RTP_MAX_LEVEL], row_w[WAKE_RTP_MAX_LEVEL];
    snapshot_terms(s, &snap, &again);
    v = snap.v;
    if (omega != 0u) {
        inverse_t inv = inverse_of(omega);                  /* 1 / |w|^2, |w|^2 in Q24 */
        /* c_vw = (b_s - b) / |w|^2 ;  c_ww = ((s - s_s) / |w|^2 - steps q) / |w|^2 */
        c_vw = divide_wide(snap.b - s->b, inv, 24 + XF, events);
        c_ww = divide_wide(s->s - snap.s, inv, 24 + XF, events) - (int64_t)grow * (INT64_C(1) << XF);
        c_ww = divide_wide(c_ww, inv, 24, events);
        /* c_z = (z - z_s) / |w|^2 */
        c_z = divide_wide(s->z - snap.z, inv, 24 + XF, events);
    }
    /* row_v_i = acc_vv v_i + c_vw w_i ;  row_w_i = c_vw v_i - c_ww w_i       Q(P + XF) */
    for (i = 0; i < J; ++i) {
        row_v[i] = clamp_cov_wide(multiply_wide_by32(s->acc_vv, v[i], 24u - XF, 1)
                                  + multiply_wide_by32(c_vw, w[i], 24u, 1), events);
        row_w[i] = clamp_cov_wide(multiply_wide_by32(c_vw, v[i], 24u, 1)
                                  - multiply_wide_by32(c_ww, w[i], 24u, 1), events);
    }
    /* P_ij = P_s,ij + grow d_ij - row_v_i v_j - row_w_i w_j   upper triangle, mirrored */
    for (i = 0; i < J; ++i) {
        for (j = i; j < J; ++j) {
            int64_t t = multiply_wide_by32(row_v[i], v[j], 24u, 1) + multiply_wide_by32(row_w[i], w[j], 24u, 1);
            int64_t p = (int64_t)s->covariance[i * J + j] + (i == j ? grow : 0) - shift_right_round(t, XF);
            P[i * J + j] = narrow_saturate(p, events);
            P[j * J + i] = P[i * J + j];
        }
    }
    covariance_guard(P, J, guarded);
    /* d_i = d_s,i + d_dir v_i + c_z w_i                                             Q23 */
    for (i = 0; i < J; ++i) {
        int64_t t = shift_right_round(multiply_wide(s->d_dir, v[i]), 24u)
                    + shift_right_round(multiply_wide_by32(c_z, w[i], 24u, 1), XF);
        d[i] = narrow_saturate((int64_t)s->correction[i] + t, events);
    }
}
#endif /* WAKE_RTP_KALMAN */

/**
 * Make (P, d) the snapshot for the current weights and restart the affine
 * form from it:  g = P_s w,  s = w'g,  v = (g - (s/|w|^2) w) / b,  z = w'd_s.
 * Also rebuilds the FIR taps h = B'w.  P (J x J, stride J) and d are read
 * before anything is written, so they may be the struct's own snapshot.
 */
/** A tap as fir_window reads it (see wake_fir_t). */
static inline wake_fir_t fir_tap(int32_t h)
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

WAKE_RTP_COLD static void rebuild(wake_rtp_t *s, const wake_q23_t *d, const wake_cov_t *P)
{
    unsigned i, j, J = s->level, N = s->n_taps;
    const wake_q24_t *w = s->weights;
    uint32_t *ev = &s->saturations;
#if WAKE_RTP_KALMAN
    uint64_t omega = weight_norm2(w, J);
    snapshot_t snap;
#endif

    if (d != s->correction) {
        memcpy(s->correction, d, (size_t)J * sizeof(wake_q23_t));
    }
    if (P != s->covariance) {
        memcpy(s->covariance, P, (size_t)J * J * sizeof(wake_cov_t));
    }
    s->d_dir = 0;
    s->acc_vv = 0;
    s->steps = 0u;
#if WAKE_RTP_KALMAN
    snapshot_terms(s, &snap, ev);
    s->s = snap.s;
    s->b = snap.b;
    s->z = snap.z;
    /* q |w|^2 = q (hi + lo / 2^24) with |w|^2 = hi 2^24 + lo in Q24: hi < 2^16, lo < 2^24 */
    s->q_omega = (int64_t)s->q * (int64_t)(omega >> 24)                   /* < 2^47 */
                 + shift_right_round((int64_t)s->q * (int64_t)(omega & 0xFFFFFFu), 24u);
#else
    /* no Kalman: d = 0 and P = 0 (init and load_state see to it), so s = b = z = 0 */
    s->s = 0;
    s->b = 0;
    s->z = 0;
    s->q_omega = 0;
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
    s->inert = (s->q == 0 && s->s == 0 && s->b == 0) ? 1u : 0u;
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
    s->inert = (q == 0) ? 1u : 0u;   /* consistent before reset's check (s = b = 0); rebuild sets it */
    s->magic = WAKE_RTP_MAGIC;
    return wake_rtp_reset(s);
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_set_weights(wake_rtp_t *s, const wake_q24_t *weights, wake_cov_t r, wake_cov_t q)
{
#if WAKE_RTP_KALMAN
    wake_q23_t d[WAKE_RTP_MAX_LEVEL];
    wake_cov_t P[WAKE_RTP_MAX_LEVEL * WAKE_RTP_MAX_LEVEL];
#endif
    wake_rtp_status_t st = check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    st = check_weights(weights, s->level, r, q);
    if (st != WAKE_RTP_OK) {
        return st;
    }
#if WAKE_RTP_KALMAN
    materialise(s, d, P, &s->saturations, &s->guard_events);   /* P, d under the old weights */
#endif
    memcpy(s->weights, weights, (size_t)s->level * sizeof(wake_q24_t));
    s->r = r;
    s->q = q;
#if WAKE_RTP_KALMAN
    rebuild(s, d, P);
#else
    rebuild(s, s->correction, s->covariance);                  /* both stay 0 */
#endif
    return WAKE_RTP_OK;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_reset(wake_rtp_t *s)
{
    unsigned i, J;
    wake_rtp_status_t st = check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    J = s->level;
    memset(s->ring, 0, sizeof(s->ring));
    memset(s->correction, 0, sizeof(s->correction));
    memset(s->covariance, 0, sizeof(s->covariance));
    for (i = 0; i < J; ++i) {
        s->covariance[i * J + i] = s->p0;     /* P(0) = p0 I */
    }
    s->head = 0u;
    s->primed = 0u;
    s->last_output = 0;
    s->saturations = 0u;
    s->guard_events = 0u;
    rebuild(s, s->correction, s->covariance);
    return WAKE_RTP_OK;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_get_state(const wake_rtp_t *s, wake_q23_t *correction, wake_cov_t *covariance)
{
    uint32_t ignored = 0u;
    wake_rtp_status_t st = check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (correction == NULL || covariance == NULL) {
        return WAKE_RTP_E_NULL;
    }
#if WAKE_RTP_KALMAN
    materialise(s, correction, covariance, &ignored, &ignored);
#else
    (void)ignored;
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
#if defined(__GNUC__)
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

/** buffer <- newest sample (the ring holds each sample twice). */
static inline void push(wake_rtp_t *s, wake_q15_t sample)
{
    if (!s->primed) {
        prime_window(s, sample);
    }
    s->ring[s->head] = sample;
    s->ring[s->head + s->n_taps] = sample;
    s->head = (uint16_t)((s->head + 1u) & (s->n_taps - 1u));
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
/**
 * Kalman measurement and time update in the affine form, for the innovation
 * e (Q23).  Constant time: one reciprocal, eight 32 x 32 -> 64-bit products.
 */
WAKE_RTP_NOINLINE static uint32_t kalman_update(wake_rtp_t *s, wake_q23_t e)
{
    uint32_t ev = 0u;
    /* S = s + R, clamped to >= 1 LSB (only a non-PSD loaded P makes s + R < 1); < 2^51 */
    int64_t S = s->s + s->r;
    inverse_t inv;
    int32_t s_norm, b_norm, half_recip;
    wake_ratio_t rho, tau;
    wake_q24_t b_over_s;
    ev += (uint32_t)(S < 1);
    S = (S < 1) ? 1 : S;
    /* 1/S = recip 2^-(61 + k), S = mant 2^k, mant in [2^30, 2^31); k in -30..20 */
    inv = inverse_of((uint64_t)S);
    half_recip = (int32_t)(inv.recip >> 1);
    /* rho = s / S = (s / 2^k) recip / 2^31                                Q30 */
    s_norm = narrow_saturate(shift_by(s->s, inv.exponent), &ev);
    rho = narrow_saturate(shift_right_round(multiply_wide(s_norm, half_recip), 30u), &ev);
    /* tau = R / S = 1 - rho                                                Q30 */
    tau = narrow_saturate((int64_t)RATIO_ONE - rho, &ev);
    /* b / S = (b / 2^(k+7)) recip / 2^30                                   Q24 */
    b_norm = narrow_saturate(shift_by(inv.exponent + 7 >= 0 ? s->b : (s->b > INT32_MAX ? INT32_MAX : s->b),
                                      inv.exponent + 7), &ev);
    b_over_s = narrow_saturate(shift_right_round(multiply_wide(b_norm, half_recip), 29u), &ev);
    /* d = d + u e / S:  z = w'd gains rho e; the v-coefficient gains (b/S) e   Q23 */
    s->z = clamp_wide(s->z + shift_right_round(multiply_wide(rho, e), 30u), &ev);
    s->d_dir = add_saturate(s->d_dir, shift_right_round(multiply_wide(b_over_s, e), 24u), &ev);
    /* P = P - u u'/S + q I: the v v' part accumulates (P w fixes the rest)   Q(P) */
    s->acc_vv = clamp_cov_wide(s->acc_vv + multiply_wide_by32(s->b, b_over_s, 24u, 1), &ev);
    /* u' = P' w = (R/S) u + q w:  s = tau s + q|w|^2,  b = tau b            Q(P) */
    s->s = clamp_cov_wide(multiply_wide_by32(s->s, tau, 30u, 1) + s->q_omega, &ev);
    /* b >= 0 and 0 < tau <= 1 (s >= 0 when P is PSD): rounding down lets b reach 0 and stay */
    s->b = clamp_cov_wide(multiply_wide_by32(s->b, tau, 30u, 0), &ev);
    return ev;
}
#endif

/** a = h' window + z = w'(B window + d), rounded to Q23 (stored as y(n)) and to Q15 (returned). */
static inline wake_q15_t predict(wake_rtp_t *s, uint32_t *events)
{
    const wake_q15_t *window = s->ring + s->head;     /* contiguous: each sample is stored twice */
    int64_t acc = fir_window(s->fir, window, s->n_taps);
    /* y(n) = h' window + w'd:  Q(FIR + 15) -> Q23, rounded once; |.| < 2^48 */
    wake_q23_t y = narrow_saturate(shift_right_round(acc, FIR_TO_SIGNAL_SHIFT) + s->z, events);
    s->last_output = y;
    return narrow_saturate16((int32_t)shift_right_round(y, SIGNAL_GUARD_BITS), events);
}

#if WAKE_RTP_KALMAN
/** A sample without a measurement update (the first of a stream, or a missing one): P = P + q I only.
 * Kept out of line, like kalman_update, so that `wake profile` bounds the inert step without it. */
WAKE_RTP_NOINLINE static void time_update(wake_rtp_t *s, uint32_t *events)
{
    /* s gains q|w|^2 (steps counts the q I) */
    s->s = clamp_cov_wide(s->s + s->q_omega, events);
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

static wake_q15_t step_validated(wake_rtp_t *s, wake_q15_t sample)
{
    uint32_t ev = 0u;
    wake_q15_t y;
    if (!s->primed) {
        /* The first sample of a stream had no prediction before it, so it has no
         * innovation (e would be 0 by construction: the window is primed with it):
         * no measurement update, only the time update P = P + q I (as for a missing
         * sample).  It also keeps the priming off the Kalman update's path: the
         * step's static bound is the longer of the two, not their sum. */
        push(s, sample);
        time_update_only(s, &ev);
    } else {
        const wake_q23_t e = innovation(s, sample, &ev); /* its saturation is counted even when inert */
        push(s, sample);
#if WAKE_RTP_KALMAN
        if (!s->inert) {
            ev += kalman_update(s, e);
        }
#else
        (void)e;
#endif
    }
    s->steps += (uint32_t)(s->steps != UINT32_MAX);      /* P gains q I per sample */
    y = predict(s, &ev);
    count_events(&s->saturations, ev);
    return y;
}

wake_rtp_status_t wake_rtp_step(wake_rtp_t *s, wake_q15_t sample, wake_q15_t *prediction)
{
    wake_rtp_status_t st = check_structure(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (prediction == NULL) {
        return WAKE_RTP_E_NULL;
    }
    *prediction = step_validated(s, sample);
    return WAKE_RTP_OK;
}

wake_rtp_status_t wake_rtp_step_missing(wake_rtp_t *s, wake_q15_t *prediction)
{
    uint32_t ev = 0u;
    wake_rtp_status_t st = check_structure(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (prediction == NULL) {
        return WAKE_RTP_E_NULL;
    }
    if (!s->primed) {
        *prediction = 0;
        return WAKE_RTP_OK;
    }
    /* the last prediction stands in for the sample; no measurement update */
    push(s, narrow_saturate16((int32_t)shift_right_round(s->last_output, SIGNAL_GUARD_BITS), &ev));
    time_update_only(s, &ev);
    s->steps += (uint32_t)(s->steps != UINT32_MAX);
    *prediction = predict(s, &ev);
    count_events(&s->saturations, ev);
    return WAKE_RTP_OK;
}

wake_rtp_status_t wake_rtp_run(wake_rtp_t *s, const wake_q15_t *in, wake_q15_t *out, size_t n)
{
    size_t k;
    wake_rtp_status_t st = check_structure(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (n == 0u) {
        return WAKE_RTP_OK;
    }
    if (in == NULL || out == NULL) {
        return WAKE_RTP_E_NULL;
    }
    for (k = 0; k < n; ++k) {
        out[k] = step_validated(s, in[k]);
    }
    return WAKE_RTP_OK;
}

WAKE_RTP_COLD wake_rtp_status_t wake_rtp_load_state(wake_rtp_t *s, const wake_q15_t *window,
                                      const wake_q23_t *correction, const wake_cov_t *covariance,
                                      wake_q23_t last_output)
{
    unsigned i, j, J;
    wake_cov_t P[WAKE_RTP_MAX_LEVEL * WAKE_RTP_MAX_LEVEL];
    wake_rtp_status_t st = check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (window == NULL || correction == NULL || covariance == NULL) {
        return WAKE_RTP_E_NULL;
    }
    J = s->level;
    for (i = 0; i < J; ++i) {
        if (covariance[i * J + i] < 0) {
            return WAKE_RTP_E_STATE;
        }
    }
#if !WAKE_RTP_KALMAN
    for (i = 0; i < J; ++i) {
        if (correction[i] != 0) {
            return WAKE_RTP_E_NO_KALMAN;
        }
        for (j = 0; j < J; ++j) {
            if (covariance[i * J + j] != 0) {
                return WAKE_RTP_E_NO_KALMAN;
            }
        }
    }
#endif
    memcpy(s->ring, window, (size_t)s->n_taps * sizeof(wake_q15_t));
    memcpy(s->ring + s->n_taps, window, (size_t)s->n_taps * sizeof(wake_q15_t));
    s->head = 0u;
    for (i = 0; i < J; ++i) {
        for (j = i; j < J; ++j) {
            P[i * J + j] = covariance[i * J + j];
            P[j * J + i] = covariance[i * J + j];
        }
    }
#if WAKE_RTP_KALMAN
    covariance_guard(P, J, &s->guard_events);
#endif
    rebuild(s, correction, P);
    s->last_output = last_output;
    s->primed = 1u;
    return WAKE_RTP_OK;
}
