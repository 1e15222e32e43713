/*
 * Host unit tests of the fixed-point WAKE RTP core.
 *
 * The fixed-point core is compared with the same recursion written here in
 * double precision, fed with exactly the quantised taps, weights, noises and
 * samples, so the difference is the core's arithmetic error alone.  Tests may
 * use double and stdio; the library may not.
 *
 * Build and run: make -C csrc test  (AddressSanitizer + UBSan).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wake_rtp.h"

#include "check.h"

#define MAXJ WAKE_RTP_MAX_LEVEL
#define MAXN WAKE_RTP_MAX_TAPS

static const double Q15 = 32768.0;
static const double PI = 3.14159265358979323846;
static const double Q24 = 16777216.0;

static double p_scale(void) { return ldexp(1.0, WAKE_RTP_P_FRAC); }

/* ---- deterministic pseudo-random numbers (xorshift32) ------------------- */
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
    return lo + (hi - lo) * ((double)rng_u32() / 4294967296.0);
}

/* ---- double-precision twin of the recursion ---------------------------- */
typedef struct {
    int J, N, head, primed;
    double taps[MAXJ * MAXN];
    double w[MAXJ];
    double r, q;
    double buf[MAXN];
    double d[MAXJ];
    double P[MAXJ * MAXJ];
    double last;
} ref_t;

static void ref_init(ref_t *f, int J, const int16_t *taps, const int32_t *w, int32_t r, int32_t q, int32_t p0)
{
    int i;
    memset(f, 0, sizeof(*f));
    f->J = J;
    f->N = 1 << J;
    for (i = 0; i < J * f->N; ++i) f->taps[i] = taps[i] / Q15;
    for (i = 0; i < J; ++i) f->w[i] = w[i] / Q24;
    f->r = r / p_scale();
    f->q = q / p_scale();
    for (i = 0; i < J; ++i) f->P[i * J + i] = p0 / p_scale();
}

/* A weight change: P restarts as (w'Pw / w'w) I with the old w (the largest P_ii when w = 0). */
static void ref_restart_covariance(ref_t *f)
{
    int i, j, J = f->J;
    double wpw = 0.0, ww = 0.0, top = 0.0;
    for (i = 0; i < J; ++i) {
        ww += f->w[i] * f->w[i];
        if (f->P[i * J + i] > top) top = f->P[i * J + i];
        for (j = 0; j < J; ++j) wpw += f->w[i] * f->P[i * J + j] * f->w[j];
    }
    for (i = 0; i < J * J; ++i) f->P[i] = 0.0;
    for (i = 0; i < J; ++i) f->P[i * J + i] = (ww > 0.0) ? (wpw > 0.0 ? wpw / ww : 0.0) : top;
}

static void ref_set_weights(ref_t *f, const int32_t *w, int32_t r, int32_t q)
{
    int i;
    ref_restart_covariance(f);
    for (i = 0; i < f->J; ++i) f->w[i] = w[i] / Q24;
    f->r = r / p_scale();
    f->q = q / p_scale();
}

static void ref_push(ref_t *f, double m)
{
    int i;
    if (!f->primed) {
        for (i = 0; i < f->N; ++i) f->buf[i] = m;
        f->last = m;
        f->primed = 1;
    }
    f->buf[f->head] = m;
    f->head = (f->head + 1) % f->N;
}

static void ref_measure(ref_t *f, double m)
{
    int i, j, J = f->J;
    double u[MAXJ], S, e;
    e = m - f->last;                                   /* e = m(n) - y(n-1) */
    for (i = 0; i < J; ++i) {                          /* u = P w */
        u[i] = 0.0;
        for (j = 0; j < J; ++j) u[i] += f->P[i * J + j] * f->w[j];
    }
    S = f->r;                                          /* S = w' u + R */
    for (j = 0; j < J; ++j) S += f->w[j] * u[j];
    for (i = 0; i < J; ++i) f->d[i] += u[i] * (e / S); /* d = d + (u / S) e */
    for (i = 0; i < J; ++i)                            /* P = P - u u' / S */
        for (j = 0; j < J; ++j) f->P[i * J + j] -= u[i] * u[j] / S;
}

static void ref_time(ref_t *f)
{
    int i;
    for (i = 0; i < f->J; ++i) f->P[i * f->J + i] += f->q;   /* P = P + q I */
}

static double ref_predict(ref_t *f)
{
    int i, j;
    double y = 0.0;
    for (j = 0; j < f->J; ++j) {                       /* a_j = sum_i B[j][i] window[i] */
        double a = 0.0;
        for (i = 0; i < f->N; ++i) a += f->taps[j * f->N + i] * f->buf[(f->head + i) % f->N];
        y += f->w[j] * (a + f->d[j]);                  /* y = w' (a + d) */
    }
    f->last = y;
    return y;
}

static double ref_step(ref_t *f, double m)
{
    const int first = !f->primed;
    ref_push(f, m);
    if (!first) {
        ref_measure(f, m);                             /* the first sample had no prediction before it */
    }
    ref_time(f);
    return ref_predict(f);
}

/* The core pushes the last prediction rounded to Q15 (saturated); the twin
 * pushes the same value, so only arithmetic error is compared. */
static double ref_step_missing(ref_t *f)
{
    double stand_in;
    if (!f->primed) return 0.0;
    stand_in = floor(f->last * Q15 + 0.5);
    if (stand_in > 32767.0) stand_in = 32767.0;
    if (stand_in < -32768.0) stand_in = -32768.0;
    ref_push(f, stand_in / Q15);
    ref_time(f);
    return ref_predict(f);
}

/* ---- fixtures ------------------------------------------------------------- */

/* Haar-like smoothing taps: row j averages the newest 2^(j+1) samples (unit DC
 * gain, sum |taps| = 1), plus a signed variant with sum |taps| close to 1.7 to
 * exercise negative taps like real wavelet rows. */
static void make_taps(int J, int16_t *taps, int signed_rows)
{
    int j, i, N = 1 << J;
    for (j = 0; j < J; ++j) {
        int len = 1 << (j + 1);
        if (len > N) len = N;
        for (i = 0; i < N; ++i) taps[j * N + i] = 0;
        for (i = N - len; i < N; ++i) taps[j * N + i] = (int16_t)(32768 / len - (len == 1));
        if (signed_rows && len >= 4) {
            /* add +0.175 at the newest, -0.175 at the oldest of the run: sum stays 1 */
            taps[j * N + N - 1] = (int16_t)(taps[j * N + N - 1] + 5734);
            taps[j * N + N - len] = (int16_t)(taps[j * N + N - len] - 5734);
        }
    }
}

static void make_weights(int J, int32_t *w, double spread)
{
    int j;
    double sum = 0.0;
    for (j = 0; j < J; ++j) {
        double v = rng_uniform(-spread, spread);
        if (j == J - 1) v = 1.0 - sum;              /* DC gain 1: sum w = 1 */
        sum += v;
        w[j] = (int32_t)lround(v * Q24);
    }
}

static double sum_abs_w(const int32_t *w, int J)
{
    int j;
    double s = 0.0;
    for (j = 0; j < J; ++j) s += fabs(w[j] / Q24);
    return s;
}

/* Static error bound in full-scale units (docs/studies/fixed_point.md, B1):
 * Q15 output rounding + Q23 rounding of y + the rounding of the 2^J FIR taps
 * h = B'w to Q(WAKE_RTP_FIR_FRAC) times |sample| <= 1. */
static double static_bound(const int32_t *w, int J)
{
    (void)w;
    return ldexp(1.0, -16) + ldexp(1.0, -24) + (double)(1 << J) * ldexp(1.0, -(WAKE_RTP_FIR_FRAC + 1));
}

/* ---- tests ---------------------------------------------------------------- */

static void test_status_codes(void)
{
    wake_rtp_t s;
    int16_t taps[MAXJ * MAXN];
    int32_t w[MAXJ] = {0};
    int16_t y = 0;
    int16_t buf[4] = {0};
    int32_t d[MAXJ] = {0}, P[MAXJ * MAXJ] = {0};

    make_taps(3, taps, 0);
    w[2] = 1 << 24;
    CHECK(wake_rtp_init(NULL, 3, taps, w, 1000, 0, 0) == WAKE_RTP_E_NULL, "null instance");
    CHECK(wake_rtp_init(&s, 3, NULL, w, 1000, 0, 0) == WAKE_RTP_E_NULL, "null taps");
    CHECK(wake_rtp_init(&s, 3, taps, NULL, 1000, 0, 0) == WAKE_RTP_E_NULL, "null weights");
    CHECK(wake_rtp_init(&s, 0, taps, w, 1000, 0, 0) == WAKE_RTP_E_LEVEL, "level 0");
    CHECK(wake_rtp_init(&s, MAXJ + 1, taps, w, 1000, 0, 0) == WAKE_RTP_E_LEVEL, "level too big");
    CHECK(wake_rtp_init(&s, -3, taps, w, 1000, 0, 0) == WAKE_RTP_E_LEVEL, "negative level");
    CHECK(wake_rtp_init(&s, 3, taps, w, 0, 0, 0) == WAKE_RTP_E_NOISE, "R = 0");
    CHECK(wake_rtp_init(&s, 3, taps, w, 1000, -1, 0) == WAKE_RTP_E_NOISE, "q < 0");
    CHECK(wake_rtp_init(&s, 3, taps, w, 1000, 0, -1) == WAKE_RTP_E_NOISE, "p0 < 0");
    w[0] = WAKE_RTP_WEIGHT_MAX + 1;
    CHECK(wake_rtp_init(&s, 3, taps, w, 1000, 0, 0) == WAKE_RTP_E_WEIGHTS, "weight > 64");
    w[0] = -WAKE_RTP_WEIGHT_MAX - 1;
    CHECK(wake_rtp_init(&s, 3, taps, w, 1000, 0, 0) == WAKE_RTP_E_WEIGHTS, "weight < -64");
    w[0] = WAKE_RTP_WEIGHT_MAX;
    CHECK(wake_rtp_init(&s, 3, taps, w, 1000, 0, 0) == WAKE_RTP_OK, "weight = 64 accepted");
    w[0] = 0;
    /* taps: a row with sum |taps| = 65535 (2 - 2^-15) is accepted, 65536 rejected */
    memset(taps, 0, sizeof(taps));
    taps[8 + 0] = 32767;
    taps[8 + 1] = -32768;
    CHECK(wake_rtp_init(&s, 3, taps, w, 1000, 0, 0) == WAKE_RTP_OK, "row sum |taps| = 65535 accepted");
    taps[8 + 2] = 1;
    CHECK(wake_rtp_init(&s, 3, taps, w, 1000, 0, 0) == WAKE_RTP_E_TAPS, "row sum |taps| = 65536 rejected");
    CHECK(s.magic != WAKE_RTP_MAGIC, "failed init leaves the struct uninitialised");
    CHECK(wake_rtp_step(&s, 0, &y) == WAKE_RTP_E_UNINIT, "step after failed init");

    /* uninitialised (garbage) struct */
    memset(&s, 0xA5, sizeof(s));
    CHECK(wake_rtp_step(&s, 100, &y) == WAKE_RTP_E_UNINIT, "garbage struct: step");
    CHECK(wake_rtp_step_missing(&s, &y) == WAKE_RTP_E_UNINIT, "garbage struct: step_missing");
    CHECK(wake_rtp_run(&s, buf, buf, 4) == WAKE_RTP_E_UNINIT, "garbage struct: run");
    CHECK(wake_rtp_reset(&s) == WAKE_RTP_E_UNINIT, "garbage struct: reset");
    CHECK(wake_rtp_set_weights(&s, w, 1000, 0) == WAKE_RTP_E_UNINIT, "garbage struct: set_weights");
    CHECK(wake_rtp_load_state(&s, buf, d, P, 0) == WAKE_RTP_E_UNINIT, "garbage struct: load_state");
    memset(&s, 0, sizeof(s));
    CHECK(wake_rtp_step(&s, 100, &y) == WAKE_RTP_E_UNINIT, "zeroed struct: step");
    CHECK(wake_rtp_step(NULL, 100, &y) == WAKE_RTP_E_NULL, "null struct: step");

    /* corrupted fields behind a valid magic */
    make_taps(3, taps, 0);
    w[2] = 1 << 24;
    CHECK(wake_rtp_init(&s, 3, taps, w, 1000, 0, 0) == WAKE_RTP_OK, "init");
    s.head = 200;
    CHECK(wake_rtp_step(&s, 1, &y) == WAKE_RTP_E_CORRUPT, "corrupt head");
    s.head = 0;
    s.level = 9;
    CHECK(wake_rtp_step(&s, 1, &y) == WAKE_RTP_E_CORRUPT, "corrupt level");
    s.level = 3;
    s.taps = NULL;
    CHECK(wake_rtp_step(&s, 1, &y) == WAKE_RTP_E_CORRUPT, "corrupt taps pointer");
    s.taps = taps;
    CHECK(wake_rtp_step(&s, 1, &y) == WAKE_RTP_OK, "repaired");
    CHECK(wake_rtp_step(&s, 1, NULL) == WAKE_RTP_E_NULL, "null prediction");
    CHECK(wake_rtp_run(&s, NULL, buf, 4) == WAKE_RTP_E_NULL, "run null input");
    CHECK(wake_rtp_run(&s, NULL, NULL, 0) == WAKE_RTP_OK, "run n = 0");
    /* set_weights errors leave the state alone */
    w[1] = WAKE_RTP_WEIGHT_MAX + 5;
    CHECK(wake_rtp_set_weights(&s, w, 1000, 0) == WAKE_RTP_E_WEIGHTS, "set_weights out of range");
    CHECK(s.weights[1] == 0, "weights unchanged after an error");
    w[1] = 0;
    CHECK(wake_rtp_set_weights(&s, w, 0, 0) == WAKE_RTP_E_NOISE, "set_weights R = 0");
    CHECK(wake_rtp_set_weights(&s, NULL, 10, 0) == WAKE_RTP_E_NULL, "set_weights null");
    P[0] = -5;
    {
        int16_t win[8] = {0};
        CHECK(wake_rtp_load_state(&s, win, d, P, 0) == WAKE_RTP_E_STATE, "negative diagonal rejected");
        CHECK(wake_rtp_load_state(&s, NULL, d, P, 0) == WAKE_RTP_E_NULL, "load_state null");
    }
}

static void test_reciprocal(void)
{
    uint32_t x;
    double worst = 0.0;
    int k;
    for (k = 0; k < 200000; ++k) {
        double exact, got, rel;
        x = (k < 4) ? (uint32_t[]){0x40000000u, 0x40000001u, 0x7FFFFFFFu, 0x5A827999u}[k]
                    : 0x40000000u + (rng_u32() & 0x3FFFFFFFu);
        exact = ldexp(1.0, 61) / (double)x;
        got = (double)wake_rtp_reciprocal(x);
        rel = fabs(got - exact) / exact;
        if (rel > worst) worst = rel;
    }
    /* every top 16 bits (the first steps run on them alone), with the low bits all 0 and all 1 */
    for (k = 0; k < 2 * 32768; ++k) {
        double exact, got, rel;
        x = ((UINT32_C(32768) + (uint32_t)(k >> 1)) << 15) | ((k & 1) ? UINT32_C(0x7FFF) : 0u);
        exact = ldexp(1.0, 61) / (double)x;
        got = (double)wake_rtp_reciprocal(x);
        rel = fabs(got - exact) / exact;
        if (rel > worst) worst = rel;
    }
    printf("reciprocal: worst relative error %.3g (%.2f units of 2^-30)\n", worst, worst * ldexp(1.0, 30));
    CHECK(worst <= ldexp(1.0, -29), "reciprocal relative error %.3g", worst);
}

/* Run the core and the double twin side by side; return the worst error in FS. */
static double compare_run(int J, int signed_taps, double spread, double r, double q, double p0,
                          int n, int kind, double *bound_out, uint32_t *sat_out)
{
    static int16_t taps[MAXJ * MAXN];
    wake_rtp_t s;
    ref_t f;
    int32_t w[MAXJ];
    int32_t rq = (int32_t)lround(r * p_scale()), qq = (int32_t)lround(q * p_scale()),
            pq = (int32_t)lround(p0 * p_scale());
    double worst = 0.0, worst_excess = -1.0;
    double bkal = 0.0, sw, sb;
    int k;

    make_taps(J, taps, signed_taps);
    make_weights(J, w, spread);
    CHECK(wake_rtp_init(&s, J, taps, w, rq, qq, pq) == WAKE_RTP_OK, "init J=%d", J);
    ref_init(&f, J, taps, w, rq, qq, pq);
    sw = sum_abs_w(w, J);
    sb = static_bound(w, J);
    for (k = 0; k < n; ++k) {
        double tt = k / 100.0, m;
        int16_t mq, y;
        double yr, err, g, S, wu, e;
        int i, j;
        switch (kind) {
        case 0: m = 0.3 * sin(2 * PI * 0.7 * tt) + 0.1 * sin(2 * PI * 6.0 * tt) + rng_uniform(-0.02, 0.02); break;
        default: m = rng_uniform(-0.3, 0.3); break;
        }
        mq = (int16_t)lround(m * Q15);
        /* first-order Kalman term (docs/studies/fixed_point.md): B = (1 - g) B + rho */
        wu = 0.0;
        for (i = 0; i < J; ++i) for (j = 0; j < J; ++j) wu += f.w[i] * f.P[i * J + j] * f.w[j];
        S = wu + f.r;
        g = wu / S;
        e = f.primed ? fabs(mq / Q15 - f.last) : 0.0;
        if (wu > 0.0 || f.q > 0.0) {
            bkal = (1.0 - g) * bkal + sw * ldexp(1.0, -24) + e * sw * sw * 4.0 / p_scale() / S;
        }
        yr = ref_step(&f, mq / Q15);
        CHECK(wake_rtp_step(&s, mq, &y) == WAKE_RTP_OK, "step");
        err = fabs(y / Q15 - yr);
        if (err > worst) worst = err;
        if (err - (sb + bkal) > worst_excess) worst_excess = err - (sb + bkal);
    }
    *bound_out = sb + bkal;
    *sat_out = s.saturations;
    CHECK(worst_excess <= 0.0, "J=%d error exceeds bound by %.3g FS", J, worst_excess);
    return worst;
}

static void test_against_double(void)
{
    int J, kind;
    for (kind = 0; kind < 2; ++kind) {
        for (J = 1; J <= MAXJ; ++J) {
            double bound;
            uint32_t sat;
            /* inert Kalman (P = 0, q = 0): pure filter bank */
            double e0 = compare_run(J, kind, 0.5, 1e-3, 0.0, 0.0, 3000, kind, &bound, &sat);
            double e1, e2;
            CHECK(sat == 0u, "no saturation expected, got %u", (unsigned)sat);
            printf("J=%d kind=%d inert: worst %.3g FS (%.3f LSB), bound %.3g\n", J, kind, e0, e0 * Q15, bound);
            /* active Kalman, q/R = 1e-2 and 1e-3 */
            e1 = compare_run(J, kind, 0.5, 1e-3, 1e-5, 1e-3, 3000, kind, &bound, &sat);
            printf("J=%d kind=%d q/R=1e-2: worst %.3g FS (%.3f LSB), final bound %.3g\n", J, kind, e1, e1 * Q15, bound);
            e2 = compare_run(J, kind, 0.5, 1e-2, 1e-5, 0.0, 3000, kind, &bound, &sat);
            printf("J=%d kind=%d q/R=1e-3: worst %.3g FS (%.3f LSB), final bound %.3g\n", J, kind, e2, e2 * Q15, bound);
        }
    }
}

/* Weight changes every 500 samples with the Kalman live: the core follows the
 * double twin, which restarts P as (w'Pw / w'w) I at every change.  The bound
 * is compare_run's, carried across a change: the core's d error lies along the
 * old w (every update of d is along w), so the new z = w_new'd inherits
 * |e_z| |w_new'w_old| / |w_old|^2, plus the Q23 rounding of each rebuilt d_i. */
static void test_weight_changes_against_double(void)
{
    static int16_t taps[MAXJ * MAXN];
    wake_rtp_t s;
    ref_t f;
    int32_t w[MAXJ], w_old[MAXJ];
    int J, k, i;
    for (J = 2; J <= MAXJ; ++J) {
        const int32_t r = 4294967, q = 42950, p0 = 4294967;           /* R = p0 = 1e-3 FS^2, q = 1e-2 R */
        double worst = 0.0, worst_excess = -1.0, bkal = 0.0, bound = 0.0;
        make_taps(J, taps, 1);
        make_weights(J, w, 0.5);
        CHECK(wake_rtp_init(&s, J, taps, w, r, q, p0) == WAKE_RTP_OK, "changes: init J=%d", J);
        ref_init(&f, J, taps, w, r, q, p0);
        for (k = 0; k < 6000; ++k) {
            double tt = k / 100.0, m, yr, wu = 0.0, S, g, e, sw = sum_abs_w(w, J);
            int16_t mq, y;
            int j;
            if (k % 500 == 499) {
                double dot = 0.0, ww = 0.0;
                memcpy(w_old, w, sizeof(w));
                make_weights(J, w, 0.5 + 0.5 * ((k / 500) % 3));
                for (i = 0; i < J; ++i) {
                    dot += fabs(w[i] / Q24) * fabs(w_old[i] / Q24);
                    ww += (w_old[i] / Q24) * (w_old[i] / Q24);
                }
                bkal = bkal * dot / ww + sum_abs_w(w, J) * ldexp(1.0, -23);
                CHECK(wake_rtp_set_weights(&s, w, r, q) == WAKE_RTP_OK, "changes: set_weights");
                ref_set_weights(&f, w, r, q);
                sw = sum_abs_w(w, J);
            }
            /* amplitude 0.2 FS: the predictions stay inside full scale (no saturation) */
            m = 0.15 * sin(2 * PI * 0.7 * tt) + 0.04 * sin(2 * PI * 6.0 * tt) + rng_uniform(-0.01, 0.01);
            mq = (int16_t)lround(m * Q15);
            for (i = 0; i < J; ++i) for (j = 0; j < J; ++j) wu += f.w[i] * f.P[i * J + j] * f.w[j];
            S = wu + f.r;
            g = wu / S;
            e = f.primed ? fabs(mq / Q15 - f.last) : 0.0;
            bkal = (1.0 - g) * bkal + sw * ldexp(1.0, -24) + e * sw * sw * 4.0 / p_scale() / S;
            yr = ref_step(&f, mq / Q15);
            CHECK(wake_rtp_step(&s, mq, &y) == WAKE_RTP_OK, "changes: step");
            bound = static_bound(w, J) + bkal;
            if (fabs(y / Q15 - yr) > worst) worst = fabs(y / Q15 - yr);
            if (fabs(y / Q15 - yr) - bound > worst_excess) worst_excess = fabs(y / Q15 - yr) - bound;
        }
        printf("J=%d weight changes: worst %.3g FS (%.3f LSB), final bound %.3g\n", J, worst, worst * Q15, bound);
        CHECK(worst_excess <= 0.0 && s.saturations == 0u, "J=%d weight changes: error exceeds bound by %.3g FS", J,
              worst_excess);
    }
}

/* The rebuilt covariance is symmetric (upper triangle mirrored). */
static int is_symmetric(const wake_rtp_t *s)
{
    int i, j, J = s->level;
    int32_t d[MAXJ], P[MAXJ * MAXJ];
    if (wake_rtp_get_state(s, d, P) != WAKE_RTP_OK) return 0;
    for (i = 0; i < J; ++i) {
        for (j = 0; j < J; ++j) {
            if (P[i * J + j] != P[j * J + i]) return 0;
        }
    }
    return 1;
}

static void test_saturation_and_psd(void)
{
    static int16_t taps[MAXJ * MAXN];
    wake_rtp_t s;
    int32_t w[MAXJ];
    int J = 5, k, ok = 1, psd = 1;
    int16_t y, prev = 0;
    int16_t in[512], out[512];

    make_taps(J, taps, 1);
    /* large weights: the prediction overshoots full scale and must saturate */
    for (k = 0; k < J; ++k) w[k] = (k % 2) ? -(40 << 24) : (40 << 24);
    CHECK(wake_rtp_init(&s, J, taps, w, 1, 0, 0) == WAKE_RTP_OK, "init");
    for (k = 0; k < 2000; ++k) {
        int16_t m = ((k / 7) % 2) ? INT16_MAX : INT16_MIN;       /* full-scale square wave */
        if (wake_rtp_step(&s, m, &y) != WAKE_RTP_OK) ok = 0;
    }
    CHECK(ok, "square wave steps ok");
    CHECK(s.saturations > 0u, "square wave with weights +-40 saturates (count %u)", (unsigned)s.saturations);

    /* steps and spikes with an active, badly scaled Kalman filter */
    make_weights(J, w, 3.0);
    CHECK(wake_rtp_init(&s, J, taps, w, 1, INT32_MAX / 4, INT32_MAX) == WAKE_RTP_OK, "init adversarial");
    for (k = 0; k < 20000; ++k) {
        int16_t m;
        switch ((k / 1000) % 4) {
        case 0: m = (k % 1000 < 500) ? INT16_MAX : INT16_MIN; break;     /* steps */
        case 1: m = (k % 97 == 0) ? INT16_MAX : 0; break;                 /* spikes */
        case 2: m = (int16_t)(rng_u32() & 0xFFFFu); break;                /* noise */
        default: m = (int16_t)(-prev); break;                             /* Nyquist */
        }
        if (k % 5 == 3) {
            if (wake_rtp_step_missing(&s, &y) != WAKE_RTP_OK) ok = 0;
        } else if (wake_rtp_step(&s, m, &y) != WAKE_RTP_OK) {
            ok = 0;
        }
        prev = y;
        if (k % 1000 == 999) {
            make_weights(J, w, 20.0);
            if (wake_rtp_set_weights(&s, w, (int32_t)(rng_u32() >> 1) | 1, (int32_t)(rng_u32() >> 3)) != WAKE_RTP_OK) ok = 0;
        }
        if (!is_symmetric(&s)) psd = 0;
    }
    CHECK(ok, "adversarial run ok");
    CHECK(psd, "rebuilt covariance symmetric throughout");
    printf("adversarial: saturations %u\n", (unsigned)s.saturations);

    /* the block API equals per-sample steps */
    {
        wake_rtp_t a, b;
        make_weights(J, w, 1.0);
        CHECK(wake_rtp_init(&a, J, taps, w, 50000, 300, 100000) == WAKE_RTP_OK, "init a");
        b = a;
        for (k = 0; k < 512; ++k) in[k] = (int16_t)((k * 37) % 2000 - 1000 + ((k % 50 == 0) ? 20000 : 0));
        CHECK(wake_rtp_run(&a, in, out, 512) == WAKE_RTP_OK, "run");
        ok = 1;
        for (k = 0; k < 512; ++k) {
            if (wake_rtp_step(&b, in[k], &y) != WAKE_RTP_OK || y != out[k]) ok = 0;
        }
        CHECK(ok, "run == step loop");
        CHECK(memcmp(&a, &b, sizeof(a)) == 0, "same state after run and steps");
        /* in-place */
        b = a;
        memcpy(out, in, sizeof(in));
        CHECK(wake_rtp_run(&a, out, out, 512) == WAKE_RTP_OK, "in-place run");
        ok = 1;
        for (k = 0; k < 512; ++k) {
            wake_rtp_step(&b, in[k], &y);
            if (y != out[k]) ok = 0;
        }
        CHECK(ok, "in-place run == step loop");
    }
}

static void test_missing_and_reset(void)
{
    static int16_t taps[MAXJ * MAXN];
    wake_rtp_t s;
    ref_t f;
    int32_t w[MAXJ];
    int J = 4, k;
    int16_t y;
    double worst = 0.0;

    make_taps(J, taps, 1);
    make_weights(J, w, 1.0);
    CHECK(wake_rtp_init(&s, J, taps, w, 40000, 400, 40000) == WAKE_RTP_OK, "init");
    /* missing before the first sample: 0, nothing changes */
    CHECK(wake_rtp_step_missing(&s, &y) == WAKE_RTP_OK && y == 0 && s.primed == 0u, "missing before priming");
    ref_init(&f, J, taps, w, 40000, 400, 40000);
    for (k = 0; k < 2000; ++k) {
        double yr;
        if (k % 11 == 5 || (k > 700 && k < 706)) {
            CHECK(wake_rtp_step_missing(&s, &y) == WAKE_RTP_OK, "missing");
            yr = ref_step_missing(&f);
        } else {
            int16_t m = (int16_t)lround(Q15 * 0.4 * sin(k * 0.05));
            CHECK(wake_rtp_step(&s, m, &y) == WAKE_RTP_OK, "step");
            yr = ref_step(&f, m / Q15);
        }
        if (fabs(y / Q15 - yr) > worst) worst = fabs(y / Q15 - yr);
    }
    {
        /* Each stand-in enters the C window rounded to Q15 (the twin keeps it exact):
         * docs/studies/fixed_point.md (B3) adds sum_i |h_i| 2^-16 per stand-in in the window;
         * at most 7 of the 16 window samples are stand-ins here.  Plus 1 LSB for the
         * static and Kalman terms measured without stand-ins (0.72 LSB). */
        double sum_h = 0.0, allowed;
        int i, j;
        for (i = 0; i < (1 << J); ++i) {
            double h = 0.0;
            for (j = 0; j < J; ++j) h += taps[j * (1 << J) + i] / Q15 * (w[j] / Q24);
            sum_h += fabs(h);
        }
        allowed = 1.0 / Q15 + 7.0 * sum_h * ldexp(1.0, -16);
        printf("missing samples: worst %.3g FS (%.3f LSB), allowed %.3f LSB\n", worst, worst * Q15, allowed * Q15);
        CHECK(worst < allowed, "missing-sample error %.3g FS", worst);
    }

    /* set_weights keeps ring, d and y(n-1); P restarts as (w'Pw / w'w) I with the old w */
    {
        wake_rtp_t before = s;
        int32_t w2[MAXJ], d0[MAXJ], P0[MAXJ * MAXJ], d1[MAXJ], P1[MAXJ * MAXJ];
        double wpw = 0.0, ww = 0.0, lambda;
        int i, j, restarted = 1;
        make_weights(J, w2, 2.0);
        CHECK(wake_rtp_get_state(&s, d0, P0) == WAKE_RTP_OK, "get_state");
        for (i = 0; i < J; ++i) {
            ww += (w[i] / Q24) * (w[i] / Q24);
            for (j = 0; j < J; ++j) wpw += (w[i] / Q24) * P0[i * J + j] * (w[j] / Q24);
        }
        lambda = wpw / ww;                                       /* in LSB of Q(P) */
        CHECK(wake_rtp_set_weights(&s, w2, 1234, 56) == WAKE_RTP_OK, "set_weights");
        CHECK(wake_rtp_get_state(&s, d1, P1) == WAKE_RTP_OK, "get_state after set_weights");
        CHECK(memcmp(s.ring, before.ring, sizeof(s.ring)) == 0 && memcmp(d0, d1, (size_t)J * sizeof(int32_t)) == 0
                  && s.head == before.head && s.last_output == before.last_output,
              "set_weights keeps ring, d and y(n-1)");
        for (i = 0; i < J; ++i) {
            for (j = 0; j < J; ++j) {
                /* get_state's P rounds each entry once; the old P entries were exact to 1 LSB each */
                double want = (i == j) ? lambda : 0.0;
                if (fabs(P1[i * J + j] - want) > 2.0 + 1e-6 * lambda) restarted = 0;
            }
        }
        CHECK(restarted && s.variance > 0, "P restarted as (w'Pw / w'w) I: lambda %.1f LSB, P_00 %d", lambda, P1[0]);
        CHECK(s.r == 1234 && s.q == 56 && s.weights[0] == w2[0], "new values installed");
    }
    /* reset */
    CHECK(wake_rtp_reset(&s) == WAKE_RTP_OK, "reset");
    CHECK(s.primed == 0u && s.variance == s.p0 && s.steps == 0u && s.correction[0] == 0 && s.saturations == 0u,
          "reset state");
    /* load_state: a primed constant window predicts the constant with d = 0, P = 0 */
    {
        int16_t win[MAXN];
        int32_t d[MAXJ] = {0}, P[MAXJ * MAXJ] = {0};
        int32_t wdc[MAXJ] = {0};
        for (k = 0; k < (1 << J); ++k) win[k] = 12345;
        wdc[J - 1] = 1 << 24;
        CHECK(wake_rtp_set_weights(&s, wdc, 1000, 0) == WAKE_RTP_OK, "dc weights");
        P[(J - 1) * J + (J - 1)] = 7;       /* the variance along w = e_J */
        P[0] = 1000;
        P[1] = 999;                         /* not observed through w: dropped */
        CHECK(wake_rtp_load_state(&s, win, d, P, 12345 << 8) == WAKE_RTP_OK, "load_state");
        {
            int32_t d2[MAXJ], P2[MAXJ * MAXJ];
            int i, iso = 1;
            CHECK(wake_rtp_get_state(&s, d2, P2) == WAKE_RTP_OK, "get_state after load_state");
            for (i = 0; i < J * J; ++i) {
                if (P2[i] != ((i % (J + 1) == 0) ? 7 : 0)) iso = 0;
            }
            CHECK(iso && s.variance == 7, "load_state keeps the variance along w: P = 7 I (P_00 %d, P_01 %d)",
                  P2[0], P2[1]);
        }
        P[(J - 1) * J + (J - 1)] = -1;
        CHECK(wake_rtp_load_state(&s, win, d, P, 0) == WAKE_RTP_E_STATE && s.variance == 7,
              "a negative diagonal entry is refused, nothing changes");
        CHECK(wake_rtp_step_missing(&s, &y) == WAKE_RTP_OK && y == 12345, "constant after load_state (%d)", y);
    }
}

static void test_instances_independent(void)
{
    static int16_t taps_a[MAXJ * MAXN], taps_b[MAXJ * MAXN];
    wake_rtp_t a, b, a2;
    int32_t wa[MAXJ], wb[MAXJ];
    int k, same = 1;
    int16_t ya, yb, ya2;
    make_taps(5, taps_a, 0);
    make_taps(3, taps_b, 1);
    make_weights(5, wa, 1.0);
    make_weights(3, wb, 1.0);
    CHECK(wake_rtp_init(&a, 5, taps_a, wa, 30000, 100, 30000) == WAKE_RTP_OK, "init a");
    CHECK(wake_rtp_init(&a2, 5, taps_a, wa, 30000, 100, 30000) == WAKE_RTP_OK, "init a2");
    CHECK(wake_rtp_init(&b, 3, taps_b, wb, 900, 9, 0) == WAKE_RTP_OK, "init b");
    for (k = 0; k < 3000; ++k) {
        int16_t m = (int16_t)lround(9000.0 * sin(k * 0.031));
        wake_rtp_step(&a, m, &ya);
        wake_rtp_step(&b, (int16_t)(rng_u32() & 0xFFFFu), &yb);   /* b gets noise */
        wake_rtp_step(&a2, m, &ya2);                             /* a2 alone */
        if (ya != ya2) same = 0;
    }
    CHECK(same, "interleaving another instance changes nothing");
    CHECK(memcmp(&a, &a2, sizeof(a)) == 0, "identical state");
}

/* The inert shortcut (q = 0, P = 0: Kalman update skipped) is bit-identical
 * to running the full update, and the flag follows q and P. */
static void test_inert_shortcut(void)
{
    static int16_t taps[MAXJ * MAXN];
    wake_rtp_t a, b;
    int32_t w[MAXJ], d[MAXJ] = {0}, P[MAXJ * MAXJ] = {0};
    int16_t win[MAXN] = {0};
    int k, same = 1, J = 5;
    int16_t ya, yb;
    make_taps(J, taps, 1);
    make_weights(J, w, 20.0);
    CHECK(wake_rtp_init(&a, J, taps, w, 3000, 0, 0) == WAKE_RTP_OK, "inert: init");
    CHECK(a.inert == 1u, "q = 0, p0 = 0: inert");
    CHECK(wake_rtp_init(&b, J, taps, w, 3000, 0, 0) == WAKE_RTP_OK, "inert: init b");
    b.inert = 0u;                                  /* b runs the full (identity) update */
    for (k = 0; k < 4000; ++k) {
        int16_t m = (int16_t)((k % 97 < 40) ? 32767 : -32768);
        if (k % 3 == 0) {
            m = (int16_t)(rng_u32() & 0xFFFFu);
        }
        if (k == 2000) {                           /* a saturated y(n-1): e saturates too */
            a.last_output = INT32_MIN;
            b.last_output = INT32_MIN;
        }
        if (k % 50 == 7) {
            wake_rtp_step_missing(&a, &ya);
            wake_rtp_step_missing(&b, &yb);
        } else {
            wake_rtp_step(&a, m, &ya);
            wake_rtp_step(&b, m, &yb);
        }
        if (ya != yb) same = 0;
    }
    CHECK(same, "inert shortcut: same predictions as the full update");
    b.inert = 1u;
    CHECK(memcmp(&a, &b, sizeof(a)) == 0, "inert shortcut: same state and counters");
    CHECK(a.saturations > 0u, "inert shortcut: saturations still counted");
    /* the flag follows q (set_weights) and P (load_state, reset) */
    CHECK(wake_rtp_set_weights(&a, w, 3000, 5) == WAKE_RTP_OK && a.inert == 0u, "q > 0: not inert");
    CHECK(wake_rtp_set_weights(&a, w, 3000, 0) == WAKE_RTP_OK && a.inert == 1u, "q = 0 again, P = 0: inert");
    P[1 * J + 1] = 1 << 24;
    CHECK(wake_rtp_load_state(&a, win, d, P, 0) == WAKE_RTP_OK && a.inert == 0u, "loaded P != 0: not inert");
    CHECK(wake_rtp_reset(&a) == WAKE_RTP_OK && a.inert == 1u, "reset to p0 = 0: inert");
    CHECK(wake_rtp_init(&a, J, taps, w, 3000, 0, 10) == WAKE_RTP_OK && a.inert == 0u, "p0 > 0: not inert");
    /* a corrupted flag is refused */
    a.inert = 2u;
    CHECK(wake_rtp_step(&a, 1, &ya) == WAKE_RTP_E_CORRUPT, "corrupt inert flag");
    CHECK(wake_rtp_init(&a, J, taps, w, 3000, 5, 0) == WAKE_RTP_OK, "init q > 0");
    a.inert = 1u;                                  /* inert claimed while q > 0 */
    CHECK(wake_rtp_step(&a, 1, &ya) == WAKE_RTP_E_CORRUPT, "inert flag with q > 0");
}

/* A live Kalman filter for 24 h at 100 Hz with fixed weights: the per-sample
 * state converges and stays bounded, nothing saturates (no creep). */
static void test_24_hours_bounded(void)
{
    static int16_t taps[MAXJ * MAXN];
    static int16_t in[8640], out[8640];
    wake_rtp_t s;
    int32_t w[MAXJ];
    int J = 5, k, hour, ok = 1;
    int32_t r = 4295, q = 4, p0 = 4295;         /* R = p0 = 1e-6 FS^2, q = 1e-3 R (Q32) */
    int64_t s_after_1h = 0, s_max = 0, s_at_18h = 0;
    make_taps(J, taps, 0);
    make_weights(J, w, 0.5);
    CHECK(wake_rtp_init(&s, J, taps, w, r, q, p0) == WAKE_RTP_OK, "24 h: init");
    for (hour = 0; hour < 24; ++hour) {
        int chunk;
        for (chunk = 0; chunk < 42; ++chunk) {          /* 41 chunks of 8640 + 5760 = 360,000 samples */
            int n = (chunk == 41) ? 5760 : 8640;
            for (k = 0; k < n; ++k) {
                double t = (hour * 360000.0 + chunk * 8640.0 + k) / 100.0;
                in[k] = (int16_t)lround(Q15 * (0.3 * sin(2 * PI * 0.4 * t) + 0.05 * sin(2 * PI * 5.5 * t))
                                        + rng_uniform(-300.0, 300.0));
            }
            if (wake_rtp_run(&s, in, out, (size_t)n) != WAKE_RTP_OK) ok = 0;
            if (llabs(s.s) > s_max) s_max = llabs(s.s);
        }
        if (hour == 0) s_after_1h = s.s;
        if (hour == 17) s_at_18h = s.s;
        if (hour == 11) {
            /* a weight update half-way: P restarts at its variance along the old w, stays bounded */
            make_weights(J, w, 0.5);
            if (wake_rtp_set_weights(&s, w, r, q) != WAKE_RTP_OK) ok = 0;
        }
    }
    CHECK(ok, "24 h: run ok");
    CHECK(s.saturations == 0u, "24 h: no saturation (%u)", (unsigned)s.saturations);
    CHECK(s.steps == 12u * 360000u, "24 h: 12 h of steps since the update (%u)", (unsigned)s.steps);
    {
        /* the fixed point of s = R s / (s + R) + q|w|^2:  s^2 = q|w|^2 (s + R)  (for the weights now in force).
         * The update rounds R s / (s + R) to 1 LSB (+-0.5) and its slope there is (R / (s + R))^2 < 1, so the
         * integer recursion settles within 0.5 / (1 - slope) LSB of it (plus 1 for the ratio's rounding). */
        const double qw = (double)s.q_omega, R = (double)s.r, fixed = 0.5 * (qw + sqrt(qw * qw + 4.0 * qw * R));
        const double slope = (R / (fixed + R)) * (R / (fixed + R)), allowed = 0.5 / (1.0 - slope) + 1.0;
        CHECK(s_after_1h > 0 && fabs((double)s.s - fixed) <= allowed,
              "24 h: w'Pw at its fixed point (%lld vs %.1f +- %.1f; %lld after 1 h, before the update)", (long long)s.s,
              fixed, allowed, (long long)s_after_1h);
    }
    /* s = w'Pw reaches the fixed point of s = tau s + q|w|^2 and stays there: no creep */
    CHECK(s.s == s_at_18h && s_max < (1 << 20), "24 h: s bounded and converged (%lld at 18 h, %lld at 24 h, max %lld)",
          (long long)s_at_18h, (long long)s.s, (long long)s_max);
    printf("24 h: s = %lld, max s = %lld, lambda = %ld, saturations %u\n", (long long)s.s, (long long)s_max,
           (long)s.variance, (unsigned)s.saturations);
}

/* Issue: a stray write into the weights gets a status, not garbage. */
static void test_corrupted_weights(void)
{
    static int16_t taps[MAXJ * MAXN];
    wake_rtp_t s;
    int32_t w[MAXJ], d[MAXJ], P[MAXJ * MAXJ];
    int16_t y;
    make_taps(4, taps, 0);
    make_weights(4, w, 0.5);
    CHECK(wake_rtp_init(&s, 4, taps, w, 3000, 3, 3000) == WAKE_RTP_OK, "init");
    s.weights[2] = INT32_MAX;
    CHECK(wake_rtp_get_state(&s, d, P) == WAKE_RTP_E_CORRUPT, "get_state refuses corrupted weights");
    CHECK(wake_rtp_set_weights(&s, w, 3000, 3) == WAKE_RTP_E_CORRUPT, "set_weights refuses corrupted weights");
    CHECK(wake_rtp_reset(&s) == WAKE_RTP_E_CORRUPT, "reset refuses corrupted weights");
    /* step never reads the weights (only h, whose every value is safe): it runs, UBSan-clean */
    CHECK(wake_rtp_step(&s, 1000, &y) == WAKE_RTP_OK, "step with corrupted weights runs");
    /* a failed init clears only the magic: every call then reports an uninitialised instance */
    w[0] = INT32_MAX;
    CHECK(wake_rtp_init(&s, 4, taps, w, 3000, 3, 3000) == WAKE_RTP_E_WEIGHTS, "init refuses weights");
    CHECK(wake_rtp_step(&s, 1, &y) == WAKE_RTP_E_UNINIT, "failed init: uninitialised");
}

/* A stray write into the Kalman scalar s = w'Pw (negative, or past its 2^50 range) is
 * counted and clamped by the next update: no undefined behaviour (UBSan), s back in range. */
static void test_corrupted_variance(void)
{
    static int16_t taps[MAXJ * MAXN];
    wake_rtp_t s;
    int32_t w[MAXJ];
    int16_t y;
    const int64_t corrupt[] = {-5, -(INT64_C(1) << 50) - 1, INT64_MIN, (INT64_C(1) << 50) + 1, INT64_MAX};
    size_t k;
    int n;
    make_taps(4, taps, 0);
    make_weights(4, w, 0.5);
    for (k = 0; k < sizeof(corrupt) / sizeof(corrupt[0]); ++k) {
        uint32_t before;
        CHECK(wake_rtp_init(&s, 4, taps, w, 3000, 3, 3000) == WAKE_RTP_OK && s.inert == 0u, "init live");
        for (n = 0; n < 20; ++n) {
            CHECK(wake_rtp_step(&s, (int16_t)(n * 300), &y) == WAKE_RTP_OK, "step");
        }
        before = s.saturations;
        s.s = corrupt[k];
        CHECK(wake_rtp_step(&s, 1000, &y) == WAKE_RTP_OK, "step with a corrupted s runs (%lld)", (long long)corrupt[k]);
        CHECK(s.saturations > before, "a corrupted s is counted (%lld)", (long long)corrupt[k]);
        CHECK(s.s >= 0 && s.s <= (INT64_C(1) << 50), "s back in [0, 2^50] (%lld -> %lld)", (long long)corrupt[k],
              (long long)s.s);
    }
}

/* A feature the build leaves off (WAKE_RTP_SPLIT, WAKE_RTP_VOLUNTARY_AHEAD 0): its module still compiles and
 * links; its entries answer WAKE_RTP_E_FEATURE once the instance is checked (WAKE_RTP_E_NULL for a NULL
 * instance), and change nothing; the block entry outputs y(n) as the voluntary ahead. */
static void test_entries_of_features_left_off(void)
{
    static int16_t taps[MAXJ * MAXN];
    static int16_t in[40], vol[40];
    static int32_t vol_ahead[40];
    wake_rtp_t s, before;
    int32_t w[MAXJ];
    int16_t y = 123;
    int32_t out = 456;
    unsigned k;
    make_taps(4, taps, 0);
    make_weights(4, w, 0.5);
    CHECK(wake_rtp_init(&s, 4, taps, w, 3000, 3, 3000) == WAKE_RTP_OK, "init");
    for (k = 0; k < 40u; ++k) {
        in[k] = (int16_t)(3000 * sin(0.3 * k));
    }
    CHECK(wake_rtp_prepare(NULL) == WAKE_RTP_E_NULL, "prepare: NULL instance");
#if !WAKE_RTP_SPLIT
    memcpy(&before, &s, sizeof(s));
    CHECK(wake_rtp_prepare(&s) == WAKE_RTP_E_FEATURE, "no split step: prepare answers E_FEATURE");
    CHECK(wake_rtp_finish(&s, 100, &y) == WAKE_RTP_E_FEATURE && y == 123, "no split step: finish answers E_FEATURE");
    CHECK(wake_rtp_finish_missing(&s, &y) == WAKE_RTP_E_FEATURE && y == 123, "no split step: finish_missing");
    CHECK(memcmp(&before, &s, sizeof(s)) == 0, "no split step: nothing changed");
#endif
#if !WAKE_RTP_VOLUNTARY_AHEAD
    memcpy(&before, &s, sizeof(s));
    CHECK(wake_rtp_set_voluntary_ahead(&s, w) == WAKE_RTP_E_FEATURE, "no voluntary ahead: set answers E_FEATURE");
    CHECK(wake_rtp_set_voluntary_ahead(&s, NULL) == WAKE_RTP_E_FEATURE, "no voluntary ahead: the feature first");
    CHECK(wake_rtp_voluntary_ahead_output(&s, &out) == WAKE_RTP_E_FEATURE && out == 456,
          "no voluntary ahead: output answers E_FEATURE");
    CHECK(memcmp(&before, &s, sizeof(s)) == 0, "no voluntary ahead: nothing changed");
    CHECK(wake_rtp_run_outputs(&s, in, NULL, 40u, vol, NULL, NULL, NULL, vol_ahead) == WAKE_RTP_OK, "run_outputs");
    CHECK(vol_ahead[39] == s.last_output && vol_ahead[39] != 0, "no voluntary ahead: run_outputs gives y(n) in Q23");
    CHECK((int32_t)vol[39] * 256 - vol_ahead[39] < 256 && vol_ahead[39] - (int32_t)vol[39] * 256 < 256,
          "no voluntary ahead: the same y(n) in Q15 and Q23");
#endif
    (void)before;
    (void)in;
    (void)y;
    (void)out;
    (void)vol;
    (void)vol_ahead;
}

int main(void)
{
    printf("sizeof(wake_rtp_t) = %u bytes (WAKE_RTP_MAX_LEVEL = %d, P_FRAC = %d)\n", (unsigned)sizeof(wake_rtp_t),
           WAKE_RTP_MAX_LEVEL, WAKE_RTP_P_FRAC);
    CHECK(WAKE_RTP_MAX_LEVEL > 5 || sizeof(wake_rtp_t) < 1024u, "J = 5 state under 1 KiB");
    test_status_codes();
    test_reciprocal();
    test_against_double();
    test_weight_changes_against_double();
    test_saturation_and_psd();
    test_missing_and_reset();
    test_instances_independent();
    test_inert_shortcut();
    test_corrupted_weights();
    test_corrupted_variance();
    test_24_hours_bounded();
    test_entries_of_features_left_off();
    printf("%d passed, %d failed\n", n_passed, n_failed);
    return n_failed ? 1 : 0;
}
