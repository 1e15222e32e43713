/*
 * Host unit tests of the split step (WAKE_RTP_SPLIT 1, issue 33): wake_rtp_prepare +
 * wake_rtp_finish / wake_rtp_finish_missing against wake_rtp_step / wake_rtp_step_missing, and
 * wake_rate_step against wake_rate_push with the unsplit step.
 *
 * Every comparison is bit for bit: the prediction of every input sample and the whole instance
 * (every field before the prepared values, compared as bytes), over streams with an active and an
 * inert Kalman filter, missing samples and whole missing groups (one before the first sample),
 * saturating inputs and weights, and weight, noise, tremor-ahead and reset calls between a prepare
 * and its finish.  Build and run: make -C csrc test (AddressSanitizer + UBSan; also with the
 * Cortex-M0+ arithmetic, without the tremor ahead and without the Kalman update).
 */
#ifndef WAKE_RTP_SPLIT
#define WAKE_RTP_SPLIT 1            /* the split step is what this file tests (make builds it with -D too) */
#endif

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "wake_rate.h"

#include "check.h"

#if !WAKE_RTP_SPLIT
#error "test_wake_rtp_split.c needs -DWAKE_RTP_SPLIT=1"
#endif

enum { J = 5, N = 1 << J };

static uint32_t rng_state = 88172645u;
static uint32_t rng_u32(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 17;
    rng_state ^= rng_state << 5;
    return rng_state;
}

/** A uniform integer in [lo, hi]. */
static int32_t rng_range(int32_t lo, int32_t hi)
{
    return (int32_t)((int64_t)lo + (int64_t)(rng_u32() % (uint32_t)((int64_t)hi - lo + 1)));
}

static wake_q15_t taps[J * N];

/** Random taps, each row's sum of |taps| below 2.0 (Q15 65536). */
static void make_taps(void)
{
    int i;
    for (i = 0; i < J * N; ++i) {
        taps[i] = (wake_q15_t)rng_range(-1900, 1900);          /* 32 x 1900 < 65536 */
    }
}

static void random_weights(wake_q24_t *w, int large)
{
    int j;
    const int32_t top = large ? WAKE_RTP_WEIGHT_MAX : (INT32_C(4) << WAKE_RTP_WEIGHT_FRAC);
    for (j = 0; j < J; ++j) {
        w[j] = rng_range(-top, top);
    }
}

/** The two instances agree in everything a step reads or writes (the prepared values excepted). */
static int same_state(const wake_rtp_t *a, const wake_rtp_t *b)
{
    return memcmp(a, b, offsetof(wake_rtp_t, split)) == 0;
}

/** Noise settings: active Kalman (q, p0 > 0) where the build has it, else inert. */
static void noise(int active, wake_cov_t *r, wake_cov_t *q, wake_cov_t *p0)
{
    *r = (wake_cov_t)1 << 20;
    *q = (WAKE_RTP_KALMAN && active) ? ((wake_cov_t)1 << 8) : 0;
    *p0 = (WAKE_RTP_KALMAN && active) ? ((wake_cov_t)1 << 24) : 0;
}

#if WAKE_RTP_AHEAD
static void random_ahead(wake_rtp_t *a, wake_rtp_t *b)
{
    int32_t c[WAKE_RTP_AHEAD_TAPS];
    int i;
    const wake_ratio_t goal = rng_range(0, WAKE_RTP_GATE_ONE);
    for (i = 0; i < WAKE_RTP_AHEAD_TAPS; ++i) {
        c[i] = rng_range(-WAKE_RTP_AHEAD_COEF_MAX, WAKE_RTP_AHEAD_COEF_MAX);
    }
    CHECK(wake_rtp_set_ahead(a, c, goal) == WAKE_RTP_OK && wake_rtp_set_ahead(b, c, goal) == WAKE_RTP_OK,
          "set_ahead");
}
#endif

/** An input sample: a slow motion, a tremor, noise, and now and then a full-scale burst. */
static wake_q15_t input_sample(long n, double fs)
{
    const double t = (double)n / fs;
    double x = 0.4 * sin(2.0 * 3.14159265358979 * 0.7 * t) + 0.08 * sin(2.0 * 3.14159265358979 * 6.0 * t)
               + 0.01 * ((double)(rng_u32() % 2001u) - 1000.0) / 1000.0;
    if ((n / 500) % 7 == 3) {
        x = ((n & 1) != 0) ? 1.0 : -1.0;                    /* saturates the predictions */
    }
    return (wake_q15_t)lround(fmax(-32768.0, fmin(32767.0, x * 32767.0)));
}

/** A configuration call applied to both instances between two input samples (any point of a group). */
static void maybe_configure(wake_rtp_t *a, wake_rtp_t *b, int active, int *resets)
{
    const uint32_t r = rng_u32() % 1000u;
    wake_cov_t rr, q, p0;
    noise(active, &rr, &q, &p0);
    if (r < 4u) {
        wake_q24_t w[J];
        random_weights(w, r == 0u);
        q = (q != 0) ? (wake_cov_t)rng_range(1, 1 << 12) : 0;
        CHECK(wake_rtp_set_weights(a, w, rr, q) == WAKE_RTP_OK && wake_rtp_set_weights(b, w, rr, q) == WAKE_RTP_OK,
              "set_weights");
    } else if (r == 4u) {
        CHECK(wake_rtp_reset(a) == WAKE_RTP_OK && wake_rtp_reset(b) == WAKE_RTP_OK, "reset");
        ++*resets;
#if WAKE_RTP_AHEAD
    } else if (r < 8u) {
        random_ahead(a, b);
    } else if (r == 8u) {
        const wake_ratio_t ramp = rng_range(1, WAKE_RTP_GATE_ONE);
        CHECK(wake_rtp_set_ahead_ramp(a, ramp) == WAKE_RTP_OK && wake_rtp_set_ahead_ramp(b, ramp) == WAKE_RTP_OK,
              "set_ahead_ramp");
#endif
    } else {
        /* no call */
    }
}

/*
 * An input stream at D x 100 Hz through wake_rate_step (split) and through wake_rate_push with
 * wake_rtp_step (the path the firmware at 100 Hz and the Python wrapper take): the held prediction
 * and the whole instance identical after every input sample.
 */
static void test_rate_stream(int factor, int active, long n_samples)
{
    wake_rtp_t split, whole;
    wake_rate_t fe_split, fe_whole;
    wake_q24_t w[J];
    wake_cov_t r, q, p0;
    wake_q15_t held_split = 0, held_whole = 0;
    long n;
    int differ = 0, groups = 0, missing_groups = 0, resets = 0, bad_status = 0;
    uint32_t saturations = 0u;
    random_weights(w, 0);
    noise(active, &r, &q, &p0);
    CHECK(wake_rtp_init(&split, J, taps, w, r, q, p0) == WAKE_RTP_OK, "init");
    CHECK(wake_rtp_init(&whole, J, taps, w, r, q, p0) == WAKE_RTP_OK, "init twin");
#if WAKE_RTP_AHEAD
    random_ahead(&split, &whole);
#endif
    CHECK(wake_rate_init(&fe_split, factor) == WAKE_RATE_OK && wake_rate_init(&fe_whole, factor) == WAKE_RATE_OK,
          "front ends");
    for (n = 0; n < n_samples; ++n) {
        const wake_q15_t x = input_sample(n, 100.0 * factor);
        /* the first group is missing whole (a missing group before the first sample), later runs of
           missing samples longer than a group now and then, and single dropped samples */
        const int present = (n >= factor) && ((n / (3 * factor)) % 41 != 17) && (rng_u32() % 29u != 0u);
        wake_rate_group_t g;
        wake_q15_t m;
        maybe_configure(&split, &whole, active, &resets);
        bad_status += wake_rate_step(&fe_split, &split, x, present, &held_split) != WAKE_RATE_OK;
        bad_status += wake_rate_push(&fe_whole, x, present, &g, &m) != WAKE_RATE_OK;
        if (g == WAKE_RATE_GROUP) {
            bad_status += wake_rtp_step(&whole, m, &held_whole) != WAKE_RTP_OK;
            ++groups;
        } else if (g == WAKE_RATE_MISSING) {
            bad_status += wake_rtp_step_missing(&whole, &held_whole) != WAKE_RTP_OK;
            ++groups;
            ++missing_groups;
        }
        differ += (held_split != held_whole) || !same_state(&split, &whole);
        saturations = whole.saturations > saturations ? whole.saturations : saturations;
    }
    CHECK(bad_status == 0, "D %d: %d calls failed", factor, bad_status);
    CHECK(differ == 0, "D %d, Kalman %s: %d of %ld input samples differ from the unsplit step", factor,
          (active && WAKE_RTP_KALMAN) ? "active" : "inert", differ, n_samples);
    CHECK(groups == (int)(n_samples / factor) && missing_groups > 1, "D %d: %d groups, %d missing", factor, groups,
          missing_groups);
    CHECK(saturations > 0u, "D %d: the stream saturates the prediction (the counted path is exercised)", factor);
    printf("  D %4d, Kalman %s: %ld input samples, %d groups (%d missing), %d resets, %u saturations: identical\n",
           factor, (active && WAKE_RTP_KALMAN) ? "active" : "inert ", n_samples, groups, missing_groups, resets, (unsigned)saturations);
}

/*
 * The split step on its own at the bank rate: prepare (one to three times, setters between),
 * then finish, against step, for measured and missing samples in any order.
 */
static void test_prepare_finish(int active)
{
    wake_rtp_t split, whole;
    wake_q24_t w[J];
    wake_cov_t r, q, p0;
    int n, differ = 0, bad_status = 0, resets = 0;
    random_weights(w, 0);
    noise(active, &r, &q, &p0);
    (void)wake_rtp_init(&split, J, taps, w, r, q, p0);
    (void)wake_rtp_init(&whole, J, taps, w, r, q, p0);
    for (n = 0; n < 20000; ++n) {
        const wake_q15_t x = input_sample(n, 100.0);
        const int present = rng_u32() % 13u != 0u;
        const int prepares = 1 + (int)(rng_u32() % 3u);
        wake_q15_t y_split = 0, y_whole = 0;
        int k;
        for (k = 0; k < prepares; ++k) {
            maybe_configure(&split, &whole, active, &resets);
            bad_status += wake_rtp_prepare(&split) != WAKE_RTP_OK;
        }
        maybe_configure(&split, &whole, active, &resets);
        if (present) {
            bad_status += wake_rtp_finish(&split, x, &y_split) != WAKE_RTP_OK;
            bad_status += wake_rtp_step(&whole, x, &y_whole) != WAKE_RTP_OK;
        } else {
            bad_status += wake_rtp_finish_missing(&split, &y_split) != WAKE_RTP_OK;
            bad_status += wake_rtp_step_missing(&whole, &y_whole) != WAKE_RTP_OK;
        }
        differ += (y_split != y_whole) || !same_state(&split, &whole);
    }
    CHECK(bad_status == 0, "%d calls failed", bad_status);
    CHECK(differ == 0, "Kalman %s: %d of 20000 finishes differ from the step", active ? "active" : "inert", differ);
}

/* What the split entries refuse, and that a refusal changes nothing. */
static void test_status(void)
{
    wake_rtp_t s, copy;
    wake_rate_t fe;
    wake_q24_t w[J];
    wake_cov_t r, q, p0;
    wake_q15_t y = 123;
    random_weights(w, 0);
    noise(1, &r, &q, &p0);
    (void)wake_rtp_init(&s, J, taps, w, r, q, p0);
    CHECK(wake_rtp_prepare(NULL) == WAKE_RTP_E_NULL, "prepare NULL");
    CHECK(wake_rtp_finish(NULL, 0, &y) == WAKE_RTP_E_NULL, "finish NULL");
    CHECK(wake_rtp_finish(&s, 0, NULL) == WAKE_RTP_E_NULL, "finish NULL prediction");
    memcpy(&copy, &s, sizeof s);
    CHECK(wake_rtp_finish(&s, 100, &y) == WAKE_RTP_E_UNPREPARED && y == 123, "finish before any prepare");
    CHECK(wake_rtp_finish_missing(&s, &y) == WAKE_RTP_E_UNPREPARED && y == 123, "finish_missing before any prepare");
    CHECK(memcmp(&copy, &s, sizeof s) == 0, "a refused finish changes nothing");
    CHECK(wake_rtp_prepare(&s) == WAKE_RTP_OK && s.split.ready == 1u, "prepare");
    CHECK(wake_rtp_step(&s, 100, &y) == WAKE_RTP_OK && s.split.ready == 0u, "a step forgets the prepared step");
    CHECK(wake_rtp_finish(&s, 100, &y) == WAKE_RTP_E_UNPREPARED, "so finish refuses");
    CHECK(wake_rtp_prepare(&s) == WAKE_RTP_OK && wake_rtp_finish(&s, 100, &y) == WAKE_RTP_OK, "prepare, finish");
    CHECK(wake_rtp_finish(&s, 100, &y) == WAKE_RTP_E_UNPREPARED, "one finish per prepare");
    s.magic = 0u;
    CHECK(wake_rtp_prepare(&s) == WAKE_RTP_E_UNINIT, "prepare of an uninitialised instance");
    s.magic = WAKE_RTP_MAGIC;

    /* corrupted prepared values give a wrong prediction, never undefined behaviour (UBSan) */
    CHECK(wake_rtp_prepare(&s) == WAKE_RTP_OK, "prepare");
    s.split.fir = INT64_MAX;
    s.split.rho = INT32_MIN;
    s.split.events = UINT32_MAX;
#if WAKE_RTP_AHEAD
    s.split.ahead.dot = INT64_MIN;
    s.split.ahead.gate = -1;
#endif
    CHECK(wake_rtp_finish(&s, 32767, &y) == WAKE_RTP_OK && s.split.ready == 0u,
          "corrupted prepared values: the finish runs (a wrong prediction at worst)");

    CHECK(wake_rate_init(&fe, 1) == WAKE_RATE_OK, "front end D 1");
    CHECK(wake_rate_step(&fe, &s, 0, 1, &y) == WAKE_RATE_E_FACTOR && fe.phase == 0u, "D 1 has no split step");
    CHECK(wake_rate_init(&fe, 2) == WAKE_RATE_OK, "front end D 2");
    CHECK(wake_rate_step(NULL, &s, 0, 1, &y) == WAKE_RATE_E_NULL, "NULL front end");
    CHECK(wake_rate_step(&fe, NULL, 0, 1, &y) == WAKE_RATE_E_NULL && fe.phase == 0u, "NULL RTP");
    CHECK(wake_rate_step(&fe, &s, 0, 1, NULL) == WAKE_RATE_E_NULL && fe.phase == 0u, "NULL prediction");
    CHECK(wake_rate_step(&fe, &s, 10, 1, &y) == WAKE_RATE_OK && s.split.ready == 1u, "the first sample prepares");
    CHECK(wake_rtp_step(&s, 10, &y) == WAKE_RTP_OK, "a step outside wake_rate_step");
    y = 77;
    CHECK(wake_rate_step(&fe, &s, 10, 1, &y) == WAKE_RATE_E_RTP && fe.phase == 0u && y == 77,
          "the group's end then finds the RTP unprepared");
}

#if WAKE_RTP_KALMAN
/* The covariance at the top of its range: the time update of a missing sample clamps (and counts it). */
static void test_clamped_time_update(void)
{
    wake_rtp_t split, whole;
    wake_q24_t w[J];
    wake_cov_t r, q, p0;
    wake_q15_t y_split = 0, y_whole = 0;
    int k;
    random_weights(w, 0);
    noise(1, &r, &q, &p0);
    (void)wake_rtp_init(&split, J, taps, w, r, q, p0);
    (void)wake_rtp_step(&split, 1000, &y_split);
    split.s = INT64_C(1) << 50;                       /* the top of the range the recursion keeps s in */
    memcpy(&whole, &split, sizeof split);
    for (k = 0; k < 3; ++k) {
        (void)wake_rtp_prepare(&split);
        (void)wake_rtp_finish_missing(&split, &y_split);
        (void)wake_rtp_step_missing(&whole, &y_whole);
    }
    CHECK(whole.saturations >= 3u, "the time update clamped s: %u saturations", (unsigned)whole.saturations);
    CHECK(y_split == y_whole && same_state(&split, &whole), "and the split step counted them as the step did");
}
#endif

int main(void)
{
    static const int factors[] = {2, 3, 10, 37};
    unsigned i;
    make_taps();
    printf("sizeof(wake_rtp_t) = %u bytes (WAKE_RTP_SPLIT 1, MAX_LEVEL %d)\n", (unsigned)sizeof(wake_rtp_t),
           WAKE_RTP_MAX_LEVEL);
    test_status();
#if WAKE_RTP_KALMAN
    test_clamped_time_update();
#endif
    test_prepare_finish(1);
    test_prepare_finish(0);
    for (i = 0; i < sizeof factors / sizeof factors[0]; ++i) {
        test_rate_stream(factors[i], 1, 200L * factors[i] * 10);
        test_rate_stream(factors[i], 0, 200L * factors[i] * 10);
    }
    printf("%d passed, %d failed\n", n_passed, n_failed);
    return n_failed ? 1 : 0;
}
