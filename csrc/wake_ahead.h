/**
 * @file wake_ahead.h
 * @brief The tremor ahead of the RTP (issue 32) as an instance: the predictor and the gate, fed by the core's
 * tremor estimate.
 *
 * One ::wake_ahead_t predicts the tremor h samples ahead from the core's tremor estimate
 * e(n) = m(n) - y(n-1) (wake.ahead.AheadStep is its float twin):
 *
 * @code
 *   line  <- e(n), rounded to Q15 of FS (saturated)         newest first
 *   P(n)   = c . line                                       c fitted per horizon by the HPA
 *   g(n)   = g(n-1) + (goal - g(n-1)) alpha                 the gate, towards its goal
 *   cmd(n) = g(n) P(n)                                      the command
 * @endcode
 *
 * A ::wake_rtp_t built with WAKE_RTP_AHEAD 1 (the default) embeds one (wake_rtp_t::ahead) and feeds it at every
 * step; the wake_rtp_*_ahead* functions of wake_rtp.h act on that instance.  A firmware may also own an
 * instance and drive it itself: wake_ahead_init, then per sample wake_ahead_step with the core's tremor
 * estimate (wake_ahead_step_missing for a sample without a measurement), wake_ahead_output for the results.
 * The module (wake_rtp_ahead.c) compiles in every configuration; a firmware that calls none of it drops it at
 * link time (-ffunction-sections, --gc-sections).
 */
#ifndef WAKE_AHEAD_H
#define WAKE_AHEAD_H

#include <stdint.h>

#include "wake_rtp_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * The tremor ahead's state.  Treat the fields as read-only; change them through the functions below.
 *
 * @par Scaling and overflow
 * See each field.  Any value of the fields is safe for wake_ahead_step (the line's index is taken modulo 8 and
 * every operation saturates or is masked); wake_ahead_check tells whether the values are the ones the setters
 * admit.
 */
typedef struct {
    int32_t coef[WAKE_RTP_AHEAD_TAPS];   /**< predictor c, newest estimate first, Q27, |c| <= 8 */
    wake_ratio_t goal;                   /**< the gate's goal, Q30, [0, 1] */
    wake_ratio_t gate;                   /**< the gate g, Q30, [0, 1] */
    wake_ratio_t ramp;                   /**< alpha = 1 / max(1, 0.3 fs), Q30, (0, 1] */
    uint32_t saturations;                /**< narrowings that saturated (sticks at UINT32_MAX); kept apart from
                                              the core's, which describe the voluntary prediction */
    wake_q23_t predicted;                /**< P(n), the tremor predicted for n + h, Q23 of FS (|P| <= 64 FS) */
    wake_q23_t command;                  /**< g(n) P(n), Q23 of FS */
    uint16_t head;                       /**< index of the newest estimate in line, 0..7 */
    uint16_t reserved;                   /**< 0 */
    wake_q15_t line[2 * WAKE_RTP_AHEAD_TAPS];  /**< tremor estimates e, Q15 of FS, each stored twice (k and
                                                    k + 8): newest first they are the contiguous
                                                    line[head .. head + 7] */
} wake_ahead_t;

/**
 * What wake_ahead_prepare computes of the next step before its estimate is known (the RTP's split step,
 * WAKE_RTP_SPLIT, keeps one beside the instance).
 */
typedef struct {
    int64_t dot;          /**< c . line less the newest estimate's product, Q42, exact, |.| < 2^49 */
    wake_ratio_t gate;    /**< g(n) towards the goal, Q30 (a missing sample's finish, whose goal is 0,
                               computes its own) */
} wake_ahead_prepared_t;

/**
 * @brief Initialise an instance: no predictor (c = 0), the gate shut with goal 0, the default ramp
 * (WAKE_RTP_AHEAD_RAMP_DEFAULT, 1/30: 0.3 s at 100 Hz), an empty line.
 * @param[out] a  instance (any content)
 * @return WAKE_RTP_OK or WAKE_RTP_E_NULL.
 * @par Scaling and overflow
 * Writes constants only.
 */
wake_rtp_status_t wake_ahead_init(wake_ahead_t *a);

/**
 * @brief Forget every estimate and shut the gate (goal 0); the coefficients and the ramp stay.
 * @return WAKE_RTP_OK or WAKE_RTP_E_NULL.
 * @par Scaling and overflow
 * Writes zeros only.
 */
wake_rtp_status_t wake_ahead_reset(wake_ahead_t *a);

/**
 * @brief Whether the instance holds values the setters admit.
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL or WAKE_RTP_E_CORRUPT (a coefficient beyond +-8, a goal or gate outside
 *         [0, 1], a ramp outside (0, 1], or the line's index beyond 7).
 * @par Scaling and overflow
 * Compares only.
 */
wake_rtp_status_t wake_ahead_check(const wake_ahead_t *a);

/**
 * @brief Install a predictor and the gate's goal between two samples (wake.ahead.AheadStep.set_model).
 *
 * The line and the gate's value carry over; the gate ramps from its value towards @p goal.
 * @param[in,out] a             instance
 * @param[in]     coefficients  WAKE_RTP_AHEAD_TAPS values c, newest estimate first, Q27, |c| <= 8
 * @param[in]     goal          the gate's goal, Q30, in [0, 2^30]
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL or WAKE_RTP_E_AHEAD (on error nothing changes).
 * @par Scaling and overflow
 * Copies only; the ranges are what wake_ahead_step's bounds assume.
 */
wake_rtp_status_t wake_ahead_set_model(wake_ahead_t *a, const int32_t *coefficients, wake_ratio_t goal);

/**
 * @brief Set the gate's ramp coefficient alpha = 1 / max(1, 0.3 fs).
 * @param[in,out] a     instance
 * @param[in]     ramp  alpha, Q30, in [1, 2^30]
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL or WAKE_RTP_E_AHEAD (nothing changes).
 * @par Scaling and overflow
 * A copy; alpha <= 2^30 keeps every gate step within [0, 1].
 */
wake_rtp_status_t wake_ahead_set_ramp(wake_ahead_t *a, wake_ratio_t ramp);

/**
 * @brief Set the line and the gate (hand-over from a float warm-up or another full scale).
 * @param[in,out] a     instance
 * @param[in]     line  WAKE_RTP_AHEAD_TAPS tremor estimates, newest first, Q15 of FS
 * @param[in]     gate  the gate's value, Q30, in [0, 2^30]
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL or WAKE_RTP_E_AHEAD (nothing changes).
 * @par Scaling and overflow
 * Copies only.
 */
wake_rtp_status_t wake_ahead_load(wake_ahead_t *a, const wake_q15_t *line, wake_ratio_t gate);

/**
 * @brief Read the line, newest first (Q15 of FS).
 * @param[in]  a     instance (not modified)
 * @param[out] line  WAKE_RTP_AHEAD_TAPS tremor estimates, newest first
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL or WAKE_RTP_E_CORRUPT (the line's index beyond 7; nothing written).
 * @par Scaling and overflow
 * Reads only.
 */
wake_rtp_status_t wake_ahead_history(const wake_ahead_t *a, wake_q15_t *line);

/**
 * @brief The outputs of the last step: P(n), g(n) and g(n) P(n); all 0 after init and reset.
 * @param[in]  a          instance (not modified)
 * @param[out] predicted  P(n), the tremor predicted for n + h, Q23 of FS (may be NULL)
 * @param[out] gate       g(n), the confidence, Q30 in [0, 2^30] (may be NULL)
 * @param[out] command    g(n) P(n), Q23 of FS (may be NULL)
 * @return WAKE_RTP_OK or WAKE_RTP_E_NULL (@p a NULL).
 * @par Scaling and overflow
 * Reads only.
 */
wake_rtp_status_t wake_ahead_output(const wake_ahead_t *a, wake_q23_t *predicted, wake_ratio_t *gate,
                                    wake_q23_t *command);

/**
 * @brief One sample with a measurement (wake.ahead.AheadStep.step): @p tremor is the core's tremor estimate
 * e(n) = m(n) - y(n-1) in Q23 of FS (0 for the first sample of a stream).
 * @param[in,out] a       instance (not NULL; any content)
 * @param[in]     tremor  e(n), Q23 of FS
 * @par Scaling and overflow
 * e(n) rounded once to Q15 and saturated; P = c . line, Q27 x Q15 products exact in int64 (|.| < 2^49),
 * rounded once to Q23; g += round((goal - g) alpha / 2^30) on 31-bit masked values (never leaves [0, 1]
 * for admitted values, defined for any); the command g P (Q53, |.| < 2^62) rounded once to Q23.  P and the
 * command keep 8 guard bits (Q23, as y(n)): a tremor far below the full scale would lose a percent to a Q15
 * rounding.  Saturations are counted in wake_ahead_t::saturations.
 */
void wake_ahead_step(wake_ahead_t *a, wake_q23_t tremor);

/**
 * @brief One sample without a measurement: the goal drops to 0 (the held-out gain needs a window's worth of
 * samples again) and the line takes the estimate 0.
 * @param[in,out] a  instance (not NULL; any content)
 * @par Scaling and overflow
 * As wake_ahead_step with e(n) = 0.
 */
void wake_ahead_step_missing(wake_ahead_t *a);

/**
 * @brief What the next wake_ahead_finish needs before its estimate: the seven older products and the gate.
 * @param[in]  a         instance (not NULL; not modified)
 * @param[out] prepared  the prepared values (not NULL)
 * @par Scaling and overflow
 * c . line less c_0 times the estimate the next step drops: Q42, exact in int64 (|.| < 2^49); the gate as
 * wake_ahead_step.
 */
void wake_ahead_prepare(const wake_ahead_t *a, wake_ahead_prepared_t *prepared);

/**
 * @brief wake_ahead_step from prepared values, bit for bit: @p gate is prepared->gate for a measured sample.
 * @param[in,out] a         instance (not NULL)
 * @param[in]     prepared  wake_ahead_prepare's values since the last step (not NULL)
 * @param[in]     tremor    e(n), Q23 of FS
 * @param[in]     gate      g(n) (Q30; read through a 31-bit mask)
 * @par Scaling and overflow
 * P = prepared (clamped to +-2^49, so a corrupted one cannot overflow) + c_0 e(n), Q42, rounded once to Q23;
 * the command as wake_ahead_step.
 */
void wake_ahead_finish(wake_ahead_t *a, const wake_ahead_prepared_t *prepared, wake_q23_t tremor,
                       wake_ratio_t gate);

#ifdef __cplusplus
}
#endif

#endif /* WAKE_AHEAD_H */
