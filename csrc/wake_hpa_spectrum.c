/**
 * @file wake_hpa_spectrum.c
 * @brief The HPA's spectrum and cut-off (wake.hpa.spectrum, wake.hpa.cutoff): the window's sums and lag sums,
 *        the fit's Rxx B' along the lags' diagonals, AR(p) by Levinson-Durbin, the AR spectrum and the tremor
 *        peak, and the valley rule.
 *
 *   STEP_SUMS      S = sum x, T = sum t x, min and max      (chunks of the window)
 *   STEP_LAGS      sum x(t) x(t+d), d < lags                (chunks of one lag)
 *   STEP_LAG_END   centre lag d exactly                     (one slice per lag)
 *   STEP_DIAG      slide lag d's diagonal of Rxx into Rxx B' (chunks of the diagonal)
 *   STEP_LEVINSON  AR(p) by Levinson-Durbin                 (one order per slice)
 *   STEP_PSD       D(f_k) of the AR spectrum and the tremor peak (chunks of bins)
 *   STEP_CUTOFF    the valley rule                          (one slice)
 */
#include "internal/wake_hpa_internal.h"

#include <string.h>

static const float PI_F = 3.14159265358979f;

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
 * tests compare a itself (a > floor(b / 2) is 2a > b for integers: analyser).
 */
void wake_hpa_unit_phasor(uint32_t num, uint32_t den, float *c, float *s)
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

/** The PSD bin of spectrum item t (see psd_last). */
static inline unsigned psd_bin(const wake_hpa_t *h, unsigned t)
{
    const unsigned run = h->psd_hi + 2u;
    return t < run ? t : WAKE_HPA_PSD_GRID / 2u - WAKE_HPA_FLOOR_STRIDE * (t - run);
}

/** S, T = sum t x(t), min, max over one chunk; a constant window ends the run (weights kept). */
int32_t wake_hpa_step_sums(wake_hpa_t *h, int32_t budget)
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
    unsigned rail = hpa_ahead_rail_so_far(h);
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
        rail += hpa_ahead_rail(v);
    }
    hpa_ahead_sums(h, rail);
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
        hpa_ahead_silent(h);
        wake_hpa_finish(h, h->weights, max_f(1e-6f * peak * (1e-6f * peak), 1.0f), 0.0f, h->cfg.ridge,
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
int32_t wake_hpa_step_lags(wake_hpa_t *h, int32_t budget)
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
void wake_hpa_step_lag_end(wake_hpa_t *h)
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
 * One chunk of lag d's diagonal: (Rxx B')[i][l] += Rxx(i, i+d) B[l][i+d] and
 * the mirror entry, with n^2 Rxx(i, i+d) = diag slid exactly along the rows:
 *   n^2 Rxx(i+1, i+1+d) = n^2 Rxx(i, i+d) - y(i) y(i+d) + y(i+rows) y(i+rows+d).
 *
 * @par Scaling and overflow
 * |y| < 2^26 (n <= 1024) fits an int32, y y' an int64; diag is loaded through the clamp to DIAG_MAX, which
 * never fires (internal/wake_bounds.h), and a chunk of at most 2^J rows moves it by at most 2^J 2^53 more: within int64.
 * Rxx = diag / n^2 as a float: |Rxx| < n 2^32 <= 2^42.
 */
int32_t wake_hpa_step_diag(wake_hpa_t *h, int32_t budget)
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
    if (step >= rest) {   /* end == N - d (analyser) */
        next_lag(h);
    }
    return (int32_t)count * COST_DIAG;
}


/**
 * One order of Levinson-Durbin on r[0..order] (wake.hpa.spectrum.levinson_durbin),
 * in a[]; h->t is the order reached, h->err its prediction error.
 */
void wake_hpa_step_levinson(wake_hpa_t *h)
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
int32_t wake_hpa_step_psd(wake_hpa_t *h, int32_t budget)
{
    const unsigned start = h->t;
    const unsigned count = chunk_count(start, items(budget, cost_psd_bin(h)), h->psd_end + 1u);
    const unsigned end = chunk_end(start, count, h->psd_end + 1u);
    const unsigned k_lo = h->psd_lo, k_hi = h->psd_hi, run = h->psd_hi + 2u;
    unsigned t, m;
    for (t = h->t; t < end; ++t) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_PSD_BIN */
        const unsigned k = psd_bin(h, t);
        float c, s, b1 = 0.0f, b2 = 0.0f, re, im, dk;
        wake_hpa_unit_phasor(k, WAKE_HPA_PSD_GRID / 2u, &c, &s);
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
void wake_hpa_step_cutoff(wake_hpa_t *h)
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
