/**
 * @file hpa_harness.c
 * @brief Bare-metal harness for profiling the HPA (wake_hpa.c) in an emulator.
 *
 * The profiler (wake/firmware/hpa_cost.py) writes a window into g_window,
 * calls hpa_profile_start(n) and then wake_hpa_slice(&g_hpa) until it
 * returns WAKE_HPA_DONE, counting the instructions of every call; or
 * wake_hpa_run(&g_hpa) for one whole HPA.  The configuration is WakeConfig's
 * default (wake_hpa_default_config: 100 Hz, L = 500, J = 5, p = 17), with
 * -DHPA_PROFILE_RIDGE_SCALE=n and -DHPA_PROFILE_GATE_CUTOFF=f the ridge's scale
 * and the gate's cut-off (python -m wake.firmware.hpa_cost --ridge-scale, --gate-cutoff).
 */
#include <stddef.h>
#include <stdint.h>

#include "wake_hpa.h"
#include "wake_rtp.h"

/** The instance under test, and the RTP a result is installed in. */
wake_hpa_t g_hpa;
wake_rtp_t g_rtp;
/** Written by the profiler: the window (Q15) and the filter bank (Q15). */
int16_t g_window[WAKE_HPA_MAX_WINDOW];
int16_t g_taps[WAKE_HPA_MAX_LEVEL * WAKE_HPA_MAX_TAPS];

/** What the emulator wrapper reads (same shape as the RTP harness's block). */
__attribute__((used)) const uint32_t g_profile_info[14] = {
    UINT32_C(0x494E464F), (uint32_t)sizeof(wake_rtp_t), 0u, 0u, 0u, 0u, 0u, 0u,
    (uint32_t)WAKE_RTP_MAX_LEVEL, (uint32_t)WAKE_RTP_P_FRAC, (uint32_t)WAKE_RTP_SAMPLE_FRAC,
    (uint32_t)WAKE_RTP_TAP_FRAC, (uint32_t)WAKE_RTP_WEIGHT_FRAC, (uint32_t)WAKE_RTP_TAP_ROW_ABS_MAX,
};

/** Default configuration, start weights (0, ..., 0, 1), and an RTP with the same bank; returns a status. */
int hpa_profile_init(void)
{
    static const float w0[WAKE_HPA_MAX_LEVEL] = {0};
    float w[WAKE_HPA_MAX_LEVEL];
    int32_t wq[WAKE_HPA_MAX_LEVEL];
    wake_hpa_config_t c;
    int j;
    (void)wake_hpa_default_config(&c);
#ifdef HPA_PROFILE_RIDGE_SCALE
    c.ridge_scale = HPA_PROFILE_RIDGE_SCALE;
#endif
#ifdef HPA_PROFILE_GATE_CUTOFF
    c.gate_cutoff = HPA_PROFILE_GATE_CUTOFF;
#endif
    for (j = 0; j < WAKE_HPA_MAX_LEVEL; ++j) {
        w[j] = w0[j];
        wq[j] = 0;
    }
    w[c.level - 1] = 1.0f;
    wq[c.level - 1] = INT32_C(1) << 24;
    if (wake_rtp_init(&g_rtp, c.level, g_taps, wq, 4000, 0, 0) != WAKE_RTP_OK) {
        return -100;
    }
    return (int)wake_hpa_init(&g_hpa, &c, g_taps, w);
}

/** wake_hpa_start on the first n samples of g_window. */
int hpa_profile_start(int n)
{
    return (int)wake_hpa_start(&g_hpa, g_window, (uint16_t)n, (uint32_t)n);
}

/** The return address of every profiled call: stops the emulator. */
__attribute__((noinline, naked)) void profile_stop(void)
{
    __asm volatile("bkpt #0x42\n\tb profile_stop");
}

int main(void)
{
    return hpa_profile_init() == 0 ? 0 : 1;
}

/** Where the step number lives in the struct on this target (the profiler's per-step breakdown). */
__attribute__((used)) const uint32_t g_hpa_phase_offset = (uint32_t)offsetof(wake_hpa_t, phase);
/** Where the count of the DFT bins below f_d lives (the profiler's per-function report: the low bins). */
__attribute__((used)) const uint32_t g_hpa_bins_offset = (uint32_t)offsetof(wake_hpa_t, bins);
