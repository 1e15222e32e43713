/*
 * Host unit tests of the tremor ahead in the fixed-point RTP core (WAKE_RTP_AHEAD).
 *
 * The core's predictor and gate are compared with the same per-sample rule
 * written here in double precision (wake/ahead.py, AheadStep), fed with the
 * core's own voluntary predictions y(n-1) (so the difference is the ahead's
 * arithmetic alone), against an explicit error bound.  Tests may use double
 * and stdio; the library may not.
 *
 * Build and run: make -C csrc test  (AddressSanitizer + UBSan).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wake_rtp.h"

#include "check.h"
#include "averaging_taps.h"

#define J 4
#define N (1 << J)
#define TAPS WAKE_RTP_AHEAD_TAPS

#if WAKE_RTP_AHEAD

static const double Q15 = 32768.0;
static const double Q27 = 134217728.0;
static const double Q30 = 1073741824.0;
static const double PI = 3.14159265358979323846;

static uint32_t rng_state = 2463534242u;
static uint32_t rng_u32(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 17;
    rng_state ^= rng_state << 5;
    return rng_state;
}

static double rng_uniform(double lo, double hi)
{
    return lo + (hi - lo) * (double)rng_u32() / 4294967296.0;
}

/* The float twin of the per-sample rule (wake.ahead.AheadStep). */
typedef struct {
    double c[TAPS], line[TAPS], goal, gate, alpha;
} ref_ahead_t;

static void ref_step(ref_ahead_t *r, double e, double *predicted, double *command)
{
    int i;
    double p = 0.0;
    for (i = TAPS - 1; i > 0; --i) r->line[i] = r->line[i - 1];
    r->line[0] = e;
    for (i = 0; i < TAPS; ++i) p += r->c[i] * r->line[i];
    r->gate += (r->goal - r->gate) * r->alpha;
    *predicted = p;
    *command = r->gate * p;
}

/* A tremor-like test signal in Q15 of FS: a slow wave plus a 6 Hz tremor of amplitude @p tremor
 * (fs = 100 Hz), plus a little noise. */
static int16_t signal_at(int n, double tremor)
{
    double v = 0.4 * sin(2 * PI * 0.3 * n / 100.0) + tremor * sin(2 * PI * 6.0 * n / 100.0)
               + rng_uniform(-0.002, 0.002);
    return (int16_t)lround(v * 32767.0);
}

static void test_status_codes(void)
{
    static int16_t taps[J * N];
    const int32_t w[J] = {0, 0, 0, 1 << 24};
    int32_t c[TAPS] = {0};
    int16_t line[TAPS];
    int32_t g, p, cmd;
    wake_rtp_t s;
    make_averaging_taps(taps, J, N);
    CHECK(wake_rtp_set_ahead(NULL, c, 0) == WAKE_RTP_E_NULL, "null instance");
    memset(&s, 0, sizeof(s));
    CHECK(wake_rtp_set_ahead(&s, c, 0) == WAKE_RTP_E_UNINIT, "uninitialised");
    CHECK(wake_rtp_init(&s, J, taps, w, 1000, 0, 0) == WAKE_RTP_OK, "init");
    CHECK(s.ahead.ramp == WAKE_RTP_AHEAD_RAMP_DEFAULT && s.ahead.gate == 0 && s.ahead.goal == 0, "init: ramp 1/30, shut");
    CHECK(wake_rtp_set_ahead(&s, NULL, 0) == WAKE_RTP_E_NULL, "null coefficients");
    c[3] = WAKE_RTP_AHEAD_COEF_MAX;
    c[5] = -WAKE_RTP_AHEAD_COEF_MAX;
    CHECK(wake_rtp_set_ahead(&s, c, WAKE_RTP_GATE_ONE) == WAKE_RTP_OK, "+-8 and goal 1 accepted");
    c[3] = WAKE_RTP_AHEAD_COEF_MAX + 1;
    CHECK(wake_rtp_set_ahead(&s, c, 0) == WAKE_RTP_E_AHEAD, "coefficient > 8");
    c[3] = -WAKE_RTP_AHEAD_COEF_MAX - 1;
    CHECK(wake_rtp_set_ahead(&s, c, 0) == WAKE_RTP_E_AHEAD, "coefficient < -8");
    c[3] = 0;
    CHECK(wake_rtp_set_ahead(&s, c, -1) == WAKE_RTP_E_AHEAD, "goal < 0");
    CHECK(wake_rtp_set_ahead(&s, c, WAKE_RTP_GATE_ONE + 1) == WAKE_RTP_E_AHEAD, "goal > 1");
    CHECK(s.ahead.coef[5] == -WAKE_RTP_AHEAD_COEF_MAX && s.ahead.goal == WAKE_RTP_GATE_ONE, "a refused call changes nothing");
    CHECK(wake_rtp_set_ahead_ramp(&s, 0) == WAKE_RTP_E_AHEAD, "ramp 0");
    CHECK(wake_rtp_set_ahead_ramp(&s, WAKE_RTP_GATE_ONE + 1) == WAKE_RTP_E_AHEAD, "ramp > 1");
    CHECK(wake_rtp_set_ahead_ramp(&s, WAKE_RTP_GATE_ONE) == WAKE_RTP_OK, "ramp 1");
    CHECK(wake_rtp_ahead_output(NULL, &p, &g, &cmd) == WAKE_RTP_E_NULL, "output: null instance");
    CHECK(wake_rtp_ahead_output(&s, NULL, NULL, NULL) == WAKE_RTP_OK, "output: every out pointer optional");
    CHECK(wake_rtp_load_ahead_state(&s, NULL, 0) == WAKE_RTP_E_NULL, "load: null line");
    memset(line, 0, sizeof(line));
    CHECK(wake_rtp_load_ahead_state(&s, line, WAKE_RTP_GATE_ONE + 1) == WAKE_RTP_E_AHEAD, "load: gate > 1");
    CHECK(wake_rtp_get_ahead_state(&s, NULL) == WAKE_RTP_E_NULL, "get: null line");
}

/* The core against the double twin over a stream with a gate that opens, changes goal and shuts,
 * with the Kalman inert and active.  Bound (units of Q15 LSB):
 *   P:       the estimate rounded to Q15 (1/2 LSB each, times sum |c|) + P rounded once to Q23 (1/512)
 *            + the coefficients rounded to Q27 (1/2 2^-27 each, times |e| <= 2^15 LSB: < 2^-10)
 *   gate:    the ramp rounded to Q30 per step: within 1/(2 alpha) + 1 units of Q30 of the twin's
 *            path, plus alpha's own rounding (1/2 unit of Q30 relative, over a few hundred steps)
 *   command: g |P err| + |P| |g err| + 1/2 (rounding). */
static void test_against_double(int live)
{
    static int16_t taps[J * N];
    const int32_t w[J] = {(int32_t)(0.2 * 16777216.0), (int32_t)(-0.1 * 16777216.0),
                          (int32_t)(0.3 * 16777216.0), (int32_t)(0.6 * 16777216.0)};
    wake_rtp_t s;
    ref_ahead_t r;
    int32_t c_q[TAPS];
    double sum_c = 0.0, worst_p = 0.0, worst_cmd = 0.0, worst_gate = 0.0, bound_p, bound_gate;
    int n, i;
    make_averaging_taps(taps, J, N);
    CHECK(wake_rtp_init(&s, J, taps, w, 40000, live ? 30 : 0, live ? 40000 : 0) == WAKE_RTP_OK, "init");
    memset(&r, 0, sizeof(r));
    r.alpha = WAKE_RTP_AHEAD_RAMP_DEFAULT / Q30;
    /* a 5-step predictor of a 6 Hz sine at 100 Hz, with both signs and sum |c| about 4 */
    for (i = 0; i < TAPS; ++i) {
        double v = (i < 2) ? (i == 0 ? 1.6 : -0.9) : rng_uniform(-0.4, 0.4);
        c_q[i] = (int32_t)lround(v * Q27);
        r.c[i] = c_q[i] / Q27;
        sum_c += fabs(r.c[i]);
    }
    CHECK(wake_rtp_set_ahead(&s, c_q, 0) == WAKE_RTP_OK, "the predictor from the start, the gate shut");
    bound_p = 0.5 * sum_c + 1.0 / 512.0 + 1e-3;
    bound_gate = 1.0 / (2.0 * r.alpha) + 2.0 + 400.0 * 0.5;     /* units of Q30 */
    for (n = 0; n < 1200; ++n) {
        int16_t m = signal_at(n, 0.1), y;
        int32_t g, p, cmd;
        double e, p_ref, cmd_ref;
        if (n == 100) {
            r.goal = 0.8;
            CHECK(wake_rtp_set_ahead(&s, c_q, (int32_t)lround(0.8 * Q30)) == WAKE_RTP_OK, "set_ahead");
        } else if (n == 500) {
            r.goal = 0.35;
            CHECK(wake_rtp_set_ahead(&s, c_q, (int32_t)lround(0.35 * Q30)) == WAKE_RTP_OK, "new goal");
        } else if (n == 900) {
            r.goal = 0.0;
            CHECK(wake_rtp_set_ahead(&s, c_q, 0) == WAKE_RTP_OK, "shut");
        }
        /* e(n) = m(n) - y(n-1), the core's own y(n-1) in Q23; 0 for the first sample */
        e = (n == 0) ? 0.0 : m / Q15 - s.last_output / 8388608.0;
        CHECK(wake_rtp_step(&s, m, &y) == WAKE_RTP_OK, "step");
        ref_step(&r, e, &p_ref, &cmd_ref);
        CHECK(wake_rtp_ahead_output(&s, &p, &g, &cmd) == WAKE_RTP_OK, "output");
        worst_p = fmax(worst_p, fabs(p / 256.0 - p_ref * Q15));         /* Q23 -> Q15 LSB */
        worst_gate = fmax(worst_gate, fabs(g - r.gate * Q30));
        worst_cmd = fmax(worst_cmd, fabs(cmd / 256.0 - cmd_ref * Q15));
        CHECK(g >= 0 && g <= WAKE_RTP_GATE_ONE, "gate in [0, 1] (%ld)", (long)g);
    }
    printf("ahead vs double (%s Kalman): max |P err| %.3f LSB (bound %.3f), |gate err| %.1f Q30 units (bound %.1f), "
           "|command err| %.3f LSB\n", live ? "active" : "inert", worst_p, bound_p, worst_gate, bound_gate, worst_cmd);
    CHECK(worst_p <= bound_p, "P within its bound: %.3f > %.3f LSB", worst_p, bound_p);
    CHECK(worst_gate <= bound_gate, "gate within its bound: %.1f > %.1f", worst_gate, bound_gate);
    CHECK(worst_cmd <= bound_p + 32768.0 * bound_gate / Q30 + 1.0 / 512.0, "command within its bound: %.3f LSB",
          worst_cmd);
    CHECK(s.ahead.saturations == 0u, "no saturation in range (%u)", (unsigned)s.ahead.saturations);
    /* 300 samples after the goal went to 0 from 0.35: 0.35 (29/30)^300 = 1.4e-5 */
    CHECK(s.ahead.gate < (int32_t)(2e-5 * Q30), "the gate closes (%ld)", (long)s.ahead.gate);
}

/* A missing sample enters 0 and shuts the gate; reset zeroes; the voluntary output is the build's
 * without the ahead (same predictions as an instance whose ahead is never set). */
static void test_missing_reset_and_voluntary(void)
{
    static int16_t taps[J * N];
    const int32_t w[J] = {0, 1 << 23, 0, 1 << 23};
    int32_t c[TAPS];
    int16_t line[TAPS], y1, y2;
    int32_t g, p, cmd;
    wake_rtp_t a, b;
    int n, i;
    make_averaging_taps(taps, J, N);
    for (i = 0; i < TAPS; ++i) c[i] = (int32_t)((i + 1) << 24);
    CHECK(wake_rtp_init(&a, J, taps, w, 1000, 5, 1000) == WAKE_RTP_OK, "init a");
    CHECK(wake_rtp_init(&b, J, taps, w, 1000, 5, 1000) == WAKE_RTP_OK, "init b");
    CHECK(wake_rtp_set_ahead(&a, c, WAKE_RTP_GATE_ONE) == WAKE_RTP_OK, "set_ahead a");
    for (n = 0; n < 200; ++n) {
        int16_t m = signal_at(n, 0.2);
        if (n % 37 == 5) {
            CHECK(wake_rtp_step_missing(&a, &y1) == WAKE_RTP_OK && wake_rtp_step_missing(&b, &y2) == WAKE_RTP_OK, "missing");
            CHECK(a.ahead.goal == 0, "a missing sample sets the goal to 0");
            CHECK(wake_rtp_get_ahead_state(&a, line) == WAKE_RTP_OK && line[0] == 0, "and enters estimate 0");
            CHECK(wake_rtp_set_ahead(&a, c, WAKE_RTP_GATE_ONE) == WAKE_RTP_OK, "re-open");
        } else {
            CHECK(wake_rtp_step(&a, m, &y1) == WAKE_RTP_OK && wake_rtp_step(&b, m, &y2) == WAKE_RTP_OK, "step");
        }
        CHECK(y1 == y2 && a.last_output == b.last_output, "voluntary output untouched by the ahead (n = %d)", n);
    }
    CHECK(a.saturations == b.saturations, "saturation counts of the voluntary part untouched");
    CHECK(wake_rtp_ahead_output(&a, &p, &g, &cmd) == WAKE_RTP_OK && g > 0 && p != 0, "the ahead ran");
    CHECK(wake_rtp_reset(&a) == WAKE_RTP_OK, "reset");
    CHECK(wake_rtp_ahead_output(&a, &p, &g, &cmd) == WAKE_RTP_OK && p == 0 && g == 0 && cmd == 0, "reset: outputs 0");
    CHECK(wake_rtp_get_ahead_state(&a, line) == WAKE_RTP_OK, "get");
    for (i = 0; i < TAPS; ++i) CHECK(line[i] == 0, "reset: delay line zeroed");
    CHECK(a.ahead.goal == 0 && a.ahead.coef[2] == c[2], "reset: goal 0, coefficients kept");
    /* the first sample after a reset has no prediction before it: estimate 0 */
    CHECK(wake_rtp_step(&a, 12000, &y1) == WAKE_RTP_OK && wake_rtp_get_ahead_state(&a, line) == WAKE_RTP_OK
          && line[0] == 0, "first sample: estimate 0");
    /* a missing sample before the first one: estimate 0, goal 0 */
    CHECK(wake_rtp_reset(&b) == WAKE_RTP_OK && wake_rtp_set_ahead(&b, c, WAKE_RTP_GATE_ONE) == WAKE_RTP_OK, "b");
    CHECK(wake_rtp_step_missing(&b, &y2) == WAKE_RTP_OK && y2 == 0 && b.ahead.goal == 0, "unprimed missing: goal 0");
}

/* load_ahead_state / get_ahead_state round trip, and the carry-over of the line into the next P. */
static void test_state_round_trip(void)
{
    static int16_t taps[J * N];
    const int32_t w[J] = {0, 0, 0, 1 << 24};
    int32_t c[TAPS] = {0};
    int16_t line[TAPS], back[TAPS], y;
    int32_t p;
    wake_rtp_t s;
    int i;
    make_averaging_taps(taps, J, N);
    CHECK(wake_rtp_init(&s, J, taps, w, 1000, 0, 0) == WAKE_RTP_OK, "init");
    for (i = 0; i < TAPS; ++i) line[i] = (int16_t)(1000 * (i + 1));
    CHECK(wake_rtp_load_ahead_state(&s, line, WAKE_RTP_GATE_ONE / 2) == WAKE_RTP_OK, "load");
    CHECK(wake_rtp_get_ahead_state(&s, back) == WAKE_RTP_OK && memcmp(line, back, sizeof(line)) == 0, "round trip");
    CHECK(s.ahead.gate == WAKE_RTP_GATE_ONE / 2, "gate loaded");
    c[1] = 1 << 27;                                         /* P = the estimate one step older */
    CHECK(wake_rtp_set_ahead(&s, c, WAKE_RTP_GATE_ONE / 2) == WAKE_RTP_OK, "set");
    CHECK(wake_rtp_step(&s, 0, &y) == WAKE_RTP_OK, "step");   /* first sample: estimate 0 enters */
    CHECK(wake_rtp_ahead_output(&s, &p, NULL, NULL) == WAKE_RTP_OK && p == 1000 * 256, "P reads the loaded line (%ld)", (long)p);
}

/* Corrupted ahead fields: the index is refused by the step; any other value runs UBSan-clean
 * and the cold functions refuse it. */
static void test_corrupted(void)
{
    static int16_t taps[J * N];
    const int32_t w[J] = {0, 0, 0, 1 << 24};
    int32_t c[TAPS];
    int16_t y;
    wake_rtp_t s;
    int i;
    make_averaging_taps(taps, J, N);
    for (i = 0; i < TAPS; ++i) c[i] = (i & 1) ? -WAKE_RTP_AHEAD_COEF_MAX : WAKE_RTP_AHEAD_COEF_MAX;
    CHECK(wake_rtp_init(&s, J, taps, w, 1000, 0, 0) == WAKE_RTP_OK, "init");
    CHECK(wake_rtp_set_ahead(&s, c, WAKE_RTP_GATE_ONE) == WAKE_RTP_OK, "set");
    s.ahead.head = 8u;
    CHECK(wake_rtp_step(&s, 100, &y) == WAKE_RTP_E_CORRUPT, "a line index out of range is refused");
    s.ahead.head = 3u;
    for (i = 0; i < TAPS; ++i) s.ahead.coef[i] = (i & 1) ? INT32_MIN : INT32_MAX;
    s.ahead.gate = INT32_MIN;
    s.ahead.goal = INT32_MAX;
    s.ahead.ramp = INT32_MIN;
    for (i = 0; i < 20; ++i) {
        CHECK(wake_rtp_step(&s, (int16_t)((i & 1) ? 32767 : -32768), &y) == WAKE_RTP_OK, "corrupted values run");
        CHECK(s.ahead.gate >= 0, "the gate stays non-negative (%ld)", (long)s.ahead.gate);
    }
    CHECK(s.ahead.saturations > 0u, "saturations counted");
    CHECK(wake_rtp_set_weights(&s, w, 1000, 0) == WAKE_RTP_E_CORRUPT, "set_weights refuses corrupted ahead fields");
    CHECK(wake_rtp_set_ahead(&s, c, 0) == WAKE_RTP_E_CORRUPT, "set_ahead refuses them too");
    /* in range, the largest values saturate only the estimate, never P, the gate or the command */
    CHECK(wake_rtp_init(&s, J, taps, w, 1000, 0, 0) == WAKE_RTP_OK, "init");
    CHECK(wake_rtp_set_ahead(&s, c, WAKE_RTP_GATE_ONE) == WAKE_RTP_OK && wake_rtp_set_ahead_ramp(&s, WAKE_RTP_GATE_ONE)
          == WAKE_RTP_OK, "set, ramp 1");
    for (i = 0; i < 20; ++i) {
        CHECK(wake_rtp_step(&s, (int16_t)((i & 1) ? 32767 : -32768), &y) == WAKE_RTP_OK, "step");
    }
    CHECK(s.ahead.gate == WAKE_RTP_GATE_ONE, "ramp 1: the gate is the goal at once");
    /* the estimate saturates at +-1 FS; P = 64 FS at most, held by Q23 (+-256 FS) without saturating */
    CHECK(labs((long)s.ahead.predicted) >= (long)(60.0 * 8388608.0), "P reaches 60 of its 64 FS (%ld)", (long)s.ahead.predicted);
}

/* A firmware that drives a tremor ahead of its own (wake_ahead.h), fed the core's tremor estimate
 * e(n) = m(n) - y(n-1) (0 for the first sample; wake_ahead_step_missing for a missing one), holds what the RTP's
 * embedded instance holds, bit for bit, at the ramp of 100 Hz and of 1000 Hz; and the instance's own checks. */
static void test_an_instance_of_its_own(double fs)
{
    static int16_t taps[J * N];
    const int32_t w[J] = {(int32_t)(0.2 * 16777216.0), (int32_t)(-0.1 * 16777216.0),
                          (int32_t)(0.3 * 16777216.0), (int32_t)(0.6 * 16777216.0)};
    const int32_t ramp = (int32_t)(Q30 / (0.3 * fs) + 0.5);
    int32_t c[TAPS];
    int16_t line[TAPS];
    wake_rtp_t s;
    wake_ahead_t own;
    int n, i, same = 1;
    make_averaging_taps(taps, J, N);
    for (i = 0; i < TAPS; ++i) {
        c[i] = (int32_t)(rng_uniform(-1.0, 1.0) * Q27);
    }
    CHECK(wake_ahead_init(NULL) == WAKE_RTP_E_NULL && wake_ahead_init(&own) == WAKE_RTP_OK, "init");
    CHECK(own.ramp == WAKE_RTP_AHEAD_RAMP_DEFAULT && wake_ahead_check(&own) == WAKE_RTP_OK, "init: ramp 1/30, valid");
    CHECK(wake_rtp_init(&s, J, taps, w, 40000, 30, 40000) == WAKE_RTP_OK, "rtp init");
    CHECK(wake_ahead_set_model(&own, c, (int32_t)(0.75 * Q30)) == WAKE_RTP_OK
          && wake_rtp_set_ahead(&s, c, (int32_t)(0.75 * Q30)) == WAKE_RTP_OK, "the same predictor");
    CHECK(wake_ahead_set_ramp(&own, ramp) == WAKE_RTP_OK && wake_rtp_set_ahead_ramp(&s, ramp) == WAKE_RTP_OK,
          "the same ramp");
    for (n = 0; n < 600; ++n) {
        int16_t y;
        const int missing = (n % 97) == 50;
        /* at 1000 Hz an accelerometer's recording: gravity, 0.3 FS, under the motion */
        const int16_t m = (int16_t)(signal_at(n, 0.2) + (fs > 500.0 ? 9830 : 0));
        /* the core's tremor estimate, read before its step: m(n) - y(n-1) in Q23, saturated (0 for the first
         * sample) */
        const int64_t diff = (int64_t)m * 256 - s.last_output;
        const int32_t e = !s.primed ? 0 : diff > INT32_MAX ? INT32_MAX : diff < INT32_MIN ? INT32_MIN : (int32_t)diff;
        if (missing) {
            CHECK(wake_rtp_step_missing(&s, &y) == WAKE_RTP_OK, "step_missing");
            wake_ahead_step_missing(&own);
        } else {
            CHECK(wake_rtp_step(&s, m, &y) == WAKE_RTP_OK, "step");
            wake_ahead_step(&own, e);
        }
        if (n == 300) {   /* a new model and goal between two samples */
            c[0] = -c[0];
            CHECK(wake_ahead_set_model(&own, c, (int32_t)(0.5 * Q30)) == WAKE_RTP_OK
                  && wake_rtp_set_ahead(&s, c, (int32_t)(0.5 * Q30)) == WAKE_RTP_OK, "a new model");
        }
        same = same && (memcmp(&own, &s.ahead, sizeof(own)) == 0);
    }
    CHECK(same, "fs %.0f Hz: the instance of its own holds the embedded one's state, bit for bit", fs);
    CHECK(own.gate > 0 && own.predicted != 0, "the gate opened and the ahead predicts");
    CHECK(wake_ahead_history(&own, line) == WAKE_RTP_OK && line[0] == own.line[own.head], "history: newest first");
    CHECK(wake_ahead_load(&own, line, WAKE_RTP_GATE_ONE + 1) == WAKE_RTP_E_AHEAD, "load: gate > 1");
    CHECK(wake_ahead_load(NULL, line, 0) == WAKE_RTP_E_NULL && wake_ahead_history(&own, NULL) == WAKE_RTP_E_NULL,
          "NULL refused");
    CHECK(wake_ahead_output(NULL, NULL, NULL, NULL) == WAKE_RTP_E_NULL, "output: NULL instance");
    c[2] = WAKE_RTP_AHEAD_COEF_MAX + 1;
    CHECK(wake_ahead_set_model(&own, c, 0) == WAKE_RTP_E_AHEAD && own.coef[2] != c[2], "a refused model changes nothing");
    own.head = TAPS;
    CHECK(wake_ahead_check(&own) == WAKE_RTP_E_CORRUPT && wake_ahead_history(&own, line) == WAKE_RTP_E_CORRUPT,
          "a line index beyond 7 is corrupt");
    wake_ahead_step(&own, INT32_MAX);                        /* any content is safe for the step */
    CHECK(own.head < TAPS && own.saturations > 0u, "the step takes its index modulo 8 and counts the saturation");
    CHECK(wake_ahead_reset(&own) == WAKE_RTP_OK && own.gate == 0 && own.goal == 0 && own.coef[0] == c[0]
          && own.ramp == ramp, "reset: shut, the model and ramp kept");
}

int main(void)
{
    printf("sizeof(wake_rtp_t) = %u bytes with the tremor ahead (J <= %d)\n", (unsigned)sizeof(wake_rtp_t),
           WAKE_RTP_MAX_LEVEL);
    test_status_codes();
    test_against_double(0);
    test_against_double(1);
    test_missing_reset_and_voluntary();
    test_state_round_trip();
    test_corrupted();
    test_an_instance_of_its_own(100.0);
    test_an_instance_of_its_own(1000.0);
    printf("%d passed, %d failed\n", n_passed, n_failed);
    return n_failed ? 1 : 0;
}

#else /* WAKE_RTP_AHEAD 0: the build without the tremor ahead */

/* The RTP's tremor-ahead entries still link; each answers WAKE_RTP_E_FEATURE once the instance is checked
 * (WAKE_RTP_E_NULL for a NULL instance, _UNINIT for one never initialised) and changes nothing. */
int main(void)
{
    static int16_t taps[J * N];
    static int32_t w[J], c[TAPS];
    static wake_q15_t line[TAPS];
    wake_rtp_t s, before;
    wake_q23_t predicted = 1, command = 3;
    wake_ratio_t gate = 2;
    unsigned j;
    CHECK(WAKE_RTP_AHEAD == 0, "built without the tremor ahead");
    make_averaging_taps(taps, J, N);
    for (j = 0; j < J; ++j) {
        w[j] = (int32_t)(16777216 / J);
    }
    memset(&s, 0, sizeof(s));
    CHECK(wake_rtp_set_ahead(&s, c, 0) == WAKE_RTP_E_UNINIT, "never initialised: E_UNINIT first");
    CHECK(wake_rtp_init(&s, J, taps, w, 3000, 3, 3000) == WAKE_RTP_OK, "init");
    memcpy(&before, &s, sizeof(s));
    CHECK(wake_rtp_set_ahead(NULL, c, 0) == WAKE_RTP_E_NULL, "set_ahead: NULL instance");
    CHECK(wake_rtp_set_ahead(&s, c, 0) == WAKE_RTP_E_FEATURE, "set_ahead answers E_FEATURE");
    CHECK(wake_rtp_set_ahead_ramp(&s, 1 << 29) == WAKE_RTP_E_FEATURE, "set_ahead_ramp answers E_FEATURE");
    CHECK(wake_rtp_ahead_output(&s, &predicted, &gate, &command) == WAKE_RTP_E_FEATURE &&
          predicted == 1 && gate == 2 && command == 3, "ahead_output answers E_FEATURE, writes nothing");
    CHECK(wake_rtp_load_ahead_state(&s, line, 0) == WAKE_RTP_E_FEATURE, "load_ahead_state answers E_FEATURE");
    CHECK(wake_rtp_get_ahead_state(&s, line) == WAKE_RTP_E_FEATURE, "get_ahead_state answers E_FEATURE");
    CHECK(memcmp(&before, &s, sizeof(s)) == 0, "nothing changed");
    printf("WAKE_RTP_AHEAD 0: %d passed, %d failed\n", n_passed, n_failed);
    return n_failed ? 1 : 0;
}

#endif
