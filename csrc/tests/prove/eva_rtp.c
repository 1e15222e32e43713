/**
 * @file eva_rtp.c
 * @brief Frama-C Eva analysis entries for the fixed-point RTP (csrc/wake_rtp.c): one per public
 *        function, every input ranged as the API allows (make -C csrc prove; docs/studies/verification.md).
 *
 * An instance given to a function other than init has any content at all (the corruption checks
 * must refuse what they cannot use), with two exceptions the header documents: the caller-owned
 * taps pointer points to a taps table (of any content), and the Kalman accumulators s, z and
 * q |w|^2 lie in the ranges the recursion keeps them in (docs/studies/verification.md, "Corrupted state").
 */
#include <stdint.h>
#include <string.h>
#include "__fc_builtin.h"
#include "wake_rtp.h"

static wake_q15_t taps[WAKE_RTP_MAX_LEVEL * WAKE_RTP_MAX_TAPS];
static wake_q24_t weights[WAKE_RTP_MAX_LEVEL];
static wake_q15_t window[WAKE_RTP_MAX_TAPS];
static wake_q23_t correction[WAKE_RTP_MAX_LEVEL];
static wake_cov_t covariance[WAKE_RTP_MAX_LEVEL * WAKE_RTP_MAX_LEVEL];
static wake_q15_t block[2 * WAKE_RTP_MAX_TAPS];
static wake_rtp_t rtp;

static void unknown(void *p, size_t n)
{
    Frama_C_make_unknown((char *)p, n);
}

static int32_t any_i32(void)
{
    return Frama_C_int_interval(INT32_MIN, INT32_MAX);
}

/** Any instance content, the taps pointer and the accumulators' documented ranges excepted. */
static void any_instance(void)
{
    unknown(&rtp, sizeof rtp);
    unknown(taps, sizeof taps);
    rtp.taps = taps;
    /* one Eva state per level (the checks refuse every other value): the loop bounds 2^J are then
       exact and the FIR's int64 sum is bounded per level instead of widened */
    rtp.level = (uint16_t)Frama_C_interval_split(0, WAKE_RTP_MAX_LEVEL + 1);
    rtp.s = Frama_C_long_long_interval(-(INT64_C(1) << 50), INT64_C(1) << 50);
    rtp.z = Frama_C_long_long_interval(-(INT64_C(1) << 40), INT64_C(1) << 40);
    rtp.q_omega = Frama_C_long_long_interval(0, INT64_C(1) << 47);
}

void eva_wake_rtp_init(void)
{
    unknown(&rtp, sizeof rtp);
    unknown(taps, sizeof taps);
    unknown(weights, sizeof weights);
    {
        int level = any_i32();
        if (level >= 1 && level <= WAKE_RTP_MAX_LEVEL) {
            level = Frama_C_interval_split(1, WAKE_RTP_MAX_LEVEL);   /* the same values, one state each */
        }
        (void)wake_rtp_init(&rtp, level, taps, weights, any_i32(), any_i32(), any_i32());
    }
}

void eva_wake_rtp_set_weights(void)
{
    any_instance();
    unknown(weights, sizeof weights);
    (void)wake_rtp_set_weights(&rtp, weights, any_i32(), any_i32());
}

void eva_wake_rtp_reset(void)
{
    any_instance();
    (void)wake_rtp_reset(&rtp);
}

void eva_wake_rtp_step(void)
{
    wake_q15_t prediction;
    any_instance();
    (void)wake_rtp_step(&rtp, Frama_C_short_interval(INT16_MIN, INT16_MAX), &prediction);
}

void eva_wake_rtp_step_missing(void)
{
    wake_q15_t prediction;
    any_instance();
    (void)wake_rtp_step_missing(&rtp, &prediction);
}

#if WAKE_RTP_SPLIT
/* the split step (WAKE_RTP_SPLIT 1): the prepared values are part of the instance, of any content too */
void eva_wake_rtp_prepare(void)
{
    any_instance();
    (void)wake_rtp_prepare(&rtp);
}

void eva_wake_rtp_finish(void)
{
    wake_q15_t prediction;
    any_instance();
    (void)wake_rtp_finish(&rtp, Frama_C_short_interval(INT16_MIN, INT16_MAX), &prediction);
}

void eva_wake_rtp_finish_missing(void)
{
    wake_q15_t prediction;
    any_instance();
    (void)wake_rtp_finish_missing(&rtp, &prediction);
}
#endif

void eva_wake_rtp_run(void)
{
    any_instance();
    unknown(block, sizeof block);
    (void)wake_rtp_run(&rtp, block, block, Frama_C_size_t_interval(0u, sizeof block / sizeof block[0]));
}

#if WAKE_RTP_VOLUNTARY_AHEAD
/* a block with every output, any sample flagged missing or none (missing NULL), any length up to the array's */
static uint8_t flags[2 * WAKE_RTP_MAX_TAPS];
static wake_q15_t voluntary[2 * WAKE_RTP_MAX_TAPS];
static wake_q23_t tremor_ahead[2 * WAKE_RTP_MAX_TAPS];
static wake_ratio_t gate[2 * WAKE_RTP_MAX_TAPS];
static wake_q23_t command[2 * WAKE_RTP_MAX_TAPS];
static wake_q23_t voluntary_ahead[2 * WAKE_RTP_MAX_TAPS];

void eva_wake_rtp_run_outputs(void)
{
    any_instance();
    unknown(block, sizeof block);
    unknown(flags, sizeof flags);
    (void)wake_rtp_run_outputs(&rtp, block, (Frama_C_interval(0, 1) != 0) ? flags : NULL,
                               Frama_C_size_t_interval(0u, sizeof block / sizeof block[0]), voluntary, tremor_ahead,
                               gate, command, voluntary_ahead);
}
#endif

void eva_wake_rtp_load_state(void)
{
    any_instance();
    unknown(window, sizeof window);
    unknown(correction, sizeof correction);
    unknown(covariance, sizeof covariance);
    (void)wake_rtp_load_state(&rtp, window, correction, covariance, any_i32());
}

void eva_wake_rtp_get_state(void)
{
    any_instance();
    (void)wake_rtp_get_state(&rtp, correction, covariance);
}

void eva_wake_rtp_reciprocal(void)
{
    (void)wake_rtp_reciprocal(Frama_C_unsigned_int_interval(0u, UINT32_MAX));
}

#if WAKE_RTP_AHEAD
static int32_t ahead_coefficients[WAKE_RTP_AHEAD_TAPS];
static wake_q15_t ahead_line[WAKE_RTP_AHEAD_TAPS];

void eva_wake_rtp_set_ahead(void)
{
    any_instance();
    unknown(ahead_coefficients, sizeof ahead_coefficients);
    (void)wake_rtp_set_ahead(&rtp, ahead_coefficients, any_i32());
}

void eva_wake_rtp_set_ahead_ramp(void)
{
    any_instance();
    (void)wake_rtp_set_ahead_ramp(&rtp, any_i32());
}

void eva_wake_rtp_ahead_output(void)
{
    wake_q23_t predicted, command;
    wake_ratio_t gate;
    any_instance();
    (void)wake_rtp_ahead_output(&rtp, &predicted, &gate, &command);
}

void eva_wake_rtp_load_ahead_state(void)
{
    any_instance();
    unknown(ahead_line, sizeof ahead_line);
    (void)wake_rtp_load_ahead_state(&rtp, ahead_line, any_i32());
}

void eva_wake_rtp_get_ahead_state(void)
{
    any_instance();
    (void)wake_rtp_get_ahead_state(&rtp, ahead_line);
}
#endif

/* the tremor ahead's own instance (wake_ahead.h), in every configuration: of any content at all (the header
   documents every content as safe for the step, and the setters check what they take) */
static wake_ahead_t ahead;
static wake_ahead_prepared_t ahead_prepared;
static int32_t instance_coefficients[WAKE_RTP_AHEAD_TAPS];
static wake_q15_t instance_line[WAKE_RTP_AHEAD_TAPS];

void eva_wake_ahead_step(void)
{
    unknown(&ahead, sizeof ahead);
    wake_ahead_step(&ahead, any_i32());
}

void eva_wake_ahead_step_missing(void)
{
    unknown(&ahead, sizeof ahead);
    wake_ahead_step_missing(&ahead);
}

void eva_wake_ahead_prepare(void)
{
    unknown(&ahead, sizeof ahead);
    wake_ahead_prepare(&ahead, &ahead_prepared);
}

void eva_wake_ahead_finish(void)
{
    unknown(&ahead, sizeof ahead);
    unknown(&ahead_prepared, sizeof ahead_prepared);
    wake_ahead_finish(&ahead, &ahead_prepared, any_i32(), any_i32());
}

void eva_wake_ahead_set_model(void)
{
    unknown(&ahead, sizeof ahead);
    unknown(instance_coefficients, sizeof instance_coefficients);
    (void)wake_ahead_set_model(&ahead, instance_coefficients, any_i32());
}

void eva_wake_ahead_load(void)
{
    unknown(&ahead, sizeof ahead);
    unknown(instance_line, sizeof instance_line);
    (void)wake_ahead_load(&ahead, instance_line, any_i32());
}

void eva_wake_ahead_history(void)
{
    unknown(&ahead, sizeof ahead);
    (void)wake_ahead_history(&ahead, instance_line);
}

/* the voluntary motion ahead's own instance (wake_voluntary_ahead.h): its output entry, in every configuration */
static wake_voluntary_ahead_t voluntary_instance;

void eva_wake_voluntary_ahead_output(void)
{
    wake_q23_t output;
    unknown(&voluntary_instance, sizeof voluntary_instance);
    (void)wake_voluntary_ahead_output(&voluntary_instance, &output);
}

#if WAKE_RTP_VOLUNTARY_AHEAD
/* the voluntary motion at n + h (WAKE_RTP_VOLUNTARY_AHEAD 1): analysed with the switch on */
static wake_q24_t weights_ahead[WAKE_RTP_MAX_LEVEL];

void eva_wake_rtp_set_voluntary_ahead(void)
{
    any_instance();
    unknown(weights_ahead, sizeof weights_ahead);
    (void)wake_rtp_set_voluntary_ahead(&rtp, weights_ahead);
}

void eva_wake_rtp_voluntary_ahead_output(void)
{
    wake_q23_t output;
    any_instance();
    (void)wake_rtp_voluntary_ahead_output(&rtp, &output);
}
#endif
