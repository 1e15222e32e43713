/**
 * @file fuzz_rtp_input.h
 * @brief The RTP harnesses' shared readers (fuzz_rtp.c, fuzz_rtp_split.c): weights, noise values, and the
 * Kalman accumulators kept in their ranges.
 */
#ifndef WAKE_FUZZ_RTP_INPUT_H
#define WAKE_FUZZ_RTP_INPUT_H

#include <stdint.h>

#include "wake_rtp.h"
#include "fuzz_input.h"

/** J weights: raw int32 or scaled into [-64, 64] Q24 (|raw| >> 1 <= 2^30 = 64 in Q24). */
static void read_weights(fuzz_input_t *in, wake_q24_t *w, unsigned level)
{
    unsigned j;
    const int scaled = (fuzz_u8(in) & 1u) == 0u;
    for (j = 0; j < level; ++j) {
        int32_t raw = fuzz_i32(in);
        w[j] = scaled ? raw / 2 : raw;
    }
}

/** A Q(P_FRAC) noise value: raw, or small and positive. */
static wake_cov_t read_noise(fuzz_input_t *in)
{
    const uint8_t mode = fuzz_u8(in);
    int32_t raw = fuzz_i32(in);
    return (mode & 1u) != 0u ? raw : (raw & 0xFFFFFF) + 1;
}

/**
 * The Kalman accumulators s, z and q |w|^2 are the recursion's own outputs, clamped by it every sample
 * to +-2^50, +-2^40 and [0, 2^47]; the per-sample path trusts those ranges rather than re-checking
 * them (a check costs cycles on every sample; docs/studies/verification.md, "Corrupted state"). A corrupted
 * value is brought back into its range, keeping the fuzzer's bits.
 */
static void keep_accumulators_in_range(wake_rtp_t *s)
{
    if (s->s > (INT64_C(1) << 50) || s->s < -(INT64_C(1) << 50)) {
        s->s >>= 13;
    }
    if (s->z > (INT64_C(1) << 40) || s->z < -(INT64_C(1) << 40)) {
        s->z >>= 23;
    }
    if (s->q_omega < 0 || s->q_omega > (INT64_C(1) << 47)) {
        s->q_omega = (int64_t)((uint64_t)s->q_omega >> 17);
    }
}

#endif /* WAKE_FUZZ_RTP_INPUT_H */
