/**
 * @file wake_rtp_types.h
 * @brief The RTP's number formats, sizes and status codes, shared by the core (wake_rtp.h) and its feature
 * instances (wake_ahead.h, wake_vahead.h).
 *
 * Included by wake_rtp.h; a firmware includes wake_rtp.h (or a feature's header) rather than this file.
 * wake_rtp.h's "Number formats" table gives each format's range.
 */
#ifndef WAKE_RTP_TYPES_H
#define WAKE_RTP_TYPES_H

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

/** Taps of the tremor-ahead predictor (wake.ahead.TAPS); fixed: the step writes its eight products out and wraps the line index with a mask. */
#define WAKE_RTP_AHEAD_TAPS 8
/**
 * Fraction bits of the predictor's coefficients (Q27, range +-16): the HPA
 * clips each to +-8 (wake.ahead.COEFFICIENT_LIMIT), which Q28 would hold only
 * up to 8 - 2^-28; Q27 holds +-8 itself with a resolution of 7.5e-9.
 */
#define WAKE_RTP_AHEAD_COEF_FRAC 27
/** Largest accepted |coefficient| in Q27 (8.0). */
#define WAKE_RTP_AHEAD_COEF_MAX (INT32_C(8) << WAKE_RTP_AHEAD_COEF_FRAC)
/** Fraction bits of the gate, its goal and its ramp coefficient (Q30, [0, 1]). */
#define WAKE_RTP_GATE_FRAC 30
/** 1.0 in the gate's format. */
#define WAKE_RTP_GATE_ONE (INT32_C(1) << WAKE_RTP_GATE_FRAC)
/** The ramp coefficient init sets: 1 / (0.3 s x 100 Hz) = 1/30 in Q30 (wake.ahead.ramp_step(100)). */
#define WAKE_RTP_AHEAD_RAMP_DEFAULT INT32_C(35791394)

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

/**
 * Fraction bits of the FIR taps h = B'w: |h_i| <= 64 sum_j |B_ji| < 64 J, so
 * Q22 (range +-512) holds every h for J <= 8 and keeps the split M0+ FIR
 * (16 x 16-bit partial products) inside int32 for J <= 6.
 */
#if WAKE_RTP_MAX_LEVEL <= 6
#define WAKE_RTP_FIR_FRAC 22
#else
#define WAKE_RTP_FIR_FRAC 21
#endif
/** Fraction bits of the ratios rho = s/S and tau = R/S (Q30). */
#define WAKE_RTP_RATIO_FRAC 30
/** Fraction bits of the direction v (Q24, |v_i| < 2). */
#define WAKE_RTP_DIR_FRAC 24

/** Value of wake_rtp_t::magic once initialised ("WAKE"). */
#define WAKE_RTP_MAGIC UINT32_C(0x57414B45)

/** A sample, a prediction or a filter-bank tap: Q15 (of FS for signals). */
typedef int16_t wake_q15_t;
/** A signal value with 8 guard bits: Q23 of FS (d, z, e, y(n-1)). */
typedef int32_t wake_q23_t;
/** An HPA weight or the direction v: Q24, |w| <= 64. */
typedef int32_t wake_q24_t;
/**
 * A FIR tap h = B'w, Q(WAKE_RTP_FIR_FRAC): `value`, or on cores without a
 * 32 x 32 -> 64-bit multiply (Cortex-M0+) `parts`, the same 32 bits split so
 * that every product of the FIR is one 32-bit multiply:
 * h = (biased_hi - 2^15) 2^16 + mid 2^8 + lo.  A build uses one of the two.
 */
typedef union {
    int32_t value;
    struct {
        uint16_t biased_hi;   /**< floor(h / 2^16) + 2^15 */
        uint8_t mid;          /**< bits 8..15 of h */
        uint8_t lo;           /**< bits 0..7 of h */
    } parts;
} wake_fir_t;
/** A covariance-like value (P, R, q, p0, s, b): Q(WAKE_RTP_P_FRAC) of FS^2. */
typedef int32_t wake_cov_t;
/** A dimensionless ratio (s/S, R/S): Q30. */
typedef int32_t wake_ratio_t;

/** Status codes: zero is success, every error is a distinct negative value. */
typedef enum {
    WAKE_RTP_OK = 0,              /**< success */
    WAKE_RTP_E_NULL = -1,         /**< a required pointer is NULL */
    WAKE_RTP_E_LEVEL = -2,        /**< level outside 1..WAKE_RTP_MAX_LEVEL */
    WAKE_RTP_E_TAPS = -3,         /**< a tap row's sum of |taps| is 2.0 or more (Q15 65536) */
    WAKE_RTP_E_WEIGHTS = -4,      /**< a weight outside [-64, 64] (Q24) */
    WAKE_RTP_E_NOISE = -5,        /**< R <= 0, q < 0 or p0 < 0 */
    WAKE_RTP_E_UNINIT = -6,       /**< the struct was never initialised (bad magic) */
    WAKE_RTP_E_CORRUPT = -7,      /**< magic present but fields inconsistent (weights included) */
    WAKE_RTP_E_STATE = -8,        /**< load_state: covariance diagonal negative */
    WAKE_RTP_E_NO_KALMAN = -9,    /**< a Kalman setting (q, p0, d or P non-zero) in a WAKE_RTP_KALMAN 0 build */
    WAKE_RTP_E_AHEAD = -10,       /**< a tremor-ahead value out of range: |coefficient| > 8 (Q27), goal or
                                       gate outside [0, 1] (Q30), ramp outside (0, 1] (Q30) */
    WAKE_RTP_E_UNPREPARED = -11,  /**< wake_rtp_finish without a wake_rtp_prepare since the last step
                                       (WAKE_RTP_SPLIT builds) */
    WAKE_RTP_E_FEATURE = -12      /**< an entry of a feature this build leaves out (WAKE_RTP_AHEAD,
                                       WAKE_RTP_SPLIT or WAKE_RTP_VOLUNTARY_AHEAD 0): nothing changes */
} wake_rtp_status_t;

#ifdef __cplusplus
}
#endif

#endif /* WAKE_RTP_TYPES_H */
