/**
 * @file wake_hpa_dft.c
 * @brief The HPA's voluntary truth (wake.hpa.sharp.detrended_highpass): the DFT bins below the cut-off by
 *        Reinsch's form of the Goertzel recursion, each bin slid over the fit rows into Cxy, and the window's
 *        end-point line's ramp.
 *
 *   STEP_BINS      count the DFT bins at or below f_d (and the gate's, up to its cut-off)  (one slice)
 *   STEP_DFT       X_m = sum x_c(t) e^{-j 2 pi m t / n}, two bins per pass (chunks of the window)
 *   STEP_BIN_START X_m and Q_m(0) from the pass's states    (one slice per bin; a gate bin: X'_m only)
 *   STEP_BIN_END   slide bin m over the fit rows into Cxy   (chunks of the 2^J rows)
 *   STEP_RAMP      the end-point line's ramp into Cxy        (chunks of the 2^J rows)
 */
#include "internal/wake_hpa_internal.h"

#include <string.h>

static void next_bin(wake_hpa_t *h);

/** e^{+j 2 pi k / n} for 0 <= k < n. */
static void turn(uint32_t k, uint32_t n, float *c, float *s)
{
    if (2u * k <= n) {
        wake_hpa_unit_phasor(2u * k, n, c, s);
    } else {
        wake_hpa_unit_phasor(2u * (n - k), n, c, s);
        *s = -*s;
    }
}

/**
 * The DFT bins m >= 1 with m fs / n <= f_d form the voluntary ground truth: count them; with the tremor ahead
 * and a gate cut-off above f_d, also the bins up to it (wake.hpa.run.gate_truth: the gate's truth leaves them
 * out as well; their X'_m feed the tremor ahead's pass only).  Start the first pass.
 */
void wake_hpa_step_bins(wake_hpa_t *h)
{
    const float gate = hpa_ahead_gate_cutoff(h);
    unsigned m, extra = 0u;
    for (m = 1; 2u * m < h->n && m <= WAKE_HPA_MAX_BINS && (float)m * (h->cfg.fs / (float)h->n) <= h->cutoff; ++m) { /* wcet-loop: WAKE_HPA_MAX_WINDOW / 2 */
    }
    h->bins = (uint16_t)(m - 1u);
    /* the gate's bins go on from there (none when its cut-off is at or below f_d) */
    for (; 2u * m < h->n && m <= WAKE_HPA_MAX_BINS && (float)m * (h->cfg.fs / (float)h->n) <= gate; ++m) { /* wcet-loop: WAKE_HPA_MAX_WINDOW / 2 */
        ++extra;
    }
    h->gate_extra = (uint16_t)extra;
    h->power = 0.0f;
    h->cross = 0.0f;
    memset(h->cxy, 0, sizeof h->cxy);
    memset(h->vhead, 0, sizeof h->vhead);
    h->d = 0;
    h->t = 0;
    h->m = 1;
    if (hpa_dft_bins(h) >= 1u) {
        wake_hpa_start_pass(h);
    } else {
        h->phase = STEP_RAMP;
    }
}

/** Set up a DFT pass over bins m and m + 1 (or m alone if it is the last): lambda = -4 sin^2(w/2). */
void wake_hpa_start_pass(wake_hpa_t *h)
{
    unsigned b;
    h->pair = (uint16_t)(h->m + 1u <= hpa_dft_bins(h) ? 2u : 1u);
    for (b = 0; b < 2u; ++b) {
        float c, s = 0.0f;
        if (b < h->pair) {
            wake_hpa_unit_phasor(h->m + b, h->n, &c, &s);   /* angle pi m / n = w / 2 */
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
 * The states are clamped every REINSCH_BLOCK samples and at the end of each run to REINSCH_S_MAX and
 * REINSCH_D_MAX, which is what STEP_BIN_START assumes (internal/wake_bounds.h: a clamp for the analyser that
 * never fires on a window of int16 samples).
 */

/*
 * Where the samples t0 <= t < t1 of a run are read: blocks of REINSCH_BLOCK samples from t0, the states
 * clamped after each.  A block is read as x[base + k] for k0 <= k < top <= REINSCH_BLOCK: a full block at
 * base = b, the last, shorter one as the last samples of the REINSCH_BLOCK samples before t1 (base = t1 -
 * REINSCH_BLOCK, k0 = b - base; base = 0 when t1 < REINSCH_BLOCK).  The same samples in the same order as
 * blocks of x[t], b <= t < min(b + REINSCH_BLOCK, t1); every index bounded by t1 alone (base <= t1 -
 * REINSCH_BLOCK, k < REINSCH_BLOCK: analyser).  The next block starts at next: b + REINSCH_BLOCK, or t1 after
 * the last.
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
int32_t wake_hpa_step_dft(wake_hpa_t *h, int32_t budget)
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
 * block of SLIDE_BLOCK rows, the first where a chunk loads it (Q_m to SLIDE_Q_MAX, each part to PHASOR_MAX;
 * internal/wake_bounds.h: clamps for the analyser that never fire on a window of int16 samples, the results
 * those of the plain slide, bit for bit).  Cost: two comparisons per clamp, eight per block of 4 rows.
 */

int32_t wake_hpa_step_bin_end(wake_hpa_t *h, int32_t budget)
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
    if (step >= rest) {   /* end == N (analyser) */
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
void wake_hpa_step_bin_start(wake_hpa_t *h)
{
    const unsigned n = h->n, rows = h->rows, N = 1u << h->cfg.level, b = h->d, m = h->m + b;
    const float half_n = 0.5f * (float)n;
    float cw, sw, ch, sh, rr, ri;
    wake_hpa_unit_phasor(2u * m, n, &cw, &sw);   /* e^{j w}, w = 2 pi m / n <= pi */
    reinsch_value(h->gs[b], h->gd[b], h->lam[b], cw, sw, (m * (n - 1u)) % n, n, &h->xr, &h->xi);
    reinsch_value(h->hs[b], h->hd[b], h->lam[b], cw, sw, (m * (rows - 1u)) % n, n, &h->qr, &h->qi);
    wake_hpa_unit_phasor(m, n, &ch, &sh);        /* w / 2 in (0, pi/2): sh > 0 */
    rr = -half_n;
    ri = half_n * ch / sh;
    /* X' = X - slope R */
    h->xr -= h->slope * rr;
    h->xi -= h->slope * ri;
    h->rot[0] = cw;
    h->rot[1] = sw;
    turn((N * m) % n, n, &h->ph[0], &h->ph[1]);
    hpa_ahead_bin(h, b, m, sw);
    if (m > h->bins) {
        /* a bin of the gate's truth only: nothing for the fit's targets */
        next_bin(h);
        return;
    }
    h->power += h->xr * h->xr + h->xi * h->xi;
    /* Re(X' conj(R)) */
    h->cross += h->xr * rr + h->xi * ri;
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
    if (h->m <= hpa_dft_bins(h)) {
        wake_hpa_start_pass(h);
    } else {
        h->phase = STEP_RAMP;
    }
}

/**
 * One chunk of the end-point line's ramp r(t) = t - (n-1)/2 into the targets
 * (wake.hpa.sharp.detrended_highpass; the low bins already hold X' = X - slope R):
 *   Cxy(i) += slope sum_{u < rows} x_c(i + u) r(i + u + N - i) = slope (U(i) + (N - (n-1)/2) wsum(i))
 *   vhead(i) += slope r(i)
 * with U(i) = sum_{u < rows} u x_c(i + u), U(0) = sum_{t < rows} t x(t) - mu rows (rows-1) / 2 from the
 * exact sum, and U(i+1) = U(i) + rows x_c(i + rows) - wsum(i + 1).
 */
int32_t wake_hpa_step_ramp(wake_hpa_t *h, int32_t budget)
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

