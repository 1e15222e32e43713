/**
 * @file wake_rate.h
 * @brief Decimating front end of WAKE: any input rate onto the filter bank's rate.
 *
 * The filter bank, the HPA and the RTP were designed at 100 Hz (a level-5
 * bank spans 320 ms).  A sensor sampled D times faster feeds one
 * ::wake_rate_t per channel: a causal boxcar that hands the RTP (and the
 * HPA) the mean of each group of D input samples, so the core runs at
 * fs / D.  The prediction the RTP makes after group m is that of group
 * m + 1, whose centre lies within (D - 1) / 2 input samples of each of its
 * samples: the firmware holds it as the prediction of every input sample
 * until the next group ends (docs/studies/design.md, "Sampling rates other than
 * 100 Hz"; the Python twin is wake.rate.FrontEnd):
 *
 * @code
 *   every input sample x(n):
 *     sum += x(n) (if present); present += 1 (if present); phase += 1
 *     at phase == D:  g = round(sum / present)  (or missing when present == 0)
 *                     y = wake_rtp_step(g)  (wake_rtp_step_missing when missing)
 *                     sum = present = phase = 0
 *     output y (held)
 * @endcode
 *
 * Portable C99, integer arithmetic only, no allocation, no global state.  The
 * mean takes one unsigned division: the divide instruction where the core has
 * one (Cortex-M3/M4/M7, hosts), else (Cortex-M0/M0+) a fixed 16-turn
 * restoring division, so no libgcc helper is called (WAKE_RATE_SOFT_DIVIDE in
 * wake_rate.c).
 */
#ifndef WAKE_RATE_H
#define WAKE_RATE_H

#include <stdint.h>

#include "wake_rtp.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Largest decimation factor D (wake.config LIMITS["decimation"]); D 2^15 fits int32. */
#define WAKE_RATE_MAX_FACTOR 1000

/** Value of wake_rate_t::magic once initialised ("RATE"). */
#define WAKE_RATE_MAGIC UINT32_C(0x52415445)

/** Status codes: zero is success, every error is a distinct negative value. */
typedef enum {
    WAKE_RATE_OK = 0,            /**< success */
    WAKE_RATE_E_NULL = -1,       /**< a required pointer is NULL */
    WAKE_RATE_E_FACTOR = -2,     /**< factor outside 1..WAKE_RATE_MAX_FACTOR */
    WAKE_RATE_E_UNINIT = -3,     /**< the struct was never initialised (bad magic) */
    WAKE_RATE_E_CORRUPT = -4,    /**< magic present but fields inconsistent */
    WAKE_RATE_E_RTP = -5         /**< wake_rate_step: the RTP refused its prepare or finish (not initialised,
                                      corrupted, or stepped outside wake_rate_step since its prepare) */
} wake_rate_status_t;

/** What wake_rate_push hands on after one input sample. */
typedef enum {
    WAKE_RATE_OPEN = 0,          /**< the group is still open: nothing for the RTP */
    WAKE_RATE_GROUP = 1,         /**< a group ended: *mean is its mean, step the RTP with it */
    WAKE_RATE_MISSING = 2        /**< a group ended with every sample missing: wake_rtp_step_missing */
} wake_rate_group_t;

/**
 * One channel's front end.  Treat the fields as read-only.
 *
 * @par Scaling and overflow
 * sum holds at most WAKE_RATE_MAX_FACTOR Q15 samples: |sum| <= 1000 2^15 < 2^25.
 */
typedef struct {
    uint32_t magic;     /**< WAKE_RATE_MAGIC when initialised */
    int32_t sum;        /**< sum of the present samples of the open group, Q15 of FS */
    uint16_t factor;    /**< D, 1..WAKE_RATE_MAX_FACTOR */
    uint16_t phase;     /**< samples in the open group, 0..D-1 */
    uint16_t present;   /**< present samples in the open group, 0..phase */
    uint16_t reserved;  /**< 0 */
} wake_rate_t;

/**
 * @brief Initialise one channel's front end (an empty group).
 * @param[out] s       instance (any content)
 * @param[in]  factor  D, input samples per bank sample, 1..WAKE_RATE_MAX_FACTOR
 * @return WAKE_RATE_OK, WAKE_RATE_E_NULL or WAKE_RATE_E_FACTOR (then only
 *         the magic is written, cleared).
 * @par Scaling and overflow
 * No arithmetic.
 */
wake_rate_status_t wake_rate_init(wake_rate_t *s, int factor);

/**
 * @brief One input sample.
 * @param[in,out] s        initialised instance
 * @param[in]     sample   Q15 of FS (ignored when @p present is 0)
 * @param[in]     present  0 for a missing sample (dropped packet), else 1
 * @param[out]    group    WAKE_RATE_OPEN, WAKE_RATE_GROUP or WAKE_RATE_MISSING
 * @param[out]    mean     at WAKE_RATE_GROUP the group's mean, Q15 of FS; else 0
 * @return WAKE_RATE_OK, WAKE_RATE_E_NULL, _UNINIT or _CORRUPT (nothing changes,
 *         *group = WAKE_RATE_OPEN when @p group is not NULL).
 * @par Scaling and overflow
 * The sum is exact in int32 (see ::wake_rate_t).  The mean is
 * round(sum / present), halves away from zero, by a restoring division of
 * 2 |sum| + present by 2 present (both below 2^26; quotient below 2^16): exact,
 * and a mean of Q15 samples lies in [-2^15, 2^15 - 1], so nothing saturates.
 */
wake_rate_status_t wake_rate_push(wake_rate_t *s, wake_q15_t sample, int present, wake_rate_group_t *group,
                                  wake_q15_t *mean);

/**
 * @brief One input sample through the front end and the split RTP step (WAKE_RTP_SPLIT builds).
 *
 * The entry a firmware calls once per input sample at D >= 2 (at D = 1 it
 * calls wake_rtp_step): wake_rate_push, then on the input sample before the
 * one that ends a group wake_rtp_prepare, and on the sample that ends it
 * wake_rtp_finish with the group's mean (wake_rtp_finish_missing when every
 * sample was missing).  The predictions and the RTP's state are those of
 * wake_rate_push with wake_rtp_step / wake_rtp_step_missing, bit for bit
 * (csrc/tests/test_wake_rtp_split.c), and no input sample runs a whole step:
 * the static bound of this function is the worst input sample
 * (docs/studies/design.md, "In firmware").  Between two calls the firmware may
 * install weights, noise or a tremor-ahead model in the RTP (the setters keep a
 * prepared step prepared); it must not step the RTP itself.  Compiled in every
 * build: with an RTP built without WAKE_RTP_SPLIT (no prepared step to hold)
 * the RTP refuses and it returns WAKE_RATE_E_RTP; a firmware that does not
 * call it does not link it.
 * @param[in,out] s           initialised front end, factor D >= 2
 * @param[in,out] rtp         initialised RTP instance (built with the same WAKE_RTP_* options)
 * @param[in]     sample      Q15 of FS (ignored when @p present is 0)
 * @param[in]     present     0 for a missing sample, else 1
 * @param[in,out] prediction  written when a group ends (the RTP's y for the next group), else left
 *                            as it is: pass the same variable every time and output it (held)
 * @return WAKE_RATE_OK; WAKE_RATE_E_NULL, _UNINIT, _CORRUPT, or _FACTOR (D = 1), with nothing
 *         changed; WAKE_RATE_E_RTP when the RTP refused (the front end has taken the sample, the
 *         RTP is unchanged and @p prediction not written).
 * @par Scaling and overflow
 * As wake_rate_push, wake_rtp_prepare and wake_rtp_finish: no arithmetic of its own.
 */
wake_rate_status_t wake_rate_step(wake_rate_t *s, wake_rtp_t *rtp, wake_q15_t sample, int present,
                                  wake_q15_t *prediction);

#ifdef __cplusplus
}
#endif

#endif /* WAKE_RATE_H */
