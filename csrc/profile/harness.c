/**
 * @file harness.c
 * @brief Bare-metal profiling harness for the WAKE fixed-point core.
 *
 * Linked with the core (wake_rtp.c), startup.c and a linker script into a
 * minimal Cortex-M image.  It is driven in two ways:
 *
 *  - by an emulator that writes ::g_profile_config (RAM, not touched by the
 *    startup code) and then calls profile_init(), profile_set_weights() and
 *    wake_rtp_step() directly, one call per sample (wake/firmware/profile/);
 *  - stand-alone: main() runs the whole configured input through
 *    wake_rtp_step() and exits through semihosting, so that an independent
 *    emulator (QEMU) can trace it.
 *
 * Nothing here is part of the core's footprint: the profiler measures the
 * core object on its own.
 */
#include <stddef.h>
#include <stdint.h>

#include "wake_rtp.h"

/** Largest input sequence main() can run. */
#define PROFILE_MAX_SAMPLES 2048
/** g_profile_config.magic once the profiler has written it ("PRFL"). */
#define PROFILE_MAGIC UINT32_C(0x5052464C)
/** g_profile_config.update_at meaning "never". */
#define PROFILE_NEVER UINT32_C(0xFFFFFFFF)

/** Everything the profiler writes before running; little-endian, no padding. */
struct profile_config {
    uint32_t magic;                 /**< PROFILE_MAGIC */
    int32_t level;                  /**< J */
    uint32_t n_samples;             /**< samples main() runs */
    uint32_t update_at;             /**< main(): set_weights before this sample, or PROFILE_NEVER */
    int32_t r, q, p0;               /**< initial R, q, p0, Q(P_FRAC) of FS^2 */
    int32_t r2, q2;                 /**< R and q installed by profile_set_weights() */
    int32_t weights[8];             /**< initial weights, Q24 */
    int32_t weights2[8];            /**< weights installed by profile_set_weights(), Q24 */
    int16_t taps[WAKE_RTP_MAX_LEVEL * WAKE_RTP_MAX_TAPS]; /**< J x 2^J, Q15 */
    int16_t input[PROFILE_MAX_SAMPLES];                     /**< Q15 */
};

/* Written by the profiler (or a loader); the startup code leaves it alone. */
__attribute__((section(".noinit"), used)) struct profile_config g_profile_config;

/** The instance under test. */
wake_rtp_t g_state;
/** Predictions, one per input sample. */
int16_t g_output[PROFILE_MAX_SAMPLES];

/**
 * Layout facts the profiler reads from the image (in .rodata of the harness,
 * not of the core): sizeof(wake_rtp_t) on the target, and the offsets of the
 * configuration block, and the number formats of the build.
 */
__attribute__((used)) const uint32_t g_profile_info[] = {
    UINT32_C(0x494E464F),                            /* "INFO" */
    (uint32_t)sizeof(wake_rtp_t),
    (uint32_t)sizeof(struct profile_config),
    (uint32_t)offsetof(struct profile_config, weights),
    (uint32_t)offsetof(struct profile_config, weights2),
    (uint32_t)offsetof(struct profile_config, taps),
    (uint32_t)offsetof(struct profile_config, input),
    (uint32_t)PROFILE_MAX_SAMPLES,
    (uint32_t)WAKE_RTP_MAX_LEVEL,
    (uint32_t)WAKE_RTP_P_FRAC,
    (uint32_t)WAKE_RTP_SAMPLE_FRAC,
    (uint32_t)WAKE_RTP_TAP_FRAC,
    (uint32_t)WAKE_RTP_WEIGHT_FRAC,
    (uint32_t)WAKE_RTP_TAP_ROW_ABS_MAX,
};

/** wake_rtp_init from the configuration block; returns the status. */
int profile_init(void)
{
    const struct profile_config *c = &g_profile_config;
#if WAKE_RTP_VOLUNTARY_AHEAD
    /* a build with the voluntary motion ahead (wake profile --define WAKE_RTP_VOLUNTARY_AHEAD=1): the second
       weight set is w_h, installed so that every step runs its FIR */
    int st = (int)wake_rtp_init(&g_state, c->level, c->taps, c->weights, c->r, c->q, c->p0);
    return st != 0 ? st : (int)wake_rtp_set_voluntary_ahead(&g_state, c->weights2);
#else
    return (int)wake_rtp_init(&g_state, c->level, c->taps, c->weights, c->r, c->q, c->p0);
#endif
}

/** wake_rtp_set_weights with the second weight set; returns the status. */
int profile_set_weights(void)
{
    const struct profile_config *c = &g_profile_config;
    return (int)wake_rtp_set_weights(&g_state, c->weights2, c->r2, c->q2);
}

/** Return address the emulator gives wake_rtp_step(); never executed. */
__attribute__((noinline, naked)) void profile_stop(void)
{
    __asm volatile("bkpt #0x42\n\tb profile_stop");
}

/** Stand-alone run: every configured sample through wake_rtp_step(). */
int main(void)
{
    const struct profile_config *c = &g_profile_config;
    uint32_t k, n;
    if (c->magic != PROFILE_MAGIC) {
        return 1;
    }
    if (profile_init() != 0) {
        return 2;
    }
    n = c->n_samples < PROFILE_MAX_SAMPLES ? c->n_samples : PROFILE_MAX_SAMPLES;
    for (k = 0; k < n; ++k) {
        if (k == c->update_at && profile_set_weights() != 0) {
            return 3;
        }
        if (wake_rtp_step(&g_state, c->input[k], &g_output[k]) != WAKE_RTP_OK) {
            return 4;
        }
    }
    return 0;
}

/* The core calls memcpy/memset (init, reset, set_weights; never step).
 * Byte loops are enough here; the build disables loop-to-libcall rewriting. */
void *memcpy(void *dst, const void *src, size_t n)
{
    unsigned char *d = (unsigned char *)dst;
    const unsigned char *s = (const unsigned char *)src;
    while (n-- != 0u) {
        *d++ = *s++;
    }
    return dst;
}

void *memset(void *dst, int v, size_t n)
{
    unsigned char *d = (unsigned char *)dst;
    while (n-- != 0u) {
        *d++ = (unsigned char)v;
    }
    return dst;
}
