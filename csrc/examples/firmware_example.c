/*
 * Bare-metal style use of the WAKE RTP core (no stdio, no heap).
 *
 * A sensor ISR delivers one int16 Q15 sample per period; the main loop runs
 * the predictor and hands the prediction to the actuator.  A host link
 * (e.g. a UART frame decoded elsewhere) occasionally delivers new HPA
 * weights, which are installed between two samples with
 * wake_rtp_set_weights(): the filter keeps its window, d and P.
 *
 * The taps live in flash (const).  In a real project they come from the
 * header written by wake.firmware.export.export_header(); here a level-3 Haar-like
 * bank stands in so the file builds on its own.
 */
#include <stdint.h>

#include "wake_rtp.h"

#define LEVEL 3
#define N_TAPS (1 << LEVEL)

/* Q15 taps, row j = level-(j+1) approximation at the newest sample, oldest first. */
static const int16_t taps_flash[LEVEL * N_TAPS] = {
    0, 0, 0, 0, 0, 0, 16384, 16384,
    0, 0, 0, 0, 8192, 8192, 8192, 8192,
    4096, 4096, 4096, 4096, 4096, 4096, 4096, 4096,
};

/* Shared with the ISRs. */
static volatile int16_t sensor_sample;
static volatile uint8_t sample_ready;
static volatile uint8_t sample_lost;      /* set by the ISR on a bus error */
static volatile uint8_t weights_ready;
static volatile int32_t new_weights[LEVEL];
static volatile int32_t new_r;
static volatile int32_t new_q;

/* Memory-mapped actuator register stand-in. */
static volatile int16_t actuator_command;
static volatile uint32_t error_flags;

/* Sensor ISR: one new sample per sampling period. */
void sensor_isr(int16_t raw_q15, int bus_error)
{
    sensor_sample = raw_q15;
    sample_lost = (uint8_t)(bus_error != 0);
    sample_ready = 1u;
}

/* Host-link ISR: a decoded weight frame (Q24 weights, R and q in Q(P_FRAC) of FS^2). */
void host_link_isr(const int32_t *w, int32_t r, int32_t q)
{
    int j;
    for (j = 0; j < LEVEL; ++j) {
        new_weights[j] = w[j];
    }
    new_r = r;
    new_q = q;
    weights_ready = 1u;
}

int main(void)
{
    static wake_rtp_t rtp;                 /* one channel; add more instances for more axes */
    const int32_t w0[LEVEL] = {0, 0, INT32_C(1) << 24};   /* start: coarsest approximation */
    /* R = 1e-3 FS^2, q = 1e-6 FS^2, p0 = 1e-3 FS^2 in Q32 */
    const int32_t r0 = 4294967, q0 = 4295, p0 = 4294967;

    if (wake_rtp_init(&rtp, LEVEL, taps_flash, w0, r0, q0, p0) != WAKE_RTP_OK) {
        error_flags |= 1u;
        for (;;) {
        }
    }

    for (;;) {
        int16_t prediction;
        wake_rtp_status_t st;

        if (weights_ready) {
            int32_t w[LEVEL];
            int j;
            /* copy out of the volatile mailbox; a real system masks the ISR here */
            for (j = 0; j < LEVEL; ++j) {
                w[j] = new_weights[j];
            }
            weights_ready = 0u;
            /* between two samples: glitch-free, the state is kept */
            if (wake_rtp_set_weights(&rtp, w, new_r, new_q) != WAKE_RTP_OK) {
                error_flags |= 2u;        /* rejected: the old weights stay in use */
            }
        }

        if (!sample_ready) {
            continue;                     /* a real system would sleep (WFI) here */
        }
        sample_ready = 0u;

        if (sample_lost) {
            st = wake_rtp_step_missing(&rtp, &prediction);
        } else {
            st = wake_rtp_step(&rtp, sensor_sample, &prediction);
        }
        if (st != WAKE_RTP_OK) {
            error_flags |= 4u;
            continue;
        }
        actuator_command = prediction;    /* voluntary motion predicted for the next sample */
        if (rtp.saturations != 0u) {
            error_flags |= 8u;            /* full scale too small for this signal */
        }
    }
}
