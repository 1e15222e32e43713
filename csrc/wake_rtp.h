/**
 * @file wake_rtp.h
 * @brief Fixed-point real-time prediction (RTP) core of WAKE.
 *
 * One ::wake_rtp_t is one channel of the WAKE real-time predictor: a ring of
 * the newest 2^J samples, a J-level wavelet filter bank and a J-state Kalman
 * correction observed through the HPA weights.  The recursion mirrors the
 * float64 oracle `wake/rtp/reference.py` line for line:
 *
 * @code
 *   buffer <- newest sample            ring of N = 2^J samples
 *   e      = m(n) - y(n-1)             innovation
 *   u      = P w
 *   S      = w' u + R
 *   d      = d + (u / S) e             correction state (J values)
 *   P      = P - u u' / S              upper triangle, mirrored
 *   P      = P + q I                   time update (F = I)
 *   a_j    = sum_i B[j][i] m_i         window oldest first
 *   y(n)   = sum_j w_j (a_j + d_j)     prediction of the voluntary motion at n+1
 * @endcode
 *
 * Portable C99, integer arithmetic only, no allocation, no global state: any
 * number of instances may live side by side.  Every narrowing saturates (and
 * is counted in wake_rtp_t::saturations); nothing wraps.
 *
 * @par Number formats
 * A value "Qf of X" is the integer round(v / X * 2^f).  FS is the full-scale
 * value chosen by the caller (the Python wrapper's `full_scale`).
 *
 * | quantity                    | C type          | format              | range              |
 * |-----------------------------|-----------------|---------------------|--------------------|
 * | sample m, prediction y (I/O)| int16_t         | Q15 of FS           | [-1, 1) FS         |
 * | taps B                      | int16_t         | Q15                 | [-1, 1), row sum of abs < 2  |
 * | filter-bank accumulator     | int32_t         | Q30 of FS           | provably < 2^31    |
 * | a_j, d_j, a_j + d_j, y(n-1) | int32_t         | Q23 of FS           | [-256, 256) FS     |
 * | weights w                   | int32_t         | Q24                 | [-64, 64]          |
 * | x_j = a_j + d_j, u = P w    | int32_t         | Q23 / Q(P_FRAC)     | saturate to +-(2^31 - 1) |
 * | P, R, q, p0, u = P w, S     | int32_t / int64 | Q(WAKE_RTP_P_FRAC) of FS^2 | default Q32: [-0.5, 0.5) FS^2 |
 * | 1/S mantissa                | uint32_t        | Q30 of 1/[0.5,1)    | (1, 2]             |
 */
#ifndef WAKE_RTP_H
#define WAKE_RTP_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Largest filter-bank level J the struct has room for (1..8). */
#ifndef WAKE_RTP_MAX_LEVEL
#define WAKE_RTP_MAX_LEVEL 6
#endif

#if WAKE_RTP_MAX_LEVEL < 1 || WAKE_RTP_MAX_LEVEL > 8
#error "WAKE_RTP_MAX_LEVEL must lie in 1..8"
#endif

/** Ring length for the largest level: 2^WAKE_RTP_MAX_LEVEL samples. */
#define WAKE_RTP_MAX_TAPS (1 << WAKE_RTP_MAX_LEVEL)

/**
 * Fraction bits of the covariance format: P, R, q, p0 (and u = P w, S) are
 * stored as round(v / FS^2 * 2^WAKE_RTP_P_FRAC) in int32_t.
 *
 * The default 32 gives a range of +-0.5 FS^2 with a resolution of
 * 2^-32 = 2.3e-10 FS^2: R = 1e-6 FS^2 is held to 5e-5 relative; q = 1e-9 FS^2
 * is 4.3 LSB and becomes 4 (-7 %).  Raise it (e.g. -DWAKE_RTP_P_FRAC=34, range
 * +-0.125 FS^2, q = 1e-9 FS^2 -> 17 LSB, -1 %) when the covariance stays
 * small, lower it when p0 or R approach 0.5 FS^2.
 */
#ifndef WAKE_RTP_P_FRAC
#define WAKE_RTP_P_FRAC 32
#endif

#if WAKE_RTP_P_FRAC < 24 || WAKE_RTP_P_FRAC > 40
#error "WAKE_RTP_P_FRAC must lie in 24..40"
#endif

/** Fraction bits of the I/O samples (Q15 of FS). */
#define WAKE_RTP_SAMPLE_FRAC 15
/** Fraction bits of the filter-bank taps (Q15). */
#define WAKE_RTP_TAP_FRAC 15
/** Fraction bits of a_j, d_j and the stored last output (Q23 of FS). */
#define WAKE_RTP_STATE_FRAC 23
/** Fraction bits of the HPA weights (Q24). */
#define WAKE_RTP_WEIGHT_FRAC 24
/** Largest accepted |weight| in Q24 (64.0). */
#define WAKE_RTP_WEIGHT_MAX (INT32_C(64) << WAKE_RTP_WEIGHT_FRAC)
/** Largest accepted sum of |taps| of one row in Q15 (2.0 - 2^-15). */
#define WAKE_RTP_TAP_ROW_ABS_MAX ((INT32_C(2) << WAKE_RTP_TAP_FRAC) - 1)

/** Value of wake_rtp_t::magic once initialised ("WAKE"). */
#define WAKE_RTP_MAGIC UINT32_C(0x57414B45)

/** Status codes: zero is success, every error is a distinct negative value. */
typedef enum {
    WAKE_RTP_OK = 0,              /**< success */
    WAKE_RTP_E_NULL = -1,         /**< a required pointer is NULL */
    WAKE_RTP_E_LEVEL = -2,        /**< level outside 1..WAKE_RTP_MAX_LEVEL */
    WAKE_RTP_E_TAPS = -3,         /**< a tap row's sum of |taps| is 2.0 or more (Q15 65536) */
    WAKE_RTP_E_WEIGHTS = -4,      /**< a weight outside [-64, 64] (Q24) */
    WAKE_RTP_E_NOISE = -5,        /**< R <= 0, q < 0 or p0 < 0 */
    WAKE_RTP_E_UNINIT = -6,       /**< the struct was never initialised (bad magic) */
    WAKE_RTP_E_CORRUPT = -7,      /**< magic present but fields inconsistent */
    WAKE_RTP_E_STATE = -8         /**< load_state: covariance diagonal negative */
} wake_rtp_status_t;

/**
 * One channel's complete state.  Treat the fields as read-only; change them
 * through the functions below.
 *
 * @par Scaling and overflow
 * See each field.  The struct holds no pointer except the taps, which the
 * caller owns (typically a `const` table in flash) and must keep alive.
 */
typedef struct {
    uint32_t magic;            /**< WAKE_RTP_MAGIC when initialised */
    uint32_t saturations;      /**< narrowings that saturated since init/reset (sticks at UINT32_MAX) */
    uint32_t guard_events;     /**< covariance entries clamped by the PSD guard since init/reset */
    uint16_t level;            /**< J, 1..WAKE_RTP_MAX_LEVEL */
    uint16_t n_taps;           /**< N = 2^J */
    uint16_t head;             /**< ring index of the oldest sample, 0..N-1 */
    uint16_t primed;           /**< 0 until the first sample, then 1 */
    uint16_t inert;            /**< 1 only while q == 0 and P == 0 (the Kalman update is then the
                                    identity and is skipped); 0 is always safe.  Kept by init,
                                    reset, set_weights and load_state */
    const int16_t *taps;       /**< J x N taps, row-major, oldest sample first, Q15 (caller-owned) */
    int32_t weights[WAKE_RTP_MAX_LEVEL];     /**< HPA weights w, Q24, |w| <= 64 */
    int32_t r;                 /**< measurement noise R, Q(P_FRAC) of FS^2, > 0 */
    int32_t q;                 /**< process noise q (Q = q I), Q(P_FRAC) of FS^2, >= 0 */
    int32_t p0;                /**< initial covariance P(0) = p0 I, Q(P_FRAC) of FS^2, >= 0 */
    int32_t last_output;       /**< y(n-1), Q23 of FS (saturated to int32) */
    int32_t correction[WAKE_RTP_MAX_LEVEL];  /**< Kalman correction d, Q23 of FS */
    int32_t covariance[WAKE_RTP_MAX_LEVEL * WAKE_RTP_MAX_LEVEL]; /**< P, J x J row-major (stride J), Q(P_FRAC) of FS^2, symmetric */
    int16_t ring[2 * WAKE_RTP_MAX_TAPS];     /**< the newest N samples, Q15 of FS, each stored twice (at k
                                                  and k + N) so that the window, oldest first, is the
                                                  contiguous ring[head .. head + N - 1]; 4-byte aligned */
} wake_rtp_t;

/**
 * @brief Initialise one channel.
 * @param[out] s        instance (any content; fully overwritten)
 * @param[in]  level    J, 1..WAKE_RTP_MAX_LEVEL
 * @param[in]  taps     J x 2^J taps, row-major, oldest sample first, Q15;
 *                      kept by pointer (not copied): must outlive @p s
 * @param[in]  weights  J weights, Q24 (copied)
 * @param[in]  r        R, Q(P_FRAC) of FS^2, > 0
 * @param[in]  q        q, Q(P_FRAC) of FS^2, >= 0
 * @param[in]  p0       P(0) = p0 I, Q(P_FRAC) of FS^2, >= 0
 * @return WAKE_RTP_OK, or WAKE_RTP_E_NULL / _LEVEL / _TAPS / _WEIGHTS / _NOISE
 *         (then @p s is left uninitialised: its magic is cleared).
 *
 * @par Scaling and overflow
 * A tap row whose sum of |taps| exceeds 65535 (2.0 - 2^-15 in Q15) is
 * rejected.  With that bound and |sample| <= 2^15, the filter-bank sum
 * sum_i B[j][i] m_i is at most 65535 * 2^15 = 2^31 - 2^15 in magnitude, so
 * its int32 accumulator provably never overflows, whatever the input.  Wavelet taps
 * have unit DC gain and a sum of |taps| below 1.7 for db/sym/haar wavelets
 * at levels 3..6; the sum is done with SMLAD on DSP targets (every
 * partial sum obeys the same bound, so it is exact there too).  Weights are
 * limited to |w| <= 64 so that every product of a weight with an int32
 * factor of magnitude <= 2^31 - 1 (P, u and a_j + d_j, see wake_rtp_step) is
 * below 2^61; even and odd j go to two int64 accumulators of at most 4 terms
 * (J <= 8), each below 2^63.
 */
wake_rtp_status_t wake_rtp_init(wake_rtp_t *s, int level, const int16_t *taps,
                                const int32_t *weights, int32_t r, int32_t q, int32_t p0);

/**
 * @brief Install new HPA weights, R and q between two samples.
 *
 * Glitch-free: the ring, d, P and the last output are untouched; the next
 * step uses the new values.
 * @param[in,out] s        initialised instance
 * @param[in]     weights  J weights, Q24, |w| <= 64
 * @param[in]     r        R, Q(P_FRAC) of FS^2, > 0
 * @param[in]     q        q, Q(P_FRAC) of FS^2, >= 0
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT, _CORRUPT, _WEIGHTS or _NOISE
 *         (on error nothing changes).
 *
 * @par Scaling and overflow
 * As wake_rtp_init.
 */
wake_rtp_status_t wake_rtp_set_weights(wake_rtp_t *s, const int32_t *weights, int32_t r, int32_t q);

/**
 * @brief Forget every sample; keep taps, weights, R, q and p0.
 *
 * Ring and d are zeroed, P = p0 I, the instance is unprimed and both event
 * counters restart from zero.
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT or _CORRUPT.
 */
wake_rtp_status_t wake_rtp_reset(wake_rtp_t *s);

/**
 * @brief Take sample m(n); return the predicted voluntary motion at n + 1.
 * @param[in,out] s           initialised instance
 * @param[in]     sample      m(n), Q15 of FS
 * @param[out]    prediction  y(n), Q15 of FS (saturated)
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT or _CORRUPT (then
 *         @p prediction is not written and the state is untouched).
 *
 * @par Scaling and overflow
 * Filter bank: int32 accumulator, exact and overflow-free (see
 * wake_rtp_init), rounded once to Q23.  Innovation e in Q23, saturated to
 * int32.  u = P w and w' u: exact int64 multiply-accumulates of Q(P_FRAC+24)
 * products (each < 2^61: |P_ij| <= 2^31 - 1 after the PSD guard, u
 * saturates symmetrically to +-(2^31 - 1)) into two accumulators (even /
 * odd j, <= 4 terms each, < 2^63), each halved, added and rounded once to
 * Q(P_FRAC).  S = w'u + R is kept in int64 and clamped to >= 1 LSB.  1/S: S is normalised to a 31-bit mantissa and its
 * reciprocal is computed by four Newton-Raphson iterations with 32 x 32 ->
 * 64-bit multiplies only (no division; relative error <= 2^-29).  The gain
 * K = u / S is kept as a 32-bit value with the exponent of S; d += K e and
 * P -= K u' are 32 x 32 -> 64-bit products rounded once and saturated to
 * int32.  The upper triangle of P is computed and mirrored, then P += q I and
 * the PSD guard (diagonal clamped to >= 0, |P_ij| <= sqrt(P_ii P_jj)) run.
 * The prediction w'x, x = a + d saturated symmetrically to +-(2^31 - 1), is
 * accumulated the same way, rounded to Q23 (stored as y(n)) and to Q15
 * (returned), both saturated.  While wake_rtp_t::inert is set (q = 0,
 * P = 0) the measurement and time updates are skipped: they would change
 * nothing (bit-identical).
 */
wake_rtp_status_t wake_rtp_step(wake_rtp_t *s, int16_t sample, int16_t *prediction);

/**
 * @brief No measurement at n (dropped packet, NaN).
 *
 * The last prediction (rounded to Q15, saturated) enters the ring as the
 * sample, the measurement update is skipped, P += q I still happens, then the
 * prediction is made.  Before the first sample: *prediction = 0 and nothing
 * changes.
 * @return as wake_rtp_step.
 * @par Scaling and overflow
 * As wake_rtp_step.
 */
wake_rtp_status_t wake_rtp_step_missing(wake_rtp_t *s, int16_t *prediction);

/**
 * @brief Run a block: out[k] = prediction after in[k], k = 0..n-1.
 *
 * Same result as n calls of wake_rtp_step; the instance is validated once.
 * @p in and @p out may be the same array.  n = 0 is allowed (pointers may
 * then be NULL).
 * @return as wake_rtp_step.
 * @par Scaling and overflow
 * As wake_rtp_step.
 */
wake_rtp_status_t wake_rtp_run(wake_rtp_t *s, const int16_t *in, int16_t *out, size_t n);

/**
 * @brief Set the full state (hand-over from a float warm-up).
 * @param[in,out] s           initialised instance
 * @param[in]     window      N = 2^J samples, oldest first, Q15 of FS
 * @param[in]     correction  J values d, Q23 of FS
 * @param[in]     covariance  J x J values P, row-major, Q(P_FRAC) of FS^2;
 *                            the upper triangle is used and mirrored, then
 *                            the PSD guard runs
 * @param[in]     last_output y(n-1), Q23 of FS
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT, _CORRUPT or _STATE (a
 *         negative diagonal entry; nothing changes).
 *
 * The instance is primed afterwards; the event counters are kept.
 */
wake_rtp_status_t wake_rtp_load_state(wake_rtp_t *s, const int16_t *window,
                                      const int32_t *correction, const int32_t *covariance,
                                      int32_t last_output);

/**
 * @brief 2^61 / x for x in [2^30, 2^31), by Newton-Raphson (no division).
 *
 * Exposed for testing.  The result lies in [2^30, 2^31]; its error is at
 * most 2^-29 relative (measured over 2e5 arguments: 1 unit of 2^-30).
 */
uint32_t wake_rtp_reciprocal(uint32_t x);

#ifdef __cplusplus
}
#endif

#endif /* WAKE_RTP_H */
