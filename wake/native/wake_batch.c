/*
 * wake_batch.c: the host-only batch driver of WakeFilter(backend="c", hpa_backend="c") (issue 44); see
 * wake_batch.h.  It reaches the core through wake_rtp.h and wake_hpa.h only, and mirrors, in float64 as the
 * Python side computes them, the steps wake.channel.Channel.apply takes to install an HPA's result: R and q
 * in physical units (wake.hpa.c_port.run_hpa_c), clamped into the RTP's formats
 * (wake.rtp.qformat.representable_noise) and rounded half to even (quantize_weights, quantize_variance,
 * quantize_ahead).  tests/hpa/test_batch_paths.py checks it against that path bit for bit.
 */
#include "wake_batch.h"

#include <math.h>
#include <string.h>

/* 2^15, 2^24, 2^27, 2^30, 2^32: the Q formats' scales (wake.rtp.qformat) */
#define Q15_SCALE 32768.0
#define WEIGHT_SCALE 16777216.0
#define COEF_SCALE 134217728.0
#define GATE_SCALE 1073741824.0
#define P_SCALE 4294967296.0
#define INT32_TOP 2147483647.0
#define WEIGHT_TOP 64.0      /* wake.rtp.qformat.WEIGHT_MAX */
#define COEF_TOP 8.0         /* wake.ahead.COEFFICIENT_LIMIT */

/* Python's max(a, b) and min(a, b) of two floats: the first unless the second is strictly beyond it */
static double py_max(double a, double b) { return b > a ? b : a; }
static double py_min(double a, double b) { return b < a ? b : a; }

/* wake.rtp.qformat.representable_noise then quantize_variance of R and q at full scale fs; 0 when not
 * representable (the Python install raises there) */
static int quantise_noise(double r, double q, double fs, int32_t *r_q, int32_t *q_q, uint8_t *clamped)
{
    double lsb = pow(fs, 2.0) / P_SCALE;
    double top = INT32_TOP * lsb;
    double r2 = py_min(py_max(r, lsb), top);
    double q2 = (q == 0.0) ? 0.0 : py_min(py_max(q, lsb), top);
    double rr, qq;
    if (!isfinite(r2) || !isfinite(q2) || r2 <= 0.0 || q2 < 0.0) {
        return 0;
    }
    *clamped = (uint8_t)(r2 != r || q2 != q);
    rr = rint(r2 / lsb);
    qq = rint(q2 / lsb);
    if (rr > INT32_TOP || qq > INT32_TOP || rr < 1.0 || (q2 > 0.0 && qq < 1.0)) {
        return 0;
    }
    *r_q = (int32_t)rr;
    *q_q = (int32_t)qq;
    return 1;
}

/* What a batch's RTP stretches read and write (sample-indexed, the whole call's length) */
typedef struct {
    const wake_q15_t *x;
    wake_q15_t *voluntary;
    wake_q23_t *tremor_ahead;
    wake_ratio_t *gate;
    wake_q23_t *command;
} stretch_io_t;

/* The RTP over samples [start, stop) with every output a batch collects; a wake_batch_status_t */
static int run_stretch(wake_rtp_t *rtp, const stretch_io_t *io, size_t start, size_t stop)
{
    if (wake_rtp_run_outputs(rtp, io->x + start, NULL, stop - start, io->voluntary + start, io->tremor_ahead + start,
                             io->gate + start, io->command + start, NULL) != WAKE_RTP_OK) {
        return WAKE_BATCH_RTP_REFUSED;
    }
    return WAKE_BATCH_DONE;
}

/* What a batch does at its k-th point, after the stretch before it; a wake_batch_status_t */
typedef int (*point_fn)(wake_rtp_t *rtp, size_t k, void *context);

/* The two drivers' loop: the stretch up to each point, the point, then the stretch after the last point;
 * stops at the first status other than WAKE_BATCH_DONE, with the points and samples done */
static int run_points(wake_rtp_t *rtp, const stretch_io_t *io, size_t n_samples, size_t n_points,
                      const uint32_t *stops, point_fn at_point, void *context, size_t *points_done,
                      size_t *samples_done)
{
    size_t k;
    size_t start = 0;
    int status = WAKE_BATCH_DONE;

    for (k = 0; k < n_points; k++) {
        size_t stop = stops[k];
        if (start < stop) {
            status = run_stretch(rtp, io, start, stop);
            if (status != WAKE_BATCH_DONE) {
                break;
            }
            start = stop;
        }
        status = at_point(rtp, k, context);
        if (status != WAKE_BATCH_DONE) {
            break;
        }
    }
    if (status == WAKE_BATCH_DONE && start < n_samples) {   /* the stretch after the last point */
        if (run_stretch(rtp, io, start, n_samples) == WAKE_BATCH_DONE) {
            start = n_samples;
        }
    }
    *points_done = k;
    *samples_done = start;
    return status;
}

/* Channel.apply's order: the weights, R and q, then the tremor-ahead predictor and goal; a wake_batch_status_t */
static int install(wake_rtp_t *rtp, const int32_t *w_q, int32_t r_q, int32_t q_q, const int32_t *c_q, int32_t goal_q)
{
    if (wake_rtp_set_weights(rtp, w_q, r_q, q_q) != WAKE_RTP_OK || wake_rtp_set_ahead(rtp, c_q, goal_q) != WAKE_RTP_OK) {
        return WAKE_BATCH_RTP_REFUSED;
    }
    return WAKE_BATCH_DONE;
}

/* Run and install one HPA point's window; a wake_batch_status_t */
static int hpa_point(wake_rtp_t *rtp, wake_hpa_t *hpa, const wake_hpa_config_t *cfg, const wake_q15_t *hpa_taps,
                     const wake_q15_t *window, uint16_t length, uint32_t count, double full_scale,
                     double process_noise_ratio, wake_batch_carry_t *carry, wake_hpa_result_t *res, uint8_t *clamped)
{
    int level = (int)cfg->level;
    int j;
    double lsb = full_scale / Q15_SCALE;
    double r, q;
    int32_t w_q[WAKE_HPA_MAX_LEVEL];
    int32_t c_q[WAKE_HPA_AHEAD_TAPS];
    int32_t r_q, q_q, goal_q;

    memset(hpa, 0, sizeof *hpa);            /* as a fresh instance from ffi.new */
    if (wake_hpa_init(hpa, cfg, hpa_taps, carry->weights) != WAKE_HPA_OK) {
        return WAKE_BATCH_HPA_REFUSED;
    }
    if (carry->has_ahead                     /* wake.hpa.c_port._previous_ahead */
        && wake_hpa_set_previous_ahead(hpa, carry->ahead, carry->ahead_index) != WAKE_HPA_OK) {
        return WAKE_BATCH_HPA_REFUSED;
    }
    if (wake_hpa_start(hpa, window, length, count) != WAKE_HPA_OK || wake_hpa_run(hpa) != WAKE_HPA_DONE
        || wake_hpa_take(hpa, res) != WAKE_HPA_OK) {
        return WAKE_BATCH_HPA_REFUSED;
    }
    /* what Channel.apply installs: weights, R = noise lsb^2, q = ratio R (run_hpa_c, Channel.process_noise) */
    for (j = 0; j < level; j++) {
        double w = (double)res->weights[j];
        if (!isfinite(w) || fabs(w) > WEIGHT_TOP) {
            return WAKE_BATCH_NOT_INSTALLABLE;
        }
        w_q[j] = (int32_t)rint(w * WEIGHT_SCALE);
    }
    r = (double)res->measurement_noise * lsb * lsb;
    q = process_noise_ratio * r;
    if (!quantise_noise(r, q, full_scale, &r_q, &q_q, clamped)) {
        return WAKE_BATCH_NOT_INSTALLABLE;
    }
    for (j = 0; j < (int)WAKE_HPA_AHEAD_TAPS; j++) {
        double c = (double)res->ahead[j];
        if (!isfinite(c) || fabs(c) > COEF_TOP) {
            return WAKE_BATCH_NOT_INSTALLABLE;
        }
        c_q[j] = (int32_t)rint(c * COEF_SCALE);
    }
    if (!(res->ahead_goal >= 0.0f && res->ahead_goal <= 1.0f)) {
        return WAKE_BATCH_NOT_INSTALLABLE;
    }
    goal_q = (int32_t)rint((double)res->ahead_goal * GATE_SCALE);
    if (install(rtp, w_q, r_q, q_q, c_q, goal_q) != WAKE_BATCH_DONE) {
        return WAKE_BATCH_RTP_REFUSED;
    }
    /* the next HPA's previous weights (wake.hpa.c_port._instance clips them to the C HPA's limit) */
    for (j = 0; j < level; j++) {
        float w = res->weights[j];
        float top = (float)WAKE_HPA_WEIGHT_LIMIT;
        carry->weights[j] = w > top ? top : (w < -top ? -top : w);
    }
    memcpy(carry->ahead, res->ahead, sizeof carry->ahead);
    carry->ahead_index = res->index;
    carry->has_ahead = 1u;
    return WAKE_BATCH_DONE;
}

/* wake_batch_run's points: each window through the C HPA, its result installed */
typedef struct {
    wake_hpa_t *hpa;
    const wake_hpa_config_t *cfg;
    const wake_q15_t *hpa_taps;
    const uint32_t *counts;
    const wake_q15_t *windows;
    const uint32_t *offsets;
    const uint16_t *lengths;
    double full_scale;
    double process_noise_ratio;
    wake_batch_carry_t *carry;
    wake_hpa_result_t *results;
    uint8_t *clamped;
} hpa_points_t;

static int hpa_at_point(wake_rtp_t *rtp, size_t k, void *context)
{
    const hpa_points_t *p = (const hpa_points_t *)context;
    return hpa_point(rtp, p->hpa, p->cfg, p->hpa_taps, p->windows + p->offsets[k], p->lengths[k], p->counts[k],
                     p->full_scale, p->process_noise_ratio, p->carry, &p->results[k], &p->clamped[k]);
}

int wake_batch_run(wake_rtp_t *rtp, wake_hpa_t *hpa, const wake_hpa_config_t *cfg, const wake_q15_t *hpa_taps,
                   const wake_q15_t *x, size_t n_samples, size_t n_points, const uint32_t *stops,
                   const uint32_t *counts,
                   const wake_q15_t *windows, const uint32_t *offsets, const uint16_t *lengths,
                   double full_scale, double process_noise_ratio, wake_batch_carry_t *carry,
                   wake_q15_t *voluntary, wake_q23_t *tremor_ahead, wake_ratio_t *gate, wake_q23_t *command,
                   wake_hpa_result_t *results, uint8_t *clamped, size_t *points_done, size_t *samples_done)
{
    stretch_io_t io = {x, voluntary, tremor_ahead, gate, command};
    hpa_points_t points = {hpa, cfg, hpa_taps, counts, windows, offsets, lengths, full_scale, process_noise_ratio,
                           carry, results, clamped};
    return run_points(rtp, &io, n_samples, n_points, stops, hpa_at_point, &points, points_done, samples_done);
}

/* wake_batch_install's points: each install's words, already quantised */
typedef struct {
    size_t level;
    const wake_q24_t *weights;
    const wake_cov_t *r;
    const wake_cov_t *q;
    const int32_t *ahead;
    const wake_ratio_t *goals;
} install_points_t;

static int install_at_point(wake_rtp_t *rtp, size_t k, void *context)
{
    const install_points_t *p = (const install_points_t *)context;
    return install(rtp, p->weights + k * p->level, p->r[k], p->q[k], p->ahead + k * WAKE_HPA_AHEAD_TAPS, p->goals[k]);
}

int wake_batch_install(wake_rtp_t *rtp, const wake_q15_t *x, size_t n_samples, size_t n_points,
                       const uint32_t *stops, size_t level, const wake_q24_t *weights, const wake_cov_t *r,
                       const wake_cov_t *q, const int32_t *ahead, const wake_ratio_t *goals, wake_q15_t *voluntary,
                       wake_q23_t *tremor_ahead, wake_ratio_t *gate, wake_q23_t *command, size_t *points_done,
                       size_t *samples_done)
{
    stretch_io_t io = {x, voluntary, tremor_ahead, gate, command};
    install_points_t points = {level, weights, r, q, ahead, goals};
    return run_points(rtp, &io, n_samples, n_points, stops, install_at_point, &points, points_done, samples_done);
}
