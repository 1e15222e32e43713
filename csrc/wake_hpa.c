/**
 * @file wake_hpa.c
 * @brief The WAKE HPA in single precision, time-sliced (see wake_hpa.h).
 *
 * The run is a sequence of steps; each call of wake_hpa_slice() does one
 * bounded piece of one step and records where it stopped:
 *
 *   STEP_SUMS      S = sum x, T = sum t x, min and max     (chunks of the window)
 *   STEP_LAGS      sum x(t) x(t+d), d < lags                (chunks of one lag)
 *   STEP_LAG_END   centre lag d exactly                     (one slice per lag)
 *   STEP_DIAG      slide lag d's diagonal of Rxx into Rxx B' (chunks of the diagonal)
 *   STEP_LEVINSON  AR(p) by Levinson-Durbin                 (one order per slice)
 *   STEP_PSD       D(f_k) of the AR spectrum and the tremor peak (chunks of bins)
 *   STEP_CUTOFF    the valley rule                          (one slice)
 *   STEP_BINS      count the DFT bins at or below f_d       (one slice)
 *   STEP_DFT       X_m = sum x_c(t) e^{-j 2 pi m t / n}, two bins per pass (chunks of the window)
 *   STEP_BIN_START X_m and Q_m(0) from the pass's states    (one slice per bin)
 *   STEP_BIN_END   slide bin m over the fit rows into Cxy   (chunks of the 2^J rows)
 *   STEP_RAMP      the end-point line's ramp into Cxy        (chunks of the 2^J rows)
 *   STEP_GRAM      G = B (Rxx B') + mean terms, b            (one entry G[l][k] per slice)
 *   STEP_SOLVE     (G + lambda I) w = b, raising lambda      (one attempt per slice)
 *   STEP_AHEAD_START the estimate's FIR w'B of the weights just installed, the tremor-ahead sums cleared
 *                    (chunks of the 2^J taps)
 *   STEP_AHEAD_PASS  y(t), T(t), the lagged Gram, its right-hand side, the held-out sums (chunks of the window)
 *   STEP_AHEAD_SOLVE the 8-tap predictor by L D L', the held-out gain, the goal (one piece per row or column)
 *
 * Each step is one piece of work or a loop whose items a slice may share
 * out (wake.firmware.hpa_cost.STEP_NAMES lists them in this order).
 *
 * Conventions: float only (no double), no libm, no division instruction in
 * an inner loop, fixed evaluation order (build with -ffp-contract=off).
 * Integer sums are exact (bounds in wake_hpa_slice's note).
 */
#include "wake_hpa.h"

#include <string.h>

enum {
    STEP_IDLE = 0,
    STEP_SUMS,
    STEP_LAGS,
    STEP_LAG_END,
    STEP_DIAG,
    STEP_LEVINSON,
    STEP_PSD,
    STEP_CUTOFF,
    STEP_BINS,
    STEP_DFT,
    STEP_BIN_START,
    STEP_BIN_END,
    STEP_RAMP,
    STEP_GRAM,
    STEP_SOLVE,
    STEP_AHEAD_START,
    STEP_AHEAD_PASS,
    STEP_AHEAD_SOLVE
};

#define NO_PEAK 0xFFFFu

/* ------------------------------------------------------------------------ */
/* Small helpers                                                            */
/* ------------------------------------------------------------------------ */

static const float PI_F = 3.14159265358979f;

static inline int is_finite(float v)
{
    /* NaN fails v == v; +-inf fails the range test. */
    return v == v && v <= 3.4028234e38f && v >= -3.4028234e38f;
}

static inline float max_f(float a, float b) { return a > b ? a : b; }

/** A counter that sticks at UINT32_MAX instead of wrapping. */
static inline void count_up(uint32_t *c)
{
    *c = *c == UINT32_MAX ? *c : *c + 1u;
}
static inline float abs_f(float a) { return a < 0.0f ? -a : a; }

/** sin and cos of x for 0 <= x <= pi/4 (Taylor to x^9 / x^10: error below 2e-9). */
static void sin_cos_octant(float x, float *s, float *c)
{
    const float x2 = x * x;
    /* sin x = x (1 - x^2/6 (1 - x^2/20 (1 - x^2/42 (1 - x^2/72)))) */
    *s = x * (1.0f - x2 / 6.0f * (1.0f - x2 / 20.0f * (1.0f - x2 / 42.0f * (1.0f - x2 / 72.0f))));
    /* cos x = 1 - x^2/2 (1 - x^2/12 (1 - x^2/30 (1 - x^2/56 (1 - x^2/90)))) */
    *c = 1.0f - x2 / 2.0f * (1.0f - x2 / 12.0f * (1.0f - x2 / 30.0f * (1.0f - x2 / 56.0f * (1.0f - x2 / 90.0f))));
}

/**
 * cos and sin of pi num / den for 0 <= num <= den (an angle in [0, pi]).
 * The reflections to [0, pi/4] are done on the integers, so the only
 * rounding before the polynomial is one division and one product.  Their
 * tests compare a itself (a > floor(b / 2) is 2a > b for integers), so that a
 * value analysis of an angle known as an interval reduces a by them and sees
 * b - a and b - 2a stay in [0, b] (Frama-C Eva's step_psd_chunk entry).
 */
static void unit_phasor(uint32_t num, uint32_t den, float *c, float *s)
{
    float sign_c = 1.0f;
    int swap = 0;
    uint32_t a = num, b = den;     /* angle = pi a / b */
    float x, sv, cv;
    if (a > (b / 2u)) {            /* 2a > b, (pi/2, pi]: cos(pi - t) = -cos t */
        a = b - a;
        sign_c = -1.0f;
    }
    if (a > (b / 4u)) {            /* 4a > b, (pi/4, pi/2]: swap with pi/2 - t = pi (b - 2a) / 2b */
        a = b - 2u * a;
        b = 2u * b;
        swap = 1;
    }
    x = PI_F * ((float)a / (float)b);
    sin_cos_octant(x, &sv, &cv);
    *c = sign_c * (swap ? sv : cv);
    *s = swap ? cv : sv;
}

/** e^{+j 2 pi k / n} for 0 <= k < n. */
static void turn(uint32_t k, uint32_t n, float *c, float *s)
{
    if (2u * k <= n) {
        unit_phasor(2u * k, n, c, s);
    } else {
        unit_phasor(2u * (n - k), n, c, s);
        *s = -*s;
    }
}

/** min(t + step, limit): where one slice of an inner loop stops. */
static inline unsigned chunk_end(unsigned t, unsigned step, unsigned limit)
{
    const unsigned end = t + step;   /* named once: a value analysis bounds it by the comparison below */
    return (end < limit) ? end : limit;
}

/**
 * The items of a slice of an inner loop from t < limit, at most step: chunk_end(t, step, limit) - t, computed
 * from limit - t so that a value analysis, which loses the relation between a chunk's start and its end, still
 * bounds it (1 <= count <= limit - t) and what the chunk spends, count times its cost.
 */
static inline unsigned chunk_count(unsigned t, unsigned step, unsigned limit)
{
    const unsigned rest = limit - t;
    return (step < rest) ? step : rest;
}

/*
 * Cost model of the slicing, in Cortex-M4F instructions at -O2, calibrated
 * with `python -m wake.firmware.hpa_cost --calibrate` (a build with a slice
 * budget of 1 runs one loop item or one indivisible step per slice, and the
 * profiler counts each; docs/studies/hpa_c.md).  A slice spends at most
 * WAKE_HPA_SLICE_BUDGET on pieces of work (each charged COST_PIECE for its
 * set-up plus its items) and starts an indivisible step only if it fits in
 * what is left, or is the slice's first piece.  What a slice costs beyond
 * its budget is its fixed entry cost (the instance check, about 250).
 */
#define COST_PIECE 60
/** One sample of the sums pass; with the tremor ahead also its full-scale count (3 instructions). */
#if WAKE_HPA_AHEAD
#define COST_SUM 25
#else
#define COST_SUM 22
#endif
#define COST_LAG 5
/* a DFT sample with one bin, two bins: the recursion (11, 16) and its share of a block's clamps and loop
   (reinsch_run1/2; docs/studies/verification.md, "The DFT pass") */
#define COST_DFT1 14
#define COST_DFT2 20
/* a row of a bin's slide and its share of a block's clamps (step_bin_end; 60 before the clamps) */
#define COST_SLIDE 90
#define COST_RAMP 40
/** The fixed part of a chunk of the tremor-ahead pass: the rows' sums and delay line in and out of registers. */
#define COST_AHEAD_CHUNK 150
/** One tap of the tremor ahead's estimate FIR w'B (J products), and the sums' clearing with the last. */
#define COST_AHEAD_TAP (20 + 8 * WAKE_HPA_MAX_LEVEL)
#define COST_AHEAD_CLEAR 300

/** The last piece of the tremor-ahead solve (0..7 assemble G's rows, 8..15 factor its columns, 16 substitutes). */
#define AHEAD_SOLVE_LAST (2u * WAKE_HPA_AHEAD_TAPS)

#if WAKE_HPA_AHEAD
/**
 * One sample of the tremor-ahead pass in a chunk of @p k samples: the 2^J-tap FIR (two samples a turn), the
 * row, and the bins' oscillators, each run over the samples of a chunk (about 5 + 4 r instructions per bin
 * for r samples, so short runs pay more per sample); a chunk of 1..3 also pays an odd sample's FIR alone.
 */
static inline int32_t cost_ahead(const wake_hpa_t *h, unsigned k)
{
    const int32_t N = (int32_t)1 << h->cfg.level;
    return k % 4u == 0u ? 140 + 3 * N + 6 * (int32_t)h->bins : 140 + 6 * N + 10 * (int32_t)h->bins;
}
#endif

static inline unsigned items(int32_t budget, int32_t cost)
{
    return budget > cost ? (unsigned)(budget / cost) : 1u;
}

/** One bin of the AR spectrum (Clenshaw over p coefficients). */
static inline int32_t cost_psd_bin(const wake_hpa_t *h)
{
    return 100 + 10 * (int32_t)h->order;
}

/** One entry of a diagonal of Rxx into Rxx B' (the tap loops run WAKE_HPA_MAX_LEVEL times). */
#define COST_DIAG (50 + 16 * WAKE_HPA_MAX_LEVEL)

/** A Q15 tap as a float (exact: q / 2^15). */
static inline float q15_to_float(wake_q15_t q)
{
    return (float)q * (1.0f / 32768.0f);
}

/**
 * An int64 as a float without libgcc's __aeabi_l2f (about 30 instructions
 * on a Cortex-M4F): |z| split in two uint32 halves, each converted by the
 * FPU.  Two roundings instead of one (error within 1 ulp of the exact
 * value), the same on every IEEE machine.
 */
static inline float int64_to_float(int64_t z)
{
    const uint64_t m = z < 0 ? (uint64_t)0 - (uint64_t)z : (uint64_t)z;
    const float f = (float)(uint32_t)(m >> 32) * 4294967296.0f + (float)(uint32_t)m;
    return z < 0 ? -f : f;
}

/** Frequency of AR-spectrum bin k, Hz. */
static inline float psd_freq(const wake_hpa_t *h, unsigned k)
{
    return (float)k * (h->cfg.fs / (float)WAKE_HPA_PSD_GRID);
}

/** First PSD bin with frequency >= f (WAKE_HPA_PSD_GRID / 2 + 1 if none). */
static unsigned first_bin_at_or_above(const wake_hpa_t *h, float f)
{
    unsigned k = 0;
    while (k <= WAKE_HPA_PSD_GRID / 2 && psd_freq(h, k) < f) {
        ++k;
    }
    return k;
}

/** Last PSD bin with frequency <= f (0 if only bin 0). */
static unsigned last_bin_at_or_below(const wake_hpa_t *h, float f)
{
    unsigned k = 0;
    while (k + 1u <= WAKE_HPA_PSD_GRID / 2 && psd_freq(h, k + 1u) <= f) {
        ++k;
    }
    return k;
}

/**
 * The spectrum step's items t = 0 .. psd_last: the PSD bins 0 .. psd_hi + 1 in order (the tremor peak's
 * local-maximum test needs the right neighbour), then, for rule floor, the noise floor's bins: fs/2 and
 * every WAKE_HPA_FLOOR_STRIDE-th bin below it, down to floor_lo (wake.hpa.cutoff.FLOOR_STRIDE).
 */
static inline unsigned psd_last(const wake_hpa_t *h)
{
    const unsigned top = WAKE_HPA_PSD_GRID / 2u;
    if (h->cfg.rule != WAKE_HPA_RULE_FLOOR || h->floor_lo > top) {
        return h->psd_hi + 1u;
    }
    return h->psd_hi + 1u + (top - h->floor_lo) / WAKE_HPA_FLOOR_STRIDE + 1u;
}

/** The PSD bin of spectrum item t (see psd_last). */
static inline unsigned psd_bin(const wake_hpa_t *h, unsigned t)
{
    const unsigned run = h->psd_hi + 2u;
    return t < run ? t : WAKE_HPA_PSD_GRID / 2u - WAKE_HPA_FLOOR_STRIDE * (t - run);
}

/* ------------------------------------------------------------------------ */
/* Validation                                                               */
/* ------------------------------------------------------------------------ */

static int weights_ok(const float *w, unsigned J)
{
    unsigned j;
    for (j = 0; j < J; ++j) {
        /* finite and within the limit (NaN fails both tests); written on w[j] itself, so interval analysis
           bounds the weights that pass */
        if (!((w[j] <= (float)WAKE_HPA_WEIGHT_LIMIT) && (w[j] >= -(float)WAKE_HPA_WEIGHT_LIMIT))) {
            return 0;
        }
    }
    return 1;
}

static int config_ok(const wake_hpa_config_t *c)
{
    unsigned J, N, k, prev;
    const float f[] = {c->fs, c->tremor_low, c->tremor_high, c->cutoff_low, c->cutoff_high, c->shallow_high,
                       c->default_cutoff, c->min_depth_ratio, c->floor_ratio, c->edge_ratio, c->ridge,
                       c->process_noise_ratio};
    for (k = 0; k < sizeof f / sizeof f[0]; ++k) {
        if (!is_finite(f[k])) {
            return 0;
        }
    }
    if (c->level < 1 || c->level > WAKE_HPA_MAX_LEVEL || c->ar_order < 1 || c->ar_order > WAKE_HPA_MAX_ORDER) {
        return 0;
    }
    J = c->level;
    N = 1u << J;
    if (c->window > WAKE_HPA_MAX_WINDOW || c->window < 2u * N || c->window <= 2u * c->ar_order) {
        return 0;
    }
    if (!(c->fs > 0.0f) || !(c->tremor_low > 0.0f) || !(c->tremor_low < c->tremor_high) ||
        !(c->tremor_high <= c->fs / 2.0f)) {
        return 0;
    }
    if (!(c->cutoff_low > 0.0f) || !(c->cutoff_low <= c->default_cutoff) || !(c->default_cutoff <= c->cutoff_high) ||
        !(c->cutoff_high < c->fs / 2.0f) || !(c->shallow_high >= c->cutoff_low)) {
        return 0;
    }
    if (!(c->min_depth_ratio > 0.0f) || !(c->min_depth_ratio < 1.0f) || !(c->floor_ratio > 0.0f) ||
        !(c->floor_ratio < 1.0f) || !(c->edge_ratio > 0.0f) || !(c->edge_ratio < 1.0f) || !(c->ridge >= 0.0f) ||
        !(c->process_noise_ratio >= 0.0f) || c->rule > WAKE_HPA_RULE_FLOOR) {
        return 0;
    }
    /* the valley search keeps D for every bin up to cutoff_high */
    if (c->cutoff_high * (float)WAKE_HPA_PSD_GRID / c->fs >= (float)(WAKE_HPA_MAX_PSD_BINS - 1)) {
        return 0;
    }
    if (c->clean_below > c->window || c->horizon < 1u || c->horizon > WAKE_HPA_MAX_AHEAD_HORIZON) {
        return 0;
    }
    prev = 0;
    for (k = 0; k < WAKE_HPA_MAX_WARMUP && c->warmup[k] != 0u; ++k) {
        if (c->warmup[k] <= prev || c->warmup[k] < 2u * N || c->warmup[k] >= c->window) {
            return 0;
        }
        prev = c->warmup[k];
    }
    for (; k < WAKE_HPA_MAX_WARMUP; ++k) {
        if (c->warmup[k] != 0u) {
            return 0;
        }
    }
    return 1;
}

/** The bits of a float (a union: C99 defines reading the other member). */
static inline uint32_t float_bits(float f)
{
    union {
        float f;
        uint32_t u;
    } v;
    v.f = f;
    return v.u;
}

/** One FNV-1a step on a 32-bit word. */
static inline uint32_t mix(uint32_t v, uint32_t w)
{
    return (v ^ w) * UINT32_C(16777619);
}

/**
 * FNV-1a over the configuration's fields and the bins init derived from
 * them: init validates the configuration once and seals it; every later
 * call checks the seal (about 60 instructions on a Cortex-M4, where
 * re-validating cost 280).  Each step is a bijection of the running value,
 * so a change of any one field is always detected.
 */
#if WAKE_HPA_HORIZON != 1u
#error "the normal equations (step_bin_end, step_ramp, step_gram) are written for WAKE_HPA_HORIZON 1"
#endif
#if WAKE_HPA_AHEAD && !WAKE_RTP_AHEAD
#error "WAKE_HPA_AHEAD fits the predictor the RTP runs: it needs WAKE_RTP_AHEAD"
#endif
#if WAKE_HPA_AHEAD && WAKE_HPA_AHEAD_TAPS != WAKE_RTP_AHEAD_TAPS
#error "the HPA fits the predictor the RTP runs: WAKE_HPA_AHEAD_TAPS must equal WAKE_RTP_AHEAD_TAPS"
#endif
#if WAKE_HPA_MAX_WARMUP != 8
#error "seal_of() hashes eight warm-up points"
#endif
static uint32_t seal_of(const wake_hpa_t *h)
{
    const wake_hpa_config_t *c = &h->cfg;
    uint32_t v = UINT32_C(2166136261);
    v = mix(v, float_bits(c->fs));
    v = mix(v, float_bits(c->tremor_low));
    v = mix(v, float_bits(c->tremor_high));
    v = mix(v, float_bits(c->cutoff_low));
    v = mix(v, float_bits(c->cutoff_high));
    v = mix(v, float_bits(c->shallow_high));
    v = mix(v, float_bits(c->default_cutoff));
    v = mix(v, float_bits(c->min_depth_ratio));
    v = mix(v, float_bits(c->floor_ratio));
    v = mix(v, float_bits(c->edge_ratio));
    v = mix(v, float_bits(c->ridge));
    v = mix(v, float_bits(c->process_noise_ratio));
    v = mix(v, (uint32_t)c->window | (uint32_t)c->level << 16);
    v = mix(v, (uint32_t)c->ar_order | (uint32_t)c->rule << 16);
    v = mix(v, (uint32_t)c->warmup[0] | (uint32_t)c->warmup[1] << 16);
    v = mix(v, (uint32_t)c->warmup[2] | (uint32_t)c->warmup[3] << 16);
    v = mix(v, (uint32_t)c->warmup[4] | (uint32_t)c->warmup[5] << 16);
    v = mix(v, (uint32_t)c->warmup[6] | (uint32_t)c->warmup[7] << 16);
    v = mix(v, (uint32_t)c->clean_below | (uint32_t)c->horizon << 16);
    v = mix(v, (uint32_t)h->psd_lo | (uint32_t)h->psd_hi << 16);
    v = mix(v, (uint32_t)h->cut_lo | (uint32_t)h->cut_hi << 16);
    v = mix(v, (uint32_t)h->floor_lo);
    return mix(v, (uint32_t)h->cut_shallow | (uint32_t)h->gap_len << 16);
}

static wake_hpa_status_t check_instance(const wake_hpa_t *h)
{
    unsigned N;
    if (h == NULL) {
        return WAKE_HPA_E_NULL;
    }
    if (h->magic != WAKE_HPA_MAGIC) {
        return WAKE_HPA_E_UNINIT;
    }
    if (h->seal != seal_of(h) || h->fill > 1u || h->fill_len >= h->cfg.window || h->phase > STEP_AHEAD_SOLVE ||
        h->base > h->count) {
        return WAKE_HPA_E_CORRUPT;
    }
    if (h->phase == STEP_IDLE) {
        return WAKE_HPA_OK;
    }
    /* a run in progress: every counter that indexes an array within its range */
    N = 1u << h->cfg.level;
    if (h->work == NULL || h->n > h->cfg.window || h->n < 2u * N || h->rows != h->n - N - (WAKE_HPA_HORIZON - 1u) ||
        h->order > h->cfg.ar_order || h->lags > (h->order + 1u > N ? h->order + 1u : N) ||
        h->t > (h->phase == STEP_PSD ? psd_last(h) + 1u : h->n) ||
        h->d > h->lags || h->bins > h->n / 2u || h->m > h->bins + 1u || h->pair > 2u ||
        h->psd_end > psd_last(h) || h->attempts >= WAKE_HPA_RIDGE_STEPS ||
        ((h->phase == STEP_BIN_START || h->phase == STEP_BIN_END) && h->d >= h->pair) ||
        ((h->phase >= STEP_DFT) && (h->phase <= STEP_BIN_END) && (h->m == 0u)) ||
        (h->phase == STEP_RAMP && h->t >= N) || h->bins > WAKE_HPA_MAX_BINS ||
#if WAKE_HPA_AHEAD
        h->ahead_pos >= WAKE_HPA_AHEAD_RING || (h->phase == STEP_AHEAD_PASS && (h->t < N || h->t >= h->n)) ||
        (h->phase == STEP_AHEAD_SOLVE && h->d > AHEAD_SOLVE_LAST) || (h->phase == STEP_AHEAD_START && h->t >= N) ||
#else
        h->phase > STEP_SOLVE ||
#endif
        ((h->phase == STEP_DIAG) && ((h->d >= N) || (h->t > (N - h->d)))) ||
        (h->phase == STEP_GRAM && (h->d >= h->cfg.level || h->t > h->d))) {
        return WAKE_HPA_E_CORRUPT;
    }
    return WAKE_HPA_OK;
}

/* ------------------------------------------------------------------------ */
/* Public: configuration, feeding                                           */
/* ------------------------------------------------------------------------ */

wake_hpa_status_t wake_hpa_default_config(wake_hpa_config_t *cfg)
{
    if (cfg == NULL) {
        return WAKE_HPA_E_NULL;
    }
    memset(cfg, 0, sizeof *cfg);
    cfg->fs = 100.0f;
    cfg->tremor_low = 2.5f;
    cfg->tremor_high = 15.0f;
    cfg->cutoff_low = 0.5f;
    cfg->cutoff_high = 6.0f;
    cfg->shallow_high = 4.0f;
    cfg->default_cutoff = 2.0f;
    cfg->min_depth_ratio = 0.50118723f;   /* 10^(-3/10) */
    cfg->floor_ratio = 0.031622777f;      /* 10^(-15/10) */
    cfg->edge_ratio = 0.50118723f;        /* 10^(-3/10) */
    cfg->ridge = 1e-6f;
    cfg->process_noise_ratio = 0.0f;
    cfg->window = 500;
    cfg->level = 5;
    cfg->ar_order = 17;
    cfg->rule = WAKE_HPA_RULE_FLOOR;
    cfg->clean_below = 200;
    cfg->horizon = 1;
    cfg->warmup[0] = 100;
    cfg->warmup[1] = 200;
    cfg->warmup[2] = 300;
    cfg->warmup[3] = 400;
    return WAKE_HPA_OK;
}

wake_hpa_status_t wake_hpa_init(wake_hpa_t *h, const wake_hpa_config_t *cfg, const wake_q15_t *taps,
                                const float *weights)
{
    if (h == NULL || cfg == NULL || taps == NULL || weights == NULL) {
        return WAKE_HPA_E_NULL;
    }
    h->magic = 0;
    if (!config_ok(cfg) || !weights_ok(weights, cfg->level)) {
        return WAKE_HPA_E_CONFIG;
    }
    memset(h, 0, sizeof *h);
    h->cfg = *cfg;
    {
        /* the bank as floats, tap-major with a stride of WAKE_HPA_MAX_LEVEL (B[l][i] at
           tapf[i MAX_LEVEL + l], zero for l >= J): the inner loops walk l a constant number of times */
        const unsigned J = cfg->level, N = 1u << J;
        unsigned i, l;
        for (i = 0; i < N; ++i) {
            for (l = 0; l < J; ++l) {
                h->tapf[i * WAKE_HPA_MAX_LEVEL + l] = q15_to_float(taps[l * N + i]);
            }
        }
    }
    memcpy(h->weights, weights, cfg->level * sizeof weights[0]);
    h->psd_lo = (uint16_t)first_bin_at_or_above(h, cfg->tremor_low);
    h->psd_hi = (uint16_t)last_bin_at_or_below(h, cfg->tremor_high);
    if (h->psd_hi > WAKE_HPA_PSD_GRID / 2u - 1u) {
        h->psd_hi = WAKE_HPA_PSD_GRID / 2u - 1u;   /* the last bin has no right neighbour */
    }
    h->cut_lo = (uint16_t)first_bin_at_or_above(h, cfg->cutoff_low);
    h->cut_hi = (uint16_t)last_bin_at_or_below(h, cfg->cutoff_high);
    h->cut_shallow = (uint16_t)last_bin_at_or_below(h, cfg->shallow_high < cfg->cutoff_high ? cfg->shallow_high
                                                                                            : cfg->cutoff_high);
    /* the floor's bins: above tremor_high up to fs/2 (none when tremor_high reaches fs/2) */
    h->floor_lo = (uint16_t)(last_bin_at_or_below(h, cfg->tremor_high) + 1u);
    h->gap_len = (uint16_t)((cfg->window + 4u) / 5u);          /* ceil(L / 5): wake.hpa.schedule.GAP_SHARE */
    h->seal = seal_of(h);
    h->magic = WAKE_HPA_MAGIC;
    return WAKE_HPA_OK;
}

static void begin(wake_hpa_t *h, const wake_q15_t *window, uint16_t n, uint32_t index)
{
    const unsigned N = 1u << h->cfg.level;
    h->work = window;
    h->n = n;
    h->index = index;
    h->rows = (uint16_t)(n - N - (WAKE_HPA_HORIZON - 1u)); /* a(t), t = N-1 .. n-1-horizon */
    h->order = (uint16_t)(h->cfg.ar_order < (n - 1u) / 2u ? h->cfg.ar_order : (n - 1u) / 2u);
    h->lags = (uint16_t)(h->order + 1u > N ? h->order + 1u : N);
    h->t = 0;
    h->d = 0;
    h->m = 0;
    h->sum = 0;
    h->prefix_rows = 0;
    h->tsum = 0;
    h->tsum_rows = 0;
    h->lo = INT16_MAX;
    h->hi = INT16_MIN;
#if WAKE_HPA_AHEAD
    h->ahead_rail = 0;
#endif
    h->flag = WAKE_HPA_VALLEY;
    h->phase = STEP_SUMS;
    count_up(&h->runs);
}

wake_hpa_status_t wake_hpa_start(wake_hpa_t *h, const wake_q15_t *window, uint16_t n, uint32_t index)
{
    wake_hpa_status_t st = check_instance(h);
    if (st != WAKE_HPA_OK) {
        return st;
    }
    if (window == NULL) {
        return WAKE_HPA_E_NULL;
    }
    if (n < 2u * (1u << h->cfg.level) || n > h->cfg.window) {
        return WAKE_HPA_E_WINDOW;
    }
    if (h->phase != STEP_IDLE) {
        return WAKE_HPA_E_BUSY;
    }
    begin(h, window, n, index);
    return WAKE_HPA_OK;
}

/**
 * Whether a running HPA reads buffer b (a window pushed here, not a caller's).  Every window a push
 * starts begins at its buffer's first sample (feed), so the test is an equality: C defines `==` between
 * pointers into different objects (a caller's window), where `<` and `>=` are undefined.
 */
static int reads_buffer(const wake_hpa_t *h, unsigned b)
{
    return h->phase != STEP_IDLE && h->work == h->buf + (size_t)b * WAKE_HPA_MAX_WINDOW;
}

/**
 * One sample into the window buffers, and the HPA it completes (wake.hpa.schedule.HPASchedule.push):
 * a full window every L samples from the schedule's base, the warm-up points counted from it;
 * none inside a long gap; a long gap's end restarts the schedule there, in a fresh buffer.
 */
static wake_hpa_status_t feed(wake_hpa_t *h, wake_q15_t sample, int missing)
{
    wake_q15_t *fill;
    int inside;
    if (missing) {
        sample = h->last_valid;
        h->missing_run = (uint16_t)(h->missing_run + (h->missing_run < UINT16_MAX ? 1u : 0u));
    } else {
        if (h->missing_run >= h->gap_len) {
            /* the last sample ended a long gap: the schedule starts again from it (a warm-up HPA that
               reads this buffer's prefix is abandoned: its samples are about to be overwritten) */
            if (reads_buffer(h, h->fill)) {
                h->phase = STEP_IDLE;
                count_up(&h->skipped);
            }
            h->base = h->count;
            /* from its first point of clean_below samples or more: the weights in use were fitted before
               the gap, and a shorter fit does not beat them (wake.hpa.schedule.HPASchedule.point_after) */
            h->warmup_next = 0;
            while (h->warmup_next < WAKE_HPA_MAX_WARMUP && h->cfg.warmup[h->warmup_next] != 0u &&
                   h->cfg.warmup[h->warmup_next] < h->cfg.clean_below) { /* wcet-loop: WAKE_HPA_MAX_WARMUP */
                h->warmup_next = (uint16_t)(h->warmup_next + 1u);
            }
            h->fill_len = 0;
        }
        h->missing_run = 0;
        h->last_valid = sample;
    }
    inside = h->missing_run >= h->gap_len;
    fill = h->buf + (size_t)h->fill * WAKE_HPA_MAX_WINDOW;
    fill[h->fill_len] = sample;
    h->fill_len = (uint16_t)(h->fill_len + 1u);
    count_up(&h->count);
    if (h->fill_len == h->cfg.window) {
        /* a full window: the HPA reads this buffer, the next samples go to the other */
        h->fill = (uint16_t)(1u - h->fill);
        h->fill_len = 0;
        if (inside) {
            /* no HPA on a window that ends in a long gap; one still reading the other buffer stops */
            if (reads_buffer(h, h->fill)) {
                h->phase = STEP_IDLE;
                count_up(&h->overruns);
            }
            count_up(&h->gap_skipped);
            return WAKE_HPA_OK;
        }
        if (h->phase != STEP_IDLE && h->n == h->cfg.window) {
            count_up(&h->overruns);
        } else if (h->phase != STEP_IDLE) {
            /* a warm-up HPA still running: the full window supersedes it */
            count_up(&h->skipped);
        }
        begin(h, fill, h->cfg.window, h->count);
        return WAKE_HPA_STARTED;
    }
    if (h->warmup_next < WAKE_HPA_MAX_WARMUP && h->cfg.warmup[h->warmup_next] != 0u &&
        h->count - h->base == h->cfg.warmup[h->warmup_next]) {
        h->warmup_next = (uint16_t)(h->warmup_next + 1u);
        if (inside) {
            count_up(&h->gap_skipped);
            return WAKE_HPA_OK;
        }
        if (h->phase != STEP_IDLE) {
            count_up(&h->skipped);
            return WAKE_HPA_OK;
        }
        /* a warm-up window: the prefix of the buffer being filled (pushes only append) */
        begin(h, fill, h->fill_len, h->count);
        return WAKE_HPA_STARTED;
    }
    return WAKE_HPA_OK;
}

wake_hpa_status_t wake_hpa_push(wake_hpa_t *h, wake_q15_t sample)
{
    wake_hpa_status_t st = check_instance(h);
    if (st != WAKE_HPA_OK) {
        return st;
    }
    return feed(h, sample, 0);
}

wake_hpa_status_t wake_hpa_push_missing(wake_hpa_t *h)
{
    wake_hpa_status_t st = check_instance(h);
    if (st != WAKE_HPA_OK) {
        return st;
    }
    return feed(h, 0, 1);
}

/* ------------------------------------------------------------------------ */
/* The steps                                                                */
/* ------------------------------------------------------------------------ */

static void start_pass(wake_hpa_t *h);
static void next_bin(wake_hpa_t *h);

#if WAKE_HPA_AHEAD
/** Keep @p c as the predictor of this run and the one the next run scores; @p goal the gate's goal. */
static void ahead_keep(wake_hpa_t *h, const float *c, float goal)
{
    unsigned i;
    for (i = 0; i < WAKE_HPA_AHEAD_TAPS; ++i) {
        h->ahead_coef[i] = c[i];
        h->ahead_prev[i] = c[i];
    }
    h->ahead_goal = goal;
    h->ahead_prev_index = h->index;
    h->ahead_has_prev = 1;
}

/**
 * A constant window: nothing to fit and nothing to score.  The gate shuts (goal 0) and the previous
 * predictor stays (zero before the first): the next window scores it on the samples since this HPA, so
 * the gate reopens at the next HPA if the tremor comes back as it was (wake.hpa.run_hpa does the same).
 */
static void ahead_silent(wake_hpa_t *h)
{
    float kept[WAKE_HPA_AHEAD_TAPS];
    unsigned i;
    for (i = 0; i < WAKE_HPA_AHEAD_TAPS; ++i) {
        kept[i] = (h->ahead_has_prev != 0u) ? h->ahead_prev[i] : 0.0f;
    }
    ahead_keep(h, kept, 0.0f);
}

/**
 * wake.ahead.installed_goal: more than n / WAKE_HPA_GLITCH_DIVISOR samples of the window at full scale
 * (counted in STEP_SUMS) shut the gate until the next HPA.
 * @par Scaling and overflow
 * ahead_rail <= n <= WAKE_HPA_MAX_WINDOW: rail x WAKE_HPA_GLITCH_DIVISOR fits a uint32_t.
 */
static void ahead_full_scale(wake_hpa_t *h)
{
    if (((uint32_t)h->ahead_rail * WAKE_HPA_GLITCH_DIVISOR) > (uint32_t)h->n) {
        h->ahead_goal = 0.0f;
        h->result.notes = (uint16_t)(h->result.notes | (uint16_t)WAKE_HPA_NOTE_FULL_SCALE);
    }
}

#endif

static void install(wake_hpa_t *h, const float *w, float r, float mse, float ridge, uint16_t notes)
{
    unsigned j;
    wake_hpa_result_t *res = &h->result;
#if WAKE_HPA_AHEAD
    /* the result is rewritten from here to publish(), with the tremor ahead's steps (many slices) in
       between: an earlier result not taken yet is superseded now, so that take and apply never hand out
       this run's weights with the earlier run's predictor and goal */
    h->ready = 0;
#endif
    if (h->n < h->cfg.clean_below && h->flag != WAKE_HPA_VALLEY && h->flag != WAKE_HPA_FLOOR_VALLEY) {
        /* a short warm-up window without a clean valley: its fit is not installed */
        w = h->weights;
        notes = (uint16_t)(notes | WAKE_HPA_NOTE_WEIGHTS_KEPT);
    }
    for (j = 0; j < h->cfg.level; ++j) {
        res->weights[j] = w[j];
        h->weights[j] = w[j];
    }
    for (; j < WAKE_HPA_MAX_LEVEL; ++j) {
        res->weights[j] = 0.0f;
    }
    res->cutoff = h->cutoff;
    res->measurement_noise = r;
    res->fit_mse = mse;
    res->ridge = ridge;
    res->index = h->index;
    res->n = h->n;
    res->flag = h->flag;
    res->notes = notes;
    res->reserved = 0;
}

/** The run's result ready: the tremor ahead's predictor and goal beside the installed weights. */
static void publish(wake_hpa_t *h)
{
    wake_hpa_result_t *res = &h->result;
    unsigned j;
#if WAKE_HPA_AHEAD
    ahead_full_scale(h);
    for (j = 0; j < WAKE_HPA_AHEAD_TAPS; ++j) {
        res->ahead[j] = h->ahead_coef[j];
    }
    res->ahead_goal = h->ahead_goal;
#else
    for (j = 0; j < WAKE_HPA_AHEAD_TAPS; ++j) {
        res->ahead[j] = 0.0f;
    }
    res->ahead_goal = 0.0f;
#endif
    h->ready = 1;
    h->phase = STEP_IDLE;
}

/** A run that ends without a fit (a constant window): its weights, published at once. */
static void finish(wake_hpa_t *h, const float *w, float r, float mse, float ridge, uint16_t notes)
{
    install(h, w, r, mse, ridge, notes);
    publish(h);
}

/**
 * A run that ends with a fit: its weights installed, then (WAKE_HPA_AHEAD) the tremor ahead fitted on
 * the estimate those weights give, the one the predictor is fed from afterwards (wake.hpa.run_hpa).
 */
static void finish_fit(wake_hpa_t *h, const float *w, float r, float mse, float ridge, uint16_t notes)
{
    install(h, w, r, mse, ridge, notes);
#if WAKE_HPA_AHEAD
    h->t = 0;
    h->d = 0;
    h->phase = STEP_AHEAD_START;
#else
    publish(h);
#endif
}

/** S, T = sum t x(t), min, max over one chunk; a constant window ends the run (weights kept). */
static int32_t step_sums(wake_hpa_t *h, int32_t budget)
{
    const unsigned start = h->t, rows = h->rows;
    const unsigned end = chunk_end(h->t, items(budget, COST_SUM), h->n);
    const unsigned split = end < rows ? end : (start > rows ? start : rows);
    const wake_q15_t *x = h->work;
    /* n <= 1024 samples of |x| <= 2^15: the chunk's sums of x fit an int32; |t x(t)| < 2^25 fits one,
       their sums (< 2^35) need an int64 */
    int32_t head = 0, all = 0;
    int64_t thead = 0, tall = 0;
    int16_t lo = h->lo, hi = h->hi;
#if WAKE_HPA_AHEAD
    unsigned rail = h->ahead_rail;
#endif
    unsigned t;
    for (t = start; t < split; ++t) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_SUM */
        head += x[t];
        thead += (int32_t)t * x[t];
    }
    for (t = start; t < end; ++t) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_SUM */
        const wake_q15_t v = x[t];
        all += v;
        tall += (int32_t)t * v;
        lo = v < lo ? v : lo;
        hi = v > hi ? v : hi;
#if WAKE_HPA_AHEAD
        {
            /* at full scale (INT16_MAX or INT16_MIN: clipped, or on the rail): u ^ (all ones when v < 0) is
               |v| for v >= 0 and |v| - 1 for v < 0, in 0..32767, and 32767 only there; + 1 reaches 2^15 */
            const uint32_t u = (uint32_t)(int32_t)v;
            rail += ((u ^ (0u - (u >> 31))) + 1u) >> 15;
        }
#endif
    }
#if WAKE_HPA_AHEAD
    h->ahead_rail = (uint16_t)rail;   /* <= n */
#endif
    h->sum += all;
    h->tsum += tall;
    h->prefix_rows += head;
    h->tsum_rows += thead;
    h->lo = lo;
    h->hi = hi;
    h->t = (uint16_t)end;
    if (end < h->n) {
        return (int32_t)(end - start) * (COST_SUM);
    }
    if (h->lo == h->hi) {
        /* silent: R = (1e-6 max|x|)^2, default cut-off, weights kept */
        const float peak = abs_f((float)h->lo);
        h->cutoff = h->cfg.default_cutoff;
        h->flag = WAKE_HPA_SILENT;
#if WAKE_HPA_AHEAD
        ahead_silent(h);
#endif
        finish(h, h->weights, max_f(1e-6f * peak * (1e-6f * peak), 1.0f), 0.0f, h->cfg.ridge,
               WAKE_HPA_NOTE_WEIGHTS_KEPT);
        return (int32_t)(end - start) * (COST_SUM);
    }
    h->mean = (float)h->sum / (float)h->n;
    h->slope = ((float)x[h->n - 1u] - (float)x[0]) / (float)(h->n - 1u);
    h->t = 0;
    h->phase = STEP_LAGS;
    h->d = 0;
    h->acc_head = 0;
    h->acc_tail = 0;
    h->prefix_lo = 0;
    h->prefix_hi = h->prefix_rows;
    h->suffix = 0;
    memset(h->bank_rxx, 0, sizeof h->bank_rxx);
    return (int32_t)(end - start) * (COST_SUM);
}

/** sum_{t0 <= t < t1} x(t) x(t + d), exact (|x(t) x(t+d)| <= 2^30, at most 1024 terms); four per turn. */
static inline int64_t lag_run(const wake_q15_t *x, unsigned d, unsigned t0, unsigned t1)
{
    int64_t acc = 0;
    const wake_q15_t *y = x + d;
    unsigned t = t0;
    for (; t + 4u <= t1; t += 4u) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_LAG / 4 */
        acc += (int32_t)x[t] * (int32_t)y[t];
        acc += (int32_t)x[t + 1u] * (int32_t)y[t + 1u];
        acc += (int32_t)x[t + 2u] * (int32_t)y[t + 2u];
        acc += (int32_t)x[t + 3u] * (int32_t)y[t + 3u];
    }
    for (; t < t1; ++t) { /* wcet-loop: 3 */
        acc += (int32_t)x[t] * (int32_t)y[t];
    }
    return acc;
}

/** One chunk of the raw lag sum sum x(t) x(t+d): t < rows into acc_head, the rest into acc_tail. */
static int32_t step_lags(wake_hpa_t *h, int32_t budget)
{
    const unsigned start = h->t, d = h->d, rows = h->rows;
    const unsigned last = h->n - d;                  /* t < n - d */
    const unsigned end = chunk_end(start, items(budget, COST_LAG), last);
    const unsigned split = end < rows ? end : (start > rows ? start : rows);
    h->acc_head += lag_run(h->work, d, start, split);
    h->acc_tail += lag_run(h->work, d, split, end);
    h->t = (uint16_t)end;
    if (end == last) {
        h->phase = STEP_LAG_END;
    }
    return (int32_t)(end - start) * (COST_LAG);
}

/** Lag d is done: advance the prefix sums to d + 1 and go on to the next lag. */
static void next_lag(wake_hpa_t *h)
{
    const unsigned d = h->d, n = h->n, rows = h->rows;
    const wake_q15_t *x = h->work;
    h->prefix_lo += x[d];
    if (rows + d < n) {
        h->prefix_hi += x[rows + d];
    }
    h->suffix += x[n - 1u - d];
    h->acc_head = 0;
    h->acc_tail = 0;
    h->t = 0;
    h->d = (uint16_t)(d + 1u);
    h->phase = h->d < h->lags ? STEP_LAGS : STEP_LEVINSON;
}

/**
 * Lag d is summed: centre it exactly and keep r(d) for the AR fit; for
 * d < 2^J, start the walk along the diagonal Rxx(i, i + d), i = 0..2^J-1-d,
 * of the fit's window correlation (STEP_DIAG).
 *
 * With y(t) = n x(t) - S (exact, |y| < 2^26):
 *   n^2 sum_{t in T} x_c(t) x_c(t+d) = sum_{t in T} y(t) y(t+d)
 *     = n^2 sum x(t)x(t+d) - n S (sum_{t in T} x(t) + sum_{t in T} x(t+d)) + |T| S^2
 */
static void step_lag_end(wake_hpa_t *h)
{
    const unsigned d = h->d, n = h->n, rows = h->rows, N = 1u << h->cfg.level;
    const int64_t S = h->sum, nn = (int64_t)n * (int64_t)n;
    if (d <= h->order) {
        /* full range t < n - d: sum x(t) = P(n-d) = S - suffix(d), sum x(t+d) = S - P(d) */
        const int64_t raw = h->acc_head + h->acc_tail;
        const int64_t z = nn * raw - (int64_t)n * S * ((S - h->suffix) + (S - h->prefix_lo)) +
                          (int64_t)(n - d) * S * S;
        h->r[d] = (float)z;
    }
    if (d >= N) {
        next_lag(h);
        return;
    }
    /* rows t < rows: sum x(t) = P(rows), sum x(t+d) = P(rows+d) - P(d) */
    h->diag = nn * h->acc_head - (int64_t)n * S * (h->prefix_rows + (h->prefix_hi - h->prefix_lo)) +
              (int64_t)rows * S * S;
    h->wsum[d] = (float)((int64_t)n * (h->prefix_hi - h->prefix_lo) - (int64_t)rows * S) / (float)n;
    h->t = 0;
    h->phase = STEP_DIAG;
}

/** v within [-top, top] by plain comparisons, for 0 <= top <= INT64_MAX (no negation of v: no overflow). */
static inline int64_t clamp_abs_i64(int64_t v, int64_t top)
{
    return (v > top) ? top : ((v < -top) ? -top : v);
}

/**
 * The bound of diag, n^2 Rxx(i, i + d) = sum_{t = i}^{i + rows - 1} y(t) y(t + d) with y(t) = n x(t) - S.
 * y(t) = sum_u (x(t) - x(u)) over the n samples, one term 0 and each within 2^16 - 1, so |y| < n 2^16;
 * by Cauchy-Schwarz |diag| <= rows max y^2 < n^3 2^32 (rows < n): below 2^59 for n <= 512 and 2^62 for
 * n <= 1024.  diag is exact (int64 sums, no rounding), so these bound it at every row of the slide.
 * STEP_DIAG clamps diag to DIAG_MAX when a chunk loads it: the clamp never changes it (the results are
 * those of the plain slide, bit for bit); it is there so that a value analysis, whose interval for diag
 * grows by up to 2 max y^2 (2^51) per row, sees a bound that holds from chunk to chunk (Frama-C Eva's
 * step_diag_chunk entry).  2^60 is also what STEP_LAG_END's analysis shows of it (eva_hpa_steps.c, R_MAX).
 */
#if WAKE_HPA_MAX_WINDOW <= 512
#define DIAG_MAX INT64_C(1152921504606846976)    /* 2^60 */
#else
#define DIAG_MAX INT64_C(4611686018427387904)    /* 2^62 */
#endif

/**
 * One chunk of lag d's diagonal: (Rxx B')[i][l] += Rxx(i, i+d) B[l][i+d] and
 * the mirror entry, with n^2 Rxx(i, i+d) = diag slid exactly along the rows:
 *   n^2 Rxx(i+1, i+1+d) = n^2 Rxx(i, i+d) - y(i) y(i+d) + y(i+rows) y(i+rows+d).
 *
 * @par Scaling and overflow
 * |y| < 2^26 (n <= 1024) fits an int32, y y' an int64; diag is loaded through the clamp to DIAG_MAX, which
 * never fires (above), and a chunk of at most 2^J rows moves it by at most 2^J 2^53 more: within int64.
 * Rxx = diag / n^2 as a float: |Rxx| < n 2^32 <= 2^42.
 */
static int32_t step_diag(wake_hpa_t *h, int32_t budget)
{
    const unsigned d = h->d, rows = h->rows, J = h->cfg.level, N = 1u << J;
    const unsigned start = h->t, rest = (N - d) - start, step = items(budget, COST_DIAG);
    const unsigned count = chunk_count(start, step, N - d);
    const unsigned end = chunk_end(start, count, N - d);
    /* |n x| <= 2^25 and |S| <= 2^25 (n <= 1024): y = n x - S fits an int32, y y' an int64 */
    const int32_t n = (int32_t)h->n, S = (int32_t)h->sum;
    const wake_q15_t *x = h->work;
    const float inv_nn = 1.0f / ((float)n * (float)n);
    const float *tapf = h->tapf;
    float *bank = h->bank_rxx;
    int64_t z = clamp_abs_i64(h->diag, DIAG_MAX);
    unsigned i, l;
    for (i = start; i < end; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
        const float rxx = int64_to_float(z) * inv_nn;
        const float *col_d = tapf + (i + d) * WAKE_HPA_MAX_LEVEL, *col_i = tapf + i * WAKE_HPA_MAX_LEVEL;
        float *row_i = bank + i * WAKE_HPA_MAX_LEVEL, *row_id = bank + (i + d) * WAKE_HPA_MAX_LEVEL;
        for (l = 0; l < WAKE_HPA_MAX_LEVEL; ++l) { /* wcet-loop: WAKE_HPA_MAX_LEVEL (unrolled) */
            row_i[l] += rxx * col_d[l];
        }
        if (d != 0u) {
            for (l = 0; l < WAKE_HPA_MAX_LEVEL; ++l) { /* wcet-loop: WAKE_HPA_MAX_LEVEL (unrolled) */
                row_id[l] += rxx * col_i[l];
            }
        }
        if (i + d + 1u < N) {
            const int32_t y0 = n * x[i] - S, y1 = n * x[i + d] - S;
            const int32_t y2 = n * x[i + rows] - S, y3 = n * x[i + rows + d] - S;
            z += (int64_t)y2 * y3 - (int64_t)y0 * y1;
        }
    }
    h->diag = z;
    h->t = (uint16_t)end;
    if (step >= rest) {   /* end == N - d, tested on what a value analysis keeps of the chunk's start */
        next_lag(h);
    }
    return (int32_t)count * COST_DIAG;
}

/**
 * The smallest prediction error Levinson-Durbin divides by: r is n^2 times the window's centred
 * autocorrelation in LSB^2, so err < 1 is a window predicted to far below one LSB (the recursion stops
 * there, as at err <= 0).  It bounds |k| before the clamp by |acc| < 2^88 (docs/studies/verification.md).
 */
#define LEVINSON_MIN_ERR 1.0f

/**
 * One order of Levinson-Durbin on r[0..order] (wake.hpa.spectrum.levinson_durbin),
 * in a[]; h->t is the order reached, h->err its prediction error.
 */
static void step_levinson(wake_hpa_t *h)
{
    const unsigned p = h->order, m = h->t + 1u;
    float err, acc, k;
    unsigned i;
    if (h->t == 0u) {
        for (i = 0; i <= WAKE_HPA_MAX_ORDER; ++i) { /* wcet-loop: WAKE_HPA_MAX_ORDER + 1 */
            h->a[i] = 0.0f;
        }
        h->a[0] = 1.0f;
        h->err = h->r[0];
    }
    err = h->err;
    if (m <= p && err >= LEVINSON_MIN_ERR) {
        acc = h->r[m];
        for (i = 1; i < m; ++i) { /* wcet-loop: WAKE_HPA_MAX_ORDER */
            acc += h->a[i] * h->r[m - i];
        }
        /* |k| < 1 in exact arithmetic (r positive definite); err >= 1 keeps the quotient finite, and a
           rounding past +-1 is clamped: k = +-1 makes err exactly 0, which ends the recursion as a
           negative err did, so |a[i]| stays below 2^m (docs/studies/verification.md, "A whole HPA run") */
        k = -acc / err;
        k = (k > 1.0f) ? 1.0f : ((k < -1.0f) ? -1.0f : k);
        /* a[i] += k a[m - i] for i = 1..m, all from the old a: pairs (i, m - i) swap together */
        for (i = 1; 2u * i < m; ++i) { /* wcet-loop: WAKE_HPA_MAX_ORDER / 2 */
            const float ai = h->a[i], aj = h->a[m - i];
            h->a[i] = ai + k * aj;
            h->a[m - i] = aj + k * ai;
        }
        if (2u * i == m) {
            h->a[i] = h->a[i] + k * h->a[i];
        }
        h->a[m] = k; /* k * a[0] */
        err *= 1.0f - k * k;
        h->err = err;
        h->t = (uint16_t)m;
        if (m < p && err >= LEVINSON_MIN_ERR) {
            return; /* the next order in the next piece */
        }
    }
    /* all orders, or a perfectly predictable window (higher orders add nothing) */
    h->t = 0;
    h->peak = NO_PEAK;
    h->prev1 = 0.0f;
    h->prev2 = 0.0f;
    if (!(err > 0.0f)) {
        /* zero prediction error: the PSD is zero (the Python flag "silent"), the fit still runs */
        h->cutoff = h->cfg.default_cutoff;
        h->flag = WAKE_HPA_SILENT;
        h->phase = STEP_CUTOFF;
        return;
    }
    h->den_floor = 0.0f;
    /* bins up to one past the tremor band's last bin (the local-maximum test needs it); rule floor: to fs/2 */
    h->psd_end = (uint16_t)psd_last(h);
    h->phase = STEP_PSD;
}

/**
 * D(f_k) = |sum_m a_m e^{-j m theta}|^2, theta = pi k / 511, by Clenshaw:
 *   b_m = a_m + 2 cos(theta) b_{m+1} - b_{m+2}  (m = p..1)
 *   Re = a_0 + cos(theta) b_1 - b_2,  Im = sin(theta) b_1.
 * A local PSD maximum is a local minimum of D.
 */
static int32_t step_psd(wake_hpa_t *h, int32_t budget)
{
    const unsigned start = h->t;
    const unsigned count = chunk_count(start, items(budget, cost_psd_bin(h)), h->psd_end + 1u);
    const unsigned end = chunk_end(start, count, h->psd_end + 1u);
    const unsigned k_lo = h->psd_lo, k_hi = h->psd_hi, run = h->psd_hi + 2u;
    unsigned t, m;
    for (t = h->t; t < end; ++t) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_PSD_BIN */
        const unsigned k = psd_bin(h, t);
        float c, s, b1 = 0.0f, b2 = 0.0f, re, im, dk;
        unit_phasor(k, WAKE_HPA_PSD_GRID / 2u, &c, &s);
        for (m = h->order; m >= 1u; --m) { /* wcet-loop: WAKE_HPA_MAX_ORDER */
            const float b0 = h->a[m] + 2.0f * c * b1 - b2;
            b2 = b1;
            b1 = b0;
        }
        re = h->a[0] + c * b1 - b2;
        im = s * b1;
        dk = re * re + im * im;
        if (t >= run) {
            /* rule floor: the noise floor, the PSD minimum over the floor bins, is the largest D there */
            h->den_floor = dk > h->den_floor ? dk : h->den_floor;
            continue;
        }
        if (k < WAKE_HPA_MAX_PSD_BINS) {
            h->den[k] = dk;
        }
        /* bin k - 1 is a tremor peak candidate once its right neighbour is known */
        if (k >= 2u && k - 1u >= k_lo && k - 1u <= k_hi && h->prev1 <= h->prev2 && h->prev1 <= dk) {
            if (h->peak == NO_PEAK || h->prev1 < h->den_peak) {
                h->peak = (uint16_t)(k - 1u);
                h->den_peak = h->prev1;
            }
        }
        h->prev2 = h->prev1;
        h->prev1 = dk;
    }
    h->t = (uint16_t)end;
    if (end == h->psd_end + 1u) {
        h->t = 0;    /* the next steps count from 0 (t may exceed n here) */
        h->phase = STEP_CUTOFF;
    }
    return (int32_t)count * cost_psd_bin(h);
}

/** The PSD minimum (the first D maximum) over the bins cut_lo .. top. */
static unsigned psd_minimum(const wake_hpa_t *h, unsigned top)
{
    unsigned k, at = h->cut_lo;
    for (k = h->cut_lo + 1u; k <= top; ++k) { /* wcet-loop: WAKE_HPA_MAX_PSD_BINS */
        if (h->den[k] > h->den[at]) {
            at = k;
        }
    }
    return at;
}

/**
 * Rule floor: bin k lies less than floor_margin_db above the noise floor.
 * dB(k) < dB(floor) + margin  <=>  D(k) > ratio D(floor), D(floor) the largest D above tremor_high.
 * Never for the other rules, nor without floor bins.
 */
static int at_floor(const wake_hpa_t *h, unsigned k)
{
    return h->cfg.rule == WAKE_HPA_RULE_FLOOR && h->floor_lo <= WAKE_HPA_PSD_GRID / 2u &&
           h->den[k] > h->cfg.floor_ratio * h->den_floor;
}

/** The valley rule (wake.hpa.cutoff.find_cutoff) on D = sigma^2 / PSD; then the DFT bins below f_d. */
static void step_cutoff(wake_hpa_t *h)
{
    if (h->flag != WAKE_HPA_SILENT) {
        h->cutoff = h->cfg.default_cutoff;
        if (h->peak == NO_PEAK) {
            h->flag = WAKE_HPA_NO_TREMOR_PEAK;
        } else {
            const unsigned upper = h->cut_hi < h->peak ? h->cut_hi : h->peak;
            if (upper < h->cut_lo || upper - h->cut_lo + 1u < 3u) {
                h->flag = WAKE_HPA_NO_VALLEY;
            } else {
                /* PSD minimum = D maximum (first one); PSD maximum to its left = D minimum */
                unsigned k, valley = psd_minimum(h, upper);
                float left;
                int shallow;
                left = h->den[0];
                for (k = 1; k <= valley; ++k) { /* wcet-loop: WAKE_HPA_MAX_PSD_BINS */
                    left = h->den[k] < left ? h->den[k] : left;
                }
                /* dB(valley) > dB(x) - depth  <=>  D(x) > ratio D(valley) */
                shallow = h->den_peak > h->cfg.min_depth_ratio * h->den[valley] ||
                          left > h->cfg.min_depth_ratio * h->den[valley];
                if (!shallow && !at_floor(h, valley)) {
                    h->flag = WAKE_HPA_VALLEY;
                    h->cutoff = psd_freq(h, valley);
                } else if (!shallow) {
                    /* rule floor, a valley at the noise floor: walk down to where the PSD first comes
                       within edge_db of it.  dB(x) <= dB(valley) + edge  <=>  D(x) >= ratio D(valley) */
                    unsigned edge = valley;
                    while (edge > h->cut_lo && h->den[edge - 1u] >= h->cfg.edge_ratio * h->den[valley]) { /* wcet-loop: WAKE_HPA_MAX_PSD_BINS */
                        --edge;
                    }
                    h->flag = WAKE_HPA_FLOOR_VALLEY;
                    h->cutoff = psd_freq(h, edge);
                } else {
                    /* rules shallow and floor: the PSD minimum at or below min(shallow_high, peak), if 3 bins
                       or more and above the lowest bin (there the PSD rises into the peak: no dip); rule floor:
                       only a dip well above the noise floor */
                    const unsigned top = h->cut_shallow < h->peak ? h->cut_shallow : h->peak;
                    h->flag = WAKE_HPA_NO_VALLEY;
                    if (h->cfg.rule != WAKE_HPA_RULE_PAPER && top >= h->cut_lo && top - h->cut_lo + 1u >= 3u) {
                        const unsigned dip = psd_minimum(h, top);
                        if ((dip > h->cut_lo) && !at_floor(h, dip)) {
                            h->flag = WAKE_HPA_SHALLOW_VALLEY;
                            h->cutoff = psd_freq(h, dip);
                        }
                    }
                }
            }
        }
    }
    h->phase = STEP_BINS;
}

/** The DFT bins m >= 1 with m fs / n <= f_d form the voluntary ground truth: count them, start the first pass. */
static void step_bins(wake_hpa_t *h)
{
    unsigned m;
    for (m = 1; 2u * m < h->n && m <= WAKE_HPA_MAX_BINS && (float)m * (h->cfg.fs / (float)h->n) <= h->cutoff; ++m) { /* wcet-loop: WAKE_HPA_MAX_WINDOW / 2 */
    }
    h->bins = (uint16_t)(m - 1u);
    h->power = 0.0f;
    h->cross = 0.0f;
    memset(h->cxy, 0, sizeof h->cxy);
    memset(h->vhead, 0, sizeof h->vhead);
    h->d = 0;
    h->t = 0;
    h->m = 1;
    if (h->bins >= 1u) {
        start_pass(h);
    } else {
        h->phase = STEP_RAMP;
    }
}

/** Set up a DFT pass over bins m and m + 1 (or m alone if it is the last): lambda = -4 sin^2(w/2). */
static void start_pass(wake_hpa_t *h)
{
    unsigned b;
    h->pair = (uint16_t)(h->m + 1u <= h->bins ? 2u : 1u);
    for (b = 0; b < 2u; ++b) {
        float c, s = 0.0f;
        if (b < h->pair) {
            unit_phasor(h->m + b, h->n, &c, &s);   /* angle pi m / n = w / 2 */
        }
        h->lam[b] = -4.0f * s * s;
        h->gs[b] = 0.0f;
        h->gd[b] = 0.0f;
        h->hs[b] = 0.0f;
        h->hd[b] = 0.0f;
    }
    h->t = 0;
    h->phase = STEP_DFT;
}

/*
 * The DFT of one bin by Reinsch's form of the Goertzel recursion over x_c(t):
 *   s(t) = x_c(t) + 2 cos(w) s(t-1) - s(t-2) is run as d(t) = s(t) - s(t-1):
 *   d(t) = d(t-1) + x_c(t) + lambda s(t-1),  s(t) = s(t-1) + d(t),  lambda = 2 cos w - 2 = -4 sin^2(w/2)
 * (the difference form keeps the precision of the low bins, where 2 cos w is
 * close to 2).  Two bins share one read of the window.  Locals only: nothing
 * in the loop can alias the struct.
 *
 * The states' bound: s(t) = sum_{u <= t} x_c(u) sin(w (t - u + 1)) / sin w and
 * d(t) = sum_{u <= t} x_c(u) cos(w (t - u + 1/2)) / cos(w / 2), |x_c| <= 2^16.  Over
 * every n <= 512 and every bin 1 <= m < n / 2 the exact states stay below 2^31.7
 * (s) and 2^32.7 (d), and the recursion's roundings add less than 2^29.2 and
 * 2^30.2 (docs/studies/verification.md, "The DFT pass"; tests/hpa/test_reinsch_bound.py):
 * below REINSCH_S_MAX and REINSCH_D_MAX, which is what STEP_BIN_START assumes
 * (the default configuration's bins, m < 0.125 n, stay below 2^30.8 and 2^24.6).  Every REINSCH_BLOCK
 * samples and at the end of each run the states are clamped to those bounds.
 * The clamp never changes a state of a window of int16 samples (the results
 * are those of the plain recursion, bit for bit); it is there so that a value
 * analysis, whose intervals grow by a factor above 1 per sample, can see the
 * bound (Frama-C Eva's step_dft entry).  Windows above 512 samples (a build
 * with a larger WAKE_HPA_MAX_WINDOW) reach 2^33.7 and 2^34.7 (2^34.5 and 2^35.5
 * with the roundings): a bound 4 times higher there.
 */
#if WAKE_HPA_MAX_WINDOW <= 512
#define REINSCH_S_MAX 8589934592.0f     /* 2^33 */
#define REINSCH_D_MAX 17179869184.0f    /* 2^34 */
#else
#define REINSCH_S_MAX 34359738368.0f    /* 2^35 */
#define REINSCH_D_MAX 68719476736.0f    /* 2^36 */
#endif
/** Samples between two clamps of the Reinsch states: an interval grows at most 5.9-fold per sample (lambda = -4), 2^41 over 16. */
#define REINSCH_BLOCK 16u

/** v within [-top, top] by plain comparisons (a NaN passes unchanged). */
static inline float clamp_abs(float v, float top)
{
    return (v > top) ? top : ((v < -top) ? -top : v);
}

/*
 * Where the samples t0 <= t < t1 of a run are read: blocks of REINSCH_BLOCK samples from t0, the states
 * clamped after each.  A block is read as x[base + k] for k0 <= k < top <= REINSCH_BLOCK: a full block at
 * base = b, the last, shorter one as the last samples of the REINSCH_BLOCK samples before t1 (base = t1 -
 * REINSCH_BLOCK, k0 = b - base; base = 0 when t1 < REINSCH_BLOCK).  The same samples in the same order as
 * blocks of x[t], b <= t < min(b + REINSCH_BLOCK, t1); written so that every index is bounded by t1 alone
 * (base <= t1 - REINSCH_BLOCK, k < REINSCH_BLOCK), which a value analysis sees for a run that starts at any
 * t0 (a chunk of a sliced pass, Frama-C Eva's step_dft_chunk entry), where the relation between b and t1 is
 * lost.  The next block starts at next: b + REINSCH_BLOCK, or t1 after the last.
 */
typedef struct {
    unsigned base;
    unsigned k0;
    unsigned top;
    unsigned next;
} reinsch_block_t;

static inline reinsch_block_t reinsch_block(unsigned b, unsigned t1)
{
    reinsch_block_t r;
    if ((b + REINSCH_BLOCK) <= t1) {
        r.base = b;
        r.k0 = 0u;
        r.top = REINSCH_BLOCK;
        r.next = b + REINSCH_BLOCK;
    } else if (t1 >= REINSCH_BLOCK) {
        const unsigned skip = b - (t1 - REINSCH_BLOCK);   /* < REINSCH_BLOCK: the min is for the analysis */
        r.base = t1 - REINSCH_BLOCK;
        r.k0 = (skip < REINSCH_BLOCK) ? skip : REINSCH_BLOCK;
        r.top = REINSCH_BLOCK;
        r.next = t1;
    } else {
        r.base = 0u;
        r.k0 = b;
        r.top = t1;
        r.next = t1;
    }
    return r;
}

static inline void reinsch_run1(const wake_q15_t *x, unsigned t0, unsigned t1, float mean, float lam, float *s_io,
                                float *d_io)
{
    float s = *s_io, d = *d_io;
    unsigned b = t0;
    while (b < t1) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_DFT1 / REINSCH_BLOCK + 1 */
        const reinsch_block_t blk = reinsch_block(b, t1);
        const wake_q15_t *const xb = &x[blk.base];
        unsigned k;
        for (k = blk.k0; k < blk.top; ++k) { /* wcet-loop: REINSCH_BLOCK */
            const float xc = (float)xb[k] - mean;
            d = d + xc + lam * s;
            s = s + d;
        }
        s = clamp_abs(s, REINSCH_S_MAX);
        d = clamp_abs(d, REINSCH_D_MAX);
        b = blk.next;
    }
    *s_io = s;
    *d_io = d;
}

static inline void reinsch_run2(const wake_q15_t *x, unsigned t0, unsigned t1, float mean, const float *lam,
                                float *s_io, float *d_io)
{
    const float lam0 = lam[0], lam1 = lam[1];
    float s0 = s_io[0], d0 = d_io[0], s1 = s_io[1], d1 = d_io[1];
    unsigned b = t0;
    while (b < t1) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_DFT2 / REINSCH_BLOCK + 1 */
        const reinsch_block_t blk = reinsch_block(b, t1);
        const wake_q15_t *const xb = &x[blk.base];
        unsigned k;
        for (k = blk.k0; k < blk.top; ++k) { /* wcet-loop: REINSCH_BLOCK */
            const float xc = (float)xb[k] - mean;
            d0 = d0 + xc + lam0 * s0;
            s0 = s0 + d0;
            d1 = d1 + xc + lam1 * s1;
            s1 = s1 + d1;
        }
        s0 = clamp_abs(s0, REINSCH_S_MAX);
        d0 = clamp_abs(d0, REINSCH_D_MAX);
        s1 = clamp_abs(s1, REINSCH_S_MAX);
        d1 = clamp_abs(d1, REINSCH_D_MAX);
        b = blk.next;
    }
    s_io[0] = s0;
    d_io[0] = d0;
    s_io[1] = s1;
    d_io[1] = d1;
}

/** One chunk of the pass; the states at t = rows are kept for Q_m(0). */
static int32_t step_dft(wake_hpa_t *h, int32_t budget)
{
    const unsigned start = h->t, n = h->n, rows = h->rows, two = h->pair == 2u;
    const int32_t cost = two ? COST_DFT2 : COST_DFT1;
    const unsigned count = chunk_count(start, items(budget, cost), n);
    const unsigned end = chunk_end(start, count, n);
    const unsigned split = end < rows ? end : (start > rows ? start : rows);
    if (two) {
        reinsch_run2(h->work, start, split, h->mean, h->lam, h->gs, h->gd);
    } else {
        reinsch_run1(h->work, start, split, h->mean, h->lam[0], &h->gs[0], &h->gd[0]);
    }
    if (split == rows && start <= rows && end >= rows) {
        h->hs[0] = h->gs[0];
        h->hd[0] = h->gd[0];
        h->hs[1] = h->gs[1];
        h->hd[1] = h->gd[1];
    }
    if (two) {
        reinsch_run2(h->work, split, end, h->mean, h->lam, h->gs, h->gd);
    } else {
        reinsch_run1(h->work, split, end, h->mean, h->lam[0], &h->gs[0], &h->gd[0]);
    }
    h->t = (uint16_t)end;
    if (end == n) {
        h->t = 0;
        h->d = 0;
        h->phase = STEP_BIN_START;
    }
    return (int32_t)count * cost;
}

/**
 * sum_{t < T} x_c(t) e^{-j w t} from the Reinsch states after x_c(T - 1)
 * (k = m (T - 1) mod n):
 *   y = s(T-1) - e^{-j w} s(T-2) = sum_{t < T} x_c(t) e^{j w (T-1-t)},  s(T-2) = s - d,
 *   Re y = -lambda/2 s + cos(w) d,  Im y = sin(w) (s - d),  and the sum is e^{-j w (T-1)} y.
 */
static void reinsch_value(float s, float d, float lam, float cw, float sw, uint32_t k, uint32_t n, float *re,
                          float *im)
{
    const float yr = -0.5f * lam * s + cw * d, yi = sw * (s - d);
    float c, sn;
    turn(k, n, &c, &sn);
    *re = yr * c + yi * sn;
    *im = yi * c - yr * sn;
}

/**
 * One chunk of bin m's slide along the fit rows.  With v_c(t) = (2/n) Re
 * sum_m X_m e^{j w t} (w = 2 pi m / n) and Q_m(i) = sum_{s=i}^{i+rows-1}
 * x_c(s) e^{-j w s}:
 *   Cxy(i) = sum_s x_c(s) v_c(s + N - i) = (2/n) Re sum_m X_m e^{j w (N - i)} conj(Q_m(i))
 *   Q_m(i+1) = Q_m(i) - x_c(i) e^{-j w i} + x_c(i + rows) e^{-j w (i + rows)}
 * and v_c(t) for t < N (the targets the fit does not use) into vhead.  The
 * phasors e^{j w (N - i)}, e^{j w i}, e^{j w (rows + i)} advance by one
 * rotation each row (32 rotations drift by a few ulp).
 *
 * @par Scaling and overflow
 * The state a chunk carries to the next, Q_m and the six phasor parts, is clamped at the start of every
 * block of SLIDE_BLOCK rows, the first where a chunk loads it (clamp_abs: Q_m to SLIDE_Q_MAX, each part to
 * PHASOR_MAX); a chunk stores it as its last block leaves it, and the next chunk's first block clamps it.
 * The bounds: turn() and unit_phasor() give parts within 1 and a modulus within 2^-20 of 1, and
 * each rotation by (cw, sw), itself of modulus within 2^-20 of 1 and rounded to float, multiplies a
 * phasor's modulus by less than 1 + 2^-19, so the 2^J <= 64 rows of a slide keep every modulus, and so
 * every part, below (1 + 2^-20)(1 + 2^-19)^64 < 1 + 2^-12 < PHASOR_MAX = 1 + 2^-8 (the largest part on
 * real windows: 1 + 1.1e-6).  Q_m(0) comes from the Reinsch states within REINSCH_S_MAX and REINSCH_D_MAX
 * (reinsch_value: |Re y| <= 2 |s| + |d|, |Im y| <= |s| + |d|, so each part within 4 REINSCH_D_MAX), and
 * |Q_m(i)| <= rows max |x_c| < n 2^16 (2^25 for n <= 512) at every row (the largest part seen: 2^23.3),
 * below SLIDE_Q_MAX = 4 REINSCH_D_MAX.  The clamps never fire on a window of int16 samples (the results
 * are those of the plain slide, bit for bit, the same operations in the same order per row); they are
 * there for a value analysis of a chunk from any row (Frama-C Eva's step_bin_end_chunk entry), whose
 * interval of a phasor grows by a factor up to |cos w| + |sin w| <= 2^(1/2) per rotation: 2^16 over 32
 * rows, but at most 2^(3/2) over the 3 rotations before the last row of a block of 4.  A row's term of
 * vhead, (2/n) Re(X'_m e^{j w i}), then stays within (2/n) 2 |X'| PHASOR_MAX 2^(3/2), 2^35.5 for n >= 64
 * and |X'| <= 2^38 (2^34.9 for n >= 100, 2^34.5 at the default schedule's top bin), below half an ulp of
 * vhead's envelope 2^60 (2^36): float addition keeps the sum inside.  A block of 5 rows would give 2^36
 * for n = 64, so 4.  Q_m's interval grows by less than 2^21 per row, additively, but without a bound on
 * the rows between two of its clamps none of its intervals is an invariant of the block loop (a value
 * analysis joins the blocks there), so it is clamped with the phasors.  Cost: two comparisons per clamp,
 * eight clamps per block of 4 rows (none after a chunk's last block: a chunk's fixed cost stays small).
 * The chunk counts its rows with chunk_count, as the other float chunks, and tests the slide's end as
 * step >= rest (the rows the budget buys against the rows left), as step_diag.
 */
#define PHASOR_MAX 1.00390625f              /* 1 + 2^-8 */
#define SLIDE_Q_MAX (4.0f * REINSCH_D_MAX)
/** Rows of a slide between two clamps of its phasors (above). */
#define SLIDE_BLOCK 4u

static int32_t step_bin_end(wake_hpa_t *h, int32_t budget)
{
    const unsigned n = h->n, rows = h->rows, N = 1u << h->cfg.level;
    const unsigned start = h->t;
    const unsigned rest = N - start;
    const unsigned step = items(budget, COST_SLIDE);
    const unsigned count = chunk_count(start, step, N);
    const unsigned end = chunk_end(start, count, N);
    const float scale = 2.0f / (float)n, mean = h->mean, xr = h->xr, xi = h->xi;
    const float cw = h->rot[0], sw = h->rot[1];
    float qr = h->qr;
    float qi = h->qi;
    float ac = h->ph[0];
    float as = h->ph[1];
    float ic = h->ph[2];
    float is = h->ph[3];
    float rc = h->ph[4];
    float rs = h->ph[5];
    float t0, t1;
    unsigned i = start;
    do { /* wcet-loop: WAKE_HPA_MAX_TAPS / SLIDE_BLOCK */
        unsigned k;
        qr = clamp_abs(qr, SLIDE_Q_MAX);
        qi = clamp_abs(qi, SLIDE_Q_MAX);
        ac = clamp_abs(ac, PHASOR_MAX);
        as = clamp_abs(as, PHASOR_MAX);
        ic = clamp_abs(ic, PHASOR_MAX);
        is = clamp_abs(is, PHASOR_MAX);
        rc = clamp_abs(rc, PHASOR_MAX);
        rs = clamp_abs(rs, PHASOR_MAX);
        for (k = 0u; k < SLIDE_BLOCK; ++k) { /* wcet-loop: SLIDE_BLOCK */
            float xc;
            float pr;
            float pi;
            if (i >= end) {
                break;
            }
            pr = xr * ac - xi * as;       /* P = X e^{j w (N - i)} */
            pi = xr * as + xi * ac;
            h->cxy[i] += scale * (pr * qr + pi * qi);
            h->vhead[i] += scale * (xr * ic - xi * is);
            xc = (float)h->work[i] - mean;
            qr -= xc * ic;
            qi += xc * is;
            xc = (float)h->work[i + rows] - mean;
            qr += xc * rc;
            qi -= xc * rs;
            /* e^{j w (N - i - 1)} = e^{j w (N - i)} e^{-j w};  the others times e^{j w} */
            t0 = ac * cw + as * sw;
            t1 = as * cw - ac * sw;
            ac = t0;
            as = t1;
            t0 = ic * cw - is * sw;
            t1 = is * cw + ic * sw;
            ic = t0;
            is = t1;
            t0 = rc * cw - rs * sw;
            t1 = rs * cw + rc * sw;
            rc = t0;
            rs = t1;
            ++i;
        }
    } while (i < end);   /* a chunk has at least one row; with none, its first block would stop at once */
    h->qr = qr;
    h->qi = qi;
    h->ph[0] = ac;
    h->ph[1] = as;
    h->ph[2] = ic;
    h->ph[3] = is;
    h->ph[4] = rc;
    h->ph[5] = rs;
    h->t = (uint16_t)end;
    if (step >= rest) {   /* end == N, tested on what a value analysis keeps of the chunk's start */
        next_bin(h);
    }
    return (int32_t)count * COST_SLIDE;
}

/**
 * X'_m and Q_m(0) of the pass's bin h->d from its Reinsch states; the slide's start phasors.
 * The truth is the low bins of x minus its end-point line (wake.hpa.sharp.detrended_highpass):
 * the line's ramp slope t has the DFT R_m = sum t e^{-j w t} = -n/2 + j (n/2) cot(w/2) (m != 0),
 * so its bins are X'_m = X_m - slope R_m, and the ramp itself goes back into the targets in STEP_RAMP.
 */
static void step_bin_start(wake_hpa_t *h)
{
    const unsigned n = h->n, rows = h->rows, N = 1u << h->cfg.level, b = h->d, m = h->m + b;
    const float half_n = 0.5f * (float)n;
    float cw, sw, ch, sh, rr, ri;
    unit_phasor(2u * m, n, &cw, &sw);   /* e^{j w}, w = 2 pi m / n <= pi */
    reinsch_value(h->gs[b], h->gd[b], h->lam[b], cw, sw, (m * (n - 1u)) % n, n, &h->xr, &h->xi);
    reinsch_value(h->hs[b], h->hd[b], h->lam[b], cw, sw, (m * (rows - 1u)) % n, n, &h->qr, &h->qi);
    unit_phasor(m, n, &ch, &sh);        /* w / 2 in (0, pi/2): sh > 0 */
    rr = -half_n;
    ri = half_n * ch / sh;
    /* X' = X - slope R */
    h->xr -= h->slope * rr;
    h->xi -= h->slope * ri;
    h->power += h->xr * h->xr + h->xi * h->xi;
    /* Re(X' conj(R)) */
    h->cross += h->xr * rr + h->xi * ri;
    h->rot[0] = cw;
    h->rot[1] = sw;
    turn((N * m) % n, n, &h->ph[0], &h->ph[1]);
    /* the tremor ahead's pass starts at t = N: X'_m e^{j w N}, and turns by e^{j w} per sample */
#if WAKE_HPA_AHEAD
    {
        /* Z = X' e^{j w N};  v(N) = (2/n) Re Z,  v(N) - v(N-1) = (2/n) Re(Z (1 - e^{-j w})) */
        const float zr = h->xr * h->ph[0] - h->xi * h->ph[1], zi = h->xr * h->ph[1] + h->xi * h->ph[0];
        const float two_n = 2.0f / (float)n;
        const unsigned at = 3u * (m - 1u);
        h->bin_osc[at] = two_n * zr;
        h->bin_osc[at + 1u] = two_n * (-0.5f * h->lam[b] * zr - sw * zi);
        h->bin_osc[at + 2u] = h->lam[b];
    }
#endif
    h->ph[2] = 1.0f;
    h->ph[3] = 0.0f;
    turn((rows * m) % n, n, &h->ph[4], &h->ph[5]);
    h->t = 0;
    h->phase = STEP_BIN_END;
}

/** The pass's bin h->d is slid: its next bin, the next pass, or the Gram step. */
static void next_bin(wake_hpa_t *h)
{
    h->t = 0;
    if (h->d + 1u < h->pair) {
        h->d = (uint16_t)(h->d + 1u);
        h->phase = STEP_BIN_START;
        return;
    }
    h->d = 0;
    h->m = (uint16_t)(h->m + h->pair);
    if (h->m <= h->bins) {
        start_pass(h);
    } else {
        h->phase = STEP_RAMP;
    }
}

#if WAKE_HPA_AHEAD
static int32_t round_clamp(float v, float lo, float hi);

/** Tap i of the estimate's FIR w'B in Q20 (oldest tap first), from the weights the run installs. */
static inline void ahead_fir_tap(wake_hpa_t *h, unsigned i)
{
    float f = 0.0f;
    unsigned l;
    for (l = 0; l < h->cfg.level; ++l) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        f += h->weights[l] * h->tapf[i * WAKE_HPA_MAX_LEVEL + l];
    }
    /* |w| <= 32, |B| < 1: |f| < 2^11, so f 2^20 fits an int32 */
    h->ahead_fir[i] = round_clamp(f * 1048576.0f, -2147483520.0f, 2147483520.0f);
}

#endif

/**
 * One chunk of the end-point line's ramp r(t) = t - (n-1)/2 into the targets
 * (wake.hpa.sharp.detrended_highpass; the low bins already hold X' = X - slope R):
 *   Cxy(i) += slope sum_{u < rows} x_c(i + u) r(i + u + N - i) = slope (U(i) + (N - (n-1)/2) wsum(i))
 *   vhead(i) += slope r(i)
 * with U(i) = sum_{u < rows} u x_c(i + u), U(0) = sum_{t < rows} t x(t) - mu rows (rows-1) / 2 from the
 * exact sum, and U(i+1) = U(i) + rows x_c(i + rows) - wsum(i + 1).
 */
static int32_t step_ramp(wake_hpa_t *h, int32_t budget)
{
    const unsigned n = h->n, rows = h->rows, N = 1u << h->cfg.level;
    const unsigned start = h->t;
    const unsigned count = chunk_count(start, items(budget, COST_RAMP), N);
    const unsigned end = chunk_end(start, count, N);
    const float slope = h->slope, mu = h->mean, fr = (float)rows;
    const float lead = (float)N - 0.5f * (float)(n - 1u), centre = 0.5f * (float)(n - 1u);
    const wake_q15_t *x = h->work;
    float u = start == 0u ? int64_to_float(h->tsum_rows) - mu * (0.5f * fr * (fr - 1.0f)) : h->ramp_u;
    unsigned i;
    for (i = start; i < end; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
        h->cxy[i] += slope * (u + lead * h->wsum[i]);
        h->vhead[i] += slope * ((float)i - centre);
        if (i + 1u < N) {
            u += fr * ((float)x[i + rows] - mu) - h->wsum[i + 1u];
        }
    }
    h->ramp_u = u;
    h->t = (uint16_t)end;
    if (end == N) {
        h->t = 0;
        h->d = 0;
        h->phase = STEP_GRAM;
    }
    return (int32_t)count * COST_RAMP;
}

#if WAKE_HPA_AHEAD
/*
 * The tremor ahead (wake.ahead; docs/studies/hpa_c.md, "The tremor ahead").  Over the window, WAKE's own tremor
 * estimate with the weights in use, and the window's tremor truth:
 *   y(t) = x(t) - w . a(t-1) = x(t) - sum_i (w'B)_i x(t - N + i),                       t = N .. n-1
 *   T(t) = x_c(t) - slope r(t) - sum_m v_m(t),  v_m(t) = (2/n) Re X'_m e^{j w_m t}  (x minus the voluntary truth)
 * each v_m by Reinsch's oscillator e += lambda v, v += e (the DFT passes' recursion run forwards).
 * The direct h-step predictor on the rows k = k0 .. k1 (k0 = N + 7, k1 = n - 1 - h; full history inside):
 *   G_ij = sum_k y(k-i) y(k-j),  b_i = sum_k y(k-i) T(k+h),  c = clip((G + 1e-3 trace(G)/8 I)^-1 b, +-8)
 * with G from the 8 lag sums g_d = sum_k y(k) y(k-d) of the rows and their edges (i <= j, d = j - i):
 *   G_ij = g_d + sum_{k = k0-i}^{k0-1} y(k) y(k-d) - sum_{k = k1-i+1}^{k1} y(k) y(k-d)
 * and the previous predictor's held-out gain over the targets new since the previous HPA:
 *   gain = clip(<T, P> / <P, P>, 0, 1),  P(k + h) = c_prev . (y(k) .. y(k-7))
 */

/** Every row of the fit is a held-out target (an HPA every L samples): <T, P>, <P, P> come from b and G. */
static inline int ahead_all_held(const wake_hpa_t *h)
{
    return h->ahead_held == (1u << h->cfg.level) + WAKE_HPA_AHEAD_TAPS - 1u + h->cfg.horizon;
}

/** The ahead sums cleared, the held-out targets' start; then the pass. */
static void ahead_clear(wake_hpa_t *h)
{
    const unsigned N = 1u << h->cfg.level, hz = h->cfg.horizon, len = h->n - N;
    unsigned first, i;
    for (i = 0; i < WAKE_HPA_AHEAD_TAPS; ++i) {
        h->ahead_lag[i] = 0.0f;
        h->ahead_rhs[i] = 0.0f;
    }
    for (i = 0; i < WAKE_HPA_AHEAD_RING; ++i) {
        h->ahead_ring[i] = 0.0f;
    }
    h->ahead_tp = 0.0f;
    h->ahead_pp = 0.0f;
    h->ahead_pos = WAKE_HPA_AHEAD_RING - 1u;   /* the first estimate goes to ring[0] */
    /* wake.ahead.held_out_gain: targets from max(len - new, 7 + h) of the estimate, at least 10 of them */
    first = WAKE_HPA_AHEAD_TAPS - 1u + hz;
    if (h->ahead_has_prev != 0u && h->index - h->ahead_prev_index < len) {
        const unsigned fresh = len - (unsigned)(h->index - h->ahead_prev_index);
        first = fresh > first ? fresh : first;
    }
    h->ahead_held = (uint16_t)(h->ahead_has_prev != 0u && first + 10u <= len ? N + first : h->n);
    h->t = (uint16_t)N;
    h->phase = STEP_AHEAD_PASS;
}

/** One chunk of the estimate's FIR w'B from the weights just installed; with its last tap, the clearing. */
static int32_t step_ahead_start(wake_hpa_t *h, int32_t budget)
{
    const unsigned N = 1u << h->cfg.level, start = h->t;
    const unsigned end = chunk_end(start, items(budget - COST_AHEAD_CLEAR, COST_AHEAD_TAP), N);
    unsigned i;
    for (i = start; i < end; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
        ahead_fir_tap(h, i);
    }
    h->t = (uint16_t)end;
    if (end < N) {
        return (int32_t)(end - start) * COST_AHEAD_TAP;
    }
    ahead_clear(h);
    return (int32_t)(end - start) * COST_AHEAD_TAP + COST_AHEAD_CLEAR;
}

/** Samples of one block of the pass: the truth's oscillators and the estimate's FIR advance a block at a time. */
#define AHEAD_BLOCK 8u

/**
 * y(t), y(t + 1) of two samples: x minus the RTP's voluntary prediction from the 2^J samples before each.
 * Each tap is read once for both outputs and each sample once for two taps.
 * @par Scaling and overflow
 * Q15 samples times Q20 taps (|tap| < 2^31): each product below 2^46, 2^J <= 64 of them below 2^52 in an
 * int64, exact in any order; one rounding to float each.
 */
static inline void ahead_estimate2(const int32_t *fir, const wake_q15_t *x, unsigned t, unsigned N, float *y)
{
    const wake_q15_t *p = &x[t - N];
    int64_t a0 = 0, a1 = 0;
    int32_t xa = p[0];
    unsigned i;
    for (i = 0; i + 4u <= N; i += 4u) { /* wcet-loop: WAKE_HPA_MAX_TAPS / 4 */
        const int32_t f0 = fir[i], f1 = fir[i + 1u], f2 = fir[i + 2u], f3 = fir[i + 3u];
        int32_t xb = p[i + 1u];
        a0 += (int64_t)f0 * xa;
        a1 += (int64_t)f0 * xb;
        xa = p[i + 2u];
        a0 += (int64_t)f1 * xb;
        a1 += (int64_t)f1 * xa;
        xb = p[i + 3u];
        a0 += (int64_t)f2 * xa;
        a1 += (int64_t)f2 * xb;
        xa = p[i + 4u];                 /* i + 4 <= N: at most x(t + 1) */
        a0 += (int64_t)f3 * xb;
        a1 += (int64_t)f3 * xa;
    }
    for (; i < N; i += 2u) { /* wcet-loop: 1 */
        const int32_t f0 = fir[i], f1 = fir[i + 1u], xb = p[i + 1u];
        a0 += (int64_t)f0 * xa;
        a1 += (int64_t)f0 * xb;
        xa = p[i + 2u];                 /* i + 2 <= N: at most x(t + 1) */
        a0 += (int64_t)f1 * xb;
        a1 += (int64_t)f1 * xa;
    }
    y[0] = (float)x[t] - int64_to_float(a0) * (1.0f / 1048576.0f);
    y[1] = (float)x[t + 1u] - int64_to_float(a1) * (1.0f / 1048576.0f);
}

/** y(t) of one sample (a block's odd last one): as ahead_estimate2. */
static inline float ahead_estimate(const int32_t *fir, const wake_q15_t *x, unsigned t, unsigned N)
{
    const unsigned first = t - N;
    int64_t acc = 0;
    unsigned i;
    for (i = 0; i < N; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
        acc += (int64_t)fir[i] * x[first + i];
    }
    return (float)x[t] - int64_to_float(acc) * (1.0f / 1048576.0f);
}

/*
 * sum_m v_m(t) of the voluntary truth's bins for a block of samples from t, each oscillator moved on by
 * Reinsch's recursion run forwards (e += lambda v;  v += e).  v[q] sums the bins in the order m = 1, 2, ...,
 * whatever the block, so the blocks' sizes do not change a bit of the result; each run (of eight, four, two
 * or one samples) keeps its sums in registers, and stores each oscillator clamped (ahead_osc_store).
 *
 * The oscillators' bound.  In exact arithmetic v(t) = (2/n) Re Z e^{j w (t - N)} and its increment
 * e(t) = v(t) - v(t-1) = (2/n) Re Z e^{j w (t - N)} (1 - e^{-j w}), |Z| = |X'_m|, so |v| <= (2/n) |X'_m| and
 * |e| <= 2 sin(w/2) (2/n) |X'_m|.  For a window of int16 samples (|x_c| <= 2^16) |X_m| <= n 2^16, and the
 * end-point line's part is |slope R_m| <= (2^16 / (n - 1)) (n/2) / sin(pi m / n) <= 2^16 n^2 / (4 (n - 1)), so
 * (2/n) |X'_m| < 2^17 + 2^16: |v| < 2^18, |e| < 2^19.  The computed states differ from these by the roundings
 * of the DFT pass and the bins' start (below 2^31.3 in X'_m for n <= 512, docs/studies/verification.md, "The DFT
 * pass": below 2^27 in (2/n) X'_m for n >= 2 2^J = 64) and of the recursion, whose matrix [[1, lambda],
 * [1, 1 + lambda]] has determinant 1 and eigenvalues e^{+-j w}: an error d in a state moves the later states
 * by at most about d / sin(w/2) <= d n / 2, so the roundings of up to 1,024 samples, each below 3 u of the
 * state's bound (u = 2^-24), add less than 1024 x 3 u x 512 < 10 % to it.  So |v| < 2^28 and |e| < 2^29 on every
 * window; AHEAD_V_MAX and AHEAD_E_MAX are 2^7 times those, and also hold what STEP_BIN_START guarantees,
 * |X'_m| <= 2^38: (2/n) 2^38 <= 2^35 and 2^36 for every n >= 16.  The clamp never changes a state of a window
 * of int16 samples (the results are those of the plain recursion, bit for bit); it is there so that a value
 * analysis, whose intervals grow by up to 3 + 2 sqrt 2 per sample (lambda = -4) while the exact recursion
 * rotates, sees a bound: from the clamp bounds a block of AHEAD_BLOCK samples reaches |v| < 2^53.1 (2^58 over
 * 30 bins) before the next clamp, far below FLT_MAX (Frama-C Eva's step_ahead_pass_chunk entry,
 * docs/studies/verification.md, "The tremor-ahead build").
 */
#define AHEAD_V_MAX 34359738368.0f      /* 2^35 */
#define AHEAD_E_MAX 68719476736.0f      /* 2^36 */

/**
 * Oscillator m's state (v, e) back after a run of samples, each clamped to its bound (clamp_abs): one test of
 * both on the path every window takes (four comparisons and branches; two clamps' conditional moves cost more).
 */
static inline void ahead_osc_store(float *osc, float v, float e)
{
    if (v <= AHEAD_V_MAX && v >= -AHEAD_V_MAX && e <= AHEAD_E_MAX && e >= -AHEAD_E_MAX) {
        osc[0] = v;
        osc[1] = e;
    } else {
        osc[0] = clamp_abs(v, AHEAD_V_MAX);
        osc[1] = clamp_abs(e, AHEAD_E_MAX);
    }
}

static void ahead_voluntary8(float *osc, unsigned bins, float *v)
{
    float v0 = 0.0f, v1 = 0.0f, v2 = 0.0f, v3 = 0.0f, v4 = 0.0f, v5 = 0.0f, v6 = 0.0f, v7 = 0.0f;
    unsigned m;
    for (m = 0; m < bins; ++m) { /* wcet-loop: WAKE_HPA_MAX_BINS */
        float vm = osc[3u * m], e = osc[3u * m + 1u];
        const float lam = osc[3u * m + 2u];
        v0 += vm; e += lam * vm; vm += e;
        v1 += vm; e += lam * vm; vm += e;
        v2 += vm; e += lam * vm; vm += e;
        v3 += vm; e += lam * vm; vm += e;
        v4 += vm; e += lam * vm; vm += e;
        v5 += vm; e += lam * vm; vm += e;
        v6 += vm; e += lam * vm; vm += e;
        v7 += vm; e += lam * vm; vm += e;
        ahead_osc_store(&osc[3u * m], vm, e);
    }
    v[0] = v0; v[1] = v1; v[2] = v2; v[3] = v3; v[4] = v4; v[5] = v5; v[6] = v6; v[7] = v7;
}

static void ahead_voluntary4(float *osc, unsigned bins, float *v)
{
    float v0 = 0.0f, v1 = 0.0f, v2 = 0.0f, v3 = 0.0f;
    unsigned m;
    for (m = 0; m < bins; ++m) { /* wcet-loop: WAKE_HPA_MAX_BINS */
        float vm = osc[3u * m], e = osc[3u * m + 1u];
        const float lam = osc[3u * m + 2u];
        v0 += vm; e += lam * vm; vm += e;
        v1 += vm; e += lam * vm; vm += e;
        v2 += vm; e += lam * vm; vm += e;
        v3 += vm; e += lam * vm; vm += e;
        ahead_osc_store(&osc[3u * m], vm, e);
    }
    v[0] = v0; v[1] = v1; v[2] = v2; v[3] = v3;
}

static void ahead_voluntary2(float *osc, unsigned bins, float *v)
{
    float v0 = 0.0f, v1 = 0.0f;
    unsigned m;
    for (m = 0; m < bins; ++m) { /* wcet-loop: WAKE_HPA_MAX_BINS */
        float vm = osc[3u * m], e = osc[3u * m + 1u];
        const float lam = osc[3u * m + 2u];
        v0 += vm; e += lam * vm; vm += e;
        v1 += vm; e += lam * vm; vm += e;
        ahead_osc_store(&osc[3u * m], vm, e);
    }
    v[0] = v0; v[1] = v1;
}

static void ahead_voluntary1(float *osc, unsigned bins, float *v)
{
    float v0 = 0.0f;
    unsigned m;
    for (m = 0; m < bins; ++m) { /* wcet-loop: WAKE_HPA_MAX_BINS */
        float vm = osc[3u * m], e = osc[3u * m + 1u];
        const float lam = osc[3u * m + 2u];
        v0 += vm; e += lam * vm; vm += e;
        ahead_osc_store(&osc[3u * m], vm, e);
    }
    v[0] = v0;
}

/**
 * @p count <= AHEAD_BLOCK samples: eight at once, or in runs of four, two and one (below eight, at most one of
 * each: a value analysis sees the offsets 0, 4 and 6 without relating them to the count).
 */
static void ahead_voluntary(float *osc, unsigned bins, unsigned count, float *v)
{
    if (count == AHEAD_BLOCK) {
        ahead_voluntary8(osc, bins, v);
    } else {
        unsigned q = 0;
        if (count >= 4u) {
            ahead_voluntary4(osc, bins, v);
            q = 4u;
        }
        if (q + 2u <= count) {
            ahead_voluntary2(osc, bins, &v[q]);
            q += 2u;
        }
        if (q < count) {
            ahead_voluntary1(osc, bins, &v[q]);
        }
    }
}

/**
 * The ring index of y(t - 1) at the pass's sample t (ahead_clear starts the ring at its last index for t = 2^J): a
 * chunk of the pass takes its ring position from its start, and hands on the one of its end, so that its ring
 * indices depend on t alone, not on a field carried between chunks (a value analysis of a chunk from any t sees
 * them; in a run the two are the same).
 */
static inline unsigned ahead_ring_pos(unsigned t, unsigned N)
{
    return (WAKE_HPA_AHEAD_RING - 1u + t - N) % WAKE_HPA_AHEAD_RING;
}

/** The ring index @p back samples before @p pos. */
static inline unsigned ring_back(unsigned pos, unsigned back)
{
    return pos >= back ? pos - back : pos + WAKE_HPA_AHEAD_RING - back;
}

/**
 * The rows k = t - h of one block (t = t0 .. t0 + count - 1, @p target[q] = T(t0 + q)), their products added
 * to the sums in the order the rows come (the result does not depend on the blocks or the slicing).  The
 * row's u_i = y(k - i) run as a delay line in registers, started from the ring (@p pos: the ring index of
 * y(t0 - 1)): u shifts by one per row, u_0 = y(t - h) from the ring.  The previous predictor's P(t) = c_prev . u only on held-out
 * targets.
 */
static void ahead_rows(wake_hpa_t *h, const float *target, unsigned t0, unsigned count, unsigned pos)
{
    const unsigned N = 1u << h->cfg.level, hz = h->cfg.horizon;
    const unsigned first_row = N + WAKE_HPA_AHEAD_TAPS - 1u + hz;
    /* every row held out: the solve takes <T, P> and <P, P> from b and G instead (ahead_held_out) */
    const unsigned held = ahead_all_held(h) ? h->n : h->ahead_held;
    const float *ring = h->ahead_ring, *prev = h->ahead_prev;
    float *lag = h->ahead_lag, *rhs = h->ahead_rhs;
    float u[WAKE_HPA_AHEAD_TAPS];
    float l0 = lag[0], l1 = lag[1], l2 = lag[2], l3 = lag[3], l4 = lag[4], l5 = lag[5], l6 = lag[6], l7 = lag[7];
    float r0 = rhs[0], r1 = rhs[1], r2 = rhs[2], r3 = rhs[3], r4 = rhs[4], r5 = rhs[5], r6 = rhs[6], r7 = rhs[7];
    float u0, u1, u2, u3, u4, u5, u6, u7;
    unsigned q;
    for (q = 0; q < WAKE_HPA_AHEAD_TAPS; ++q) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
        /* the previous row's y(t0 - 1 - h - q), 0 before y(2^J) */
        u[q] = t0 >= N + 1u + hz + q ? ring[ring_back(pos, hz + q)] : 0.0f;
    }
    u0 = u[0]; u1 = u[1]; u2 = u[2]; u3 = u[3]; u4 = u[4]; u5 = u[5]; u6 = u[6]; u7 = u[7];
    for (q = 0; q < count; ++q) { /* wcet-loop: AHEAD_BLOCK */
        const unsigned t = t0 + q;
        const float tq = target[q];
        pos = pos + 1u < WAKE_HPA_AHEAD_RING ? pos + 1u : 0u;
        u7 = u6; u6 = u5; u5 = u4; u4 = u3; u3 = u2; u2 = u1; u1 = u0;
        u0 = t >= N + hz ? ring[ring_back(pos, hz)] : 0.0f;
        if (t >= first_row) {
            /* g_d += y(k) y(k - d);  b_i += y(k - i) T(k + h) */
            l0 += u0 * u0; l1 += u0 * u1; l2 += u0 * u2; l3 += u0 * u3;
            l4 += u0 * u4; l5 += u0 * u5; l6 += u0 * u6; l7 += u0 * u7;
            r0 += u0 * tq; r1 += u1 * tq; r2 += u2 * tq; r3 += u3 * tq;
            r4 += u4 * tq; r5 += u5 * tq; r6 += u6 * tq; r7 += u7 * tq;
            if (t >= held) {
                float p = 0.0f;
                p += prev[0] * u0; p += prev[1] * u1; p += prev[2] * u2; p += prev[3] * u3;
                p += prev[4] * u4; p += prev[5] * u5; p += prev[6] * u6; p += prev[7] * u7;
                h->ahead_tp += tq * p;
                h->ahead_pp += p * p;
            }
        }
    }
    lag[0] = l0; lag[1] = l1; lag[2] = l2; lag[3] = l3; lag[4] = l4; lag[5] = l5; lag[6] = l6; lag[7] = l7;
    rhs[0] = r0; rhs[1] = r1; rhs[2] = r2; rhs[3] = r3; rhs[4] = r4; rhs[5] = r5; rhs[6] = r6; rhs[7] = r7;
}

/** Samples a chunk of the pass takes within @p budget: whole blocks of four where there is room for them. */
static inline unsigned ahead_items(const wake_hpa_t *h, int32_t budget)
{
    const unsigned k = items(budget - COST_AHEAD_CHUNK, cost_ahead(h, 4u));
    return k >= 4u ? k - k % 4u : items(budget - COST_AHEAD_CHUNK, cost_ahead(h, 1u));
}

/**
 * One block of the pass: samples t .. t + count - 1 (count <= AHEAD_BLOCK), @p pos the ring index of y(t - 1):
 * the block's truth T(t) = x_c(t) - slope r(t) - sum_m v_m(t) and estimates y(t) (into the ring), then its rows.
 * A function of its own (inlined: one call) so that a value analysis keeps a block's states apart by its count
 * inside it and joins them between blocks.
 */
static void ahead_block(wake_hpa_t *h, unsigned t, unsigned count, unsigned pos)
{
    const unsigned N = 1u << h->cfg.level;
    const float centre = 0.5f * (float)(h->n - 1u), mean = h->mean, slope = h->slope;
    const wake_q15_t *x = h->work;
    float *ring = h->ahead_ring;
    float vol[AHEAD_BLOCK], y[AHEAD_BLOCK];
    unsigned q;
    /* the block reads only the elements it writes; zeroed so that a value analysis, which joins blocks of
       different counts, sees every element it reads initialised and bounded (stores, not a call) */
    for (q = 0; q < AHEAD_BLOCK; q += 2u) { /* wcet-loop: AHEAD_BLOCK / 2 */
        vol[q] = 0.0f;
        vol[q + 1u] = 0.0f;
        y[q] = 0.0f;
        y[q + 1u] = 0.0f;
    }
    ahead_voluntary(h->bin_osc, h->bins, count, vol);
    for (q = 0; q + 2u <= count; q += 2u) { /* wcet-loop: AHEAD_BLOCK / 2 */
        ahead_estimate2(h->ahead_fir, x, t + q, N, &y[q]);
    }
    if (q < count) {
        y[q] = ahead_estimate(h->ahead_fir, x, t + q, N);
    }
    for (q = 0; q < count; ++q) { /* wcet-loop: AHEAD_BLOCK */
        const unsigned s = t + q, at = pos + 1u + q;
        ring[at < WAKE_HPA_AHEAD_RING ? at : at - WAKE_HPA_AHEAD_RING] = y[q];
        if (s < N + WAKE_HPA_AHEAD_TAPS) {
            h->ahead_head[s - N] = y[q];
        }
        vol[q] = (((float)x[s] - mean) - slope * ((float)s - centre)) - vol[q];
    }
    ahead_rows(h, vol, t, count, pos);
}

/**
 * The pass's samples start .. end - 1, a block of up to AHEAD_BLOCK samples at a time (ahead_block).  A function of its
 * own (inlined: one call) so that a value analysis can join the states of its blocks without joining the chunk's ends.
 */
static void ahead_blocks(wake_hpa_t *h, unsigned start, unsigned end)
{
    unsigned t = start, pos = ahead_ring_pos(start, 1u << h->cfg.level);
    while (t < end) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_AHEAD / (AHEAD_BLOCK / 2) */
        const unsigned left = end - t;   /* named once: a value analysis bounds the count by the comparison */
        const unsigned count = left < AHEAD_BLOCK ? left : AHEAD_BLOCK;
        ahead_block(h, t, count, pos);
        pos += count;   /* < RING + AHEAD_BLOCK; the wrap tests pos itself, which a value analysis bounds */
        pos = pos < WAKE_HPA_AHEAD_RING ? pos : pos - WAKE_HPA_AHEAD_RING;
        t += count;
    }
}

/** One chunk of the pass over t = N .. n-1 (ahead_blocks); the ring position of its end for the next chunk. */
static int32_t step_ahead_pass(wake_hpa_t *h, int32_t budget)
{
    const unsigned N = 1u << h->cfg.level, n = h->n;
    const unsigned start = h->t, k = chunk_count(start, ahead_items(h, budget), n), end = chunk_end(start, k, n);
    ahead_blocks(h, start, end);
    if (end == n) {
        h->ahead_pos = (uint16_t)ahead_ring_pos(n, N);   /* of n, not end: a value analysis relates it to n */
        h->t = 0;
        h->d = 0;
        h->phase = STEP_AHEAD_SOLVE;
    } else {
        h->ahead_pos = (uint16_t)ahead_ring_pos(end, N);
        h->t = (uint16_t)end;
    }
    return COST_AHEAD_CHUNK + (int32_t)k * cost_ahead(h, k);   /* k = end - start, bounded by n - start */
}

/** y(k) of the pass's last rows (k within WAKE_HPA_AHEAD_RING of n - 1). */
static inline float ahead_tail(const wake_hpa_t *h, unsigned k)
{
    const unsigned back = (h->n - 1u) - k;
    return h->ahead_ring[h->ahead_pos >= back ? h->ahead_pos - back : h->ahead_pos + WAKE_HPA_AHEAD_RING - back];
}

/**
 * The previous predictor's held-out sums when every row is held out (the steady state: an HPA every L
 * samples), from the sums of the fit instead of a product per row: with P(k + h) = c_prev . u(k),
 *   <T, P> = sum_k T(k + h) c_prev . u(k) = c_prev . b,    <P, P> = c_prev' G c_prev
 * (G before its ridge, read from the upper triangle).
 */
static void ahead_held_out(wake_hpa_t *h)
{
    const unsigned P = WAKE_HPA_AHEAD_TAPS;
    const float *g = h->ahead_gram, *c = h->ahead_prev;
    float tp = 0.0f, pp = 0.0f;
    unsigned i, j;
    for (i = 0; i < P; ++i) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
        float gc = 0.0f;
        for (j = 0; j < P; ++j) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
            gc += (i <= j ? g[i * P + j] : g[j * P + i]) * c[j];
        }
        tp += c[i] * h->ahead_rhs[i];
        pp += c[i] * gc;
    }
    h->ahead_tp = tp;
    h->ahead_pp = pp;
}

/** Row i of G (upper triangle) from the lag sums and the rows' edges; after the last, the ridge (-1: nothing
 *  to fit). */
static void ahead_assemble(wake_hpa_t *h, unsigned i)
{
    const unsigned P = WAKE_HPA_AHEAD_TAPS, N = 1u << h->cfg.level, hz = h->cfg.horizon;
    const unsigned k0 = N + P - 1u;
    unsigned j, k;
    /* fewer than two rows: zeros (wake.ahead.fit_predictor) */
    if (h->n < k0 + hz + 2u) {
        h->ahead_ridge = -1.0f;
        return;
    }
    {
        const unsigned k1 = h->n - 1u - hz;
        for (j = i; j < P; ++j) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
            const unsigned d = j - i;
            float g = h->ahead_lag[d];
            for (k = k0 - i; k < k0; ++k) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
                g += h->ahead_head[k - N] * h->ahead_head[k - d - N];
            }
            for (k = k1 + 1u - i; k <= k1; ++k) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
                g -= ahead_tail(h, k) * ahead_tail(h, k - d);
            }
            h->ahead_gram[i * P + j] = g;
        }
    }
    if (i + 1u == P) {
        float trace = 0.0f;
        for (j = 0; j < P; ++j) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
            trace += h->ahead_gram[j * P + j];
        }
        /* no power: zeros */
        h->ahead_ridge = trace > 0.0f && is_finite(trace) ? 1e-3f * trace / (float)P : -1.0f;
        if (ahead_all_held(h)) {
            ahead_held_out(h);
        }
    }
}

/**
 * Column j of (G + ridge I) = L D L' in place (no square root): D on the diagonal, L below it, G read
 * from the upper triangle; a pivot not positive and finite: nothing to fit (ridge -1).
 */
static void ahead_factor(wake_hpa_t *h, unsigned j)
{
    const unsigned P = WAKE_HPA_AHEAD_TAPS;
    float *g = h->ahead_gram;
    float dj;
    unsigned i, k;
    if (!(h->ahead_ridge > 0.0f)) {
        return;
    }
    /* d_j = M_jj + ridge - sum_k L_jk^2 d_k */
    dj = g[j * P + j] + h->ahead_ridge;
    for (k = 0; k < j; ++k) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
        dj -= g[j * P + k] * g[j * P + k] * g[k * P + k];
    }
    if (!(dj > 0.0f) || !is_finite(dj)) {
        h->ahead_ridge = -1.0f;
        return;
    }
    g[j * P + j] = dj;
    /* L_ij = (M_ji - sum_k L_ik L_jk d_k) / d_j */
    for (i = j + 1u; i < P; ++i) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
        float v = g[j * P + i];
        for (k = 0; k < j; ++k) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
            v -= g[i * P + k] * g[j * P + k] * g[k * P + k];
        }
        g[i * P + j] = v / dj;
    }
}

/** L z = b;  D y = z;  L' c = y;  each c clipped to +-8 (wake.ahead.COEFFICIENT_LIMIT). */
static void ahead_substitute(const float *g, const float *b, float *c)
{
    const unsigned P = WAKE_HPA_AHEAD_TAPS;
    unsigned i, r, k;
    for (i = 0; i < P; ++i) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
        float v = b[i];
        for (k = 0; k < i; ++k) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
            v -= g[i * P + k] * c[k];
        }
        c[i] = v;
    }
    for (i = 0; i < P; ++i) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
        c[i] /= g[i * P + i];
    }
    for (r = 0; r < P; ++r) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
        float v;
        i = P - 1u - r;
        v = c[i];
        for (k = i + 1u; k < P; ++k) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
            v -= g[k * P + i] * c[k];
        }
        c[i] = v;
    }
    for (i = 0; i < P; ++i) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
        c[i] = c[i] > 8.0f ? 8.0f : (c[i] < -8.0f ? -8.0f : (is_finite(c[i]) ? c[i] : 0.0f));
    }
}

/** One piece of the solve (h->d: 0..7 a row of G, 8..15 factor a column, 16 the predictor, gain and goal). */
static void step_ahead_solve(wake_hpa_t *h)
{
    float c[WAKE_HPA_AHEAD_TAPS], gain = 0.0f;
    unsigned i;
    if (h->d < WAKE_HPA_AHEAD_TAPS) {
        ahead_assemble(h, h->d);
        h->d = (uint16_t)(h->d + 1u);
        return;
    }
    if (h->d < AHEAD_SOLVE_LAST) {
        ahead_factor(h, h->d - WAKE_HPA_AHEAD_TAPS);
        h->d = (uint16_t)(h->d + 1u);
        return;
    }
    for (i = 0; i < WAKE_HPA_AHEAD_TAPS; ++i) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
        c[i] = 0.0f;
    }
    if (h->ahead_ridge > 0.0f) {
        ahead_substitute(h->ahead_gram, h->ahead_rhs, c);
    }
    if (h->ahead_held < h->n && h->ahead_pp > 0.0f && is_finite(h->ahead_pp)) {
        gain = h->ahead_tp / h->ahead_pp;
        gain = gain > 1.0f ? 1.0f : (gain > 0.0f ? gain : 0.0f);   /* NaN: 0 */
    }
    /* wake.ahead.gate_target: no tremor peak, nothing to predict */
    if (h->flag == WAKE_HPA_NO_TREMOR_PEAK || h->flag == WAKE_HPA_SILENT) {
        gain = 0.0f;
    }
    ahead_keep(h, c, gain);
    publish(h);
}

#endif

/**
 * The normal equations of the causal fit from the centred sums.  With the
 * window mean mu, A = A_c + mu 1 s' (s = row sums of B) and y = y_c + mu 1:
 *   G  = B (Rxx B') + mu (c s' + s c') + rows mu^2 s s',   c = A_c'1 = B wsum
 *   b  = B Cxy + mu c + mu sy s + rows mu^2 s,             sy = 1'y_c = -sum vhead
 * The centred target is v_c(t) = F(t) + slope r(t): F the low bins X' of x_c
 * minus the end-point line, r(t) = t - (n-1)/2 the line's ramp (STEP_RAMP has
 * put the ramp's part into Cxy and vhead), and with sum F = sum r = 0,
 * sum r^2 = n (n^2-1)/12:
 *   y'y = (2/n) (sum |X'_m|^2 + 2 slope sum Re X'_m conj R_m) + slope^2 sum r^2
 *         - sum vhead^2 + 2 mu sy + rows mu^2
 *   R  = max((sum x_c^2 - 2 slope sum x_c r + slope^2 sum r^2 - (2/n) sum |X'_m|^2) / n, 1e-6 var x)
 */
static void step_gram(wake_hpa_t *h)
{
    const unsigned J = h->cfg.level, N = 1u << J, l = h->d, k = h->t;
    const float mu = h->mean, fr = (float)h->rows;
    float g = 0.0f;
    unsigned i;
    if (k == 0u) {
        /* row l's first piece: s_l, c_l = (B wsum)_l, (B Cxy)_l */
        float sl = 0.0f, cl = 0.0f, bl = 0.0f;
        if (l == 0u) {
            h->sy = 0.0f;
            h->vv = 0.0f;
            h->trace = 0.0f;
            for (i = 0; i < N; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
                h->sy -= h->vhead[i];
                h->vv += h->vhead[i] * h->vhead[i];
            }
        }
        for (i = 0; i < N; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
            const float b = h->tapf[i * WAKE_HPA_MAX_LEVEL + l];
            sl += b;
            cl += b * h->wsum[i];
            bl += b * h->cxy[i];
        }
        h->rowsum[l] = sl;
        h->colsum[l] = cl;
        h->rhs[l] = bl + mu * cl + mu * h->sy * sl + fr * mu * mu * sl;
    }
    /* one entry G[l][k], k <= l, per piece */
    for (i = 0; i < N; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
        g += h->tapf[i * WAKE_HPA_MAX_LEVEL + l] * h->bank_rxx[i * WAKE_HPA_MAX_LEVEL + k];
    }
    g += mu * (h->colsum[l] * h->rowsum[k] + h->rowsum[l] * h->colsum[k]) +
         fr * mu * mu * h->rowsum[l] * h->rowsum[k];
    h->gram[l * J + k] = g;
    h->gram[k * J + l] = g;
    if (k < l) {
        h->t = (uint16_t)(k + 1u);
        return;
    }
    h->trace += g;
    h->t = 0;
    h->d = (uint16_t)(l + 1u);
    if (h->d < J) {
        return;
    }
    {
        const float fn = (float)h->n, slope = h->slope;
        const float sum_sq = h->r[0] / (fn * fn);             /* sum x_c^2 */
        const float var = sum_sq / fn;
        const float ramp_sq = fn * (fn * fn - 1.0f) / 12.0f;  /* sum r^2 */
        /* sum x_c r = T - (n-1) S / 2, exact as 2T - (n-1) S */
        const float x_ramp = 0.5f * int64_to_float(2 * h->tsum - (int64_t)(h->n - 1u) * h->sum);
        const float line_sq = slope * slope * ramp_sq;
        h->yy = (h->power + 2.0f * slope * h->cross) * (2.0f / fn) + line_sq - h->vv + 2.0f * mu * h->sy +
                fr * mu * mu;
        h->noise = max_f((sum_sq - 2.0f * slope * x_ramp + line_sq - h->power * (2.0f / fn)) / fn, 1e-6f * var);
        h->scale = h->trace / (float)J;
        h->factor = h->cfg.ridge;
        h->attempts = 0;
        h->phase = STEP_SOLVE;
    }
}

/** e_L^2 = (w'Gw - 2 w'b + y'y) / rows, at least 0. */
static float fit_mse(const wake_hpa_t *h, const float *w)
{
    const unsigned J = h->cfg.level;
    float q = h->yy;
    unsigned l, k;
    for (l = 0; l < J; ++l) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        float gw = 0.0f;
        for (k = 0; k < J; ++k) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            gw += h->gram[l * J + k] * w[k];
        }
        q += w[l] * (gw - 2.0f * h->rhs[l]);
    }
    return max_f(q / (float)h->rows, 0.0f);
}

/**
 * The smallest mean diagonal trace(G) / J of a system the solve takes (LSB^2): below it the regressors are
 * zero to far below one LSB and the fit gives zero weights, as at trace(G) <= 0.  It keeps the ridge
 * factor scale (>= 1e-6 2^-80 at the default ridge) a normal float, so the pivot floor below is one.
 */
#define SOLVE_MIN_SCALE 8.2718061e-25f /* 2^-80 */
/** The smallest ridge factor once the ridge has risen (and the one the bounds of a ridge below it assume). */
#define RIDGE_FLOOR 1e-9f
/** A pivot d_j below PIVOT_FLOOR lambda refuses the attempt (d_j >= lambda when G is positive semi-definite). */
#define PIVOT_FLOOR 0.5f
/** Doublings of the bound on |L_ij| from 1 (solve_bounds): 2^18 squared is above 2^36 > 4 (2 J + f) / f. */
#define LMAX_DOUBLINGS 18u

/**
 * The bounds of one ridge attempt (factor, scale = trace(G) / J), each a guard of solve_ridge that a positive
 * semi-definite G never reaches (docs/studies/verification.md, "The solve"): with M = G + lambda I, lambda = factor
 * scale, and the pivots d_j >= PIVOT_FLOOR lambda,
 *   |G_ij| <= sqrt(G_ii G_jj) <= trace(G)                           -> gmax = 2 J scale
 *   L_ij^2 d_j <= M_ii <= (2 J + factor) scale                      -> |L_ij| <= lmax, the smallest power of two
 *                                                                      with lmax^2 >= 2 (2 J + factor) / (PIVOT_FLOOR factor)
 *   z = D L' w, so |w| <= 32 gives |z_i| <= d_i 32 (1 + (J - 1) lmax) -> zlim = 64 (1 + (J - 1) lmax) (2 J + factor) scale
 * Each holds with a factor of 2 (sqrt 2 for lmax) to spare for the roundings.
 */
typedef struct {
    float lambda; /**< the ridge factor scale */
    float dmin;   /**< the smallest pivot, PIVOT_FLOOR lambda */
    float gmax;   /**< the largest |G_ij| */
    float lmax;   /**< the largest |L_ij| */
    float zlim;   /**< the largest |z_i| of L z = b */
} solve_bounds_t;

static solve_bounds_t solve_bounds(unsigned J, float factor, float scale)
{
    const float f = max_f(factor, RIDGE_FLOOR);
    const float side = (2.0f * (float)J) + f;
    const float need = (2.0f * side) / (PIVOT_FLOOR * f);
    solve_bounds_t s;
    unsigned n;
    s.lambda = factor * scale;
    s.dmin = PIVOT_FLOOR * s.lambda;
    s.gmax = 2.0f * (float)J * scale;
    s.lmax = 1.0f;
    /* need <= 4 (2 J + f) / f < 2^36 for J <= WAKE_HPA_MAX_LEVEL and f >= RIDGE_FLOOR: 18 doublings at most */
    for (n = 0; n < LMAX_DOUBLINGS; ++n) { /* wcet-loop: 18 */
        if ((s.lmax * s.lmax) < need) {
            s.lmax *= 2.0f;
        }
    }
    s.zlim = 64.0f * (1.0f + (((float)J - 1.0f) * s.lmax)) * side * scale;
    return s;
}

/**
 * G + lambda I = L D L' (no square root), D in dg, L below the diagonal of h->chol; 0 if a bound of @p s
 * is not kept (a pivot below the floor or not finite, |G_ij| or |L_ij| above its bound).
 */
static int factor_ridge(wake_hpa_t *h, const solve_bounds_t *s, float *dg)
{
    const unsigned J = h->cfg.level;
    float *L = h->chol;
    unsigned i, j, k;
    for (j = 0; j < J; ++j) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        /* d_j = M_jj - sum_k L_jk^2 d_k, in [dmin, M_jj] (each term subtracted is >= 0) */
        const float gjj = h->gram[j * J + j];
        float top;
        float dj;
        if (!((gjj <= s->gmax) && (gjj >= -s->gmax))) {
            return 0;
        }
        top = gjj + s->lambda;
        dj = top;
        for (k = 0; k < j; ++k) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            dj -= L[j * J + k] * L[j * J + k] * dg[k];
        }
        if (!(dj > 0.0f) || !(dj >= s->dmin) || !(dj <= top) || !is_finite(dj)) { /* NaN fails each */
            return 0;
        }
        dg[j] = dj;
        /* L_ij = (M_ij - sum_k L_ik L_jk d_k) / d_j */
        for (i = j + 1u; i < J; ++i) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            const float gij = h->gram[i * J + j];
            float v;
            float lij;
            if (!((gij <= s->gmax) && (gij >= -s->gmax))) {
                return 0;
            }
            v = gij;
            for (k = 0; k < j; ++k) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
                v -= L[i * J + k] * L[j * J + k] * dg[k];
            }
            lij = v / dj;
            if (!((lij <= s->lmax) && (lij >= -s->lmax))) {
                return 0;
            }
            L[i * J + j] = lij;
        }
    }
    return 1;
}

/**
 * (G + factor scale I) w = b by L D L' (no square root); 0 (the ridge rises) if a bound of solve_bounds
 * is not kept or a weight is not finite or above the limit.
 */
static int solve_ridge(wake_hpa_t *h, float factor, float *w)
{
    const unsigned J = h->cfg.level;
    const solve_bounds_t s = solve_bounds(J, factor, h->scale);
    const float *L = h->chol;
    float dg[WAKE_HPA_MAX_LEVEL];
    unsigned i;
    unsigned k;
    if (!factor_ridge(h, &s, dg)) {
        return 0;
    }
    /* L z = b (|z_i| <= zlim);  D y = z;  L' w = y */
    for (i = 0; i < J; ++i) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        float v = h->rhs[i];
        for (k = 0; k < i; ++k) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            v -= L[i * J + k] * w[k];
        }
        if (!((v <= s.zlim) && (v >= -s.zlim))) {
            return 0;
        }
        w[i] = v;
    }
    for (i = 0; i < J; ++i) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        w[i] /= dg[i];
    }
    for (i = J; i-- > 0;) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        float v = w[i];
        for (k = i + 1u; k < J; ++k) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            v -= L[k * J + i] * w[k];
        }
        w[i] = v;
    }
    return weights_ok(w, J);
}

/** One ridge attempt (wake.hpa.fit.fit_weights: the ridge rises tenfold until |w| <= 32). */
static void step_solve(wake_hpa_t *h)
{
    const unsigned J = h->cfg.level;
    float *w = h->trial;
    unsigned j;
    if (!(h->scale >= SOLVE_MIN_SCALE) || !is_finite(h->scale)) {
        for (j = 0; j < J; ++j) {
            w[j] = 0.0f;
        }
        finish_fit(h, w, h->noise, max_f(h->yy / (float)h->rows, 0.0f), h->cfg.ridge, 0u);
        return;
    }
    if (solve_ridge(h, h->factor, w)) {
        finish_fit(h, w, h->noise, fit_mse(h, w), h->factor,
               h->factor > h->cfg.ridge ? (uint16_t)WAKE_HPA_NOTE_REGULARISED : (uint16_t)0u);
        return;
    }
    h->attempts = (uint16_t)(h->attempts + 1u);
    h->factor = max_f(h->factor * 10.0f, RIDGE_FLOOR);
    if (h->attempts >= WAKE_HPA_RIDGE_STEPS) {
        /* a ridge of 1e7 trace(G) still fails: zero weights, never NaN */
        for (j = 0; j < J; ++j) {
            w[j] = 0.0f;
        }
        finish_fit(h, w, h->noise, max_f(h->yy / (float)h->rows, 0.0f), h->factor,
               (uint16_t)(WAKE_HPA_NOTE_REGULARISED | WAKE_HPA_NOTE_CLIPPED));
    }
}

/* ------------------------------------------------------------------------ */
/* Public: running, results                                                 */
/* ------------------------------------------------------------------------ */

/**
 * Cost of the next indivisible step, or of one item of a loop step (without COST_PIECE).  The contract is what
 * run_pieces' termination proof assumes (docs/studies/verification.md, "Termination"): Eva shows it in the default
 * configuration on every phase, from any 16-bit counter t (the dispatch entries); by reading, in any
 * configuration wake_hpa.h and config_ok admit: at least COST_LAG, at most Levinson's 80 + 12 (t + 1) +
 * 2 WAKE_HPA_MAX_ORDER < 10^6 for any t (t < p <= 255 in a run: 3,662), the cut-off's 400 + 26 cut_hi <= 13,660 (cut_hi <=
 * WAKE_HPA_MAX_PSD_BINS - 2), the Gram entry's 160 + 28 2^J <= 7,328, every other below 7,000.
 */
/*@ requires \valid_read(h);
    assigns \nothing;
    ensures 1 <= \result <= 1000000;
*/
static int32_t piece_cost(const wake_hpa_t *h)
{
    const int32_t J = (int32_t)h->cfg.level, N = (int32_t)1 << J;
    switch (h->phase) {
    case STEP_LAG_END:
        return 150;
    case STEP_LEVINSON:
        /* order t + 1 (the first piece also clears a[]) */
        return 80 + 12 * ((int32_t)h->t + 1) + (h->t == 0u ? 2 * WAKE_HPA_MAX_ORDER : 0);
    case STEP_CUTOFF:
        /* the valley and left searches, the shallow minimum, rule floor's edge walk */
        return 400 + 20 * (int32_t)h->cut_hi + 6 * (int32_t)h->cut_shallow;
    case STEP_BINS:
        /* the count stops at f_d <= cutoff_high: at most cutoff_high n / fs bins */
        return 450 + 10 * (int32_t)(h->cfg.cutoff_high * ((float)h->n / h->cfg.fs));
    case STEP_BIN_START:
        return 450;
    case STEP_GRAM:
        /* one entry; a row's first also sums the row, and the first row the targets */
        return 60 + 8 * N + (h->t == 0u ? 12 * N : 0) + (h->t == 0u && h->d == 0u ? 8 * N : 0) +
               (h->t == h->d && h->d + 1u == h->cfg.level ? 100 : 0);
    case STEP_SOLVE:
        /* the factorisation and substitutions, plus the bounds of the guards (18 doublings) and the guards */
        return 6 * J * J * J + 12 * J * J + 500;
#if WAKE_HPA_AHEAD
    case STEP_AHEAD_START:
        return COST_AHEAD_TAP;
    case STEP_AHEAD_SOLVE:
        /* a row of G with up to 14 edge products per entry (the last with the held-out sums from b and G when
           every row is held out); a column: up to 7 x 8 products; the substitution, gain and goal */
        if (h->d == AHEAD_SOLVE_LAST) {
            return 950;
        }
        if (h->d < WAKE_HPA_AHEAD_TAPS) {
            return h->d + 1u == WAKE_HPA_AHEAD_TAPS && ahead_all_held(h) ? 1300 : 700;
        }
        return 300;
    case STEP_AHEAD_PASS:
        return COST_AHEAD_CHUNK + cost_ahead(h, 1u);
#endif
    case STEP_SUMS:
        return COST_SUM;
    case STEP_LAGS:
        return COST_LAG;
    case STEP_DIAG:
        return COST_DIAG;
    case STEP_PSD:
        return cost_psd_bin(h);
    case STEP_DFT:
        return h->pair == 2u ? COST_DFT2 : COST_DFT1;
    case STEP_RAMP:
        return COST_RAMP;
    default: /* STEP_BIN_END */
        return COST_SLIDE;
    }
}

/** Run the current step within @p budget (@p fixed: an indivisible step's piece_cost); returns what it spent. */
static int32_t run_step(wake_hpa_t *h, int32_t budget, int32_t fixed)
{
    switch (h->phase) {
    case STEP_SUMS:
        return step_sums(h, budget);
    case STEP_LAGS:
        return step_lags(h, budget);
    case STEP_DIAG:
        return step_diag(h, budget);
    case STEP_PSD:
        return step_psd(h, budget);
    case STEP_DFT:
        return step_dft(h, budget);
    case STEP_BIN_END:
        return step_bin_end(h, budget);
    case STEP_RAMP:
        return step_ramp(h, budget);
#if WAKE_HPA_AHEAD
    case STEP_AHEAD_PASS:
        return step_ahead_pass(h, budget);
    case STEP_AHEAD_START:
        return step_ahead_start(h, budget);

    case STEP_AHEAD_SOLVE:
        step_ahead_solve(h);
        break;
#endif
    case STEP_LAG_END:
        step_lag_end(h);
        break;
    case STEP_LEVINSON:
        step_levinson(h);
        break;
    case STEP_CUTOFF:
        step_cutoff(h);
        break;
    case STEP_BINS:
        step_bins(h);
        break;
    case STEP_BIN_START:
        step_bin_start(h);
        break;
    case STEP_GRAM:
        step_gram(h);
        break;
    case STEP_SOLVE:
        step_solve(h);
        break;
    default:
        break;
    }
    return fixed;
}

/** Pieces of work until @p budget is spent; the next piece only if it fits (or comes first). */
static void run_pieces(wake_hpa_t *h, int32_t budget)
{
    int32_t left = budget;
    int first = 1;
    /* termination (WP; docs/studies/verification.md, "Termination"): a piece after the first runs only if need <= left,
       need >= 1 + COST_PIECE, and every piece lowers left by what run_step spent (> 0) plus COST_PIECE */
    /*@ loop invariant first == 0 || first == 1;
        loop invariant first == 1 ==> left == budget;
        loop invariant left <= budget;
        loop invariant STEP_IDLE <= h->phase <= (WAKE_HPA_AHEAD ? STEP_AHEAD_SOLVE : STEP_SOLVE);
        loop invariant h->d <= h->lags && h->pair <= 2;
        loop assigns left, first, *h;
        loop variant left;
    */
    while (h->phase != STEP_IDLE) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_PIECE */
        const int32_t need = piece_cost(h) + COST_PIECE;
        if (!first && need > left) {
            break;
        }
        left -= run_step(h, left - COST_PIECE, need - COST_PIECE) + COST_PIECE;
        first = 0;
    }
}

wake_hpa_status_t wake_hpa_slice(wake_hpa_t *h)
{
    wake_hpa_status_t st = check_instance(h);
    if (st != WAKE_HPA_OK) {
        return st;
    }
    if (h->phase == STEP_IDLE) {
        return WAKE_HPA_OK;
    }
    run_pieces(h, WAKE_HPA_SLICE_BUDGET);
    return h->phase == STEP_IDLE ? WAKE_HPA_DONE : WAKE_HPA_RUNNING;
}

wake_hpa_status_t wake_hpa_run(wake_hpa_t *h)
{
    /* no time limit: every loop step runs to its end in one piece (the same arithmetic as slices).  One call of
       run_pieces: its budget is far above what a whole run spends (docs/studies/verification.md, "Termination"), and its
       loop ends (WP), so this call ends too */
    wake_hpa_status_t st = check_instance(h);
    if (st != WAKE_HPA_OK) {
        return st;
    }
    if (h->phase == STEP_IDLE) {
        return WAKE_HPA_OK;
    }
    run_pieces(h, INT32_MAX / 2);
    return (h->phase == STEP_IDLE) ? WAKE_HPA_DONE : WAKE_HPA_RUNNING;
}

wake_hpa_status_t wake_hpa_take(wake_hpa_t *h, wake_hpa_result_t *out)
{
    wake_hpa_status_t st = check_instance(h);
    if (st != WAKE_HPA_OK) {
        return st;
    }
    if (out == NULL) {
        return WAKE_HPA_E_NULL;
    }
    if (!h->ready) {
        return WAKE_HPA_E_IDLE;
    }
    *out = h->result;
    h->ready = 0;
    return WAKE_HPA_OK;
}

/** round(v) as int32, v clamped to [lo, hi] first (no undefined conversion). */
static int32_t round_clamp(float v, float lo, float hi)
{
    if (!(v >= lo)) {
        v = lo; /* NaN too */
    }
    if (v > hi) {
        v = hi;
    }
    return (int32_t)(v + (v >= 0.0f ? 0.5f : -0.5f));
}

wake_hpa_status_t wake_hpa_to_rtp(const wake_hpa_result_t *res, int level, float process_noise_ratio,
                                  wake_q24_t *weights, wake_cov_t *r, wake_cov_t *q)
{
    /* Q(P_FRAC) of FS^2 from LSB^2 of Q15: times 2^(P_FRAC - 30) */
    float to_cov = 1.0f;
    int k;
    if (res == NULL || weights == NULL || r == NULL || q == NULL) {
        return WAKE_HPA_E_NULL;
    }
    if (level < 1 || level > WAKE_HPA_MAX_LEVEL || !(process_noise_ratio >= 0.0f) || !is_finite(process_noise_ratio)) {
        return WAKE_HPA_E_CONFIG;
    }
    for (k = 30; k < WAKE_RTP_P_FRAC; ++k) {
        to_cov *= 2.0f;
    }
    for (k = WAKE_RTP_P_FRAC; k < 30; ++k) {
        to_cov *= 0.5f;
    }
    for (k = 0; k < level; ++k) {
        weights[k] = round_clamp(res->weights[k] * 16777216.0f, -1073741824.0f, 1073741824.0f);
    }
    /* 2147483520 is the largest float below 2^31 */
    *r = round_clamp(res->measurement_noise * to_cov, 1.0f, 2147483520.0f);
    *q = round_clamp(process_noise_ratio * res->measurement_noise * to_cov, 0.0f, 2147483520.0f);
    return WAKE_HPA_OK;
}

wake_hpa_status_t wake_hpa_ahead_to_rtp(const wake_hpa_result_t *res, int32_t *coefficients, wake_ratio_t *goal)
{
    unsigned k;
    if (res == NULL || coefficients == NULL || goal == NULL) {
        return WAKE_HPA_E_NULL;
    }
    /* Q27: 2^27 = 134217728; +-8 is +-2^30 */
    for (k = 0; k < WAKE_HPA_AHEAD_TAPS; ++k) {
        coefficients[k] = round_clamp(res->ahead[k] * 134217728.0f, -1073741824.0f, 1073741824.0f);
    }
    *goal = round_clamp(res->ahead_goal * 1073741824.0f, 0.0f, 1073741824.0f);
    return WAKE_HPA_OK;
}

wake_hpa_status_t wake_hpa_apply(wake_hpa_t *h, wake_rtp_t *rtp)
{
    wake_q24_t w[WAKE_HPA_MAX_LEVEL];
    wake_cov_t r, q;
    wake_hpa_status_t st = check_instance(h);
    if (st != WAKE_HPA_OK) {
        return st;
    }
    if (rtp == NULL) {
        return WAKE_HPA_E_NULL;
    }
    if (!h->ready) {
        return WAKE_HPA_E_IDLE;
    }
    if (rtp->magic != WAKE_RTP_MAGIC || rtp->level != h->cfg.level) {
        return WAKE_HPA_E_RTP;
    }
    st = wake_hpa_to_rtp(&h->result, h->cfg.level, h->cfg.process_noise_ratio, w, &r, &q);
    if (st != WAKE_HPA_OK) {
        return st;
    }
    if (wake_rtp_set_weights(rtp, w, r, q) != WAKE_RTP_OK) {
        return WAKE_HPA_E_RTP;
    }
#if WAKE_HPA_AHEAD && WAKE_RTP_AHEAD
    {
        int32_t c[WAKE_HPA_AHEAD_TAPS];
        wake_ratio_t goal;
        (void)wake_hpa_ahead_to_rtp(&h->result, c, &goal);
        if (wake_rtp_set_ahead(rtp, c, goal) != WAKE_RTP_OK) {
            return WAKE_HPA_E_RTP;
        }
    }
#endif
    h->ready = 0;
    return WAKE_HPA_OK;
}
