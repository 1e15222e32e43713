/*
 * A stream with the Kalman inert (q = 0, p0 = 0), printed sample by sample:
 * built twice, with and without the Kalman update (WAKE_RTP_KALMAN 1 / 0),
 * the two outputs must be identical (`make test` compares them).  Built with
 * WAKE_RTP_KALMAN 0 it also checks that every Kalman setting is refused.
 *
 * Covers step, step_missing, run, set_weights (with and without new
 * weights), get_state, load_state and reset.
 */
#include <stdio.h>
#include <stdlib.h>

#include "wake_rtp.h"

#define J 4
#define N (1 << J)

static uint32_t rng_state = 12345u;

static uint32_t rng_u32(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return rng_state;
}

static int16_t rng_sample(void)
{
    return (int16_t)((int32_t)(rng_u32() >> 16) - 32768);
}

static void fail(const char *what, int status)
{
    printf("FAIL: %s (status %d)\n", what, status);
    exit(1);
}

int main(void)
{
    static int16_t taps[J * N];
    int32_t w[J], d[J], P[J * J];
    int16_t in[64], out[64], win[N];
    wake_rtp_t s;
    int i, k, st;
    for (k = 0; k < J; ++k) {
        for (i = 0; i < N; ++i) {
            taps[k * N + i] = (int16_t)((i < (N >> k)) ? (2048 << k) / 2 : -(int)(rng_u32() % 512u));
        }
        w[k] = (int32_t)(rng_u32() % (1u << 26)) - (1 << 25);
    }
    st = wake_rtp_init(&s, J, taps, w, 1 << 20, 0, 0);
    if (st != WAKE_RTP_OK) fail("init", st);
    for (k = 0; k < 300; ++k) {
        int16_t y;
        if (k % 37 == 5) {
            st = wake_rtp_step_missing(&s, &y);
        } else {
            st = wake_rtp_step(&s, (k % 53 < 3) ? 32767 : rng_sample(), &y);
        }
        if (st != WAKE_RTP_OK) fail("step", st);
        printf("%d\n", y);
        if (k % 100 == 99) {
            w[k % J] = (int32_t)(rng_u32() % (1u << 27)) - (1 << 26);
            st = wake_rtp_set_weights(&s, w, 1 << 18, 0);
            if (st != WAKE_RTP_OK) fail("set_weights", st);
        }
    }
    for (i = 0; i < 64; ++i) in[i] = rng_sample();
    st = wake_rtp_run(&s, in, out, 64);
    if (st != WAKE_RTP_OK) fail("run", st);
    for (i = 0; i < 64; ++i) printf("%d\n", out[i]);
    st = wake_rtp_get_state(&s, d, P);
    if (st != WAKE_RTP_OK) fail("get_state", st);
    for (i = 0; i < J; ++i) printf("d %ld\n", (long)d[i]);
    for (i = 0; i < J * J; ++i) printf("P %ld\n", (long)P[i]);
    for (i = 0; i < N; ++i) win[i] = rng_sample();
    st = wake_rtp_load_state(&s, win, d, P, 12345);
    if (st != WAKE_RTP_OK) fail("load_state", st);
    st = wake_rtp_run(&s, in, out, 64);
    if (st != WAKE_RTP_OK) fail("run after load_state", st);
    for (i = 0; i < 64; ++i) printf("%d\n", out[i]);
    st = wake_rtp_reset(&s);
    if (st != WAKE_RTP_OK) fail("reset", st);
    st = wake_rtp_run(&s, in, out, 64);
    if (st != WAKE_RTP_OK) fail("run after reset", st);
    for (i = 0; i < 64; ++i) printf("%d\n", out[i]);
    printf("saturations %lu\n", (unsigned long)s.saturations);
#if !WAKE_RTP_KALMAN
    /* every Kalman setting is refused, and a refused call leaves the stream as it was */
    {
        wake_rtp_t t;
        if (wake_rtp_init(&t, J, taps, w, 1 << 20, 1, 0) != WAKE_RTP_E_NO_KALMAN) fail("init with q > 0", 0);
        if (wake_rtp_init(&t, J, taps, w, 1 << 20, 0, 7) != WAKE_RTP_E_NO_KALMAN) fail("init with p0 > 0", 0);
        if (wake_rtp_set_weights(&s, w, 1 << 20, 3) != WAKE_RTP_E_NO_KALMAN) fail("set_weights with q > 0", 0);
        d[1] = 5;
        if (wake_rtp_load_state(&s, win, d, P, 0) != WAKE_RTP_E_NO_KALMAN) fail("load_state with d != 0", 0);
        d[1] = 0;
        P[J + 1] = 9;
        if (wake_rtp_load_state(&s, win, d, P, 0) != WAKE_RTP_E_NO_KALMAN) fail("load_state with P != 0", 0);
        P[J + 1] = 0;
        s.inert = 0u;   /* a corrupted flag would reach the absent update: the step refuses it */
        if (wake_rtp_step(&s, 0, out) != WAKE_RTP_E_CORRUPT) fail("step with inert cleared", 0);
        s.inert = 1u;
        if (wake_rtp_step(&s, 0, out) != WAKE_RTP_OK) fail("step after the refusals", 0);
        fprintf(stderr, "run_fixed_weights: WAKE_RTP_KALMAN 0 refuses every Kalman setting\n");
    }
#endif
    return 0;
}
