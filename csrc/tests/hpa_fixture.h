/*
 * What the C HPA's host unit tests share: a failure counter with CHECK(cond),
 * the level, taps and window length they run at, and a crude but valid Q15
 * filter bank (row j averages the newest 2^(j+1) samples) with the start-up
 * weights.  Each test program includes it once, after wake_hpa.h.
 */
#ifndef WAKE_TESTS_HPA_FIXTURE_H
#define WAKE_TESTS_HPA_FIXTURE_H

#include <stdint.h>
#include <stdio.h>

static int failures;
#define CHECK(cond)                                                                   \
    do {                                                                              \
        if (!(cond)) {                                                                \
            printf("FAIL %s:%d: %s\n", __FILE__, __LINE__, #cond);                    \
            ++failures;                                                               \
        }                                                                             \
    } while (0)

#define J 5
#define N 32
#define L 500
static const double TWO_PI = 6.283185307179586;

static int16_t taps[J * N];
static const float start_w[J] = {0.0f, 0.0f, 0.0f, 0.0f, 1.0f};

static void make_taps(void)
{
    int j, i;
    for (j = 0; j < J; ++j) {
        const int width = 2 << j;
        for (i = 0; i < N; ++i) {
            taps[j * N + i] = (int16_t)(i >= N - width ? 32768 / width : 0);
        }
    }
}

#endif /* WAKE_TESTS_HPA_FIXTURE_H */
