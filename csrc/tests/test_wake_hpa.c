/*
 * Host unit tests of the single-precision HPA (wake_hpa.c), built with
 * AddressSanitizer and UBSan by `make test`.  Agreement with the Python HPA
 * is tested from Python (tests/hpa/test_c_port.py); here: every status path,
 * degenerate windows give finite results, push + slices equal start + run,
 * and the RTP is never touched by a refused call.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "wake_hpa.h"
#include "wake_rtp.h"

#include "hpa_fixture.h"

static wake_hpa_t hpa, other;
static int16_t window[L];

static void init_default(wake_hpa_t *h)
{
    wake_hpa_config_t c;
    CHECK(wake_hpa_default_config(&c) == WAKE_HPA_OK);
    CHECK(wake_hpa_init(h, &c, taps, start_w) == WAKE_HPA_OK);
}

static int result_is_sane(const wake_hpa_result_t *r)
{
    int j, ok = r->flag <= WAKE_HPA_SHALLOW_VALLEY && isfinite(r->cutoff) && r->cutoff > 0.0f &&
                isfinite(r->measurement_noise) && r->measurement_noise > 0.0f && isfinite(r->fit_mse) &&
                r->fit_mse >= 0.0f;
    for (j = 0; j < J; ++j) {
        ok = ok && isfinite(r->weights[j]) && fabsf(r->weights[j]) <= (float)WAKE_HPA_WEIGHT_LIMIT;
    }
    return ok;
}

static wake_hpa_result_t analyse(const int16_t *x, uint16_t n)
{
    wake_hpa_result_t r;
    memset(&r, 0, sizeof r);
    init_default(&hpa);
    CHECK(wake_hpa_start(&hpa, x, n, n) == WAKE_HPA_OK);
    CHECK(wake_hpa_run(&hpa) == WAKE_HPA_DONE);
    CHECK(wake_hpa_take(&hpa, &r) == WAKE_HPA_OK);
    return r;
}

static void test_bad_input(void)
{
    wake_hpa_config_t c;
    wake_hpa_result_t r;
    wake_rtp_t rtp, rtp_copy;
    const int32_t w0[J] = {0, 0, 0, 0, 1 << 24};
    static int16_t taps3[3 * 8];

    CHECK(wake_hpa_default_config(NULL) == WAKE_HPA_E_NULL);
    wake_hpa_default_config(&c);
    CHECK(wake_hpa_init(NULL, &c, taps, start_w) == WAKE_HPA_E_NULL);
    CHECK(wake_hpa_init(&hpa, NULL, taps, start_w) == WAKE_HPA_E_NULL);
    CHECK(wake_hpa_init(&hpa, &c, NULL, start_w) == WAKE_HPA_E_NULL);
    CHECK(wake_hpa_init(&hpa, &c, taps, NULL) == WAKE_HPA_E_NULL);

    /* each bad field alone: refused, and the instance left unusable */
    {
        wake_hpa_config_t bad;
        int k;
        for (k = 0; k < 26; ++k) {
            bad = c;
            switch (k) {
            case 0: bad.level = 0; break;
            case 1: bad.level = WAKE_HPA_MAX_LEVEL + 1; break;
            case 2: bad.window = 63; break;
            case 3: bad.window = WAKE_HPA_MAX_WINDOW + 1; break;
            case 4: bad.fs = NAN; break;
            case 5: bad.cutoff_high = 50.0f; break;
            case 6: bad.default_cutoff = 7.0f; break;
            case 7: bad.warmup[1] = 90; break;             /* not increasing (100, 90) */
            case 8: bad.warmup[3] = 450; bad.warmup[2] = 0; break; /* a gap in the list */
            case 9: bad.min_depth_ratio = 1.5f; break;
            case 10: bad.ar_order = 250; break;            /* L <= 2p */
            case 11: bad.shallow_high = 0.25f; break;      /* below cutoff_low */
            case 12: bad.shallow_high = NAN; break;
            case 13: bad.floor_ratio = 0.0f; break;
            case 14: bad.floor_ratio = 1.0f; break;
            case 15: bad.edge_ratio = NAN; break;
            case 16: bad.rule = WAKE_HPA_RULE_FLOOR + 1; break;
            case 17: bad.clean_below = (uint16_t)(bad.window + 1u); break;
            case 18: bad.horizon = 0; break;
            case 19: bad.horizon = WAKE_HPA_MAX_AHEAD_HORIZON + 1u; break;
            case 20: bad.ridge_scale = WAKE_HPA_RIDGE_CENTRED + 1u; break;
            case 21: bad.gate_cutoff = -1.0f; break;
            case 22: bad.gate_cutoff = NAN; break;
            case 23: bad.gate_cutoff = 50.0f; break;          /* fs / 2 */
            case 24: bad.gate_cutoff = INFINITY; break;
            default: bad.rule = 7; break;
            }
            init_default(&hpa);
            CHECK(wake_hpa_init(&hpa, &bad, taps, start_w) == WAKE_HPA_E_CONFIG);
            CHECK(wake_hpa_push(&hpa, 1) == WAKE_HPA_E_UNINIT);
        }
    }
    {
        float big[J] = {0.0f, 0.0f, 0.0f, 0.0f, 33.0f};
        CHECK(wake_hpa_init(&hpa, &c, taps, big) == WAKE_HPA_E_CONFIG);
        big[4] = NAN;
        CHECK(wake_hpa_init(&hpa, &c, taps, big) == WAKE_HPA_E_CONFIG);
    }

    /* never initialised */
    memset(&other, 0, sizeof other);
    CHECK(wake_hpa_push(&other, 1) == WAKE_HPA_E_UNINIT);
    CHECK(wake_hpa_push_missing(&other) == WAKE_HPA_E_UNINIT);
    CHECK(wake_hpa_push_missing(NULL) == WAKE_HPA_E_NULL);
    CHECK(wake_hpa_slice(&other) == WAKE_HPA_E_UNINIT);
    CHECK(wake_hpa_run(&other) == WAKE_HPA_E_UNINIT);
    CHECK(wake_hpa_start(&other, window, 100, 0) == WAKE_HPA_E_UNINIT);
    CHECK(wake_hpa_take(&other, &r) == WAKE_HPA_E_UNINIT);
    CHECK(wake_hpa_slice(NULL) == WAKE_HPA_E_NULL);

    /* corrupted fields */
    init_default(&hpa);
    hpa.phase = 99;
    CHECK(wake_hpa_slice(&hpa) == WAKE_HPA_E_CORRUPT);
    init_default(&hpa);
    hpa.fill_len = 1000;
    CHECK(wake_hpa_push(&hpa, 1) == WAKE_HPA_E_CORRUPT);
    init_default(&hpa);
    hpa.fill_len = hpa.cfg.window;  /* a full buffer is swapped at once: never seen by a call (with L equal to
                                       WAKE_HPA_MAX_WINDOW the write would land past the buffers; found by Eva) */
    hpa.fill = 1;
    CHECK(wake_hpa_push(&hpa, 1) == WAKE_HPA_E_CORRUPT);
    /* a run sliding lag d's diagonal: d < 2^J (else the bank's rows i + d lie past it; found by fuzzing) */
    {
        static int16_t ramp[L];
        int k;
        for (k = 0; k < L; ++k) {
            ramp[k] = (int16_t)((k * 37) % 2001 - 1000);
        }
        init_default(&hpa);
        CHECK(wake_hpa_start(&hpa, ramp, L, L) == WAKE_HPA_OK);
        while (hpa.phase != 0u && hpa.phase != 4u && wake_hpa_slice(&hpa) == WAKE_HPA_RUNNING) {
        }
        CHECK(hpa.phase == 4u);      /* STEP_DIAG (wake_hpa.c) */
        hpa.d = (uint16_t)(1u << hpa.cfg.level);
        CHECK(wake_hpa_slice(&hpa) == WAKE_HPA_E_CORRUPT);
        /* a bin's start: bins count from m = 1 (m = 0 would divide by sin 0; found by fuzzing) */
        init_default(&hpa);
        CHECK(wake_hpa_start(&hpa, ramp, L, L) == WAKE_HPA_OK);
        while (hpa.phase != 0u && hpa.phase != 10u && wake_hpa_slice(&hpa) == WAKE_HPA_RUNNING) {
        }
        CHECK(hpa.phase == 10u);     /* STEP_BIN_START */
        hpa.m = 0;
        hpa.d = 0;
        CHECK(wake_hpa_slice(&hpa) == WAKE_HPA_E_CORRUPT);
    }
    /* any configuration field changed after init breaks the seal */
    init_default(&hpa);
    hpa.cfg.fs = 50.0f;
    CHECK(wake_hpa_slice(&hpa) == WAKE_HPA_E_CORRUPT);
    init_default(&hpa);
    hpa.cfg.warmup[3] = 7;
    CHECK(wake_hpa_push(&hpa, 1) == WAKE_HPA_E_CORRUPT);
    init_default(&hpa);
    hpa.psd_hi = 500;
    CHECK(wake_hpa_run(&hpa) == WAKE_HPA_E_CORRUPT);
    init_default(&hpa);
    hpa.base = 5;                   /* the schedule's base after the samples pushed */
    CHECK(wake_hpa_push_missing(&hpa) == WAKE_HPA_E_CORRUPT);
    init_default(&hpa);
    hpa.gap_len = 7;                /* a derived length: sealed */
    CHECK(wake_hpa_push(&hpa, 1) == WAKE_HPA_E_CORRUPT);
    /* a long gap: the points inside it are skipped, and the schedule starts again at its end */
    {
        int k;
        wake_hpa_status_t st;
        wake_hpa_config_t c3;
        /* the warm-up points 200, 300, 400 (the default also has 100) */
        CHECK(wake_hpa_default_config(&c3) == WAKE_HPA_OK);
        c3.warmup[0] = 200;
        c3.warmup[1] = 300;
        c3.warmup[2] = 400;
        c3.warmup[3] = 0;
        CHECK(wake_hpa_init(&hpa, &c3, taps, start_w) == WAKE_HPA_OK);
        for (k = 0; k < 150; ++k) {
            CHECK(wake_hpa_push(&hpa, (wake_q15_t)(k % 7)) == WAKE_HPA_OK);
        }
        for (k = 151; k <= 310; ++k) {              /* samples 151..310 missing */
            st = wake_hpa_push_missing(&hpa);
            /* point 200: 50 missing so far, not yet a long gap (the window holds them) */
            CHECK(st == (k == 200 ? WAKE_HPA_STARTED : WAKE_HPA_OK));
        }
        CHECK(hpa.gap_skipped == 1u && hpa.missing_run == 160u);   /* point 300: inside */
        CHECK(wake_hpa_push(&hpa, 3) == WAKE_HPA_OK); /* sample 311 ends the gap: base 310 */
        CHECK(hpa.base == 310u && hpa.fill_len == 1u && hpa.missing_run == 0u);
        CHECK(hpa.phase == 0u);                     /* the warm-up run on the old prefix was abandoned */
        for (k = 0; k < 198; ++k) {
            CHECK(wake_hpa_push(&hpa, (wake_q15_t)(k % 5)) == WAKE_HPA_OK);
        }
        CHECK(wake_hpa_push(&hpa, 1) == WAKE_HPA_STARTED);   /* 310 + 200: a warm-up window of 200 */
        CHECK(hpa.n == 200u && hpa.index == 510u);
    }
    /* the default schedule (100, 200, 300, 400) after a long gap: from its first point of clean_below (200)
       samples or more, the 1-s point is not run (wake.hpa.schedule.HPASchedule.point_after) */
    {
        int k;
        wake_hpa_result_t first;
        init_default(&hpa);
        for (k = 1; k <= 100; ++k) {
            CHECK(wake_hpa_push(&hpa, (wake_q15_t)(k % 7)) == (k == 100 ? WAKE_HPA_STARTED : WAKE_HPA_OK));
        }
        CHECK(hpa.n == 100u);
        CHECK(wake_hpa_run(&hpa) == WAKE_HPA_DONE && wake_hpa_take(&hpa, &first) == WAKE_HPA_OK);
        for (k = 0; k < 150; ++k) {
            CHECK(wake_hpa_push_missing(&hpa) == WAKE_HPA_OK);   /* points 200 and 300 fall inside */
        }
        for (k = 1; k < 200; ++k) {
            CHECK(wake_hpa_push(&hpa, (wake_q15_t)(k % 5)) == WAKE_HPA_OK);   /* no HPA at 250 + 100 */
        }
        CHECK(wake_hpa_push(&hpa, 1) == WAKE_HPA_STARTED);
        CHECK(hpa.n == 200u && hpa.index == 450u);   /* base 250 + 200 */
    }
    init_default(&hpa);
    hpa.cut_shallow = 600;          /* a derived bin: past the PSD the valley search keeps */
    CHECK(wake_hpa_run(&hpa) == WAKE_HPA_E_CORRUPT);
    init_default(&hpa);
    hpa.cfg.shallow_high = 5.0f;
    CHECK(wake_hpa_slice(&hpa) == WAKE_HPA_E_CORRUPT);
    init_default(&hpa);
    hpa.floor_lo = 3;               /* the floor's first bin is derived (sealed) */
    CHECK(wake_hpa_slice(&hpa) == WAKE_HPA_E_CORRUPT);
    init_default(&hpa);
    hpa.cfg.floor_ratio = 0.5f;
    CHECK(wake_hpa_slice(&hpa) == WAKE_HPA_E_CORRUPT);
    /* a loop counter out of its range in the middle of a run */
    {
        int k;
        for (k = 0; k < 4; ++k) {
            init_default(&hpa);
            CHECK(wake_hpa_start(&hpa, window, L, 0) == WAKE_HPA_OK);
            CHECK(wake_hpa_slice(&hpa) == WAKE_HPA_RUNNING);
            if (k == 0) {
                hpa.t = (uint16_t)(L + 1);
            } else if (k == 1) {
                hpa.d = 999;
            } else if (k == 2) {
                hpa.rows = 3;
            } else {
                hpa.bins = 400;
            }
            CHECK(wake_hpa_slice(&hpa) == WAKE_HPA_E_CORRUPT);
        }
    }

    /* window sizes, busy, idle */
    init_default(&hpa);
    CHECK(wake_hpa_start(&hpa, NULL, 100, 0) == WAKE_HPA_E_NULL);
    CHECK(wake_hpa_start(&hpa, window, 2 * N - 1, 0) == WAKE_HPA_E_WINDOW);
    CHECK(wake_hpa_start(&hpa, window, L + 1, 0) == WAKE_HPA_E_WINDOW);
    CHECK(wake_hpa_take(&hpa, &r) == WAKE_HPA_E_IDLE);
    CHECK(wake_hpa_take(&hpa, NULL) == WAKE_HPA_E_NULL);
    CHECK(wake_hpa_slice(&hpa) == WAKE_HPA_OK);           /* idle */
    CHECK(wake_hpa_start(&hpa, window, 100, 0) == WAKE_HPA_OK);
    CHECK(wake_hpa_start(&hpa, window, 100, 0) == WAKE_HPA_E_BUSY);

    /* apply: refused calls leave the RTP byte for byte unchanged */
    CHECK(wake_rtp_init(&rtp, J, taps, w0, 4000, 0, 0) == WAKE_RTP_OK);
    memcpy(&rtp_copy, &rtp, sizeof rtp);
    init_default(&hpa);
    CHECK(wake_hpa_apply(&hpa, &rtp) == WAKE_HPA_E_IDLE);
    CHECK(wake_hpa_apply(&hpa, NULL) == WAKE_HPA_E_NULL);
    CHECK(memcmp(&rtp, &rtp_copy, sizeof rtp) == 0);
    {
        int i;
        for (i = 0; i < L; ++i) {
            window[i] = (int16_t)(1000.0 * sin(0.02 * i) + 300.0 * sin(0.5 * i));
        }
    }
    CHECK(wake_hpa_start(&hpa, window, L, L) == WAKE_HPA_OK);
    CHECK(wake_hpa_run(&hpa) == WAKE_HPA_DONE);
    {
        wake_rtp_t rtp3, rtp3_copy;
        const int32_t w3[3] = {0, 0, 1 << 24};
        CHECK(wake_rtp_init(&rtp3, 3, taps3, w3, 4000, 0, 0) == WAKE_RTP_OK);
        memcpy(&rtp3_copy, &rtp3, sizeof rtp3);
        CHECK(wake_hpa_apply(&hpa, &rtp3) == WAKE_HPA_E_RTP);  /* level 3 != 5 */
        CHECK(memcmp(&rtp3, &rtp3_copy, sizeof rtp3) == 0);
    }
    memset(&rtp_copy, 0, sizeof rtp_copy);
    CHECK(wake_hpa_apply(&hpa, &rtp_copy) == WAKE_HPA_E_RTP);  /* uninitialised RTP */
    CHECK(wake_hpa_apply(&hpa, &rtp) == WAKE_HPA_OK);          /* the result stayed ready until now */
    CHECK(wake_hpa_apply(&hpa, &rtp) == WAKE_HPA_E_IDLE);
    CHECK(memcmp(rtp.weights, w0, sizeof w0) != 0);
}

static void test_degenerate_windows(void)
{
    int kind, i;
    uint32_t lcg = 12345u;
    for (kind = 0; kind < 8; ++kind) {
        wake_hpa_result_t r;
        for (i = 0; i < L; ++i) {
            double v;
            lcg = lcg * 1664525u + 1013904223u;
            switch (kind) {
            case 0: v = 123.0; break;                                       /* silent (constant) */
            case 1: v = 0.0; break;                                         /* zero */
            case 2: v = 8000.0 * sin(TWO_PI * 8.0 * i / 100.0); break;    /* pure tremor */
            case 3: v = 8000.0 * sin(TWO_PI * 0.3 * i / 100.0); break;    /* pure voluntary */
            case 4: v = (double)(int32_t)(lcg >> 16) - 32768.0; break;      /* white noise, full range */
            case 5: v = 90000.0 * sin(TWO_PI * 0.5 * i / 100.0); break;   /* clipped */
            case 6: v = (i & 1) ? 32767.0 : -32768.0; break;                /* Nyquist at full scale */
            default: v = 32000.0 + 20.0 * sin(TWO_PI * 6.0 * i / 100.0); break; /* huge offset */
            }
            v = v > 32767.0 ? 32767.0 : (v < -32768.0 ? -32768.0 : v);
            window[i] = (int16_t)v;
        }
        r = analyse(window, L);
        CHECK(result_is_sane(&r));
        if (kind <= 1) {
            CHECK(r.flag == WAKE_HPA_SILENT);
            CHECK(r.notes & WAKE_HPA_NOTE_WEIGHTS_KEPT);
            CHECK(memcmp(r.weights, start_w, sizeof start_w) == 0);
        }
        if (kind == 3) {
            CHECK(r.flag != WAKE_HPA_VALLEY);
        }
    }
    /* shortest window */
    {
        wake_hpa_result_t r = analyse(window, 2 * N);
        CHECK(result_is_sane(&r) && r.n == 2 * N);
    }
}

static void test_push_and_slices_equal_start_and_run(void)
{
    wake_hpa_result_t a, b;
    uint32_t i, slices = 0, starts = 0;
    int got = 0;
    init_default(&hpa);
    for (i = 0; i < 2u * L && !got; ++i) {
        const int16_t x = (int16_t)(6000.0 * sin(0.013 * i) + 900.0 * sin(0.47 * i) + (double)(i % 7) * 11.0);
        int st;
        if (i < L) {
            window[i] = x;
        }
        st = wake_hpa_push(&hpa, x);
        starts += st == WAKE_HPA_STARTED;
        st = wake_hpa_slice(&hpa);
        slices += st == WAKE_HPA_RUNNING || st == WAKE_HPA_DONE;
        if (hpa.ready && hpa.result.n == L) {
            CHECK(wake_hpa_take(&hpa, &a) == WAKE_HPA_OK);
            got = 1;
        }
    }
    CHECK(got);
    CHECK(starts >= 2u);             /* warm-up points and the full window */
    CHECK(slices >= 1u);             /* the full window ran in slices, not all at once in push */
    CHECK(hpa.overruns == 0u);
    b = analyse(window, L);
    CHECK(memcmp(a.weights, b.weights, sizeof a.weights) == 0);
    CHECK(a.cutoff == b.cutoff && a.measurement_noise == b.measurement_noise && a.flag == b.flag);
    /* one full-window HPA finishes well within L slices */
    {
        uint32_t k = 0;
        init_default(&hpa);
        CHECK(wake_hpa_start(&hpa, window, L, 0) == WAKE_HPA_OK);
        while (wake_hpa_slice(&hpa) == WAKE_HPA_RUNNING) {
            ++k;
        }
        printf("full-window HPA: %u slices (L = %d)\n", (unsigned)(k + 1u), L);
        CHECK(k + 1u < (uint32_t)L);
    }
}

/*
 * A long gap stops a run only when it reads one of the instance's window buffers (reads_buffer): a
 * warm-up run on the buffer being filled when the gap ends, a full-window run on the other buffer when
 * the next window ends inside a gap; a run on a caller's window goes on in both cases.
 */
static void test_gap_stops_only_runs_on_own_buffers(void)
{
    int k;
    wake_hpa_config_t c;
    wake_hpa_result_t r;
    CHECK(wake_hpa_default_config(&c) == WAKE_HPA_OK);
    memset(c.warmup, 0, sizeof c.warmup);          /* full windows only: the runs below are the test's */
    for (k = 0; k < L; ++k) {
        window[k] = (int16_t)(3000.0 * sin(0.05 * k) + (double)(k % 11) * 40.0);
    }
    /* the gap's end: a caller's window keeps running */
    CHECK(wake_hpa_init(&hpa, &c, taps, start_w) == WAKE_HPA_OK);
    for (k = 0; k < 10; ++k) {
        CHECK(wake_hpa_push(&hpa, (wake_q15_t)k) == WAKE_HPA_OK);
    }
    CHECK(wake_hpa_start(&hpa, window, 100, 7) == WAKE_HPA_OK);
    for (k = 0; k < 120; ++k) {                     /* a long gap (gap_len = 100) */
        CHECK(wake_hpa_push_missing(&hpa) == WAKE_HPA_OK);
    }
    CHECK(wake_hpa_push(&hpa, 5) == WAKE_HPA_OK);   /* ends the gap: the fill buffer restarts */
    CHECK(hpa.fill_len == 1u && hpa.phase != 0u && hpa.work == window && hpa.skipped == 0u);
    CHECK(wake_hpa_run(&hpa) == WAKE_HPA_DONE && wake_hpa_take(&hpa, &r) == WAKE_HPA_OK);
    CHECK(r.n == 100u && r.index == 7u && result_is_sane(&r));
    /* the gap's end: a run started by the caller on the buffer being filled is abandoned */
    CHECK(wake_hpa_init(&hpa, &c, taps, start_w) == WAKE_HPA_OK);
    for (k = 0; k < 80; ++k) {
        CHECK(wake_hpa_push(&hpa, (wake_q15_t)(k * 37 % 101)) == WAKE_HPA_OK);
    }
    CHECK(wake_hpa_start(&hpa, hpa.buf, 80, 80) == WAKE_HPA_OK);
    for (k = 0; k < 120; ++k) {
        CHECK(wake_hpa_push_missing(&hpa) == WAKE_HPA_OK);
    }
    CHECK(wake_hpa_push(&hpa, 5) == WAKE_HPA_OK);
    CHECK(hpa.phase == 0u && hpa.skipped == 1u && !hpa.ready);
    /* a window that ends inside a gap: the full-window run on the other buffer stops ... */
    CHECK(wake_hpa_init(&hpa, &c, taps, start_w) == WAKE_HPA_OK);
    for (k = 0; k < L; ++k) {
        CHECK(wake_hpa_push(&hpa, window[k]) == (k == L - 1 ? WAKE_HPA_STARTED : WAKE_HPA_OK));
    }
    CHECK(hpa.work == hpa.buf && hpa.fill == 1u);
    for (k = 0; k < L - 101; ++k) {
        CHECK(wake_hpa_push(&hpa, window[k]) == WAKE_HPA_OK);
    }
    for (k = 0; k < 101; ++k) {                     /* the window's last 101 samples: a long gap */
        CHECK(wake_hpa_push_missing(&hpa) == WAKE_HPA_OK);
    }
    CHECK(hpa.phase == 0u && hpa.overruns == 1u && hpa.gap_skipped == 1u && !hpa.ready);
    /* ... and a caller's run in its place goes on */
    CHECK(wake_hpa_init(&hpa, &c, taps, start_w) == WAKE_HPA_OK);
    for (k = 0; k < L; ++k) {
        CHECK(wake_hpa_push(&hpa, window[k]) == (k == L - 1 ? WAKE_HPA_STARTED : WAKE_HPA_OK));
    }
    CHECK(wake_hpa_run(&hpa) == WAKE_HPA_DONE && wake_hpa_take(&hpa, &r) == WAKE_HPA_OK);
    CHECK(wake_hpa_start(&hpa, window, L, 1) == WAKE_HPA_OK);
    for (k = 0; k < L - 101; ++k) {
        CHECK(wake_hpa_push(&hpa, window[k]) == WAKE_HPA_OK);
    }
    for (k = 0; k < 101; ++k) {
        CHECK(wake_hpa_push_missing(&hpa) == WAKE_HPA_OK);
    }
    CHECK(hpa.phase != 0u && hpa.work == window && hpa.overruns == 0u && hpa.gap_skipped == 1u);
    CHECK(wake_hpa_run(&hpa) == WAKE_HPA_DONE && wake_hpa_take(&hpa, &r) == WAKE_HPA_OK);
    CHECK(r.n == L && r.index == 1u && result_is_sane(&r));
}

int main(void)
{
    make_taps();
    test_bad_input();
    test_degenerate_windows();
    test_push_and_slices_equal_start_and_run();
    test_gap_stops_only_runs_on_own_buffers();
    if (failures) {
        printf("%d failure(s)\n", failures);
        return 1;
    }
    printf("test_wake_hpa: all passed\n");
    return 0;
}
