/*
 * Host unit tests of the decimating front end (wake_rate.c).
 *
 * The rounded group mean is compared with the same mean computed here in
 * double precision (round halves away from zero), over random groups with
 * missing samples, every factor 1..WAKE_RATE_MAX_FACTOR at the extremes, and a
 * whole 1 kHz stream fed through the front end and a level-5 RTP.  Tests may
 * use double and stdio; the library may not.
 *
 * Build and run: make -C csrc test  (AddressSanitizer + UBSan).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "wake_rate.h"

#include "check.h"

static uint32_t rng_state = 2463534242u;
static uint32_t rng_u32(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 17;
    rng_state ^= rng_state << 5;
    return rng_state;
}

static void test_status_codes(void)
{
    wake_rate_t s;
    wake_rate_group_t g = WAKE_RATE_GROUP;
    wake_q15_t m = 1;
    CHECK(wake_rate_init(NULL, 10) == WAKE_RATE_E_NULL, "NULL instance");
    CHECK(wake_rate_init(&s, 0) == WAKE_RATE_E_FACTOR, "factor 0");
    CHECK(wake_rate_init(&s, WAKE_RATE_MAX_FACTOR + 1) == WAKE_RATE_E_FACTOR, "factor too large");
    CHECK(wake_rate_push(&s, 0, 1, &g, &m) == WAKE_RATE_E_UNINIT && g == WAKE_RATE_OPEN, "refused init");
    CHECK(wake_rate_init(&s, 3) == WAKE_RATE_OK, "init");
    CHECK(wake_rate_push(&s, 0, 1, NULL, &m) == WAKE_RATE_E_NULL, "NULL group");
    CHECK(wake_rate_push(&s, 0, 1, &g, NULL) == WAKE_RATE_E_NULL && g == WAKE_RATE_OPEN, "NULL mean");
    s.phase = 3u;
    CHECK(wake_rate_push(&s, 0, 1, &g, &m) == WAKE_RATE_E_CORRUPT, "phase beyond the factor");
    CHECK(wake_rate_init(&s, 3) == WAKE_RATE_OK, "init again");
    s.present = 1u;
    s.sum = 40000;
    CHECK(wake_rate_push(&s, 0, 1, &g, &m) == WAKE_RATE_E_CORRUPT, "present above phase");
    s.phase = 1u;
    CHECK(wake_rate_push(&s, 0, 1, &g, &m) == WAKE_RATE_E_CORRUPT, "sum beyond present samples");
}

/* round(sum / k), halves away from zero, in double */
static long expected_mean(long sum, long k)
{
    const double v = (double)sum / (double)k;
    return (long)(v < 0.0 ? -floor(-v + 0.5) : floor(v + 0.5));
}

static void test_means_against_double(void)
{
    int trial;
    int bad = 0;
    for (trial = 0; trial < 20000; ++trial) {
        const int factor = 1 + (int)(rng_u32() % (trial < 100 ? (uint32_t)WAKE_RATE_MAX_FACTOR : 12u));
        wake_rate_t s;
        long sum = 0;
        int k = 0, i;
        wake_rate_group_t g = WAKE_RATE_OPEN;
        wake_q15_t m = 0;
        (void)wake_rate_init(&s, factor);
        for (i = 0; i < factor; ++i) {
            const uint32_t r = rng_u32();
            /* extremes often: full scale both ways, and ties (+-0.5 LSB means) */
            const wake_q15_t x = (r % 7u == 0u) ? (wake_q15_t)-32768 : (r % 7u == 1u) ? (wake_q15_t)32767
                               : (wake_q15_t)(int32_t)((r >> 8) % 65536u - 32768u);
            const int present = (r % 5u) != 4u;
            if (present) {
                sum += x;
                ++k;
            }
            if (wake_rate_push(&s, x, present, &g, &m) != WAKE_RATE_OK) {
                ++bad;
            }
            if (i < factor - 1 && g != WAKE_RATE_OPEN) {
                ++bad;
            }
        }
        if (k == 0) {
            bad += (g != WAKE_RATE_MISSING);
        } else {
            bad += (g != WAKE_RATE_GROUP) || ((long)m != expected_mean(sum, k));
        }
    }
    CHECK(bad == 0, "%d of 20000 groups differ from the rounded double mean", bad);
    {
        wake_rate_t s;
        wake_rate_group_t g;
        wake_q15_t m = 0;
        (void)wake_rate_init(&s, 2);
        (void)wake_rate_push(&s, -3, 1, &g, &m);
        (void)wake_rate_push(&s, 0, 1, &g, &m);
        CHECK(m == -2, "-1.5 rounds away from zero to -2, got %d", m);
        (void)wake_rate_push(&s, 3, 1, &g, &m);
        (void)wake_rate_push(&s, 0, 1, &g, &m);
        CHECK(m == 2, "1.5 rounds to 2, got %d", m);
    }
}

/* A 1 kHz stream (0.5 Hz motion + 8 Hz tremor, 3 % of samples missing) through D = 10 and a level-5
 * RTP: the held prediction is, sample for sample, that of a second RTP stepped at 100 Hz with the
 * group means computed here in double (the composition wake.rate makes in Python). */
static void test_stream_at_1khz(void)
{
    static wake_q15_t taps[5 * 32];
    wake_q24_t w[5] = {(wake_q24_t)1 << 22, 0, (wake_q24_t)1 << 22, 0, (wake_q24_t)1 << 23};
    wake_rtp_t rtp, twin;
    wake_rate_t fe;
    wake_q15_t held = 0, twin_held = 0;
    long sum = 0;
    int n, i, k = 0, groups = 0, differ = 0;
    for (i = 0; i < 5 * 32; ++i) {
        taps[i] = (wake_q15_t)(1024 >> (i / 32 == 4 ? 0 : 1));   /* small smoothing rows, row sums < 2 */
    }
    CHECK(wake_rtp_init(&rtp, 5, taps, w, (wake_cov_t)1 << 20, 0, 0) == WAKE_RTP_OK, "rtp init");
    CHECK(wake_rtp_init(&twin, 5, taps, w, (wake_cov_t)1 << 20, 0, 0) == WAKE_RTP_OK, "twin init");
    CHECK(wake_rate_init(&fe, 10) == WAKE_RATE_OK, "front end init");
    for (n = 0; n < 20000; ++n) {
        const double t = n / 1000.0;
        const double x = 0.5 * sin(2.0 * 3.14159265358979 * 0.5 * t) + 0.05 * sin(2.0 * 3.14159265358979 * 8.0 * t);
        const wake_q15_t q = (wake_q15_t)lround(x * 32767.0);
        const int present = (rng_u32() % 33u) != 0u;
        wake_rate_group_t g;
        wake_q15_t m;
        (void)wake_rate_push(&fe, q, present, &g, &m);
        if (present) {
            sum += q;
            ++k;
        }
        if (g == WAKE_RATE_GROUP) {
            (void)wake_rtp_step(&rtp, m, &held);
            ++groups;
        } else if (g == WAKE_RATE_MISSING) {
            (void)wake_rtp_step_missing(&rtp, &held);
            ++groups;
        }
        if (n % 10 == 9) {
            if (k > 0) {
                (void)wake_rtp_step(&twin, (wake_q15_t)expected_mean(sum, k), &twin_held);
            } else {
                (void)wake_rtp_step_missing(&twin, &twin_held);
            }
            sum = 0;
            k = 0;
        }
        differ += (held != twin_held);
    }
    CHECK(groups == 2000, "one group per 10 samples, got %d", groups);
    CHECK(differ == 0, "%d of 20000 held predictions differ from the 100 Hz twin", differ);
    CHECK(sizeof(wake_rate_t) <= 16u, "front end state %u bytes", (unsigned)sizeof(wake_rate_t));
}

int main(void)
{
    printf("sizeof(wake_rate_t) = %u bytes\n", (unsigned)sizeof(wake_rate_t));
    test_status_codes();
    test_means_against_double();
    test_stream_at_1khz();
    printf("%d passed, %d failed\n", n_passed, n_failed);
    return n_failed ? 1 : 0;
}
