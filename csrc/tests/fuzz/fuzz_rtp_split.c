/**
 * @file fuzz_rtp_split.c
 * @brief libFuzzer harness for the split step (WAKE_RTP_SPLIT=1): wake_rtp_prepare, wake_rtp_finish,
 * wake_rtp_finish_missing and wake_rate_step, each against the unsplit call it replaces.
 *
 * Two RTP instances are initialised from the same decoded configuration (as fuzz_rtp.c: level, taps,
 * weights, R, q, p0, raw or scaled): "split" runs the split step, "whole" the unsplit one.  The input then
 * picks one of two modes and a sequence of calls:
 *
 * - direct: a sample goes through wake_rtp_prepare (once, twice, or not again when a "prepare" call has
 *   already prepared it) and wake_rtp_finish on split, through wake_rtp_step on whole; a missing sample
 *   through wake_rtp_finish_missing / wake_rtp_step_missing; a finish without a prepare must be refused
 *   with WAKE_RTP_E_UNPREPARED and change nothing;
 * - rate: every input sample (present or missing) goes through wake_rate_step on split, through
 *   wake_rate_push and wake_rtp_step / wake_rtp_step_missing at each group's end on whole (D from the input,
 *   1..WAKE_RATE_MAX_FACTOR; D = 1 must be refused by wake_rate_step and leave everything as it was);
 *
 * and in both modes the setters on both instances, between a prepare and its finish too (set_weights,
 * reset, load_state, set_ahead, set_ahead_ramp, load_ahead_state: each keeps a prepared step prepared),
 * wake_rtp_run on both (it forgets a prepared step), and "corrupt" (the same input bytes written into both
 * instances' observable state, only while split is not prepared: a prepared step is computed from the state
 * as it was).
 *
 * The property, beyond the sanitizers: after every call both instances return the same status, the same
 * prediction and the same observable state, byte for byte (everything before wake_rtp_t::split, as
 * csrc/tests/test_wake_rtp_split.c compares), and the front ends the same state.  After a corruption only
 * the statuses must agree: a corrupted state is one no call sequence makes (the ring holds each sample
 * twice, and the split step reads the other copy of some: docs/studies/verification.md, "Fuzzing"), on which the
 * header promises safety (every operation saturates), not the same prediction.
 */
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "wake_rtp.h"
#include "wake_rate.h"

#if !WAKE_RTP_SPLIT
/* Built without the split step (make warnings compiles every variant): nothing to fuzz; csrc/Makefile's
   fuzz target builds this harness with -DWAKE_RTP_SPLIT=1. */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (data != NULL || size > 0u) {
        __builtin_trap();
    }
    return 0;
}
#else
#include "fuzz_input.h"
#include "fuzz_rtp_input.h"

enum { OP_SAMPLE, OP_MISSING, OP_PREPARE, OP_UNPREPARED, OP_SET_WEIGHTS, OP_RESET, OP_LOAD_STATE, OP_RUN,
#if WAKE_RTP_AHEAD
       OP_SET_AHEAD, OP_SET_AHEAD_RAMP, OP_LOAD_AHEAD,
#endif
       OP_CORRUPT, OP_COUNT };

static wake_q15_t taps[WAKE_RTP_MAX_LEVEL * WAKE_RTP_MAX_TAPS];
static wake_rtp_t split, whole, copy;
static wake_rate_t rate_split, rate_whole;
/** 1 once the input has corrupted the instances: from then on only the statuses are compared. */
static int corrupted;

static int status_known(wake_rtp_status_t st)
{
    return st <= WAKE_RTP_OK && st >= WAKE_RTP_E_UNPREPARED;
}

/** The observable state: everything before the prepared values (test_wake_rtp_split.c, same_state). */
static int same_state(const wake_rtp_t *a, const wake_rtp_t *b)
{
    return memcmp(a, b, offsetof(wake_rtp_t, split)) == 0;
}

/** One sample (or a missing one) on both, in the direct mode. */
static void direct_sample(fuzz_input_t *in, int missing)
{
    const int prepared = split.split.ready != 0u;
    const uint8_t how = fuzz_u8(in);
    const wake_q15_t sample = missing ? 0 : fuzz_i16(in);
    wake_q15_t y_split = 0x1234, y_whole = 0x1234;
    wake_rtp_status_t st_split = WAKE_RTP_OK, st_whole;
    unsigned k;
    /* prepare 0 (already prepared), 1 or 2 times: a second prepare recomputes the same values */
    for (k = prepared ? (unsigned)(how & 1u) : 1u + (unsigned)(how & 1u); k > 0u && st_split == WAKE_RTP_OK; --k) {
        st_split = wake_rtp_prepare(&split);
        FUZZ_REQUIRE(status_known(st_split));
    }
    if (st_split == WAKE_RTP_OK) {
        st_split = missing ? wake_rtp_finish_missing(&split, &y_split) : wake_rtp_finish(&split, sample, &y_split);
    }
    st_whole = missing ? wake_rtp_step_missing(&whole, &y_whole) : wake_rtp_step(&whole, sample, &y_whole);
    FUZZ_REQUIRE(status_known(st_split) && st_split == st_whole);
    FUZZ_REQUIRE(corrupted || (y_split == y_whole && same_state(&split, &whole)));
    FUZZ_REQUIRE(st_split != WAKE_RTP_OK || split.split.ready == 0u);   /* a step forgets the prepared one */
}

/** One input sample through the front ends, in the rate mode. */
static void rate_sample(fuzz_input_t *in, int missing, wake_q15_t *held_split, wake_q15_t *held_whole)
{
    const wake_q15_t sample = missing ? 0 : fuzz_i16(in);
    wake_rate_group_t group;
    wake_q15_t mean;
    wake_rate_status_t st_split, st_whole;
    memcpy(&copy, &split, sizeof split);
    st_split = wake_rate_step(&rate_split, &split, sample, !missing, held_split);
    if (rate_split.factor < 2u) {
        /* D = 1 is wake_rtp_step's case: refused, nothing taken */
        FUZZ_REQUIRE(st_split == WAKE_RATE_E_FACTOR && memcmp(&copy, &split, sizeof split) == 0);
        return;
    }
    st_whole = wake_rate_push(&rate_whole, sample, !missing, &group, &mean);
    FUZZ_REQUIRE(st_whole == WAKE_RATE_OK);
    if (group != WAKE_RATE_OPEN) {
        const wake_rtp_status_t st = group == WAKE_RATE_GROUP ? wake_rtp_step(&whole, mean, held_whole)
                                                              : wake_rtp_step_missing(&whole, held_whole);
        FUZZ_REQUIRE(status_known(st));
        st_whole = st == WAKE_RTP_OK ? WAKE_RATE_OK : WAKE_RATE_E_RTP;
    } else if (st_split == WAKE_RATE_E_RTP) {
        /* the prepare before a group's end was refused: only by an instance the step refuses too */
        static wake_rtp_t probe;
        memcpy(&probe, &whole, sizeof whole);
        FUZZ_REQUIRE(wake_rtp_prepare(&probe) != WAKE_RTP_OK);
        st_whole = WAKE_RATE_E_RTP;
    }
    FUZZ_REQUIRE(st_split == st_whole);
    FUZZ_REQUIRE(corrupted || (*held_split == *held_whole && same_state(&split, &whole)));
    FUZZ_REQUIRE(memcmp(&rate_split, &rate_whole, sizeof rate_split) == 0);
}

/** The same setter call on both; the statuses and states must agree and a refusal change nothing. */
static void both_set(wake_rtp_status_t st_split, wake_rtp_status_t st_whole)
{
    FUZZ_REQUIRE(status_known(st_split) && st_split == st_whole);
    FUZZ_REQUIRE(corrupted || same_state(&split, &whole));
    if (st_split != WAKE_RTP_OK) {
        FUZZ_REQUIRE(memcmp(&copy, &split, sizeof split) == 0);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input_t in = {data, size, 0u};
    wake_q24_t w[WAKE_RTP_MAX_LEVEL];
    wake_q23_t correction[WAKE_RTP_MAX_LEVEL];
    wake_cov_t covariance[WAKE_RTP_MAX_LEVEL * WAKE_RTP_MAX_LEVEL];
    wake_q15_t window[WAKE_RTP_MAX_TAPS];
    wake_q15_t block_split[64], block_whole[64];
#if WAKE_RTP_AHEAD
    wake_q15_t line[WAKE_RTP_AHEAD_TAPS];
#endif
    wake_q15_t held_split = 0, held_whole = 0;
    wake_rtp_status_t st;
    unsigned level, n, i, ops = 0;
    int rate_mode;
    uint8_t shift;

    corrupted = 0;
    level = fuzz_u8(&in) % (WAKE_RTP_MAX_LEVEL + 2u);
    shift = (uint8_t)(fuzz_u8(&in) % 17u);
    n = (level >= 1u && level <= WAKE_RTP_MAX_LEVEL) ? level << level : 0u;
    for (i = 0; i < n; ++i) {
        taps[i] = (wake_q15_t)(fuzz_i16(&in) >> shift);
    }
    memset(&split, 0xA5, sizeof split);        /* init takes any content; the same bytes in both */
    memset(&whole, 0xA5, sizeof whole);
    read_weights(&in, w, level <= WAKE_RTP_MAX_LEVEL ? level : WAKE_RTP_MAX_LEVEL);
    {
        const wake_cov_t r = read_noise(&in), q = read_noise(&in), p0 = read_noise(&in);
        const int kalman = fuzz_u8(&in) & 1u;
        st = wake_rtp_init(&split, (int)level, taps, w, r, kalman ? q : 0, kalman ? p0 : 0);
        FUZZ_REQUIRE(status_known(st));
        FUZZ_REQUIRE(wake_rtp_init(&whole, (int)level, taps, w, r, kalman ? q : 0, kalman ? p0 : 0) == st);
    }
    FUZZ_REQUIRE(same_state(&split, &whole));
    /* a refused init leaves the prepared values as they were (here 0xA5 bytes): not prepared, so that the
       harness never finishes from bytes no prepare wrote (the comparisons exclude them) */
    split.split.ready = 0u;
    whole.split.ready = 0u;
    {
        /* the mode and D: the low bit picks rate, the rest D = 1 + value % 16 (often), or up to 1000 */
        const uint16_t mode = fuzz_u16(&in);
        const int factor = (mode & 2u) != 0u ? 1 + (int)((mode >> 2) % 16u) : 1 + (int)((mode >> 2) % 1000u);
        rate_mode = (mode & 1u) != 0u;
        FUZZ_REQUIRE(wake_rate_init(&rate_split, factor) == WAKE_RATE_OK);
        FUZZ_REQUIRE(wake_rate_init(&rate_whole, factor) == WAKE_RATE_OK);
    }

    while (fuzz_more(&in) && ops++ < 4096u) {
        const unsigned op = fuzz_u8(&in) % OP_COUNT;
        memcpy(&copy, &split, sizeof split);
        switch (op) {
        case OP_SAMPLE:
        case OP_MISSING:
            if (rate_mode) {
                rate_sample(&in, op == OP_MISSING, &held_split, &held_whole);
            } else {
                direct_sample(&in, op == OP_MISSING);
            }
            break;
        case OP_PREPARE:   /* a prepare ahead of the next sample (rate mode: the front end's own is redone) */
            st = wake_rtp_prepare(&split);
            FUZZ_REQUIRE(status_known(st));
            FUZZ_REQUIRE(corrupted || same_state(&split, &whole));   /* observable state untouched */
            break;
        case OP_UNPREPARED:   /* a finish without a prepare is refused and changes nothing */
            if (split.split.ready == 0u && !rate_mode) {
                wake_q15_t y = 0x1234;
                st = (fuzz_u8(&in) & 1u) != 0u ? wake_rtp_finish_missing(&split, &y)
                                                : wake_rtp_finish(&split, fuzz_i16(&in), &y);
                FUZZ_REQUIRE(st != WAKE_RTP_OK && status_known(st) && y == 0x1234);
                FUZZ_REQUIRE(memcmp(&copy, &split, sizeof split) == 0);
            }
            break;
        case OP_SET_WEIGHTS:
            read_weights(&in, w, WAKE_RTP_MAX_LEVEL);
            {
                const wake_cov_t r = read_noise(&in), q = read_noise(&in);
                const wake_rtp_status_t a = wake_rtp_set_weights(&split, w, r, q);
                both_set(a, wake_rtp_set_weights(&whole, w, r, q));
            }
            break;
        case OP_RESET: {
            const wake_rtp_status_t a = wake_rtp_reset(&split);
            both_set(a, wake_rtp_reset(&whole));
            break;
        }
        case OP_LOAD_STATE: {
            wake_rtp_status_t a;
            int32_t count;
            fuzz_bytes(&in, window, sizeof window);
            fuzz_bytes(&in, correction, sizeof correction);
            fuzz_bytes(&in, covariance, sizeof covariance);
            count = fuzz_i32(&in);
            a = wake_rtp_load_state(&split, window, correction, covariance, count);
            both_set(a, wake_rtp_load_state(&whole, window, correction, covariance, count));
            break;
        }
        case OP_RUN: {
            wake_rtp_status_t a;
            n = fuzz_u8(&in) % 65u;
            for (i = 0; i < n; ++i) {
                block_split[i] = fuzz_i16(&in);
                block_whole[i] = block_split[i];
            }
            a = wake_rtp_run(&split, block_split, block_split, n);
            FUZZ_REQUIRE(a == wake_rtp_run(&whole, block_whole, block_whole, n) && status_known(a));
            FUZZ_REQUIRE(corrupted || (memcmp(block_split, block_whole, n * sizeof block_split[0]) == 0 &&
                                        same_state(&split, &whole)));
            FUZZ_REQUIRE(a != WAKE_RTP_OK || n == 0u || split.split.ready == 0u);   /* a run forgets it */
            break;
        }
#if WAKE_RTP_AHEAD
        case OP_SET_AHEAD: {
            int32_t c[WAKE_RTP_AHEAD_TAPS];
            int32_t goal;
            wake_rtp_status_t a;
            const int scaled = (fuzz_u8(&in) & 1u) == 0u;
            for (i = 0; i < (unsigned)WAKE_RTP_AHEAD_TAPS; ++i) {
                const int32_t raw = fuzz_i32(&in);
                c[i] = scaled ? raw / 2 : raw;
            }
            goal = fuzz_i32(&in);
            a = wake_rtp_set_ahead(&split, c, goal);
            both_set(a, wake_rtp_set_ahead(&whole, c, goal));
            break;
        }
        case OP_SET_AHEAD_RAMP: {
            const int32_t alpha = fuzz_i32(&in);
            const wake_rtp_status_t a = wake_rtp_set_ahead_ramp(&split, alpha);
            both_set(a, wake_rtp_set_ahead_ramp(&whole, alpha));
            break;
        }
        case OP_LOAD_AHEAD: {
            int32_t gate;
            wake_rtp_status_t a;
            fuzz_bytes(&in, line, sizeof line);
            gate = fuzz_i32(&in);
            a = wake_rtp_load_ahead_state(&split, line, gate);
            both_set(a, wake_rtp_load_ahead_state(&whole, line, gate));
            break;
        }
#endif
        default: {   /* OP_CORRUPT: the same bytes into both observable states, the taps pointer kept */
            const size_t offset = fuzz_u16(&in) % offsetof(wake_rtp_t, split);
            size_t len = (size_t)(fuzz_u8(&in) % 16u) + 1u;
            uint8_t bytes[16];
            if (split.split.ready != 0u) {
                break;
            }
            if (len > offsetof(wake_rtp_t, split) - offset) {
                len = offsetof(wake_rtp_t, split) - offset;
            }
            fuzz_bytes(&in, bytes, len);
            memcpy((uint8_t *)&split + offset, bytes, len);
            memcpy((uint8_t *)&whole + offset, bytes, len);
            split.taps = taps;
            whole.taps = taps;
            keep_accumulators_in_range(&split);
            keep_accumulators_in_range(&whole);
            corrupted = 1;
            break;
        }
        }
        if (rate_mode && op != OP_SAMPLE && op != OP_MISSING && rate_split.factor >= 2u &&
            (uint32_t)rate_split.phase + 1u == (uint32_t)rate_split.factor) {
            /* wake_rate_step prepares on the sample before a group's end: a firmware that runs, resets or
               repairs the RTP after that sample prepares again (any prepare between two steps is the same) */
            (void)wake_rtp_prepare(&split);
            FUZZ_REQUIRE(corrupted || same_state(&split, &whole));
        }
    }
    return 0;
}
#endif /* WAKE_RTP_SPLIT */
