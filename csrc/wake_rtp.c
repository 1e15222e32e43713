/**
 * @file wake_rtp.c
 * @brief Fixed-point WAKE real-time prediction; mirrors wake/rtp/reference.py.
 *
 * Conventions: no signed overflow, no left shift of a negative value, no
 * float.  Right shifts of negative values go through asr64(), which is
 * written with non-negative operands only, so the code does not rely on the
 * implementation-defined behaviour of `>>` on negative numbers (compilers
 * still emit one arithmetic shift).
 */
#include "wake_rtp.h"

#include <string.h>

#if defined(__ARM_FEATURE_DSP) && __ARM_FEATURE_DSP && defined(__ARM_FEATURE_SIMD32)
#include <arm_acle.h>
/* Filter bank with SMLAD (two 16 x 16 multiplies added to a 32-bit accumulator). */
#define WAKE_RTP_USE_SMLAD 1
#else
#define WAKE_RTP_USE_SMLAD 0
#endif

/* The ring is 4-byte aligned inside the struct (it follows int32 fields). */
typedef char wake_rtp_ring_is_aligned[(offsetof(wake_rtp_t, ring) % 4u == 0u) ? 1 : -1];

#define P_FRAC WAKE_RTP_P_FRAC

/* ---------------------------------------------------------------------- */
/* Saturating helpers (libfixmath style: static inline, no macros).        */
/* ---------------------------------------------------------------------- */

/** Count one saturation event (the counter itself saturates). */
static inline void count_event(uint32_t *counter)
{
    if (*counter != UINT32_MAX) {
        (*counter)++;
    }
}

/** floor(v / 2^sh) for 0 <= sh <= 63, without shifting a negative value. */
static inline int64_t asr64(int64_t v, unsigned sh)
{
    if (v >= 0) {
        return v >> sh;
    }
    /* v < 0: -1 - v is in [0, INT64_MAX]; floor(v/2^k) = -1 - floor((-1-v)/2^k) */
    return -1 - ((-1 - v) >> sh);
}

/** floor(v / 2^sh) for int32, 0 <= sh <= 31 (as asr64). */
static inline int32_t asr32(int32_t v, unsigned sh)
{
    if (v >= 0) {
        return v >> sh;
    }
    return -1 - ((-1 - v) >> sh);
}

/** round(v / 2^sh), halves rounded up, for 0 <= sh <= 62; cannot overflow. */
static inline int64_t rshift_round64(int64_t v, unsigned sh)
{
    int64_t t;
    if (sh == 0) {
        return v;
    }
    t = asr64(v, sh - 1u);
    /* ceil(t / 2) = floor((v + 2^(sh-1)) / 2^sh); (uint64) cast gives t mod 2 */
    return asr64(t, 1u) + (int64_t)((uint64_t)t & 1u);
}

/** Narrow int64 to int32, saturating and counting. */
static inline int32_t sat32(int64_t v, uint32_t *sat)
{
    if (v > INT32_MAX) {
        count_event(sat);
        return INT32_MAX;
    }
    if (v < INT32_MIN) {
        count_event(sat);
        return INT32_MIN;
    }
    return (int32_t)v;
}

/** Narrow int64 to [-(2^31 - 1), 2^31 - 1] (symmetric), saturating and counting. */
static inline int32_t sat32s(int64_t v, uint32_t *sat)
{
    if (v > INT32_MAX) {
        count_event(sat);
        return INT32_MAX;
    }
    if (v < -INT32_MAX) {
        count_event(sat);
        return -INT32_MAX;
    }
    return (int32_t)v;
}

/** Narrow int32 to int16, saturating and counting. */
static inline int16_t sat16(int32_t v, uint32_t *sat)
{
    if (v > INT16_MAX) {
        count_event(sat);
        return INT16_MAX;
    }
    if (v < INT16_MIN) {
        count_event(sat);
        return INT16_MIN;
    }
    return (int16_t)v;
}

/** a + b for int32 operands, saturated and counted (computed in int64). */
static inline int32_t add_sat32(int32_t a, int32_t b, uint32_t *sat)
{
    return sat32((int64_t)a + (int64_t)b, sat);
}

/** Number of significant bits of v (0 for v = 0). */
static inline unsigned bit_length64(uint64_t v)
{
#if defined(__GNUC__)
    return v ? 64u - (unsigned)__builtin_clzll(v) : 0u;   /* CLZ on ARMv7-M */
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

/** floor(sqrt(v)), bit by bit (only on the rare PSD-guard path). */
static inline uint32_t isqrt64(uint64_t v)
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

uint32_t wake_rtp_reciprocal(uint32_t x)
{
    /* x in [2^30, 2^31) is X = x / 2^31 in [0.5, 1); r is 1/X in Q30.
     * Start: r0 = 48/17 - 32/17 X (max relative error 1/17), then
     * r <- r (2 - X r): 1/17 -> 3.5e-3 -> 1.2e-5 -> 1.4e-10 -> rounding.
     * The result is within 2^-29 relative of 2^61 / x (csrc/tests). */
    uint32_t r = (uint32_t)(UINT32_C(3031741621)
                            - (uint32_t)(((uint64_t)x * UINT64_C(2021161081)) >> 31));
    int it;
    for (it = 0; it < 4; ++it) {
        uint64_t xr = ((uint64_t)x * r) >> 31;               /* X r, Q30, about 2^30 */
        uint64_t two_minus = (UINT64_C(1) << 31) - xr;      /* 2 - X r, Q30 */
        r = (uint32_t)(((uint64_t)r * two_minus) >> 30);
    }
    return r;
}

/* ---------------------------------------------------------------------- */
/* Validation                                                              */
/* ---------------------------------------------------------------------- */

static wake_rtp_status_t check_instance(const wake_rtp_t *s)
{
    if (s == NULL) {
        return WAKE_RTP_E_NULL;
    }
    if (s->magic != WAKE_RTP_MAGIC) {
        return WAKE_RTP_E_UNINIT;
    }
    if (s->level < 1u || s->level > (unsigned)WAKE_RTP_MAX_LEVEL
        || s->n_taps != (uint16_t)(1u << s->level) || s->head >= s->n_taps
        || s->primed > 1u || s->taps == NULL || s->r <= 0 || s->q < 0 || s->p0 < 0
        || s->inert > 1u || (s->inert != 0u && s->q != 0)) {
        return WAKE_RTP_E_CORRUPT;
    }
    return WAKE_RTP_OK;
}

static wake_rtp_status_t check_weights(const int32_t *weights, unsigned level,
                                       int32_t r, int32_t q)
{
    unsigned j;
    if (weights == NULL) {
        return WAKE_RTP_E_NULL;
    }
    for (j = 0; j < level; ++j) {
        if (weights[j] > WAKE_RTP_WEIGHT_MAX || weights[j] < -WAKE_RTP_WEIGHT_MAX) {
            return WAKE_RTP_E_WEIGHTS;
        }
    }
    if (r <= 0 || q < 0) {
        return WAKE_RTP_E_NOISE;
    }
    return WAKE_RTP_OK;
}

/* ---------------------------------------------------------------------- */
/* Configuration                                                           */
/* ---------------------------------------------------------------------- */

/**
 * inert = 1 iff q == 0 and P == 0.  Then u = P w = 0, K = 0: the measurement
 * update leaves d and P unchanged, P + q I = P and the PSD guard has nothing
 * to clamp, so wake_rtp_step skips both updates (bit-identical output).
 * Called wherever q or P is set from outside the recursion.
 */
static void refresh_inert(wake_rtp_t *s)
{
    unsigned k, JJ = (unsigned)s->level * s->level;
    uint16_t inert = (s->q == 0) ? 1u : 0u;
    for (k = 0; k < JJ; ++k) {
        if (s->covariance[k] != 0) {
            inert = 0u;
        }
    }
    s->inert = inert;
}

wake_rtp_status_t wake_rtp_init(wake_rtp_t *s, int level, const int16_t *taps,
                                const int32_t *weights, int32_t r, int32_t q, int32_t p0)
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
        /* sum of |taps| <= 65535 (Q15) keeps the filter-bank sum below 2^31 */
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
    memset(s, 0, sizeof(*s));
    s->level = (uint16_t)level;
    s->n_taps = (uint16_t)n;
    s->taps = taps;
    memcpy(s->weights, weights, (size_t)level * sizeof(int32_t));
    s->r = r;
    s->q = q;
    s->p0 = p0;
    s->magic = WAKE_RTP_MAGIC;
    return wake_rtp_reset(s);
}

wake_rtp_status_t wake_rtp_set_weights(wake_rtp_t *s, const int32_t *weights, int32_t r, int32_t q)
{
    wake_rtp_status_t st = check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    st = check_weights(weights, s->level, r, q);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    memcpy(s->weights, weights, (size_t)s->level * sizeof(int32_t));
    s->r = r;
    s->q = q;
    refresh_inert(s);
    return WAKE_RTP_OK;
}

wake_rtp_status_t wake_rtp_reset(wake_rtp_t *s)
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
    refresh_inert(s);
    return WAKE_RTP_OK;
}

/* ---------------------------------------------------------------------- */
/* Per-sample recursion                                                    */
/* ---------------------------------------------------------------------- */

/** buffer <- newest sample (on the very first one the whole window is filled). */
static void push(wake_rtp_t *s, int16_t sample)
{
    if (!s->primed) {
        unsigned i;
        for (i = 0; i < 2u * s->n_taps; ++i) {
            s->ring[i] = sample;
        }
        s->last_output = (int32_t)sample * (INT32_C(1) << (WAKE_RTP_STATE_FRAC - WAKE_RTP_SAMPLE_FRAC));
        s->primed = 1u;
    }
    s->ring[s->head] = sample;                   /* both copies */
    s->ring[s->head + s->n_taps] = sample;
    s->head = (uint16_t)((s->head + 1u) & (s->n_taps - 1u));
}

/** PSD guard on P (upper triangle, mirrored): P_ii >= 0, |P_ij| <= sqrt(P_ii P_jj). */
static void psd_guard(wake_rtp_t *s)
{
    unsigned i, j, J = s->level;
    int32_t *P = s->covariance;
    for (i = 0; i < J; ++i) {
        if (P[i * J + i] < 0) {
            P[i * J + i] = 0;
            count_event(&s->guard_events);
        }
    }
    for (i = 0; i < J; ++i) {
        for (j = i + 1u; j < J; ++j) {
            int64_t pij = P[i * J + j];
            int32_t pii = P[i * J + i], pjj = P[j * J + j];
            int64_t apij = (pij < 0) ? -pij : pij;
            int64_t bound2;
            if (apij <= ((pii < pjj) ? pii : pjj)) {
                /* |P_ij| <= min(P_ii, P_jj) implies P_ij^2 <= P_ii P_jj: nothing to clamp */
                P[j * J + i] = (int32_t)pij;
                continue;
            }
            bound2 = (int64_t)pii * pjj;                               /* < 2^62 */
            if (pij * pij > bound2) {                                  /* <= 2^62 */
                int32_t b = (int32_t)isqrt64((uint64_t)bound2);       /* < 2^31 */
                P[i * J + j] = (pij < 0) ? -b : b;
                count_event(&s->guard_events);
            }
            P[j * J + i] = P[i * J + j];
        }
    }
}

/** e = m(n) - y(n-1), Q23, saturated and counted. */
static int32_t innovation(wake_rtp_t *s, int16_t sample)
{
    return sat32((int64_t)sample * (INT64_C(1) << (WAKE_RTP_STATE_FRAC - WAKE_RTP_SAMPLE_FRAC))
                 - s->last_output, &s->saturations);
}

/**
 * round(sum_j w_j x_j / 2^24) for n <= 8 terms, |w_j| <= 2^30 (64 in Q24)
 * and |x_j| <= 2^31 - 1.  Each product is below 2^61 in magnitude; the even
 * and the odd j go to two int64 accumulators (plain multiply-accumulate,
 * SMLAL on Cortex-M4) of at most 4 terms each, so each stays below 2^63.
 * Both are halved (floor) before they are added, then the sum is rounded
 * once: exact up to 2^-25 of the result's LSB per accumulator.  |result| < 2^39.
 */
static inline int64_t dot_w(const int32_t *w, const int32_t *x, unsigned n)
{
    int64_t acc0 = 0, acc1 = 0;
    unsigned j = 0;
    for (; j + 2u <= n; j += 2u) {
        acc0 += (int64_t)w[j] * x[j];
        acc1 += (int64_t)w[j + 1u] * x[j + 1u];
    }
    if (j < n) {
        acc0 += (int64_t)w[j] * x[j];
    }
    return rshift_round64(asr64(acc0, 1u) + asr64(acc1, 1u), WAKE_RTP_WEIGHT_FRAC - 1u);
}

/** round(v / 2^sh), halves up, for 0 <= sh <= 62 and |v| <= 2^62 (no overflow check needed). */
static inline int64_t round_shift62(int64_t v, unsigned sh)
{
    int64_t half = (INT64_C(1) << sh) >> 1;          /* 2^(sh-1), 0 for sh = 0 */
    return asr64(v + half, sh);
}

/** Kalman measurement update for the innovation e (Q23). */
static void measurement_update(wake_rtp_t *s, int32_t e)
{
    unsigned i, j, J = s->level;
    const int32_t *w = s->weights;
    int32_t *P = s->covariance;
    int32_t u[WAKE_RTP_MAX_LEVEL];
    int32_t t[WAKE_RTP_MAX_LEVEL];
    int64_t S;
    unsigned nbits, shift;
    int k;
    uint32_t mant, recip;

    /* u = P w                                   Q(P); |P_ij| <= 2^31 - 1 here (PSD guard) */
    for (i = 0; i < J; ++i) {
        u[i] = sat32s(dot_w(w, P + i * J, J), &s->saturations);
    }

    /* S = w' u + R                              Q(P), int64, |w'u| < 2^39 */
    S = dot_w(w, u, J) + s->r;
    if (S < 1) {
        /* only reachable if rounding left P slightly indefinite along w */
        S = 1;
        count_event(&s->saturations);
    }

    /* 1/S: S = mant 2^k with mant in [2^30, 2^31); 1/S = recip 2^-(61+k) */
    nbits = bit_length64((uint64_t)S);           /* 1..40 */
    k = (int)nbits - 31;                         /* -30..9 */
    if (k >= 0) {
        mant = (uint32_t)((uint64_t)S >> (unsigned)k);
    } else {
        mant = (uint32_t)((uint64_t)S << (unsigned)(-k));
    }
    recip = wake_rtp_reciprocal(mant);
    shift = (unsigned)(30 + k);                  /* 0..39 */

    /* K = u / S = t 2^-(30+k), t = u recip / 2^31: |u recip| < 2^62, |t| <= 2^31 - 1 */
    for (i = 0; i < J; ++i) {
        t[i] = (int32_t)round_shift62((int64_t)u[i] * (int64_t)recip, 31u);
    }

    /* d = d + K e                               (reference: d += u (e / S)); Q23 */
    for (i = 0; i < J; ++i) {
        int64_t delta = round_shift62((int64_t)t[i] * e, shift);      /* |t e| < 2^62 */
        s->correction[i] = sat32((int64_t)s->correction[i] + delta, &s->saturations);
    }

    /* P = P - u u' / S = P - K u'               upper triangle, mirrored: symmetric */
    for (i = 0; i < J; ++i) {
        int32_t *Pi = P + i * J;
        for (j = i; j < J; ++j) {
            int64_t delta = round_shift62((int64_t)t[i] * u[j], shift); /* |t u| < 2^62 */
            int32_t p = sat32((int64_t)Pi[j] - delta, &s->saturations);
            Pi[j] = p;
            P[j * J + i] = p;
        }
    }
}

/** P = P + q I (F = I), then the PSD guard. */
static void time_update(wake_rtp_t *s)
{
    unsigned i, J = s->level;
    for (i = 0; i < J; ++i) {
        s->covariance[i * J + i] = add_sat32(s->covariance[i * J + i], s->q, &s->saturations);
    }
    psd_guard(s);
}

#if WAKE_RTP_USE_SMLAD
/**
 * Two adjacent int16 as one 32-bit word, any alignment.  __builtin_memcpy
 * (gcc, clang, armclang: the compilers that provide arm_acle.h) stays a
 * builtin under -ffreestanding and becomes one LDR on ARMv7E-M; with
 * -mno-unaligned-access (a firmware that sets CCR.UNALIGN_TRP) it becomes
 * byte loads: slower, still correct.
 */
static inline int32_t load_pair(const int16_t *p)
{
    int32_t v;
    __builtin_memcpy(&v, p, sizeof(v));
    return v;
}
#endif

/**
 * sum_i b[i] x[i] for n = 2^J >= 2 int16 pairs.  With sum_i |b[i]| <= 65535
 * and |x[i]| <= 2^15 every partial sum is below 2^31 in magnitude, so the
 * int32 accumulation (also SMLAD's) is exact whatever the order.
 */
static inline int32_t fir(const int16_t *b, const int16_t *x, unsigned n)
{
    int32_t acc = 0;
    unsigned i = 0;
#if WAKE_RTP_USE_SMLAD
    for (; i + 16u <= n; i += 16u) {
        acc = __smlad(load_pair(b + i), load_pair(x + i), acc);
        acc = __smlad(load_pair(b + i + 2u), load_pair(x + i + 2u), acc);
        acc = __smlad(load_pair(b + i + 4u), load_pair(x + i + 4u), acc);
        acc = __smlad(load_pair(b + i + 6u), load_pair(x + i + 6u), acc);
        acc = __smlad(load_pair(b + i + 8u), load_pair(x + i + 8u), acc);
        acc = __smlad(load_pair(b + i + 10u), load_pair(x + i + 10u), acc);
        acc = __smlad(load_pair(b + i + 12u), load_pair(x + i + 12u), acc);
        acc = __smlad(load_pair(b + i + 14u), load_pair(x + i + 14u), acc);
    }
    for (; i < n; i += 2u) {
        acc = __smlad(load_pair(b + i), load_pair(x + i), acc);
    }
#else
    for (; i < n; ++i) {
        acc += (int32_t)b[i] * (int32_t)x[i];
    }
#endif
    return acc;
}

/** a_j = sum_i B[j][i] window[i] (oldest first); y = w' (a + d). */
static int16_t predict(wake_rtp_t *s)
{
    unsigned j, J = s->level, N = s->n_taps;
    const int16_t *window = s->ring + s->head;     /* contiguous: each sample is stored twice */
    int32_t x[WAKE_RTP_MAX_LEVEL];
    int32_t y;
    for (j = 0; j < J; ++j) {
        /* |acc| <= (sum_i |B_ji|) 2^15 <= 65535 * 2^15 < 2^31: exact in int32 */
        int32_t acc = fir(s->taps + (size_t)j * N, window, N);
        /* a_j: Q30 -> Q23, rounded; acc + 2^6 < 2^31 */
        int32_t a = asr32(acc + (INT32_C(1) << 6), (WAKE_RTP_TAP_FRAC + WAKE_RTP_SAMPLE_FRAC) - WAKE_RTP_STATE_FRAC);
        /* x_j = a_j + d_j                       Q23, |x_j| <= 2^31 - 1 */
        x[j] = sat32s((int64_t)a + s->correction[j], &s->saturations);
    }
    /* y(n) = w' x: Q47 -> Q23 (stored), -> Q15 (returned) */
    y = sat32(dot_w(s->weights, x, J), &s->saturations);
    s->last_output = y;
    return sat16((int32_t)rshift_round64(y, WAKE_RTP_STATE_FRAC - WAKE_RTP_SAMPLE_FRAC),
                 &s->saturations);
}

static int16_t step_checked(wake_rtp_t *s, int16_t sample)
{
    int32_t e;
    push(s, sample);
    e = innovation(s, sample);        /* always: its saturation is counted even when inert */
    if (!s->inert) {
        measurement_update(s, e);
        time_update(s);
    }
    return predict(s);
}

wake_rtp_status_t wake_rtp_step(wake_rtp_t *s, int16_t sample, int16_t *prediction)
{
    wake_rtp_status_t st = check_instance(s);
    if (st != WAKE_RTP_OK) {
        return st;
    }
    if (prediction == NULL) {
        return WAKE_RTP_E_NULL;
    }
    *prediction = step_checked(s, sample);
    return WAKE_RTP_OK;
}

wake_rtp_status_t wake_rtp_step_missing(wake_rtp_t *s, int16_t *prediction)
{
    wake_rtp_status_t st = check_instance(s);
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
    push(s, sat16((int32_t)rshift_round64(s->last_output,
                                          WAKE_RTP_STATE_FRAC - WAKE_RTP_SAMPLE_FRAC),
                  &s->saturations));
    if (!s->inert) {
        time_update(s);
    }
    *prediction = predict(s);
    return WAKE_RTP_OK;
}

wake_rtp_status_t wake_rtp_run(wake_rtp_t *s, const int16_t *in, int16_t *out, size_t n)
{
    size_t k;
    wake_rtp_status_t st = check_instance(s);
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
        out[k] = step_checked(s, in[k]);
    }
    return WAKE_RTP_OK;
}

wake_rtp_status_t wake_rtp_load_state(wake_rtp_t *s, const int16_t *window,
                                      const int32_t *correction, const int32_t *covariance,
                                      int32_t last_output)
{
    unsigned i, j, J;
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
    memcpy(s->ring, window, (size_t)s->n_taps * sizeof(int16_t));
    memcpy(s->ring + s->n_taps, window, (size_t)s->n_taps * sizeof(int16_t));
    s->head = 0u;
    memcpy(s->correction, correction, (size_t)J * sizeof(int32_t));
    for (i = 0; i < J; ++i) {
        for (j = i; j < J; ++j) {
            s->covariance[i * J + j] = covariance[i * J + j];
            s->covariance[j * J + i] = covariance[i * J + j];
        }
    }
    psd_guard(s);
    refresh_inert(s);
    s->last_output = last_output;
    s->primed = 1u;
    return WAKE_RTP_OK;
}
