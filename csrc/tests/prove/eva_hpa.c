/**
 * @file eva_hpa.c
 * @brief Frama-C Eva analysis entries for the single-precision HPA (csrc/wake_hpa.c): one per
 *        public function (make -C csrc prove; docs/studies/verification.md).
 *
 * Inputs: any int16 sample, any configuration and start weights for init (floats of any bit
 * pattern: init must refuse what is not finite or out of range), and, for the functions that take
 * an initialised instance, an instance init accepted whose counters then have any content (see
 * any_checked_fields). The run's numeric state is the run's own output; slice and run are analysed
 * from a run started on a window of any int16 samples by a valid init (the default configuration),
 * which is how they are reached.
 *
 * Built with WAKE_HPA_AHEAD 1 too (eva_check.py's tremor-ahead unit, hpa_ahead): the same entries, the
 * ahead counters also of any content, the ahead part of apply checked, and
 * eva_wake_hpa_ahead_to_rtp, which exists only there.
 */
#include <float.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include "__fc_builtin.h"
#include "wake_hpa.h"

static wake_q15_t taps[WAKE_HPA_MAX_LEVEL * WAKE_HPA_MAX_TAPS];
static wake_q15_t window[WAKE_HPA_MAX_WINDOW];
static float weights[WAKE_HPA_MAX_LEVEL];
static wake_hpa_config_t cfg;
static wake_hpa_result_t result;
static wake_hpa_t hpa;
static wake_rtp_t rtp;
static wake_q15_t rtp_taps[WAKE_RTP_MAX_LEVEL * WAKE_RTP_MAX_TAPS];

static void unknown(void *p, size_t n)
{
    Frama_C_make_unknown((char *)p, n);
}

/** A valid instance (the default configuration, the mean-of-the-window taps) ... */
static void valid_instance(void)
{
    unsigned j, i;
    (void)wake_hpa_default_config(&cfg);
    for (j = 0; j < cfg.level; ++j) {
        for (i = 0; i < (1u << cfg.level); ++i) {
            taps[j * (1u << cfg.level) + i] = (wake_q15_t)(i >= (1u << cfg.level) - (1u << (cfg.level - j)) ?
                                                          32768 >> (cfg.level - j) : 0);
        }
        weights[j] = 0.25f;
    }
    (void)wake_hpa_init(&hpa, &cfg, taps, weights);
}

/**
 * An instance initialised by init with any configuration, bank and start weights init accepts, whose
 * feeding and run counters (wake_hpa_t::count up to wake_hpa_t::lo) then take any content; the work
 * pointer points to a window buffer. The configuration itself is guarded by a 32-bit seal (a hash,
 * which Eva cannot invert): the analysis takes it as init left it (docs/studies/verification.md).
 * Returns 0 when init refused the configuration (nothing to analyse).
 */
static int any_checked_fields(void)
{
    unsigned j;
    float *const fields[] = {&cfg.fs, &cfg.tremor_low, &cfg.tremor_high, &cfg.cutoff_low, &cfg.cutoff_high,
                             &cfg.shallow_high, &cfg.default_cutoff, &cfg.min_depth_ratio, &cfg.floor_ratio,
                             &cfg.edge_ratio, &cfg.ridge, &cfg.process_noise_ratio, &cfg.gate_cutoff};
    unknown(&cfg, sizeof cfg);
    if (cfg.level >= 1u && cfg.level <= WAKE_HPA_MAX_LEVEL) {
        /* the same values, one Eva state each: loops over the level stay exact (apply's weights) */
        cfg.level = (uint16_t)Frama_C_interval_split(1, WAKE_HPA_MAX_LEVEL);
    }
    /* finite floats: a NaN or infinite field is refused by init, which eva_wake_hpa_init shows */
    for (j = 0; j < sizeof fields / sizeof fields[0]; ++j) {
        *fields[j] = Frama_C_float_interval(-FLT_MAX, FLT_MAX);
    }
    /* a negative ratio is refused by init (config_ok); Eva loses that through config_ok's status, and apply's
       conversion would then keep a refusal path whose outputs are unset: the driver leaves it out */
    cfg.process_noise_ratio = Frama_C_float_interval(0.0f, FLT_MAX);
    unknown(taps, sizeof taps);
    for (j = 0; j < WAKE_HPA_MAX_LEVEL; ++j) {
        weights[j] = Frama_C_float_interval(-FLT_MAX, FLT_MAX);
    }
    if (wake_hpa_init(&hpa, &cfg, taps, weights) != WAKE_HPA_OK) {
        return 0;
    }
    unknown(&hpa.count, offsetof(wake_hpa_t, lo) - offsetof(wake_hpa_t, count));
#if WAKE_HPA_AHEAD
    /* the tremor ahead's counters, which check_instance and the next run read: any content too */
    unknown(&hpa.ahead.prev_index, sizeof hpa.ahead.prev_index);
    unknown(&hpa.ahead.has_prev, sizeof hpa.ahead.has_prev);
    unknown(&hpa.ahead.pos, sizeof hpa.ahead.pos);
    unknown(&hpa.ahead.held, sizeof hpa.ahead.held);
    unknown(&hpa.ahead.rail, sizeof hpa.ahead.rail);
#endif
    hpa.work = Frama_C_nondet(0, 1) ? window : hpa.buf;
    return 1;
}

void eva_wake_hpa_default_config(void)
{
    (void)wake_hpa_default_config(&cfg);
}

void eva_wake_hpa_init(void)
{
    unknown(&cfg, sizeof cfg);
    unknown(taps, sizeof taps);
    unknown(weights, sizeof weights);
    unknown(&hpa, sizeof hpa);
    (void)wake_hpa_init(&hpa, &cfg, taps, weights);
}

void eva_wake_hpa_push(void)
{
    if (any_checked_fields()) {
        (void)wake_hpa_push(&hpa, Frama_C_short_interval(INT16_MIN, INT16_MAX));
    }
}

void eva_wake_hpa_push_missing(void)
{
    if (any_checked_fields()) {
        (void)wake_hpa_push_missing(&hpa);
    }
}

void eva_wake_hpa_start(void)
{
    if (any_checked_fields()) {
        unknown(window, sizeof window);
        (void)wake_hpa_start(&hpa, window, Frama_C_unsigned_short_interval(0u, UINT16_MAX),
                             Frama_C_unsigned_int_interval(0u, UINT32_MAX));
    }
}

/** A run on a full window of any int16 samples, from a valid instance. */
static void started(void)
{
    valid_instance();
    unknown(window, sizeof window);
    (void)wake_hpa_start(&hpa, window, cfg.window, cfg.window);
}

void eva_wake_hpa_slice(void)
{
    started();
    (void)wake_hpa_slice(&hpa);
}

void eva_wake_hpa_run(void)
{
    started();
    (void)wake_hpa_run(&hpa);
}

void eva_wake_hpa_take(void)
{
    if (any_checked_fields()) {
        (void)wake_hpa_take(&hpa, &result);
    }
}

void eva_wake_hpa_to_rtp(void)
{
    wake_q24_t w[WAKE_HPA_MAX_LEVEL];
    wake_cov_t r, q;
    unknown(&result, sizeof result);
    (void)wake_hpa_to_rtp(&result, Frama_C_interval(INT32_MIN, INT32_MAX), Frama_C_float_interval(-1e30f, 1e30f),
                          w, &r, &q);
}

/** The previous predictor given to an instance init accepted (its counters of any content): coefficients of any bit
 *  pattern, NaN and infinities included (the setter tests them), any index. */
void eva_wake_hpa_set_previous_ahead(void)
{
    float c[WAKE_HPA_AHEAD_TAPS];
    if (any_checked_fields()) {
        unknown(c, sizeof c);
        (void)wake_hpa_set_previous_ahead(&hpa, c, Frama_C_unsigned_int_interval(0u, UINT32_MAX));
    }
}

void eva_wake_hpa_apply(void)
{
    if (any_checked_fields()) {
        /* an RTP of any content, with eva_rtp.c's two exceptions (docs/studies/verification.md, "Corrupted state"):
           the taps pointer points to a table, the Kalman accumulators lie in their documented ranges */
        unknown(&rtp, sizeof rtp);
        unknown(rtp_taps, sizeof rtp_taps);
        rtp.taps = rtp_taps;
        if (rtp.level >= 1u && rtp.level <= WAKE_RTP_MAX_LEVEL) {
            rtp.level = (uint16_t)Frama_C_interval_split(1, WAKE_RTP_MAX_LEVEL);   /* one state each */
        }
        rtp.s = Frama_C_long_long_interval(-(INT64_C(1) << 50), INT64_C(1) << 50);
        rtp.z = Frama_C_long_long_interval(-(INT64_C(1) << 40), INT64_C(1) << 40);
        rtp.q_omega = Frama_C_long_long_interval(0, INT64_C(1) << 47);
        unknown(&hpa.result, sizeof hpa.result);   /* any result, NaN and infinities included */
#if WAKE_HPA_AHEAD
        {
            /* the RTP's predictor and goal start within their ranges: out of them the RTP's check refuses the
               instance before apply writes anything (the RTP's own entries show that refusal).  Eva joins the
               states of apply's statuses, so the ranges are checked after the call whatever its status */
            unsigned k;
            for (k = 0; k < WAKE_HPA_AHEAD_TAPS; ++k) {
                rtp.ahead.coef[k] = Frama_C_interval(-WAKE_RTP_AHEAD_COEF_MAX, WAKE_RTP_AHEAD_COEF_MAX);
            }
            rtp.ahead.goal = Frama_C_interval(0, WAKE_RTP_GATE_ONE);
            (void)wake_hpa_apply(&hpa, &rtp);
            /* what apply installs (the result's predictor and goal converted) lies within the RTP's ranges */
            /*@ assert \forall integer k; 0 <= k < WAKE_HPA_AHEAD_TAPS ==>
                       -1073741824 <= rtp.ahead.coef[k] <= 1073741824; */
            /*@ assert 0 <= rtp.ahead.goal <= 1073741824; */
        }
#else
        (void)wake_hpa_apply(&hpa, &rtp);
#endif
    }
}

#if WAKE_HPA_AHEAD
/**
 * A result of any bit pattern (NaN and infinities included: -warn-special-float none, the conversion clamps
 * them): the RTP's ranges, |c| <= 8 in Q27 and the goal in [0, 1] in Q30, as fuzz_hpa_ahead checks.
 */
void eva_wake_hpa_ahead_to_rtp(void)
{
    int32_t c[WAKE_HPA_AHEAD_TAPS];
    wake_ratio_t goal;
    unknown(&result, sizeof result);
    if (wake_hpa_ahead_to_rtp(&result, c, &goal) == WAKE_HPA_OK) {
        /*@ assert \forall integer k; 0 <= k < WAKE_HPA_AHEAD_TAPS ==>
                   -1073741824 <= c[k] <= 1073741824; */
        /*@ assert 0 <= goal <= 1073741824; */
    }
}
#endif
