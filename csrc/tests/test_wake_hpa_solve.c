/*
 * The C HPA's ridge solve (STEP_SOLVE) against its guards (issue 34, docs/studies/verification.md "The solve").
 *
 * It reaches the solve through the internal header (wake_hpa_solve_ridge, wake_hpa_step_solve).  Three properties:
 *  1. On positive semi-definite systems (Gram matrices of random regressors, from well-conditioned to
 *     nearly collinear, scales from 1e-3 to 1e12 LSB^2) no guard fires: solve_ridge accepts and refuses
 *     exactly the attempts the unguarded L D L' solve (reference_solve, the code before the guards)
 *     accepts and refuses, with bit-identical weights.
 *  2. On systems of any content (symmetric G, b, y'y of random magnitudes and signs, any scale), every
 *     attempt of step_solve ends refused or with finite weights within the limit, a finite e_L^2 >= 0,
 *     a finite ridge: never a NaN or an infinity.
 *  3. Each guard refuses what it is there for: |G_ij| above 2 trace(G), a pivot below lambda / 2,
 *     a scale below SOLVE_MIN_SCALE (zero weights).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "internal/wake_hpa_internal.h"
#include "check.h"

enum { LEVEL = 5, TAPS = 32, WINDOW = 500 };

static wake_hpa_t hpa;
static wake_q15_t bank[WAKE_HPA_MAX_LEVEL * WAKE_HPA_MAX_TAPS];
static wake_q15_t window[WAKE_HPA_MAX_WINDOW];

/** xorshift32: the same sequence on every machine. */
static uint32_t rng = 2463534242u;
static uint32_t next_u32(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 17;
    rng ^= rng << 5;
    return rng;
}

/** Uniform in [-1, 1). */
static float uniform(void)
{
    return (float)(next_u32() >> 8) * (2.0f / 16777216.0f) - 1.0f;
}

/** 10^u with u uniform in [lo, hi]. */
static float log_uniform(float lo, float hi)
{
    return powf(10.0f, lo + (hi - lo) * 0.5f * (uniform() + 1.0f));
}

/** An instance at STEP_SOLVE of a full window (the default configuration, any valid bank). */
static void at_solve(void)
{
    wake_hpa_config_t cfg;
    const float w0[WAKE_HPA_MAX_LEVEL] = {0.0f, 0.0f, 0.0f, 0.0f, 1.0f};
    unsigned i;
    (void)wake_hpa_default_config(&cfg);
    for (i = 0; i < LEVEL * TAPS; ++i) {
        bank[i] = (wake_q15_t)(i % 7u == 0u ? 1000 : -200);
    }
    CHECK(wake_hpa_init(&hpa, &cfg, bank, w0) == WAKE_HPA_OK, "init");
    wake_hpa_begin(&hpa, window, WINDOW, 0u);
    hpa.flag = WAKE_HPA_VALLEY;
    hpa.factor = hpa.cfg.ridge;
    hpa.attempts = 0;
    hpa.phase = STEP_SOLVE;
}

/** The solve before its guards: (G + lambda I) w = b by L D L'; 0 if a pivot is not positive and finite. */
static int reference_solve(const wake_hpa_t *h, float lambda, float *w)
{
    const unsigned n = h->cfg.level;
    float dg[WAKE_HPA_MAX_LEVEL], lo[WAKE_HPA_MAX_LEVEL * WAKE_HPA_MAX_LEVEL];
    unsigned i, j, k;
    for (j = 0; j < n; ++j) {
        float dj = h->gram[j * n + j] + lambda;
        for (k = 0; k < j; ++k) {
            dj -= lo[j * n + k] * lo[j * n + k] * dg[k];
        }
        if (!(dj > 0.0f) || !is_finite(dj)) {
            return 0;
        }
        dg[j] = dj;
        for (i = j + 1u; i < n; ++i) {
            float v = h->gram[i * n + j];
            for (k = 0; k < j; ++k) {
                v -= lo[i * n + k] * lo[j * n + k] * dg[k];
            }
            lo[i * n + j] = v / dj;
        }
    }
    for (i = 0; i < n; ++i) {
        float v = h->rhs[i];
        for (k = 0; k < i; ++k) {
            v -= lo[i * n + k] * w[k];
        }
        w[i] = v;
    }
    for (i = 0; i < n; ++i) {
        w[i] /= dg[i];
    }
    for (i = n; i-- > 0;) {
        float v = w[i];
        for (k = i + 1u; k < n; ++k) {
            v -= lo[k * n + i] * w[k];
        }
        w[i] = v;
    }
    for (i = 0; i < n; ++i) {
        if (!is_finite(w[i]) || fabsf(w[i]) > (float)WAKE_HPA_WEIGHT_LIMIT) {
            return 0;
        }
    }
    return 1;
}

/**
 * G = A'A, b = A'y of 64 random rows (float sums, as the HPA's are: G is positive semi-definite up to
 * its roundings); column j of A mixes a shared column with weight `collinear` into its own, so the
 * system runs from well-conditioned to nearly singular.  trace(G) / J as step_gram leaves it.
 */
static void psd_system(float amplitude, float collinear)
{
    float a[64][LEVEL], y[64];
    unsigned r, l, k;
    for (r = 0; r < 64u; ++r) {
        const float shared = uniform();
        for (l = 0; l < LEVEL; ++l) {
            a[r][l] = amplitude * (collinear * shared + (1.0f - collinear) * uniform());
        }
        y[r] = amplitude * (uniform() + 3.0f * a[r][0] / amplitude);
    }
    hpa.trace = 0.0f;
    for (l = 0; l < LEVEL; ++l) {
        float bl = 0.0f;
        for (k = 0; k < LEVEL; ++k) {
            float g = 0.0f;
            for (r = 0; r < 64u; ++r) {
                g += a[r][l] * a[r][k];
            }
            hpa.gram[l * LEVEL + k] = g;
        }
        for (r = 0; r < 64u; ++r) {
            bl += a[r][l] * y[r];
        }
        hpa.rhs[l] = bl;
        hpa.trace += hpa.gram[l * LEVEL + l];
    }
    hpa.scale = hpa.trace / (float)LEVEL;
}

static void test_psd_systems_unchanged(void)
{
    unsigned t, a, accepted = 0, refused = 0, differ = 0;
    for (t = 0; t < 4000u; ++t) {
        const float collinear = t % 4u == 0u ? 0.0f : 1.0f - log_uniform(-7.0f, 0.0f);
        float factor;
        at_solve();
        psd_system(sqrtf(log_uniform(-3.0f, 12.0f) / 64.0f), collinear);
        factor = hpa.cfg.ridge;
        for (a = 0; a < WAKE_HPA_RIDGE_STEPS; ++a) {
            float w[WAKE_HPA_MAX_LEVEL], ref[WAKE_HPA_MAX_LEVEL];
            const int ok = wake_hpa_solve_ridge(&hpa, factor, w);
            const int ref_ok = reference_solve(&hpa, factor * hpa.scale, ref);
            differ += (unsigned)(ok != ref_ok || (ok && memcmp(w, ref, sizeof(float) * LEVEL) != 0));
            if (ok) {
                ++accepted;
                break;
            }
            ++refused;
            factor = max_f(factor * 10.0f, RIDGE_FLOOR);
        }
    }
    printf("PSD systems: %u attempts accepted, %u refused, %u differ from the unguarded solve\n", accepted, refused,
           differ);
    CHECK(differ == 0u, "%u attempts differ", differ);
    CHECK(refused > 100u, "the nearly collinear systems must need a higher ridge (%u refusals)", refused);
}

/** Every attempt of step_solve on a system of any content: refused, or a finite result within the limit. */
static void test_any_system_finite(void)
{
    unsigned t, l, k, published = 0, gave_up = 0, bad = 0;
    for (t = 0; t < 20000u; ++t) {
        const float mag = log_uniform(-30.0f, 30.0f);
        at_solve();
        for (l = 0; l < LEVEL; ++l) {
            for (k = 0; k <= l; ++k) {
                const float g = uniform() * mag * log_uniform(-6.0f, 0.0f);
                hpa.gram[l * LEVEL + k] = g;
                hpa.gram[k * LEVEL + l] = g;
            }
            /* a diagonal of either sign, or dominant */
            hpa.gram[l * LEVEL + l] = t % 3u == 0u ? fabsf(hpa.gram[l * LEVEL + l]) * 10.0f : hpa.gram[l * LEVEL + l];
            hpa.rhs[l] = uniform() * log_uniform(-30.0f, 30.0f);
        }
        hpa.yy = uniform() * log_uniform(-30.0f, 30.0f);
        hpa.noise = log_uniform(-10.0f, 10.0f);
        hpa.scale = t % 5u == 0u ? uniform() * mag : mag * log_uniform(-8.0f, 1.0f);
        while (hpa.phase == STEP_SOLVE) {
            wake_hpa_step_solve(&hpa);
        }
        published += (hpa.result.notes & WAKE_HPA_NOTE_CLIPPED) == 0u;
        gave_up += (hpa.result.notes & WAKE_HPA_NOTE_CLIPPED) != 0u;
        for (l = 0; l < LEVEL; ++l) {
            bad += (unsigned)!(fabsf(hpa.result.weights[l]) <= (float)WAKE_HPA_WEIGHT_LIMIT);
        }
        bad += (unsigned)!(isfinite(hpa.result.fit_mse) && hpa.result.fit_mse >= 0.0f);
        bad += (unsigned)!(isfinite(hpa.result.measurement_noise) && isfinite(hpa.result.ridge));
        bad += (unsigned)(hpa.ready != 1u);
    }
    printf("systems of any content: %u fitted, %u gave up after %d attempts, %u bad results\n", published, gave_up,
           WAKE_HPA_RIDGE_STEPS, bad);
    CHECK(bad == 0u, "%u results not finite or above the limit", bad);
    CHECK(published > 1000u && gave_up > 1000u, "both ends reached (%u, %u)", published, gave_up);
}

static void test_guards_refuse(void)
{
    float w[WAKE_HPA_MAX_LEVEL];
    unsigned l;
    /* the identity: accepted */
    at_solve();
    memset(hpa.gram, 0, sizeof hpa.gram);
    for (l = 0; l < LEVEL; ++l) {
        hpa.gram[l * LEVEL + l] = 1.0f;
        hpa.rhs[l] = 0.5f;
    }
    hpa.scale = 1.0f;
    CHECK(wake_hpa_solve_ridge(&hpa, 1e-6f, w) == 1, "the identity is solved");
    CHECK(fabsf(w[0] - 0.5f) < 1e-5f, "w = b / (1 + 1e-6): %g", (double)w[0]);
    /* |G_10| above 2 trace(G) = 10: refused (a positive semi-definite G has |G_ij| <= trace(G)) */
    hpa.gram[1 * LEVEL + 0] = 10.5f;
    hpa.gram[0 * LEVEL + 1] = 10.5f;
    CHECK(wake_hpa_solve_ridge(&hpa, 1e-6f, w) == 0, "|G_ij| > 2 J scale is refused");
    /* the same G with its off-diagonal at 1 - 1e-7 relative: pivot d_1 = 2e-7 + lambda, above lambda / 2 */
    hpa.gram[1 * LEVEL + 0] = 0.9999999f;
    hpa.gram[0 * LEVEL + 1] = 0.9999999f;
    hpa.rhs[1] = 0.5f;
    CHECK(wake_hpa_solve_ridge(&hpa, 1e-6f, w) == 1, "a nearly singular but positive definite system is solved");
    /* an indefinite G (G_11 = G_10^2 - 0.015) whose pivot d_1 = 1 - 0.015 + 0.01 - 1 / 1.01 = 0.0049 lies in
       (0, lambda / 2) at lambda = 0.01: the unguarded solve takes it, the pivot floor refuses it (a positive
       semi-definite G has d_1 >= lambda) */
    hpa.gram[1 * LEVEL + 1] = 1.0f - 0.015f;
    hpa.gram[1 * LEVEL + 0] = 1.0f;
    hpa.gram[0 * LEVEL + 1] = 1.0f;
    hpa.rhs[0] = 0.0f;
    hpa.rhs[1] = 0.0f;
    CHECK(reference_solve(&hpa, 1e-2f, w) == 1, "the unguarded solve takes the small pivot");
    CHECK(wake_hpa_solve_ridge(&hpa, 1e-2f, w) == 0, "a pivot below lambda / 2 is refused");
    CHECK(wake_hpa_solve_ridge(&hpa, 1e-1f, w) == 1, "a ridge of 0.1 makes it positive definite (d_1 = 0.18)");
    /* a scale below SOLVE_MIN_SCALE: zero weights at once */
    at_solve();
    hpa.scale = SOLVE_MIN_SCALE * 0.5f;
    hpa.yy = 1.0f;
    wake_hpa_step_solve(&hpa);
    CHECK(hpa.phase != STEP_SOLVE && hpa.result.weights[0] == 0.0f && hpa.result.weights[4] == 0.0f,
          "zero weights below the smallest scale");
}

int main(void)
{
    test_guards_refuse();
    test_psd_systems_unchanged();
    test_any_system_finite();
    printf("test_wake_hpa_solve: %d passed, %d failed\n", n_passed, n_failed);
    return n_failed == 0 ? 0 : 1;
}
