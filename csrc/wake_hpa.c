/**
 * @file wake_hpa.c
 * @brief The WAKE HPA in single precision, time-sliced (see wake_hpa.h).
 *
 * The run is a sequence of steps; each call of wake_hpa_slice() does one
 * bounded piece of one step and records where it stopped:
 *
 *   STEP_SUMS      S = sum x, min and max                  (chunks of the window)
 *   STEP_TABLE     cos/sin(2 pi k / n), k <= n/2            (chunks of entries; once per n)
 *   STEP_LAGS      sum x(t) x(t+d), d < lags                (chunks of one lag)
 *   STEP_LAG_END   centre lag d exactly; slide its diagonal of Rxx into Rxx B'
 *   STEP_LEVINSON  AR(p) by Levinson-Durbin                 (one slice)
 *   STEP_PSD       D(f_k) of the AR spectrum and the tremor peak (chunks of bins)
 *   STEP_CUTOFF    the valley rule                          (one slice)
 *   STEP_DFT       X_m = sum x_c(t) e^{-j 2 pi m t / n}     (chunks of one bin)
 *   STEP_BIN_END   slide bin m over the fit rows into Cxy   (one slice per bin)
 *   STEP_GRAM      G = B (Rxx B') + mean terms, b            (one slice)
 *   STEP_SOLVE     (G + lambda I) w = b, raising lambda      (one attempt per slice)
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
    STEP_TABLE,
    STEP_LAGS,
    STEP_LAG_END,
    STEP_LEVINSON,
    STEP_PSD,
    STEP_CUTOFF,
    STEP_DFT,
    STEP_BIN_END,
    STEP_GRAM,
    STEP_SOLVE
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
 * rounding before the polynomial is one division and one product.
 */
static void unit_phasor(uint32_t num, uint32_t den, float *c, float *s)
{
    float sign_c = 1.0f;
    int swap = 0;
    uint32_t a = num, b = den;     /* angle = pi a / b */
    float x, sv, cv;
    if (2u * a > b) {              /* (pi/2, pi]: cos(pi - t) = -cos t */
        a = b - a;
        sign_c = -1.0f;
    }
    if (4u * a > b) {              /* (pi/4, pi/2]: swap with pi/2 - t = pi (b - 2a) / 2b */
        a = b - 2u * a;
        b = 2u * b;
        swap = 1;
    }
    x = PI_F * ((float)a / (float)b);
    sin_cos_octant(x, &sv, &cv);
    *c = sign_c * (swap ? sv : cv);
    *s = swap ? cv : sv;
}

/** e^{+j 2 pi idx / n} from the half table, 0 <= idx < n. */
static inline void twiddle(const wake_hpa_t *h, uint32_t idx, float *c, float *s)
{
    if (2u * idx <= h->n) {
        *c = h->tw_cos[idx];
        *s = h->tw_sin[idx];
    } else {
        *c = h->tw_cos[h->n - idx];
        *s = -h->tw_sin[h->n - idx];
    }
}

/** min(t + step, limit): where one slice of an inner loop stops. */
static inline unsigned chunk_end(unsigned t, unsigned step, unsigned limit)
{
    return t + step < limit ? t + step : limit;
}

/*
 * Cost model of the slicing, in Cortex-M4F instructions (measured by
 * `wake profile`, docs/hpa_c.md): a slice spends at most
 * WAKE_HPA_SLICE_BUDGET on loop items, and starts an indivisible step only
 * if it fits in what is left (or is the slice's first piece of work).
 */
#define COST_SUM 9
#define COST_TABLE 75
#define COST_LAG 6
#define COST_DFT 22

static inline unsigned items(int32_t budget, int32_t cost)
{
    return budget > cost ? (unsigned)(budget / cost) : 1u;
}

static inline int32_t cost_psd_bin(const wake_hpa_t *h)
{
    return 70 + 9 * (int32_t)h->order;
}

/** A Q15 tap as a float (exact: q / 2^15). */
static inline float q15_to_float(wake_q15_t q)
{
    return (float)q * (1.0f / 32768.0f);
}

/** Tap B[j][i] as a float. */
static inline float tap(const wake_hpa_t *h, unsigned j, unsigned i)
{
    return q15_to_float(h->taps[j * (1u << h->cfg.level) + i]);
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

/* ------------------------------------------------------------------------ */
/* Validation                                                               */
/* ------------------------------------------------------------------------ */

static int weights_ok(const float *w, unsigned J)
{
    unsigned j;
    for (j = 0; j < J; ++j) {
        if (!is_finite(w[j]) || abs_f(w[j]) > (float)WAKE_HPA_WEIGHT_LIMIT) {
            return 0;
        }
    }
    return 1;
}

static int config_ok(const wake_hpa_config_t *c)
{
    unsigned J, N, k, prev;
    const float f[] = {c->fs, c->tremor_low, c->tremor_high, c->cutoff_low, c->cutoff_high,
                       c->default_cutoff, c->min_depth_ratio, c->ridge, c->process_noise_ratio};
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
        !(c->cutoff_high < c->fs / 2.0f)) {
        return 0;
    }
    if (!(c->min_depth_ratio > 0.0f) || !(c->min_depth_ratio < 1.0f) || !(c->ridge >= 0.0f) ||
        !(c->process_noise_ratio >= 0.0f) || c->rule > WAKE_HPA_RULE_SHALLOW) {
        return 0;
    }
    /* the valley search keeps D for every bin up to cutoff_high */
    if (c->cutoff_high * (float)WAKE_HPA_PSD_GRID / c->fs >= (float)(WAKE_HPA_MAX_PSD_BINS - 1)) {
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

static wake_hpa_status_t check_instance(const wake_hpa_t *h)
{
    if (h == NULL) {
        return WAKE_HPA_E_NULL;
    }
    if (h->magic != WAKE_HPA_MAGIC) {
        return WAKE_HPA_E_UNINIT;
    }
    if (h->taps == NULL || !config_ok(&h->cfg) || h->fill > 1u || h->fill_len > h->cfg.window ||
        h->phase > STEP_SOLVE || (h->phase != STEP_IDLE && (h->work == NULL || h->n > h->cfg.window ||
                                                             h->n < 2u * (1u << h->cfg.level))) ||
        h->tw_n > h->cfg.window) {
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
    cfg->default_cutoff = 2.0f;
    cfg->min_depth_ratio = 0.50118723f;   /* 10^(-3/10) */
    cfg->ridge = 1e-6f;
    cfg->process_noise_ratio = 0.0f;
    cfg->window = 500;
    cfg->level = 5;
    cfg->ar_order = 17;
    cfg->rule = WAKE_HPA_RULE_PAPER;
    cfg->warmup[0] = 200;
    cfg->warmup[1] = 300;
    cfg->warmup[2] = 400;
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
    h->taps = taps;
    memcpy(h->weights, weights, cfg->level * sizeof weights[0]);
    h->psd_lo = (uint16_t)first_bin_at_or_above(h, cfg->tremor_low);
    h->psd_hi = (uint16_t)last_bin_at_or_below(h, cfg->tremor_high);
    if (h->psd_hi > WAKE_HPA_PSD_GRID / 2u - 1u) {
        h->psd_hi = WAKE_HPA_PSD_GRID / 2u - 1u;   /* the last bin has no right neighbour */
    }
    h->cut_lo = (uint16_t)first_bin_at_or_above(h, cfg->cutoff_low);
    h->cut_hi = (uint16_t)last_bin_at_or_below(h, cfg->cutoff_high);
    h->magic = WAKE_HPA_MAGIC;
    return WAKE_HPA_OK;
}

static void begin(wake_hpa_t *h, const wake_q15_t *window, uint16_t n, uint32_t index)
{
    const unsigned N = 1u << h->cfg.level;
    h->work = window;
    h->n = n;
    h->index = index;
    h->rows = (uint16_t)(n - N);
    h->order = (uint16_t)(h->cfg.ar_order < (n - 1u) / 2u ? h->cfg.ar_order : (n - 1u) / 2u);
    h->lags = (uint16_t)(h->order + 1u > N ? h->order + 1u : N);
    h->t = 0;
    h->d = 0;
    h->m = 0;
    h->sum = 0;
    h->prefix_rows = 0;
    h->lo = INT16_MAX;
    h->hi = INT16_MIN;
    h->flag = WAKE_HPA_VALLEY;
    h->phase = STEP_SUMS;
    h->runs = h->runs == UINT32_MAX ? h->runs : h->runs + 1u;
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

wake_hpa_status_t wake_hpa_push(wake_hpa_t *h, wake_q15_t sample)
{
    wake_q15_t *fill;
    wake_hpa_status_t st = check_instance(h);
    if (st != WAKE_HPA_OK) {
        return st;
    }
    fill = h->buf + (size_t)h->fill * WAKE_HPA_MAX_WINDOW;
    fill[h->fill_len] = sample;
    h->fill_len = (uint16_t)(h->fill_len + 1u);
    h->count = h->count == UINT32_MAX ? h->count : h->count + 1u;
    if (h->fill_len == h->cfg.window) {
        /* a full window: the HPA reads this buffer, the next samples go to the other */
        if (h->phase != STEP_IDLE && h->n == h->cfg.window) {
            h->overruns = h->overruns == UINT32_MAX ? h->overruns : h->overruns + 1u;
        } else if (h->phase != STEP_IDLE) {
            /* a warm-up HPA still running: the full window supersedes it */
            h->skipped = h->skipped == UINT32_MAX ? h->skipped : h->skipped + 1u;
        }
        h->fill = (uint16_t)(1u - h->fill);
        h->fill_len = 0;
        begin(h, fill, h->cfg.window, h->count);
        return WAKE_HPA_STARTED;
    }
    if (h->warmup_next < WAKE_HPA_MAX_WARMUP && h->cfg.warmup[h->warmup_next] != 0u &&
        h->count == h->cfg.warmup[h->warmup_next]) {
        h->warmup_next = (uint16_t)(h->warmup_next + 1u);
        if (h->phase != STEP_IDLE) {
            h->skipped = h->skipped == UINT32_MAX ? h->skipped : h->skipped + 1u;
            return WAKE_HPA_OK;
        }
        /* a warm-up window: the prefix of the buffer being filled (pushes only append) */
        begin(h, fill, h->fill_len, h->count);
        return WAKE_HPA_STARTED;
    }
    return WAKE_HPA_OK;
}

/* ------------------------------------------------------------------------ */
/* The steps                                                                */
/* ------------------------------------------------------------------------ */

static void finish(wake_hpa_t *h, const float *w, float r, float mse, float ridge, uint16_t notes)
{
    unsigned j;
    wake_hpa_result_t *res = &h->result;
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
    h->ready = 1;
    h->phase = STEP_IDLE;
}

/** S, min, max over one chunk; a constant window ends the run (weights kept). */
static int32_t step_sums(wake_hpa_t *h, int32_t budget)
{
    const unsigned start = h->t;
    const unsigned end = chunk_end(h->t, items(budget, COST_SUM), h->n);
    unsigned t;
    for (t = h->t; t < end; ++t) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_SUM */
        const wake_q15_t x = h->work[t];
        h->sum += x;
        if (t < h->rows) {
            h->prefix_rows += x;
        }
        h->lo = x < h->lo ? x : h->lo;
        h->hi = x > h->hi ? x : h->hi;
    }
    h->t = (uint16_t)end;
    if (end < h->n) {
        return (int32_t)(end - start) * (COST_SUM);
    }
    if (h->lo == h->hi) {
        /* silent: R = (1e-6 max|x|)^2, default cut-off, weights kept */
        const float peak = abs_f((float)h->lo);
        h->cutoff = h->cfg.default_cutoff;
        h->flag = WAKE_HPA_SILENT;
        finish(h, h->weights, max_f(1e-6f * peak * (1e-6f * peak), 1.0f), 0.0f, h->cfg.ridge,
               WAKE_HPA_NOTE_WEIGHTS_KEPT);
        return (int32_t)(end - start) * (COST_SUM);
    }
    h->mean = (float)h->sum / (float)h->n;
    h->t = 0;
    h->phase = h->tw_n == h->n ? STEP_LAGS : STEP_TABLE;
    h->d = 0;
    h->acc_head = 0;
    h->acc_tail = 0;
    h->prefix_lo = 0;
    h->prefix_hi = h->prefix_rows;
    h->suffix = 0;
    memset(h->bank_rxx, 0, sizeof h->bank_rxx);
    return (int32_t)(end - start) * (COST_SUM);
}

/** cos/sin(2 pi k / n) = phasor(pi 2k / n) for k = 0..n/2, one chunk. */
static int32_t step_table(wake_hpa_t *h, int32_t budget)
{
    const unsigned start = h->t;
    const unsigned half = h->n / 2u;
    const unsigned end = chunk_end(h->t, items(budget, COST_TABLE), half + 1u);
    unsigned k;
    h->tw_n = 0; /* invalid until complete */
    for (k = h->t; k < end; ++k) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_TABLE */
        unit_phasor(2u * k, h->n, &h->tw_cos[k], &h->tw_sin[k]);
    }
    h->t = (uint16_t)end;
    if (end == half + 1u) {
        h->tw_n = h->n;
        h->t = 0;
        h->phase = STEP_LAGS;
    }
    return (int32_t)(end - start) * (COST_TABLE);
}

/** One chunk of the raw lag sum sum x(t) x(t+d): t < rows into acc_head, the rest into acc_tail. */
/** sum_{t0 <= t < t1} x(t) x(t + d), exact (|x(t) x(t+d)| <= 2^30, at most 1024 terms). */
static inline int64_t lag_run(const wake_q15_t *x, unsigned d, unsigned t0, unsigned t1)
{
    int64_t acc = 0;
    unsigned t;
    for (t = t0; t < t1; ++t) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_LAG */
        acc += (int32_t)x[t] * (int32_t)x[t + d];
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

/**
 * Lag d is summed: centre it exactly, keep r(d) for the AR fit and, for
 * d < 2^J, walk the diagonal Rxx(i, i + d) (i = 0..2^J-1-d) of the fit's
 * window correlation and add it into Rxx B'.
 *
 * With y(t) = n x(t) - S (exact, |y| < 2^26):
 *   n^2 sum_{t in T} x_c(t) x_c(t+d) = sum_{t in T} y(t) y(t+d)
 *     = n^2 sum x(t)x(t+d) - n S (sum_{t in T} x(t) + sum_{t in T} x(t+d)) + |T| S^2
 * and Rxx(i+1, i+1+d) = Rxx(i, i+d) - x_c(i) x_c(i+d) + x_c(i+rows) x_c(i+rows+d).
 */
static void step_lag_end(wake_hpa_t *h)
{
    const unsigned d = h->d, n = h->n, rows = h->rows, J = h->cfg.level, N = 1u << J;
    const int64_t S = h->sum, nn = (int64_t)n * (int64_t)n;
    const wake_q15_t *x = h->work;
    const float inv_nn = 1.0f / ((float)n * (float)n);
    if (d <= h->order) {
        /* full range t < n - d: sum x(t) = P(n-d) = S - suffix(d), sum x(t+d) = S - P(d) */
        const int64_t raw = h->acc_head + h->acc_tail;
        const int64_t z = nn * raw - (int64_t)n * S * ((S - h->suffix) + (S - h->prefix_lo)) +
                          (int64_t)(n - d) * S * S;
        h->r[d] = (float)z;
    }
    if (d < N) {
        /* rows t < rows: sum x(t) = P(rows), sum x(t+d) = P(rows+d) - P(d) */
        int64_t z = nn * h->acc_head - (int64_t)n * S * (h->prefix_rows + (h->prefix_hi - h->prefix_lo)) +
                    (int64_t)rows * S * S;
        unsigned i, l;
        float *br = h->bank_rxx;
        const wake_q15_t *tp = h->taps;
        h->wsum[d] = (float)((int64_t)n * (h->prefix_hi - h->prefix_lo) - (int64_t)rows * S) / (float)n;
        for (i = 0; i + d < N; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
            const float rxx = (float)z * inv_nn;
            const int64_t y0 = (int64_t)n * x[i] - S, y1 = (int64_t)n * x[i + d] - S;
            const int64_t y2 = (int64_t)n * x[i + rows] - S, y3 = (int64_t)n * x[i + rows + d] - S;
            /* (Rxx B')[i][l] += Rxx(i, i+d) B[l][i+d]; and the mirror entry */
            float *row_i = br + i * J, *row_id = br + (i + d) * J;
            const wake_q15_t *col = tp + i;
            for (l = 0; l < J; ++l) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
                row_i[l] += rxx * q15_to_float(col[l * N + d]);
            }
            if (d != 0u) {
                for (l = 0; l < J; ++l) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
                    row_id[l] += rxx * q15_to_float(col[l * N]);
                }
            }
            if (i + d + 1u < N) {
                z += y2 * y3 - y0 * y1;
            }
        }
    }
    /* advance the prefix sums to d + 1 */
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

/** Levinson-Durbin on r[0..order] (wake.hpa.spectrum.levinson_durbin), in a[]. */
static void step_levinson(wake_hpa_t *h)
{
    const unsigned p = h->order;
    float err = h->r[0];
    unsigned m, i;
    for (i = 0; i <= WAKE_HPA_MAX_ORDER; ++i) {
        h->a[i] = 0.0f;
    }
    h->a[0] = 1.0f;
    for (m = 1; m <= p; ++m) { /* wcet-loop: WAKE_HPA_MAX_ORDER */
        float acc = h->r[m], k;
        if (!(err > 0.0f)) {
            break; /* a perfectly predictable window: higher orders add nothing */
        }
        for (i = 1; i < m; ++i) { /* wcet-loop: WAKE_HPA_MAX_ORDER */
            acc += h->a[i] * h->r[m - i];
        }
        k = -acc / err;
        /* a[i] += k a[m - i] for i = 1..m, all from the old a: pairs (i, m - i) swap together */
        for (i = 1; 2u * i < m; ++i) { /* wcet-loop: WAKE_HPA_MAX_ORDER */
            const float ai = h->a[i], aj = h->a[m - i];
            h->a[i] = ai + k * aj;
            h->a[m - i] = aj + k * ai;
        }
        if (2u * i == m) {
            h->a[i] = h->a[i] + k * h->a[i];
        }
        h->a[m] = k; /* k * a[0] */
        err *= 1.0f - k * k;
    }
    h->err = err;
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
    /* bins up to one past the tremor band's last bin (the local-maximum test needs it) */
    h->psd_end = (uint16_t)(h->psd_hi + 1u);
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
    const unsigned end = chunk_end(h->t, items(budget, cost_psd_bin(h)), h->psd_end + 1u);
    const unsigned k_lo = h->psd_lo, k_hi = h->psd_hi;
    unsigned k, m;
    for (k = h->t; k < end; ++k) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_PSD_BIN */
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
        h->phase = STEP_CUTOFF;
    }
    return (int32_t)(end - start) * (cost_psd_bin(h));
}

/** The valley rule (wake.hpa.cutoff.find_cutoff) on D = sigma^2 / PSD; then the DFT bins below f_d. */
static void step_cutoff(wake_hpa_t *h)
{
    unsigned m;
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
                unsigned k, valley = h->cut_lo;
                float left;
                int shallow;
                for (k = h->cut_lo + 1u; k <= upper; ++k) { /* wcet-loop: WAKE_HPA_MAX_PSD_BINS */
                    if (h->den[k] > h->den[valley]) {
                        valley = k;
                    }
                }
                left = h->den[0];
                for (k = 1; k <= valley; ++k) { /* wcet-loop: WAKE_HPA_MAX_PSD_BINS */
                    left = h->den[k] < left ? h->den[k] : left;
                }
                /* dB(valley) > dB(x) - depth  <=>  D(x) > ratio D(valley) */
                shallow = h->den_peak > h->cfg.min_depth_ratio * h->den[valley] ||
                          left > h->cfg.min_depth_ratio * h->den[valley];
                if (!shallow) {
                    h->flag = WAKE_HPA_VALLEY;
                    h->cutoff = psd_freq(h, valley);
                } else if (h->cfg.rule == WAKE_HPA_RULE_SHALLOW) {
                    h->flag = WAKE_HPA_SHALLOW_VALLEY;
                    h->cutoff = psd_freq(h, valley);
                } else {
                    h->flag = WAKE_HPA_NO_VALLEY;
                }
            }
        }
    }
    /* DFT bins m >= 1 with m fs / n <= f_d form the voluntary ground truth */
    for (m = 1; 2u * m < h->n && (float)m * (h->cfg.fs / (float)h->n) <= h->cutoff; ++m) { /* wcet-loop: WAKE_HPA_MAX_WINDOW / 2 */
    }
    h->bins = (uint16_t)(m - 1u);
    h->m = 1;
    h->t = 0;
    h->idx = 0;
    h->xr = 0.0f;
    h->xi = 0.0f;
    h->power = 0.0f;
    memset(h->cxy, 0, sizeof h->cxy);
    memset(h->vhead, 0, sizeof h->vhead);
    h->d = 0;
    h->phase = h->bins >= 1u ? STEP_DFT : STEP_GRAM;
}

/** One chunk of X_m = sum x_c(t) e^{-j 2 pi m t / n}; Q_m(0) is the partial sum at t = rows. */
/** sum_{t0 <= t < t1} x_c(t) e^{-j 2 pi idx(t) / n} into (xr, xi); idx advances by m mod n.  Locals only:
 *  nothing in the loop can alias the struct, so the compiler keeps every value in a register. */
static inline unsigned dft_run(const wake_q15_t *x, unsigned t0, unsigned t1, unsigned n, unsigned m,
                               const float *tc, const float *ts, float mean, unsigned idx, float *xr_io,
                               float *xi_io)
{
    float xr = *xr_io, xi = *xi_io;
    unsigned t;
    for (t = t0; t < t1; ++t) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_DFT */
        const float xc = (float)x[t] - mean;
        float c, s;
        if (2u * idx <= n) {
            c = tc[idx];
            s = ts[idx];
        } else {
            c = tc[n - idx];
            s = -ts[n - idx];
        }
        xr += xc * c;
        xi -= xc * s;
        idx += m;
        idx = idx >= n ? idx - n : idx;
    }
    *xr_io = xr;
    *xi_io = xi;
    return idx;
}

/** One chunk of X_m = sum x_c(t) e^{-j 2 pi m t / n}; Q_m(0) is the partial sum at t = rows. */
static int32_t step_dft(wake_hpa_t *h, int32_t budget)
{
    const unsigned start = h->t;
    const unsigned n = h->n, m = h->m, rows = h->rows;
    const unsigned end = chunk_end(h->t, items(budget, COST_DFT), n);
    const unsigned split = end < rows ? end : (start > rows ? start : rows);
    float xr = h->xr, xi = h->xi;
    unsigned idx = h->idx;
    idx = dft_run(h->work, start, split, n, m, h->tw_cos, h->tw_sin, h->mean, idx, &xr, &xi);
    if (split == rows && start <= rows && end >= rows) {
        h->qr = xr;   /* Q_m(0) = sum over t < rows */
        h->qi = xi;
    }
    idx = dft_run(h->work, split, end, n, m, h->tw_cos, h->tw_sin, h->mean, idx, &xr, &xi);
    h->xr = xr;
    h->xi = xi;
    h->idx = (uint16_t)idx;
    h->t = (uint16_t)end;
    if (end == n) {
        h->phase = STEP_BIN_END;
    }
    return (int32_t)(end - start) * (COST_DFT);
}

/**
 * Bin m is summed.  With v_c(t) = (2/n) Re sum_m X_m e^{j w t} (w = 2 pi m / n)
 * and Q_m(i) = sum_{s=i}^{i+rows-1} x_c(s) e^{-j w s}:
 *   Cxy(i) = sum_s x_c(s) v_c(s + N - i) = (2/n) Re sum_m X_m e^{j w (N - i)} conj(Q_m(i))
 *   Q_m(i+1) = Q_m(i) - x_c(i) e^{-j w i} + x_c(i + rows) e^{-j w (i + rows)}
 * and v_c(t) for t < N (the targets the fit does not use) into vhead.
 */
static void step_bin_end(wake_hpa_t *h)
{
    const unsigned n = h->n, m = h->m, rows = h->rows, N = 1u << h->cfg.level;
    const float scale = 2.0f / (float)n, mean = h->mean, xr = h->xr, xi = h->xi;
    float qr = h->qr, qi = h->qi;
    unsigned i, idx_i = 0, idx_r = (rows * m) % n, idx_a = (N * m) % n;
    h->power += xr * xr + xi * xi;
    for (i = 0; i < N; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
        float ca, sa, ci, si, cr, sr, pr, pi, xc;
        twiddle(h, idx_a, &ca, &sa);
        pr = xr * ca - xi * sa;       /* P = X e^{j w (N - i)} */
        pi = xr * sa + xi * ca;
        h->cxy[i] += scale * (pr * qr + pi * qi);
        twiddle(h, idx_i, &ci, &si);
        h->vhead[i] += scale * (xr * ci - xi * si);
        xc = (float)h->work[i] - mean;
        qr -= xc * ci;
        qi += xc * si;
        twiddle(h, idx_r, &cr, &sr);
        xc = (float)h->work[i + rows] - mean;
        qr += xc * cr;
        qi -= xc * sr;
        idx_a = idx_a >= m ? idx_a - m : idx_a + n - m;
        idx_i += m;
        idx_i = idx_i >= n ? idx_i - n : idx_i;
        idx_r += m;
        idx_r = idx_r >= n ? idx_r - n : idx_r;
    }
    h->m = (uint16_t)(m + 1u);
    h->t = 0;
    h->idx = 0;
    h->xr = 0.0f;
    h->xi = 0.0f;
    h->d = 0;
    h->phase = h->m <= h->bins ? STEP_DFT : STEP_GRAM;
}

/**
 * The normal equations of the causal fit from the centred sums.  With the
 * window mean mu, A = A_c + mu 1 s' (s = row sums of B) and y = y_c + mu 1:
 *   G  = B (Rxx B') + mu (c s' + s c') + rows mu^2 s s',   c = A_c'1 = B wsum
 *   b  = B Cxy + mu c + mu sy s + rows mu^2 s,             sy = 1'y_c = -sum vhead
 *   y'y = (2/n) sum |X_m|^2 - sum vhead^2 + 2 mu sy + rows mu^2
 *   R  = max(var x - (2/n^2) sum |X_m|^2, 1e-6 var x)
 */
static void step_gram(wake_hpa_t *h)
{
    const unsigned J = h->cfg.level, N = 1u << J, l = h->d;
    const float mu = h->mean, fr = (float)h->rows;
    float sl = 0.0f, cl = 0.0f, bl = 0.0f;
    unsigned i, k;
    if (l == 0u) {
        h->sy = 0.0f;
        h->vv = 0.0f;
        h->trace = 0.0f;
        for (i = 0; i < N; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
            h->sy -= h->vhead[i];
            h->vv += h->vhead[i] * h->vhead[i];
        }
    }
    /* row l: s_l, c_l = (B wsum)_l, (B Cxy)_l, then G[l][k] for k <= l */
    for (i = 0; i < N; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
        const float b = tap(h, l, i);
        sl += b;
        cl += b * h->wsum[i];
        bl += b * h->cxy[i];
    }
    h->rowsum[l] = sl;
    h->colsum[l] = cl;
    h->rhs[l] = bl + mu * cl + mu * h->sy * sl + fr * mu * mu * sl;
    for (k = 0; k <= l; ++k) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        float g = 0.0f;
        for (i = 0; i < N; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
            g += tap(h, l, i) * h->bank_rxx[i * J + k];
        }
        g += mu * (cl * h->rowsum[k] + sl * h->colsum[k]) + fr * mu * mu * sl * h->rowsum[k];
        h->gram[l * J + k] = g;
        h->gram[k * J + l] = g;
    }
    h->trace += h->gram[l * J + l];
    h->d = (uint16_t)(l + 1u);
    if (h->d < J) {
        return;
    }
    {
        const float fn = (float)h->n;
        const float sum_sq = h->r[0] / (fn * fn);             /* sum x_c^2 */
        const float var = sum_sq / fn;
        h->yy = h->power * (2.0f / fn) - h->vv + 2.0f * mu * h->sy + fr * mu * mu;
        h->noise = max_f((sum_sq - h->power * (2.0f / fn)) / fn, 1e-6f * var);
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
 * (G + factor scale I) w = b by L D L' (no square root); 0 if a pivot is not
 * positive and finite.
 */
static int solve_ridge(wake_hpa_t *h, float lambda, float *w)
{
    const unsigned J = h->cfg.level;
    float dg[WAKE_HPA_MAX_LEVEL];
    float *L = h->chol;
    unsigned i, j, k;
    for (j = 0; j < J; ++j) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        /* d_j = M_jj - sum_k L_jk^2 d_k */
        float dj = h->gram[j * J + j] + lambda;
        for (k = 0; k < j; ++k) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            dj -= L[j * J + k] * L[j * J + k] * dg[k];
        }
        if (!(dj > 0.0f) || !is_finite(dj)) {
            return 0;
        }
        dg[j] = dj;
        /* L_ij = (M_ij - sum_k L_ik L_jk d_k) / d_j */
        for (i = j + 1u; i < J; ++i) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            float v = h->gram[i * J + j];
            for (k = 0; k < j; ++k) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
                v -= L[i * J + k] * L[j * J + k] * dg[k];
            }
            L[i * J + j] = v / dj;
        }
    }
    /* L z = b;  D y = z;  L' w = y */
    for (i = 0; i < J; ++i) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        float v = h->rhs[i];
        for (k = 0; k < i; ++k) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
            v -= L[i * J + k] * w[k];
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
    if (!(h->scale > 0.0f) || !is_finite(h->scale)) {
        for (j = 0; j < J; ++j) {
            w[j] = 0.0f;
        }
        finish(h, w, h->noise, max_f(h->yy / (float)h->rows, 0.0f), h->cfg.ridge, 0u);
        return;
    }
    if (solve_ridge(h, h->factor * h->scale, w)) {
        finish(h, w, h->noise, fit_mse(h, w), h->factor,
               h->factor > h->cfg.ridge ? (uint16_t)WAKE_HPA_NOTE_REGULARISED : (uint16_t)0u);
        return;
    }
    h->attempts = (uint16_t)(h->attempts + 1u);
    h->factor = max_f(h->factor * 10.0f, 1e-9f);
    if (h->attempts >= WAKE_HPA_RIDGE_STEPS) {
        /* a ridge of 1e7 trace(G) still fails: zero weights, never NaN */
        for (j = 0; j < J; ++j) {
            w[j] = 0.0f;
        }
        finish(h, w, h->noise, max_f(h->yy / (float)h->rows, 0.0f), h->factor,
               (uint16_t)(WAKE_HPA_NOTE_REGULARISED | WAKE_HPA_NOTE_CLIPPED));
    }
}

/* ------------------------------------------------------------------------ */
/* Public: running, results                                                 */
/* ------------------------------------------------------------------------ */

/** Cost of the next indivisible step (0: the step is a loop that takes any budget). */
static int32_t indivisible_cost(const wake_hpa_t *h)
{
    const int32_t J = (int32_t)h->cfg.level, N = (int32_t)1 << J, d = (int32_t)h->d;
    switch (h->phase) {
    case STEP_LAG_END:
        return d < N ? (N - d) * (12 * J + 30) + 80 : 80;
    case STEP_LEVINSON:
        return 5 * (int32_t)h->order * (int32_t)h->order + 150;
    case STEP_CUTOFF:
        return 8 * (int32_t)h->cut_hi + 400;
    case STEP_BIN_END:
        return 60 * N + 80;
    case STEP_GRAM:
        return N * (4 + d) * 6 + (d == 0 ? 6 * N : 0) + 100;
    case STEP_SOLVE:
        return 4 * J * J * J + 10 * J * J + 200;
    default:
        return 0;
    }
}

/** Run the current step within @p budget (@p fixed: its indivisible_cost); returns what it spent. */
static int32_t run_step(wake_hpa_t *h, int32_t budget, int32_t fixed)
{
    switch (h->phase) {
    case STEP_SUMS:
        return step_sums(h, budget);
    case STEP_TABLE:
        return step_table(h, budget);
    case STEP_LAGS:
        return step_lags(h, budget);
    case STEP_PSD:
        return step_psd(h, budget);
    case STEP_DFT:
        return step_dft(h, budget);
    case STEP_LAG_END:
        step_lag_end(h);
        break;
    case STEP_LEVINSON:
        step_levinson(h);
        break;
    case STEP_CUTOFF:
        step_cutoff(h);
        break;
    case STEP_BIN_END:
        step_bin_end(h);
        break;
    case STEP_GRAM:
        step_gram(h);
        break;
    default:
        step_solve(h);
        break;
    }
    return fixed;
}

wake_hpa_status_t wake_hpa_slice(wake_hpa_t *h)
{
    int32_t left = WAKE_HPA_SLICE_BUDGET;
    int first = 1;
    wake_hpa_status_t st = check_instance(h);
    if (st != WAKE_HPA_OK) {
        return st;
    }
    if (h->phase == STEP_IDLE) {
        return WAKE_HPA_OK;
    }
    /* pieces of work until the budget is spent; an indivisible step only if it fits (or comes first) */
    while (h->phase != STEP_IDLE && left > 0) { /* wcet-loop: a few steps */
        const int32_t fixed = indivisible_cost(h);
        if (!first && fixed > left) {
            break;
        }
        left -= run_step(h, left, fixed);
        first = 0;
    }
    return h->phase == STEP_IDLE ? WAKE_HPA_DONE : WAKE_HPA_RUNNING;
}

wake_hpa_status_t wake_hpa_run(wake_hpa_t *h)
{
    wake_hpa_status_t st = wake_hpa_slice(h);
    while (st == WAKE_HPA_RUNNING) {
        st = wake_hpa_slice(h);
    }
    return st;
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
    h->ready = 0;
    return WAKE_HPA_OK;
}
