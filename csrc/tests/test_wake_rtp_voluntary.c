/*
 * Host unit tests of the voluntary motion at n + h in the fixed-point RTP core (WAKE_RTP_VOLUNTARY_AHEAD).
 *
 * The core's v_h(n) = w_h' (a + d) is compared with the literal recursion written here in double
 * precision (wake/rtp/reference.py: d and the full J x J covariance P, a = B window), fed with the same
 * Q15 samples, against an explicit tolerance; the one-step outputs must not move with w_h, bit for bit.
 * Tests may use double and stdio; the library may not.
 *
 * Build and run: make -C csrc test  (AddressSanitizer + UBSan; built with -DWAKE_RTP_VOLUNTARY_AHEAD=1).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wake_rtp.h"

#include "check.h"
#include "averaging_taps.h"

#if WAKE_RTP_VOLUNTARY_AHEAD

#define J 4
#define N (1 << J)

static const double Q15 = 32768.0;
static const double Q23 = 8388608.0;
static const double Q24 = 16777216.0;
static const double PI = 3.14159265358979323846;

/* The literal float recursion (ReferenceRTP): window, d, P; y = w'(a + d), v_h = w_h'(a + d). */
typedef struct {
    double window[N], d[J], P[J * J], w[J], wh[J], taps[J * N], r, q, y, vh;
    int primed;
} twin_t;

static void twin_init(twin_t *t, const int16_t *taps, const int32_t *w, const int32_t *wh, double r, double q,
                      double p0)
{
    int i, j;
    memset(t, 0, sizeof(*t));
    for (i = 0; i < J * N; ++i) t->taps[i] = taps[i] / Q15;
    for (j = 0; j < J; ++j) {
        t->w[j] = w[j] / Q24;
        t->wh[j] = wh[j] / Q24;
        t->P[j * J + j] = p0;
    }
    t->r = r;
    t->q = q;
    (void)i;
}

/* @p measured 0: a missing sample (the stand-in @p m enters the window; no measurement update). */
static void twin_step(twin_t *t, double m, int measured)
{
    int i, j;
    double a[J];
    if (!t->primed) {
        for (i = 0; i < N; ++i) t->window[i] = m;
        t->y = m;
        t->primed = 1;
    } else {
        double u[J], S = t->r, e = m - t->y;
        for (i = 0; i < J; ++i) {
            u[i] = 0.0;
            for (j = 0; j < J; ++j) u[i] += t->P[i * J + j] * t->w[j];
            S += t->w[i] * u[i];
        }
        for (i = 0; i < J && measured; ++i) t->d[i] += u[i] * e / S;
        for (i = 0; i < J && measured; ++i)
            for (j = 0; j < J; ++j) t->P[i * J + j] -= u[i] * u[j] / S;
        memmove(t->window, t->window + 1, (N - 1) * sizeof(double));
        t->window[N - 1] = m;
    }
    for (i = 0; i < J; ++i) t->P[i * J + i] += t->q;
    t->y = 0.0;
    t->vh = 0.0;
    for (j = 0; j < J; ++j) {
        a[j] = 0.0;
        for (i = 0; i < N; ++i) a[j] += t->taps[j * N + i] * t->window[i];
        t->y += t->w[j] * (a[j] + t->d[j]);
        t->vh += t->wh[j] * (a[j] + t->d[j]);
    }
}

static int16_t sample_at(int k)
{
    double v = 0.45 * sin(2 * PI * 0.7 * k / 100.0) + 0.15 * sin(2 * PI * 6.0 * k / 100.0 + 0.3);
    return (int16_t)lrint(v * Q15);
}

static void test_status_codes(void)
{
    static int16_t taps[J * N];
    wake_rtp_t s, before;
    const int32_t w[J] = {4194304, 4194304, 4194304, 4194304};
    int32_t wh[J] = {0, 0, 0, WAKE_RTP_WEIGHT_MAX + 1};
    wake_q23_t out = 7;
    make_averaging_taps(taps, J, N);
    memset(&s, 0, sizeof(s));
    CHECK(wake_rtp_set_voluntary_ahead(NULL, w) == WAKE_RTP_E_NULL, "null instance");
    CHECK(wake_rtp_set_voluntary_ahead(&s, w) == WAKE_RTP_E_UNINIT, "uninitialised");
    CHECK(wake_rtp_voluntary_ahead_output(&s, &out) == WAKE_RTP_E_UNINIT && out == 7, "output: uninitialised");
    CHECK(wake_rtp_init(&s, J, taps, w, 1000, 0, 0) == WAKE_RTP_OK, "init");
    CHECK(s.voluntary_ahead.set == 0u && s.voluntary_ahead.output == 0, "init: no w_h, output 0");
    memcpy(&before, &s, sizeof(s));
    CHECK(wake_rtp_set_voluntary_ahead(&s, NULL) == WAKE_RTP_E_NULL, "null w_h");
    CHECK(wake_rtp_set_voluntary_ahead(&s, wh) == WAKE_RTP_E_WEIGHTS, "w_h above 64");
    wh[3] = -WAKE_RTP_WEIGHT_MAX - 1;
    CHECK(wake_rtp_set_voluntary_ahead(&s, wh) == WAKE_RTP_E_WEIGHTS, "w_h below -64");
    CHECK(memcmp(&before, &s, sizeof(s)) == 0, "a refused w_h changes nothing");
    wh[3] = WAKE_RTP_WEIGHT_MAX;
    CHECK(wake_rtp_set_voluntary_ahead(&s, wh) == WAKE_RTP_OK && s.voluntary_ahead.set == 1u, "w_h at 64 is accepted");
    CHECK(wake_rtp_voluntary_ahead_output(&s, NULL) == WAKE_RTP_E_NULL, "output: null");
    s.voluntary_ahead.set = 2u;
    CHECK(wake_rtp_reset(&s) == WAKE_RTP_E_CORRUPT, "a corrupted set flag of w_h is caught");
    s.voluntary_ahead.set = 1u;
    s.voluntary_ahead.weights[0] = WAKE_RTP_WEIGHT_MAX + 1;
    CHECK(wake_rtp_set_weights(&s, w, 1000, 0) == WAKE_RTP_E_CORRUPT, "a corrupted w_h is caught");
}

/* Live Kalman (q, p0 > 0 when the build has it): the core against the double twin, and against itself without w_h. */
static void test_against_double(int missing)
{
    static int16_t taps[J * N];
    wake_rtp_t s, plain;
    twin_t t;
    const int32_t w[J] = {-3355443, 5033165, 6710886, 8388608};     /* -0.2, 0.3, 0.4, 0.5 */
    const int32_t wh[J] = {-1677722, 3355443, 8388608, 6710886};    /* -0.1, 0.2, 0.5, 0.4 */
    /* R = 0.0056 FS^2 (a tremor of 0.075 FS rms), q = R / 100, p0 = R: the configuration of tests/rtp/test_fixed_point.py */
    const wake_cov_t r = 24159191, q = WAKE_RTP_KALMAN ? 241592 : 0, p0 = WAKE_RTP_KALMAN ? 24159191 : 0;
    double worst = 0.0, moved = 0.0, worst_y = 0.0;
    int k, identical = 1;
    make_averaging_taps(taps, J, N);
    CHECK(wake_rtp_init(&s, J, taps, w, r, q, p0) == WAKE_RTP_OK, "init");
    CHECK(wake_rtp_init(&plain, J, taps, w, r, q, p0) == WAKE_RTP_OK, "init");
    CHECK(wake_rtp_set_voluntary_ahead(&s, wh) == WAKE_RTP_OK, "set w_h");
    twin_init(&t, taps, s.weights, s.voluntary_ahead.weights, r / 4294967296.0, q / 4294967296.0, p0 / 4294967296.0);
    for (k = 0; k < 3000; ++k) {
        wake_q15_t y, y_plain;
        wake_q23_t vh, vh_plain;
        const int gap = missing && k > 100 && k % 97 < 3;
        if (gap) {
            CHECK(wake_rtp_step_missing(&s, &y) == WAKE_RTP_OK, "missing");
            (void)wake_rtp_step_missing(&plain, &y_plain);
            twin_step(&t, (double)lrint(t.y * Q15) / Q15, 0);  /* the last prediction stands in, as in Q15 */
        } else {
            const int16_t m = sample_at(k);
            CHECK(wake_rtp_step(&s, m, &y) == WAKE_RTP_OK, "step");
            (void)wake_rtp_step(&plain, m, &y_plain);
            twin_step(&t, m / Q15, 1);
        }
        (void)wake_rtp_voluntary_ahead_output(&s, &vh);
        (void)wake_rtp_voluntary_ahead_output(&plain, &vh_plain);
        identical &= (y == y_plain) && (s.last_output == plain.last_output) && (s.z == plain.z) && (s.s == plain.s)
                     && (s.ahead.predicted == plain.ahead.predicted) && (vh_plain == plain.last_output);
        worst = fmax(worst, fabs(vh / Q23 - t.vh));
        worst_y = fmax(worst_y, fabs(s.last_output / Q23 - t.y));
        moved = fmax(moved, fabs(vh / Q23 - s.last_output / Q23));
    }
    CHECK(identical, "the one-step outputs and the Kalman state do not move with w_h; without it v_h = y");
    /* the one-step prediction's error (docs/studies/fixed_point.md) is a few Q15 LSB; v_h's is of the same size */
    CHECK(worst < 4.0 / Q15, "v_h within 4 Q15 LSB of the double twin (missing %d): %.3g FS (y: %.3g)", missing, worst, worst_y);
    CHECK(worst > 0.0, "not accidentally exact");
    CHECK(moved > 1e-3, "w_h moves v_h away from y (%.3g FS)", moved);
    CHECK(s.voluntary_ahead.saturations == 0u && s.saturations == 0u, "no saturation");
}

/* load_state restarts d_s and z_s: right after it v_h is w_h'(a + d) of the loaded window and d. */
static void test_load_state_and_reset(void)
{
    static int16_t taps[J * N];
    wake_rtp_t s;
    const int32_t w[J] = {0, 4194304, 4194304, 8388608};
    const int32_t wh[J] = {1677722, 3355443, 4194304, 8388608};
    int16_t window[N];
    wake_q23_t d[J] = {0}, vh;
    wake_cov_t P[J * J] = {0};
    wake_q15_t y;
    double want = 0.0;
    int i, j;
    make_averaging_taps(taps, J, N);
    for (i = 0; i < N; ++i) window[i] = sample_at(3 * i);
    if (WAKE_RTP_KALMAN) {
        for (j = 0; j < J; ++j) {
            d[j] = (wake_q23_t)(83886 * (j + 1) - 200000);       /* 0.01 (j + 1) - 0.024 FS */
            P[j * J + j] = 42950;
        }
    }
    CHECK(wake_rtp_init(&s, J, taps, w, 42950, WAKE_RTP_KALMAN ? 43 : 0, 0) == WAKE_RTP_OK, "init");
    CHECK(wake_rtp_set_voluntary_ahead(&s, wh) == WAKE_RTP_OK, "set w_h");
    CHECK(wake_rtp_load_state(&s, window, d, P, 0) == WAKE_RTP_OK, "load_state");
    CHECK(wake_rtp_step_missing(&s, &y) == WAKE_RTP_OK, "a missing sample predicts from the loaded state");
    (void)wake_rtp_voluntary_ahead_output(&s, &vh);
    for (j = 0; j < J; ++j) {
        double a = 0.0;
        /* the window moved by one; y(n-1) = 0 stands in for the newest sample */
        for (i = 1; i < N; ++i) a += taps[j * N + i - 1] / Q15 * window[i] / Q15;
        want += wh[j] / Q24 * (a + d[j] / Q23);
    }
    CHECK(fabs(vh / Q23 - want) < 4.0 / Q23 + N * ldexp(1.0, -WAKE_RTP_FIR_FRAC - 1),
          "v_h after load_state: %.9f, want %.9f", vh / Q23, want);
    {   /* the instance alone (wake_voluntary_ahead.h) reads what the RTP's entry reads */
        wake_q23_t alone = 1, via_rtp = 2;
        CHECK(wake_voluntary_ahead_output(&s.voluntary_ahead, &alone) == WAKE_RTP_OK
              && wake_rtp_voluntary_ahead_output(&s, &via_rtp) == WAKE_RTP_OK && alone == via_rtp && alone == vh,
              "the instance's output %ld is the RTP's %ld", (long)alone, (long)via_rtp);
        CHECK(wake_voluntary_ahead_output(NULL, &alone) == WAKE_RTP_E_NULL
              && wake_voluntary_ahead_output(&s.voluntary_ahead, NULL) == WAKE_RTP_E_NULL, "NULL is refused");
    }
    CHECK(wake_rtp_reset(&s) == WAKE_RTP_OK && s.voluntary_ahead.output == 0 && s.voluntary_ahead.set == 1u, "reset: output 0, w_h kept");
}

/* One state's outputs after a step, as a batch caller reads them per sample. */
typedef struct {
    wake_q15_t y;
    wake_q23_t predicted, command, vh;
    wake_ratio_t gate;
} outputs_t;

/*
 * wake_rtp_run_outputs against a loop of wake_rtp_step / wake_rtp_step_missing and the output reads, bit for
 * bit, state included: blocks of uneven lengths over a stream with gaps (one before the first sample), a
 * tremor-ahead predictor and w_h installed between two blocks (before it, v_h is y held), outputs left NULL.
 */
static void test_run_outputs(void)
{
    static int16_t taps[J * N];
    enum { LEN = 1500 };
    static int16_t in[LEN];
    static uint8_t missing[LEN];
    static outputs_t want[LEN];
    static wake_q15_t y[LEN];
    static wake_q23_t predicted[LEN], command[LEN], vh[LEN];
    static wake_ratio_t gate[LEN];
    const int32_t w[J] = {-3355443, 5033165, 6710886, 8388608};
    const int32_t wh[J] = {-1677722, 3355443, 8388608, 6710886};
    const int32_t c[WAKE_RTP_AHEAD_TAPS] = {201326592, -67108864, 33554432, 0, -16777216, 8388608, 0, 4194304};
    const wake_cov_t r = 24159191, q = WAKE_RTP_KALMAN ? 241592 : 0, p0 = WAKE_RTP_KALMAN ? 24159191 : 0;
    const int blocks[] = {1, 7, 64, 333, 2, 1000};
    wake_rtp_t a, b;
    int k, start, i, same = 1, gaps = 0;
    make_averaging_taps(taps, J, N);
    for (k = 0; k < LEN; ++k) {
        missing[k] = (uint8_t)(k == 0 || (k > 200 && k % 89 < 3));
        gaps += missing[k];
        in[k] = missing[k] ? (int16_t)12345 : sample_at(k);   /* not read where missing */
    }
    CHECK(wake_rtp_init(&a, J, taps, w, r, q, p0) == WAKE_RTP_OK, "init");
    memcpy(&b, &a, sizeof(a));
    CHECK(wake_rtp_run_outputs(&b, NULL, NULL, 0, NULL, NULL, NULL, NULL, NULL) == WAKE_RTP_OK, "n = 0");
    CHECK(wake_rtp_run_outputs(&b, NULL, missing, 3, y, NULL, NULL, NULL, NULL) == WAKE_RTP_E_NULL, "null input");
    CHECK(wake_rtp_run_outputs(NULL, in, missing, 3, y, NULL, NULL, NULL, NULL) == WAKE_RTP_E_NULL, "null instance");
    b.level = 0;
    CHECK(wake_rtp_run_outputs(&b, in, missing, 3, y, NULL, NULL, NULL, NULL) == WAKE_RTP_E_CORRUPT, "corrupt");
    b.level = a.level;
    CHECK(memcmp(&a, &b, sizeof(a)) == 0 && y[0] == 0, "a refused block writes nothing and changes nothing");
    memcpy(&b, &a, sizeof(a));
    for (k = 0, start = 0, i = 0; k < LEN; ++k) {
        outputs_t *o = &want[k];
        if (k == 500) {        /* between two blocks of the other instance (500 = 1 + 7 + 64 + 333 + 2 + 93) */
            CHECK(wake_rtp_set_ahead(&a, c, WAKE_RTP_GATE_ONE) == WAKE_RTP_OK, "set_ahead");
            CHECK(wake_rtp_set_voluntary_ahead(&a, wh) == WAKE_RTP_OK, "set w_h");
        }
        if (missing[k]) {
            (void)wake_rtp_step_missing(&a, &o->y);
        } else {
            (void)wake_rtp_step(&a, in[k], &o->y);
        }
        (void)wake_rtp_ahead_output(&a, &o->predicted, &o->gate, &o->command);
        (void)wake_rtp_voluntary_ahead_output(&a, &o->vh);
    }
    while (start < LEN) {
        int len = blocks[i++ % 6];
        if (start < 500 && start + len > 500) {
            len = 500 - start;
        }
        if (start + len > LEN) {
            len = LEN - start;
        }
        if (start == 500) {
            (void)wake_rtp_set_ahead(&b, c, WAKE_RTP_GATE_ONE);
            (void)wake_rtp_set_voluntary_ahead(&b, wh);
        }
        if (i % 3 == 0) {      /* a block that wants only the prediction */
            CHECK(wake_rtp_run_outputs(&b, in + start, missing + start, (size_t)len, y + start, NULL, NULL, NULL,
                                       NULL) == WAKE_RTP_OK, "block of %d", len);
            for (k = start; k < start + len; ++k) {
                predicted[k] = want[k].predicted, gate[k] = want[k].gate;
                command[k] = want[k].command, vh[k] = want[k].vh;
            }
        } else {
            CHECK(wake_rtp_run_outputs(&b, in + start, missing + start, (size_t)len, y + start, predicted + start,
                                       gate + start, command + start, vh + start) == WAKE_RTP_OK, "block of %d", len);
        }
        start += len;
    }
    for (k = 0; k < LEN; ++k) {
        same &= (y[k] == want[k].y) && (predicted[k] == want[k].predicted) && (gate[k] == want[k].gate)
                && (command[k] == want[k].command) && (vh[k] == want[k].vh);
    }
    CHECK(same, "every output of the blocks is the steps' bit for bit");
    CHECK(memcmp(&a, &b, sizeof(a)) == 0, "and so is the state");
    CHECK(gaps > 10, "the stream had gaps (%d)", gaps);
    for (k = 1, same = 1; k < 500; ++k) {
        same &= abs(want[k].vh - want[k].y * 256) <= 128 && want[k].gate == 0;   /* y(n) held, rounded to Q15 */
    }
    CHECK(same, "before w_h and a predictor: v_h is y held and the gate shut");
    CHECK(abs(want[1400].vh - want[1400].y * 256) > 4096 && want[1400].gate > 0 && want[1400].predicted != 0,
          "w_h and the tremor ahead live at the end: v_h %d, y %d, gate %d", (int)want[1400].vh,
          (int)want[1400].y * 256, (int)want[1400].gate);
}

int main(void)
{
    printf("sizeof(wake_rtp_t) = %u bytes with the voluntary motion ahead (J <= %d)\n", (unsigned)sizeof(wake_rtp_t),
           WAKE_RTP_MAX_LEVEL);
    test_status_codes();
    test_against_double(0);
    test_against_double(1);
    test_load_state_and_reset();
    test_run_outputs();
    printf("%d passed, %d failed\n", n_passed, n_failed);
    return n_failed ? 1 : 0;
}

#else /* WAKE_RTP_VOLUNTARY_AHEAD 0 */

int main(void)
{
    wake_voluntary_ahead_t v;
    wake_q23_t out = 0;
    memset(&v, 0, sizeof v);
    v.output = 1234;
    CHECK(WAKE_RTP_VOLUNTARY_AHEAD == 0, "built without the voluntary motion ahead");
    CHECK(wake_voluntary_ahead_output(&v, &out) == WAKE_RTP_OK && out == 1234,
          "the instance's own entry is there in every build");
    printf("WAKE_RTP_VOLUNTARY_AHEAD 0: nothing to test (%d passed)\n", n_passed);
    return n_failed ? 1 : 0;
}

#endif
