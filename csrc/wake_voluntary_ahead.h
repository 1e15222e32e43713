/**
 * @file wake_voluntary_ahead.h
 * @brief The voluntary motion ahead of the RTP (issue 32) as an instance: w_h, its restart scalars, its output,
 * its saturations and its FIR.
 *
 * With the HPA's weights w_h of the voluntary motion h samples ahead the RTP also outputs
 *
 * @code
 *   v_h(n) = w_h' (a + d) = h_h' window + w_h' d_s + k (z - z_s)       h_h = B' w_h,  k = w_h' w / |w|^2
 * @endcode
 *
 * (y(n) while no w_h is installed; docs/studies/design.md, "Voluntary motion at n + h"; the float twin is
 * wake/rtp/reference.py, ReferenceRTP.last_voluntary_ahead).  Its terms read the core's window, weights w,
 * correction d_s and innovation sum z, so the instance is driven by the core it is embedded in: a
 * ::wake_rtp_t built with WAKE_RTP_VOLUNTARY_AHEAD 1 holds one (wake_rtp_t::voluntary_ahead), set by
 * wake_rtp_set_voluntary_ahead and read by wake_rtp_voluntary_ahead_output (wake_rtp.h), or by
 * wake_voluntary_ahead_output below on the instance alone.  The module is wake_rtp_voluntary.c.
 */
#ifndef WAKE_VOLUNTARY_AHEAD_H
#define WAKE_VOLUNTARY_AHEAD_H

#include <stdint.h>

#include "wake_rtp_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * The voluntary motion ahead's state.  Treat the fields as read-only; change them through
 * wake_rtp_set_voluntary_ahead.
 *
 * @par Scaling and overflow
 * See each field.  The step reads z_start and start clamped to +-2^41 and narrows its sum once with
 * saturation, so any value of the fields is safe for it; the RTP's checks (wake_rtp_reset, wake_rtp_step)
 * tell whether weights and set are the ones the setter admits.
 */
typedef struct {
    wake_q24_t weights[WAKE_RTP_MAX_LEVEL];  /**< w_h, Q24, |w_h| <= 64 (0 until set) */
    int64_t z_start;                         /**< z_s = w' d_s, Q23 of FS in int64 (|.| < 2^41) */
    int64_t start;                           /**< w_h' d_s, Q23 of FS in int64 (|.| < 2^41) */
    int32_t gain;                            /**< k = w_h' w / |w|^2, Q24, saturated to [-128, 128) (0 for w = 0) */
    wake_q23_t output;                       /**< v_h(n) = w_h' (a + d) after the last step (y(n) while unset),
                                                  Q23 of FS */
    uint32_t saturations;                    /**< narrowings of v_h that saturated (sticks at UINT32_MAX); apart
                                                  from the core's, which describe the one-step prediction */
    uint16_t set;                            /**< 1 once a w_h is installed, else 0 (v_h = y(n)) */
    uint16_t reserved;                       /**< 0 */
    wake_fir_t fir[WAKE_RTP_MAX_TAPS];       /**< h_h = B' w_h, oldest sample first, as fir */
} wake_voluntary_ahead_t;

/**
 * @brief The voluntary motion h samples ahead made by the instance's last step: v_h(n) = w_h' (a + d).
 *
 * What wake_rtp_voluntary_ahead_output reads from the RTP's embedded instance (wake_rtp_t::voluntary_ahead),
 * for a firmware that holds a pointer to the instance alone.
 * @param[in]  v       instance (not modified)
 * @param[out] output  v_h(n), Q23 of FS
 * @return WAKE_RTP_OK or WAKE_RTP_E_NULL.
 * @par Scaling and overflow
 * Reads only.
 */
wake_rtp_status_t wake_voluntary_ahead_output(const wake_voluntary_ahead_t *v, wake_q23_t *output);

#ifdef __cplusplus
}
#endif

#endif /* WAKE_VOLUNTARY_AHEAD_H */
