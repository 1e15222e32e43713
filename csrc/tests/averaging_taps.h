/*
 * A filter bank whose rows are plain moving averages, shared by the RTP tests that compare the C core
 * with a double twin (test_wake_rtp_ahead.c, test_wake_rtp_voluntary.c): row j averages the newest
 * 2^(j+1) of the n_taps samples (unit DC gain in Q15).
 */
#ifndef WAKE_TESTS_AVERAGING_TAPS_H
#define WAKE_TESTS_AVERAGING_TAPS_H

#include <stdint.h>

static inline void make_averaging_taps(int16_t *taps, int levels, int n_taps)
{
    int j, i;
    for (j = 0; j < levels; ++j) {
        int len = 1 << (j + 1);
        for (i = 0; i < n_taps; ++i) taps[j * n_taps + i] = 0;
        for (i = n_taps - len; i < n_taps; ++i) taps[j * n_taps + i] = (int16_t)(32768 / len - (len == 1));
    }
}

#endif /* WAKE_TESTS_AVERAGING_TAPS_H */
