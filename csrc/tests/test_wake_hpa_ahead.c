/*
 * Host unit tests of the C HPA's tremor-ahead fit (WAKE_HPA_AHEAD 1), built with AddressSanitizer and
 * UBSan by `make test`.  Agreement with wake.ahead (fit_predictor, held_out_gain, gate_target) is tested
 * from Python (tests/hpa/test_c_ahead.py); here: the horizon is validated, the first HPA's goal is 0 and
 * a steady tremor's next one opens the gate, a window without tremor shuts it, so does one clipped at full
 * scale on more than 1 % of its samples, a silent one keeps the predictor, slices equal one run bit for bit, the Q27 / Q30 conversion, and wake_hpa_apply() installs the predictor in the RTP; wake_hpa_set_previous_ahead() gives a fresh
 * instance the previous predictor as the instance that ran it holds it.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "wake_rtp.h"
/* the fit is what this file tests: on unless a build variant turns the RTP's tremor ahead off */
#ifndef WAKE_HPA_AHEAD
#define WAKE_HPA_AHEAD WAKE_RTP_AHEAD
#endif
#include "wake_hpa.h"

#if WAKE_HPA_AHEAD

#include "hpa_fixture.h"

static wake_hpa_t hpa, other;
static int16_t stream[3 * L];

static void init_h(wake_hpa_t *h, uint16_t horizon)
{
    wake_hpa_config_t c;
    CHECK(wake_hpa_default_config(&c) == WAKE_HPA_OK);
    CHECK(c.horizon == 1u);
    c.horizon = horizon;
    CHECK(wake_hpa_init(h, &c, taps, start_w) == WAKE_HPA_OK);
}

static wake_hpa_result_t run_window(wake_hpa_t *h, const int16_t *x, uint16_t n, uint32_t index)
{
    wake_hpa_result_t r;
    memset(&r, 0, sizeof r);
    CHECK(wake_hpa_start(h, x, n, index) == WAKE_HPA_OK);
    CHECK(wake_hpa_run(h) == WAKE_HPA_DONE);
    CHECK(wake_hpa_take(h, &r) == WAKE_HPA_OK);
    return r;
}

static int ahead_is_sane(const wake_hpa_result_t *r)
{
    unsigned i;
    int ok = isfinite(r->ahead_goal) && r->ahead_goal >= 0.0f && r->ahead_goal <= 1.0f;
    for (i = 0; i < WAKE_HPA_AHEAD_TAPS; ++i) {
        ok = ok && isfinite(r->ahead[i]) && fabsf(r->ahead[i]) <= 8.0f;
    }
    return ok;
}

static void test_horizon_is_validated(void)
{
    wake_hpa_config_t c;
    CHECK(wake_hpa_default_config(&c) == WAKE_HPA_OK);
    c.horizon = 0;
    CHECK(wake_hpa_init(&hpa, &c, taps, start_w) == WAKE_HPA_E_CONFIG);
    c.horizon = WAKE_HPA_MAX_AHEAD_HORIZON + 1u;
    CHECK(wake_hpa_init(&hpa, &c, taps, start_w) == WAKE_HPA_E_CONFIG);
    c.horizon = WAKE_HPA_MAX_AHEAD_HORIZON;
    CHECK(wake_hpa_init(&hpa, &c, taps, start_w) == WAKE_HPA_OK);
}

/* wake_hpa_set_previous_ahead: checked coefficients into an idle instance; the next run scores them exactly as the
   instance that produced them would (the same goal, bit for bit); refusals change nothing. */
static void test_set_previous_ahead(void)
{
    wake_hpa_result_t first, chained, fresh;
    float c[WAKE_HPA_AHEAD_TAPS];
    unsigned i;
    for (i = 0; i < 3u * L; ++i) {
        const double t = (double)i / 100.0;
        stream[i] = (int16_t)(6000.0 * sin(TWO_PI * 0.3 * t) + 3000.0 * sin(TWO_PI * 6.0 * t));
    }
    init_h(&hpa, 5);
    first = run_window(&hpa, stream, L, L);
    chained = run_window(&hpa, stream + L, L, 2 * L);
    init_h(&other, 5);
    CHECK(wake_hpa_set_previous_ahead(&other, first.ahead, L) == WAKE_HPA_OK);
    CHECK(other.ahead.has_prev == 1u && other.ahead.prev_index == L);
    fresh = run_window(&other, stream + L, L, 2 * L);
    CHECK(chained.ahead_goal > 0.5f && fresh.ahead_goal == chained.ahead_goal);
    CHECK(memcmp(fresh.ahead, chained.ahead, sizeof fresh.ahead) == 0);
    for (i = 0; i < WAKE_HPA_AHEAD_TAPS; ++i) {
        c[i] = first.ahead[i];
    }
    c[2] = NAN;
    CHECK(wake_hpa_set_previous_ahead(&other, c, 7u) == WAKE_HPA_E_CONFIG);
    c[2] = 8.5f;
    CHECK(wake_hpa_set_previous_ahead(&other, c, 7u) == WAKE_HPA_E_CONFIG);
    CHECK(other.ahead.prev_index == 2u * L);   /* the run kept its own predictor */
    CHECK(wake_hpa_set_previous_ahead(&other, NULL, 7u) == WAKE_HPA_E_NULL);
    CHECK(wake_hpa_set_previous_ahead(NULL, first.ahead, 7u) == WAKE_HPA_E_NULL);
    CHECK(wake_hpa_start(&other, stream, L, 3 * L) == WAKE_HPA_OK);
    CHECK(wake_hpa_set_previous_ahead(&other, first.ahead, 7u) == WAKE_HPA_E_BUSY);
    CHECK(wake_hpa_run(&other) == WAKE_HPA_DONE);
}

/* A steady 6 Hz tremor on a slow movement: the first HPA has nothing to score (goal 0), the next one scores
   the first predictor on its new samples and opens the gate; the predictor is the same bits sliced or run. */
static void test_steady_tremor_opens_the_gate(void)
{
    unsigned k, h;
    for (k = 0; k < 3u * L; ++k) {
        const double t = (double)k / 100.0;
        stream[k] = (int16_t)(6000.0 * sin(TWO_PI * 0.3 * t) + 3000.0 * sin(TWO_PI * 6.0 * t));
    }
    for (h = 1; h <= 20u; h += 19u) {
        wake_hpa_result_t a, b, c;
        unsigned slices = 0;
        init_h(&hpa, (uint16_t)h);
        a = run_window(&hpa, stream, L, L);
        CHECK(ahead_is_sane(&a));
        CHECK(a.ahead_goal == 0.0f);
        {
            float mass = 0.0f;                                    /* a predictor was fitted */
            unsigned i;
            for (i = 0; i < WAKE_HPA_AHEAD_TAPS; ++i) {
                mass += fabsf(a.ahead[i]);
            }
            CHECK(mass > 0.1f);
        }
        b = run_window(&hpa, stream + L, L, 2u * L);
        CHECK(ahead_is_sane(&b));
        CHECK(b.ahead_goal > 0.8f);
        printf("steady tremor, h = %u: goal %.4f after the second HPA, c0 %.4f\n", h, (double)b.ahead_goal,
               (double)b.ahead[0]);
        /* the same two windows in slices */
        init_h(&other, (uint16_t)h);
        (void)run_window(&other, stream, L, L);
        CHECK(wake_hpa_start(&other, stream + L, L, 2u * L) == WAKE_HPA_OK);
        while (wake_hpa_slice(&other) == WAKE_HPA_RUNNING) {
            ++slices;
        }
        CHECK(wake_hpa_take(&other, &c) == WAKE_HPA_OK);
        CHECK(memcmp(c.ahead, b.ahead, sizeof c.ahead) == 0 && c.ahead_goal == b.ahead_goal);
        CHECK(memcmp(c.weights, b.weights, sizeof c.weights) == 0);
        printf("full-window HPA with the tremor ahead: %u slices (L = %d)\n", slices + 1u, L);
    }
}

/* No tremor peak (a slow movement alone) shuts the gate; a silent window shuts it and keeps the predictor
   it had (here the no-peak window's); a window too short for two rows at h = 32 gives zeros. */
static void test_no_tremor_shuts_the_gate(void)
{
    wake_hpa_result_t a, b;
    unsigned k;
    for (k = 0; k < 2u * L; ++k) {
        stream[k] = (int16_t)(6000.0 * sin(TWO_PI * 0.3 * (double)k / 100.0) + 3000.0 * sin(TWO_PI * 6.0 * k / 100.0));
    }
    for (k = L; k < 2u * L; ++k) {
        stream[k] = (int16_t)(9000.0 * sin(TWO_PI * 0.3 * (double)k / 100.0));
    }
    init_h(&hpa, 1);
    (void)run_window(&hpa, stream, L, L);
    a = run_window(&hpa, stream + L, L, 2u * L);
    CHECK(ahead_is_sane(&a));
    CHECK(a.flag == WAKE_HPA_NO_TREMOR_PEAK);
    CHECK(a.ahead_goal == 0.0f);
    for (k = 0; k < L; ++k) {
        stream[k] = 1234;
    }
    b = run_window(&hpa, stream, L, 3u * L);
    CHECK(b.flag == WAKE_HPA_SILENT && b.ahead_goal == 0.0f);
    CHECK(memcmp(b.ahead, a.ahead, sizeof b.ahead) == 0);
    for (k = 0; k < 2u * N; ++k) {
        stream[k] = (int16_t)(3000.0 * sin(TWO_PI * 6.0 * k / 100.0));
    }
    init_h(&hpa, (uint16_t)WAKE_HPA_MAX_AHEAD_HORIZON);
    b = run_window(&hpa, stream, 2u * N, 2u * N);
    for (k = 0; k < WAKE_HPA_AHEAD_TAPS; ++k) {
        CHECK(b.ahead[k] == 0.0f);
    }
}

/* The steady tremor of test_steady_tremor_opens_the_gate, scaled by @p gain and saturated to int16. */
static void scaled_tremor(double gain)
{
    unsigned k;
    for (k = 0; k < 3u * L; ++k) {
        const double t = (double)k / 100.0;
        const double v = gain * (6000.0 * sin(TWO_PI * 0.3 * t) + 3000.0 * sin(TWO_PI * 6.0 * t));
        stream[k] = (int16_t)(v > 32767.0 ? 32767.0 : (v < -32768.0 ? -32768.0 : v));
    }
}

/* wake.ahead.installed_goal: a window with more than n / 100 samples at full scale shuts the gate (goal 0,
   WAKE_HPA_NOTE_FULL_SCALE); the same window unclipped opens it; exactly n / 100 does not shut it. */
static void test_clipped_window_shuts_the_gate(void)
{
    wake_hpa_result_t a, b;
    unsigned k, rail = 0;
    scaled_tremor(3.0);                                   /* peak about 27,000: nothing at full scale */
    init_h(&hpa, 1);
    (void)run_window(&hpa, stream, L, L);
    a = run_window(&hpa, stream + L, L, 2u * L);
    CHECK(a.ahead_goal > 0.8f && (a.notes & WAKE_HPA_NOTE_FULL_SCALE) == 0u);
    /* L / 100 = 5 samples of the second window on the rail: not more than 1 %, the gate stays open */
    for (k = L; k < 2u * L && rail < L / WAKE_HPA_GLITCH_DIVISOR; k += 37u, ++rail) {
        stream[k] = (rail & 1u) != 0u ? INT16_MIN : INT16_MAX;
    }
    init_h(&hpa, 1);
    (void)run_window(&hpa, stream, L, L);
    b = run_window(&hpa, stream + L, L, 2u * L);
    CHECK(b.ahead_goal > 0.5f && (b.notes & WAKE_HPA_NOTE_FULL_SCALE) == 0u);
    stream[2u * L - 1u] = INT16_MAX;                      /* one more: 6 of 500 */
    init_h(&hpa, 1);
    (void)run_window(&hpa, stream, L, L);
    b = run_window(&hpa, stream + L, L, 2u * L);
    CHECK(b.ahead_goal == 0.0f && (b.notes & WAKE_HPA_NOTE_FULL_SCALE) != 0u);
    /* the same tremor 4 times larger: its peaks saturate on far more than 1 % of the window */
    scaled_tremor(4.0);
    init_h(&hpa, 1);
    (void)run_window(&hpa, stream, L, L);
    b = run_window(&hpa, stream + L, L, 2u * L);
    CHECK(ahead_is_sane(&b));
    CHECK(b.ahead_goal == 0.0f && (b.notes & WAKE_HPA_NOTE_FULL_SCALE) != 0u);
    printf("clipped window: goal %.4f unclipped, %.4f clipped\n", (double)a.ahead_goal, (double)b.ahead_goal);
}

/* A silent window between two windows of the same tremor: the gate shuts at the silent HPA and reopens at
   the next one, which scores the predictor kept through the silent window. */
static void test_silent_window_keeps_the_predictor(void)
{
    wake_hpa_result_t a, s, b;
    unsigned k;
    scaled_tremor(1.0);
    for (k = L; k < 2u * L; ++k) {
        stream[k] = -77;
    }
    init_h(&hpa, 3);
    a = run_window(&hpa, stream, L, L);
    s = run_window(&hpa, stream + L, L, 2u * L);
    CHECK(s.flag == WAKE_HPA_SILENT && s.ahead_goal == 0.0f);
    CHECK(memcmp(s.ahead, a.ahead, sizeof s.ahead) == 0);
    b = run_window(&hpa, stream + 2u * L, L, 3u * L);
    CHECK(ahead_is_sane(&b) && b.ahead_goal > 0.8f);
    printf("after a silent window: goal %.4f at the next HPA\n", (double)b.ahead_goal);
}

/* Found by fuzz_hpa_ahead: a run started while an earlier result was not taken rewrote the result's weights
   and flag when its fit ended but its predictor and goal only when the tremor ahead's steps ended, many
   slices later; a take or an apply in between handed out the mix.  Now whatever is taken at any slice of
   the second run is the earlier result whole, or nothing until the second is published. */
static void test_a_result_is_never_taken_half_written(void)
{
    static wake_hpa_t copy;
    wake_hpa_result_t first, got, last;
    unsigned k, taken_first = 0, refused = 0;
    scaled_tremor(1.0);
    for (k = 2u * L; k < 3u * L; ++k) {                   /* the third window: no tremor peak */
        stream[k] = (int16_t)(9000.0 * sin(TWO_PI * 0.3 * (double)k / 100.0));
    }
    init_h(&hpa, 1);
    (void)run_window(&hpa, stream, L, L);
    CHECK(wake_hpa_start(&hpa, stream + L, L, 2u * L) == WAKE_HPA_OK);
    CHECK(wake_hpa_run(&hpa) == WAKE_HPA_DONE);           /* the second result, left ready, not taken */
    first = hpa.result;
    CHECK(first.ahead_goal > 0.5f);
    CHECK(wake_hpa_start(&hpa, stream + 2u * L, L, 3u * L) == WAKE_HPA_OK);
    while (wake_hpa_slice(&hpa) == WAKE_HPA_RUNNING) {
        memcpy(&copy, &hpa, sizeof hpa);
        if (wake_hpa_take(&copy, &got) == WAKE_HPA_OK) {
            ++taken_first;
            CHECK(memcmp(&got, &first, sizeof got) == 0);
        } else {
            ++refused;
        }
    }
    CHECK(wake_hpa_take(&hpa, &last) == WAKE_HPA_OK);
    CHECK(last.flag == WAKE_HPA_NO_TREMOR_PEAK && last.ahead_goal == 0.0f);
    CHECK(taken_first > 0u && refused > 0u);
    printf("a third run over the second's untaken result: the second taken whole at %u slices, nothing at %u\n",
           taken_first, refused);
}

static void test_conversion_and_apply(void)
{
    wake_hpa_result_t r;
    int32_t c[WAKE_HPA_AHEAD_TAPS];
    wake_ratio_t goal;
    wake_rtp_t rtp;
    wake_q24_t w0[J] = {0, 0, 0, 0, 1 << 24};
    unsigned k;
    memset(&r, 0, sizeof r);
    for (k = 0; k < WAKE_HPA_AHEAD_TAPS; ++k) {
        r.ahead[k] = (float)k - 3.5f;
    }
    r.ahead[0] = 9.0f;          /* beyond the clip: clamped to 8 */
    r.ahead[1] = NAN;           /* NaN: the lower bound */
    r.ahead_goal = 0.25f;
    CHECK(wake_hpa_ahead_to_rtp(NULL, c, &goal) == WAKE_HPA_E_NULL);
    CHECK(wake_hpa_ahead_to_rtp(&r, NULL, &goal) == WAKE_HPA_E_NULL);
    CHECK(wake_hpa_ahead_to_rtp(&r, c, NULL) == WAKE_HPA_E_NULL);
    CHECK(wake_hpa_ahead_to_rtp(&r, c, &goal) == WAKE_HPA_OK);
    CHECK(c[0] == INT32_C(1) << 30 && c[1] == -(INT32_C(1) << 30));
    CHECK(c[2] == -(INT32_C(3) << 26) && c[7] == INT32_C(7) << 26);
    CHECK(goal == INT32_C(1) << 28);
    /* apply: the RTP gets the converted predictor and goal */
    CHECK(wake_rtp_init(&rtp, J, taps, w0, 4000, 0, 0) == WAKE_RTP_OK);
    for (k = 0; k < 2u * L; ++k) {
        stream[k] = (int16_t)(6000.0 * sin(TWO_PI * 0.3 * k / 100.0) + 3000.0 * sin(TWO_PI * 6.0 * k / 100.0));
    }
    init_h(&hpa, 5);
    (void)run_window(&hpa, stream, L, L);
    CHECK(wake_hpa_start(&hpa, stream + L, L, 2u * L) == WAKE_HPA_OK);
    CHECK(wake_hpa_run(&hpa) == WAKE_HPA_DONE);
    CHECK(wake_hpa_ahead_to_rtp(&hpa.result, c, &goal) == WAKE_HPA_OK);
    CHECK(goal > 0);
    CHECK(wake_hpa_apply(&hpa, &rtp) == WAKE_HPA_OK);
    CHECK(memcmp(rtp.ahead.coef, c, sizeof c) == 0 && rtp.ahead.goal == goal);
}

int main(void)
{
    make_taps();
    test_horizon_is_validated();
    test_set_previous_ahead();
    test_steady_tremor_opens_the_gate();
    test_no_tremor_shuts_the_gate();
    test_clipped_window_shuts_the_gate();
    test_silent_window_keeps_the_predictor();
    test_a_result_is_never_taken_half_written();
    test_conversion_and_apply();
    printf("%s (%d failures)\n", failures ? "FAILED" : "OK", failures);
    return failures ? 1 : 0;
}
#else
int main(void)
{
    printf("FAILED: built without WAKE_HPA_AHEAD, nothing tested\n");
    return 1;
}
#endif
