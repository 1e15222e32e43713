/* The cffi declarations of the host-only batch driver (wake_batch.h beside this file), read by build_ffi.py
 * after csrc/wake_cffi.h: written for cffi as that file is (no conditionals, no includes). */
typedef enum {
    WAKE_BATCH_DONE = 0,
    WAKE_BATCH_RTP_REFUSED = 1,
    WAKE_BATCH_HPA_REFUSED = 2,
    WAKE_BATCH_NOT_INSTALLABLE = 3
} wake_batch_status_t;
typedef struct {
    float weights[...];
    float ahead[...];
    uint32_t ahead_index;
    uint16_t has_ahead;
    uint16_t reserved;
} wake_batch_carry_t;
int wake_batch_run(wake_rtp_t *rtp, wake_hpa_t *hpa, const wake_hpa_config_t *cfg, const wake_q15_t *hpa_taps,
                   const wake_q15_t *x, size_t n_samples, size_t n_points, const uint32_t *stops,
                   const uint32_t *counts,
                   const wake_q15_t *windows, const uint32_t *offsets, const uint16_t *lengths,
                   double full_scale, double process_noise_ratio, wake_batch_carry_t *carry,
                   wake_q15_t *voluntary, wake_q23_t *tremor_ahead, wake_ratio_t *gate, wake_q23_t *command,
                   wake_hpa_result_t *results, uint8_t *clamped, size_t *points_done, size_t *samples_done);
int wake_batch_install(wake_rtp_t *rtp, const wake_q15_t *x, size_t n_samples, size_t n_points,
                       const uint32_t *stops, size_t level, const wake_q24_t *weights, const wake_cov_t *r,
                       const wake_cov_t *q, const int32_t *ahead, const wake_ratio_t *goals, wake_q15_t *voluntary,
                       wake_q23_t *tremor_ahead, wake_ratio_t *gate, wake_q23_t *command, size_t *points_done,
                       size_t *samples_done);
