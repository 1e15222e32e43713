/**
 * @file wake_hpa.c
 * @brief The WAKE HPA in single precision, time-sliced (see wake_hpa.h): the configuration, the instance
 *        check, the feeding schedule, the results and their conversion to the RTP's formats.
 *
 * A run is a sequence of steps (csrc/internal/wake_hpa_internal.h lists them and the files that hold them);
 * each call of wake_hpa_slice() (wake_hpa_slice.c) does bounded pieces of them and records where it stopped.
 *
 * Conventions: float only (no double), no libm, no division instruction in
 * an inner loop, fixed evaluation order (build with -ffp-contract=off).
 * Integer sums are exact (bounds in wake_hpa_slice's note).
 */
#include "internal/wake_hpa_internal.h"

#include <string.h>

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

/* ---- validation ---------------------------------------------------------------------------------------------- */

static int config_ok(const wake_hpa_config_t *c)
{
    unsigned J, N, k, prev;
    const float f[] = {c->fs, c->tremor_low, c->tremor_high, c->cutoff_low, c->cutoff_high, c->shallow_high,
                       c->default_cutoff, c->min_depth_ratio, c->floor_ratio, c->edge_ratio, c->ridge,
                       c->process_noise_ratio, c->gate_cutoff};
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
    if (c->clean_below > c->window || c->horizon < 1u || c->horizon > WAKE_HPA_MAX_AHEAD_HORIZON ||
        c->ridge_scale > WAKE_HPA_RIDGE_CENTRED) {
        return 0;
    }
    /* the gate's truth: 0 (above f_d), or below fs/2 with its bins inside the ones the truth has room for,
       gate_cutoff < (B - 1) fs / 1022 (written so that no product overflows: fs > 0 and finite here) */
    if (!(c->gate_cutoff >= 0.0f) || !(c->gate_cutoff < c->fs / 2.0f) ||
        !(c->gate_cutoff < (float)(WAKE_HPA_MAX_PSD_BINS - 1) * (c->fs / (float)WAKE_HPA_PSD_GRID))) {
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
    v = mix(v, float_bits(c->gate_cutoff));
    v = mix(v, (uint32_t)c->window | (uint32_t)c->level << 16);
    v = mix(v, (uint32_t)c->ar_order | (uint32_t)c->rule << 16);
    v = mix(v, (uint32_t)c->warmup[0] | (uint32_t)c->warmup[1] << 16);
    v = mix(v, (uint32_t)c->warmup[2] | (uint32_t)c->warmup[3] << 16);
    v = mix(v, (uint32_t)c->warmup[4] | (uint32_t)c->warmup[5] << 16);
    v = mix(v, (uint32_t)c->warmup[6] | (uint32_t)c->warmup[7] << 16);
    v = mix(v, (uint32_t)c->clean_below | (uint32_t)c->horizon << 16);
    v = mix(v, (uint32_t)h->psd_lo | (uint32_t)h->psd_hi << 16);
    v = mix(v, (uint32_t)h->cut_lo | (uint32_t)h->cut_hi << 16);
    v = mix(v, (uint32_t)h->floor_lo | (uint32_t)c->ridge_scale << 16);
    return mix(v, (uint32_t)h->cut_shallow | (uint32_t)h->gap_len << 16);
}

wake_hpa_status_t wake_hpa_check_instance(const wake_hpa_t *h)
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
        h->d > h->lags || hpa_dft_bins(h) > h->n / 2u || h->m > hpa_dft_bins(h) + 1u ||
        h->pair > 2u ||
        h->psd_end > psd_last(h) || h->attempts >= WAKE_HPA_RIDGE_STEPS ||
        ((h->phase == STEP_BIN_START || h->phase == STEP_BIN_END) && h->d >= h->pair) ||
        ((h->phase >= STEP_DFT) && (h->phase <= STEP_BIN_END) && (h->m == 0u)) ||
        (h->phase == STEP_RAMP && h->t >= N) || hpa_dft_bins(h) > WAKE_HPA_MAX_BINS ||
        hpa_ahead_corrupt(h) ||
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

void wake_hpa_begin(wake_hpa_t *h, const wake_q15_t *window, uint16_t n, uint32_t index)
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
    hpa_ahead_begin(h);
    h->flag = WAKE_HPA_VALLEY;
    h->phase = STEP_SUMS;
    count_up(&h->runs);
}

wake_hpa_status_t wake_hpa_start(wake_hpa_t *h, const wake_q15_t *window, uint16_t n, uint32_t index)
{
    wake_hpa_status_t st = wake_hpa_check_instance(h);
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
    wake_hpa_begin(h, window, n, index);
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
        wake_hpa_begin(h, fill, h->cfg.window, h->count);
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
        wake_hpa_begin(h, fill, h->fill_len, h->count);
        return WAKE_HPA_STARTED;
    }
    return WAKE_HPA_OK;
}

wake_hpa_status_t wake_hpa_push(wake_hpa_t *h, wake_q15_t sample)
{
    wake_hpa_status_t st = wake_hpa_check_instance(h);
    if (st != WAKE_HPA_OK) {
        return st;
    }
    return feed(h, sample, 0);
}

wake_hpa_status_t wake_hpa_push_missing(wake_hpa_t *h)
{
    wake_hpa_status_t st = wake_hpa_check_instance(h);
    if (st != WAKE_HPA_OK) {
        return st;
    }
    return feed(h, 0, 1);
}

static void install(wake_hpa_t *h, const float *w, float r, float mse, float ridge, uint16_t notes)
{
    unsigned j;
    wake_hpa_result_t *res = &h->result;
    hpa_ahead_install(h);
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
void wake_hpa_publish(wake_hpa_t *h)
{
    hpa_ahead_publish(h);
    h->ready = 1;
    h->phase = STEP_IDLE;
}

/** A run that ends without a fit (a constant window): its weights, published at once. */
void wake_hpa_finish(wake_hpa_t *h, const float *w, float r, float mse, float ridge, uint16_t notes)
{
    install(h, w, r, mse, ridge, notes);
    wake_hpa_publish(h);
}

/**
 * A run that ends with a fit: its weights installed, then (WAKE_HPA_AHEAD) the tremor ahead fitted on
 * the estimate those weights give, the one the predictor is fed from afterwards (wake.hpa.run_hpa).
 */
void wake_hpa_finish_fit(wake_hpa_t *h, const float *w, float r, float mse, float ridge, uint16_t notes)
{
    install(h, w, r, mse, ridge, notes);
    if (!hpa_ahead_after_fit(h)) {
        wake_hpa_publish(h);
    }
}

wake_hpa_status_t wake_hpa_take(wake_hpa_t *h, wake_hpa_result_t *out)
{
    wake_hpa_status_t st = wake_hpa_check_instance(h);
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
int32_t wake_hpa_round_clamp(float v, float lo, float hi)
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
        weights[k] = wake_hpa_round_clamp(res->weights[k] * 16777216.0f, -1073741824.0f, 1073741824.0f);
    }
    /* 2147483520 is the largest float below 2^31 */
    *r = wake_hpa_round_clamp(res->measurement_noise * to_cov, 1.0f, 2147483520.0f);
    *q = wake_hpa_round_clamp(process_noise_ratio * res->measurement_noise * to_cov, 0.0f, 2147483520.0f);
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
        coefficients[k] = wake_hpa_round_clamp(res->ahead[k] * 134217728.0f, -1073741824.0f, 1073741824.0f);
    }
    *goal = wake_hpa_round_clamp(res->ahead_goal * 1073741824.0f, 0.0f, 1073741824.0f);
    return WAKE_HPA_OK;
}

wake_hpa_status_t wake_hpa_set_previous_ahead(wake_hpa_t *h, const float *coefficients, uint32_t index)
{
    unsigned k;
    wake_hpa_status_t st = wake_hpa_check_instance(h);
    if (st != WAKE_HPA_OK) {
        return st;
    }
    if (coefficients == NULL) {
        return WAKE_HPA_E_NULL;
    }
    if (h->phase != STEP_IDLE) {
        return WAKE_HPA_E_BUSY;
    }
    for (k = 0; k < WAKE_HPA_AHEAD_TAPS; ++k) {
        /* NaN fails both tests */
        if (!(coefficients[k] >= -WAKE_HPA_AHEAD_COEF_LIMIT) || !(coefficients[k] <= WAKE_HPA_AHEAD_COEF_LIMIT)) {
            return WAKE_HPA_E_CONFIG;
        }
    }
    return hpa_ahead_set_previous(h, coefficients, index) ? WAKE_HPA_OK : WAKE_HPA_E_CONFIG;
}

wake_hpa_status_t wake_hpa_apply(wake_hpa_t *h, wake_rtp_t *rtp)
{
    wake_q24_t w[WAKE_HPA_MAX_LEVEL];
    wake_cov_t r, q;
    wake_hpa_status_t st = wake_hpa_check_instance(h);
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
    if (!hpa_ahead_apply(h, rtp)) {
        return WAKE_HPA_E_RTP;
    }
    h->ready = 0;
    return WAKE_HPA_OK;
}
