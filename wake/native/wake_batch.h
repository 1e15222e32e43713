/*
 * wake_batch.h: the host-only batch driver of WakeFilter(backend="c") (issue 44): wake_batch_run runs the C HPA's
 * points (hpa_backend="c"), wake_batch_install the RTP stretches and installs of the Python HPA's finished windows.
 *
 * Not firmware: it lives beside the Python package, is compiled into the extension wake._rtp by build_ffi.py
 * and reaches the C core through its public headers only (wake_rtp.h, wake_hpa.h).  wake/native/batch.py
 * decides in Python which HPA points it may take (the schedule's points and each window's full-scale decision
 * follow from the input alone) and hands them over; the driver runs, for each point in turn, the RTP stretch
 * before it, the C HPA on its window and the install of the HPA's result into the RTP.
 */
#ifndef WAKE_BATCH_H
#define WAKE_BATCH_H

#include <stddef.h>
#include <stdint.h>

#include "wake_hpa.h"
#include "wake_rtp.h"

/** Why wake_batch_run stopped before its last point (0: it ran them all). */
typedef enum {
    WAKE_BATCH_DONE = 0,
    WAKE_BATCH_RTP_REFUSED = 1,     /**< wake_rtp_run_outputs, wake_rtp_set_weights or wake_rtp_set_ahead
                                         refused */
    WAKE_BATCH_HPA_REFUSED = 2,     /**< wake_hpa_init, wake_hpa_start, wake_hpa_run or wake_hpa_take refused */
    WAKE_BATCH_NOT_INSTALLABLE = 3  /**< the HPA's result is not what the Python install accepts (non-finite,
                                         out of range) */
} wake_batch_status_t;

/** What the Python side holds between two HPAs and the driver carries from point to point. */
typedef struct {
    float weights[WAKE_HPA_MAX_LEVEL];      /**< the weights in use (the next HPA's previous weights), float32 */
    float ahead[WAKE_HPA_AHEAD_TAPS];       /**< the last HPA's tremor-ahead predictor */
    uint32_t ahead_index;                   /**< its index */
    uint16_t has_ahead;                     /**< 0 before the first HPA */
    uint16_t reserved;
} wake_batch_carry_t;

/**
 * Run @p n_points HPA points of one channel's block on the C core.
 *
 * For point k: the RTP steps x[stops[k-1] .. stops[k]) (wake_rtp_run_outputs, the four output rows written at
 * the samples' places), a fresh C HPA (wake_hpa_init with @p carry's weights, its previous predictor from
 * @p carry) runs on windows[offsets[k] .. offsets[k] + lengths[k]) at index counts[k], and its result is
 * installed: the weights, R and q = process_noise_ratio R in physical units clamped into the RTP's formats
 * and rounded half to even as wake.rtp.qformat does (float64), then the tremor-ahead predictor and goal.
 *
 * After the last point the RTP steps on to x[n_samples - 1] (nothing more when stops[n_points - 1] = n_samples).
 *
 * @param x         the block's samples as int16 Q15 of @p full_scale (finite, none clipped: the caller checks)
 * @param results   per point: the HPA's result
 * @param clamped   per point: 1 when R or q was clamped into the RTP's formats (the history's "noise_clamped")
 * @param points_done  points fully run and installed
 * @param samples_done samples the RTP has stepped (stops[points_done] when the point after them was refused)
 * @return a ::wake_batch_status_t: the point points_done was refused after its stretch ran (nothing of its HPA
 *         installed), so the caller can run it its own way
 */
int wake_batch_run(wake_rtp_t *rtp, wake_hpa_t *hpa, const wake_hpa_config_t *cfg, const wake_q15_t *hpa_taps,
                   const wake_q15_t *x, size_t n_samples, size_t n_points, const uint32_t *stops,
                   const uint32_t *counts,
                   const wake_q15_t *windows, const uint32_t *offsets, const uint16_t *lengths,
                   double full_scale, double process_noise_ratio, wake_batch_carry_t *carry,
                   wake_q15_t *voluntary, wake_q23_t *tremor_ahead, wake_ratio_t *gate, wake_q23_t *command,
                   wake_hpa_result_t *results, uint8_t *clamped, size_t *points_done, size_t *samples_done);

/**
 * Run @p n_points HPA points of one channel's block on the C core with their results given: the batch path of the
 * Python HPA (wake.hpa.c_batch.InstallBatch), whose windows Python analyses and finishes.
 *
 * For point k: the RTP steps x[stops[k-1] .. stops[k]) (wake_rtp_run_outputs, the four output rows written at the
 * samples' places), then installs weights[k * level .. (k + 1) * level), r[k] and q[k] (wake_rtp_set_weights) and
 * the tremor-ahead predictor ahead[k * WAKE_HPA_AHEAD_TAPS ..] with goals[k] (wake_rtp_set_ahead): every word
 * quantised by the Python install's own code (wake.rtp.fixed, wake.rtp.qformat).  After the last point the RTP
 * steps on to x[n_samples - 1].
 *
 * @return WAKE_BATCH_DONE, or WAKE_BATCH_RTP_REFUSED when the core refused a stretch or an install: the point
 *         points_done was not installed (its stretch ran when samples_done = stops[points_done]), so the caller
 *         can run it its own way
 */
int wake_batch_install(wake_rtp_t *rtp, const wake_q15_t *x, size_t n_samples, size_t n_points,
                       const uint32_t *stops, size_t level, const wake_q24_t *weights, const wake_cov_t *r,
                       const wake_cov_t *q, const int32_t *ahead, const wake_ratio_t *goals, wake_q15_t *voluntary,
                       wake_q23_t *tremor_ahead, wake_ratio_t *gate, wake_q23_t *command, size_t *points_done,
                       size_t *samples_done);

#endif
