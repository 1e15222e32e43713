/**
 * @file wake_hpa_ahead.c
 * @brief The HPA's tremor-ahead fit (wake.ahead; docs/studies/hpa_c.md, "The tremor ahead") on its own state,
 *        wake_hpa_ahead_t, fed by the run's outputs (the window, the installed weights, the voluntary truth's
 *        bins).  An instance holds that state, and a run takes these steps after the fit, when the instance is
 *        configured with the tremor ahead (WAKE_HPA_AHEAD 1, wake_hpa.h); otherwise nothing calls this file.
 *
 *   STEP_AHEAD_START the estimate's FIR w'B of the weights just installed, the tremor-ahead sums cleared
 *                    (chunks of the 2^J taps)
 *   STEP_AHEAD_PASS  y(t), T(t), the lagged Gram, its right-hand side, the held-out sums (chunks of the window)
 *   STEP_AHEAD_SOLVE the 8-tap predictor by L D L', the held-out gain, the goal (one piece per row or column)
 */
#include "internal/wake_hpa_internal.h"

/** Keep @p c as the predictor of this run and the one the next run scores; @p goal the gate's goal. */
void wake_hpa_ahead_keep(const wake_hpa_t *h, wake_hpa_ahead_t *a, const float *c, float goal)
{
    unsigned i;
    for (i = 0; i < WAKE_HPA_AHEAD_TAPS; ++i) {
        a->coef[i] = c[i];
        a->prev[i] = c[i];
    }
    a->goal = goal;
    a->prev_index = h->index;
    a->has_prev = 1;
}

void wake_hpa_ahead_set_previous(wake_hpa_ahead_t *a, const float *c, uint32_t index)
{
    unsigned i;
    for (i = 0; i < WAKE_HPA_AHEAD_TAPS; ++i) {
        a->prev[i] = c[i];
    }
    a->prev_index = index;
    a->has_prev = 1;
}

/**
 * A constant window: nothing to fit and nothing to score.  The gate shuts (goal 0) and the previous
 * predictor stays (zero before the first): the next window scores it on the samples since this HPA, so
 * the gate reopens at the next HPA if the tremor comes back as it was (wake.hpa.run_hpa does the same).
 */
void wake_hpa_ahead_silent(const wake_hpa_t *h, wake_hpa_ahead_t *a)
{
    float kept[WAKE_HPA_AHEAD_TAPS];
    unsigned i;
    for (i = 0; i < WAKE_HPA_AHEAD_TAPS; ++i) {
        kept[i] = (a->has_prev != 0u) ? a->prev[i] : 0.0f;
    }
    wake_hpa_ahead_keep(h, a, kept, 0.0f);
}

/**
 * wake.ahead.installed_goal: more than n / WAKE_HPA_GLITCH_DIVISOR samples of the window at full scale
 * (counted in STEP_SUMS) shut the gate until the next HPA.
 * @par Scaling and overflow
 * ahead_rail <= n <= WAKE_HPA_MAX_WINDOW: rail x WAKE_HPA_GLITCH_DIVISOR fits a uint32_t.
 */
static void ahead_full_scale(wake_hpa_t *h, wake_hpa_ahead_t *a)
{
    if (((uint32_t)a->rail * WAKE_HPA_GLITCH_DIVISOR) > (uint32_t)h->n) {
        a->goal = 0.0f;
        h->result.notes = (uint16_t)(h->result.notes | (uint16_t)WAKE_HPA_NOTE_FULL_SCALE);
    }
}

void wake_hpa_ahead_publish(wake_hpa_t *h, wake_hpa_ahead_t *a)
{
    wake_hpa_result_t *res = &h->result;
    unsigned j;
    ahead_full_scale(h, a);
    for (j = 0; j < WAKE_HPA_AHEAD_TAPS; ++j) {
        res->ahead[j] = a->coef[j];
    }
    res->ahead_goal = a->goal;
}

/**
 * The tremor ahead's pass starts at t = N: X'_m e^{j w N} (X'_m in h->xr, h->xi; e^{j w N} in h->ph[0], h->ph[1]),
 * and turns by e^{j w} per sample.  Z = X' e^{j w N};  v(N) = (2/n) Re Z,  v(N) - v(N-1) = (2/n) Re(Z (1 - e^{-j w})).
 */
void wake_hpa_ahead_bin(const wake_hpa_t *h, wake_hpa_ahead_t *a, unsigned b, unsigned m, float sw)
{
    const float zr = h->xr * h->ph[0] - h->xi * h->ph[1], zi = h->xr * h->ph[1] + h->xi * h->ph[0];
    const float two_n = 2.0f / (float)h->n;
    const unsigned at = 3u * (m - 1u);
    a->bin_osc[at] = two_n * zr;
    a->bin_osc[at + 1u] = two_n * (-0.5f * h->lam[b] * zr - sw * zi);
    a->bin_osc[at + 2u] = h->lam[b];
}

int wake_hpa_ahead_corrupt(const wake_hpa_t *h, const wake_hpa_ahead_t *a)
{
    const unsigned N = 1u << h->cfg.level;
    return a->pos >= WAKE_HPA_AHEAD_RING || (h->phase == STEP_AHEAD_PASS && (h->t < N || h->t >= h->n)) ||
           (h->phase == STEP_AHEAD_SOLVE && h->d > AHEAD_SOLVE_LAST) || (h->phase == STEP_AHEAD_START && h->t >= N);
}

/** Tap i of the estimate's FIR w'B in Q20 (oldest tap first), from the weights the run installs. */
static inline void ahead_fir_tap(const wake_hpa_t *h, wake_hpa_ahead_t *a, unsigned i)
{
    float f = 0.0f;
    unsigned l;
    for (l = 0; l < h->cfg.level; ++l) { /* wcet-loop: WAKE_HPA_MAX_LEVEL */
        f += h->weights[l] * h->tapf[i * WAKE_HPA_MAX_LEVEL + l];
    }
    /* |w| <= 32, |B| < 1: |f| < 2^11, so f 2^20 fits an int32 */
    a->fir[i] = wake_hpa_round_clamp(f * 1048576.0f, -2147483520.0f, 2147483520.0f);
}


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
 *   gain = clip(<T_g, P> / <P, P>, 0, 1),  P(k + h) = c_prev . (y(k) .. y(k-7))
 * against the gate's truth T_g = T - sum_m v_m(t) over the bins m with f_d < m fs / n <= gate_cutoff
 * (wake.hpa.run.gate_truth; T itself without a gate cut-off above f_d)
 */

/**
 * Every row of the fit is a held-out target (an HPA every L samples) and the gate scores against the fit's own
 * truth (no gate bins above f_d): <T, P>, <P, P> come from b and G.
 */
int wake_hpa_ahead_all_held(const wake_hpa_t *h, const wake_hpa_ahead_t *a)
{
    return a->held == (1u << h->cfg.level) + WAKE_HPA_AHEAD_TAPS - 1u + h->cfg.horizon && h->gate_extra == 0u;
}

/** The ahead sums cleared, the held-out targets' start; then the pass. */
static void ahead_clear(wake_hpa_t *h, wake_hpa_ahead_t *a)
{
    const unsigned N = 1u << h->cfg.level, hz = h->cfg.horizon, len = h->n - N;
    unsigned first, i;
    for (i = 0; i < WAKE_HPA_AHEAD_TAPS; ++i) {
        a->lag[i] = 0.0f;
        a->rhs[i] = 0.0f;
    }
    for (i = 0; i < WAKE_HPA_AHEAD_RING; ++i) {
        a->ring[i] = 0.0f;
    }
    a->tp = 0.0f;
    a->pp = 0.0f;
    a->pos = WAKE_HPA_AHEAD_RING - 1u;   /* the first estimate goes to ring[0] */
    /* wake.ahead.held_out_gain: targets from max(len - new, 7 + h) of the estimate, at least 10 of them */
    first = WAKE_HPA_AHEAD_TAPS - 1u + hz;
    if (a->has_prev != 0u && h->index - a->prev_index < len) {
        const unsigned fresh = len - (unsigned)(h->index - a->prev_index);
        first = fresh > first ? fresh : first;
    }
    a->held = (uint16_t)(a->has_prev != 0u && first + 10u <= len ? N + first : h->n);
    h->t = (uint16_t)N;
    h->phase = STEP_AHEAD_PASS;
}

/** One chunk of the estimate's FIR w'B from the weights just installed; with its last tap, the clearing. */
int32_t wake_hpa_step_ahead_start(wake_hpa_t *h, wake_hpa_ahead_t *a, int32_t budget)
{
    const unsigned N = 1u << h->cfg.level, start = h->t;
    const unsigned end = chunk_end(start, items(budget - COST_AHEAD_CLEAR, COST_AHEAD_TAP), N);
    unsigned i;
    for (i = start; i < end; ++i) { /* wcet-loop: WAKE_HPA_MAX_TAPS */
        ahead_fir_tap(h, a, i);
    }
    h->t = (uint16_t)end;
    if (end < N) {
        return (int32_t)(end - start) * COST_AHEAD_TAP;
    }
    ahead_clear(h, a);
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
static inline float ahead_estimate1(const int32_t *fir, const wake_q15_t *x, unsigned t, unsigned N)
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
 * Each oscillator is clamped after each run to AHEAD_V_MAX and AHEAD_E_MAX (internal/wake_bounds.h: a clamp for
 * the analyser that never fires on a window of int16 samples).
 */

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
 * each: the offsets 0, 4 and 6 need no relation to the count; analyser).
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
 * chunk of the pass takes its ring position from its start, and hands on the one of its end: its ring indices
 * depend on t alone, not on a field carried between chunks (analyser; in a run the two are the same).
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
 * targets, scored against the gate's truth @p gate (the same as @p target without gate bins above f_d).
 */
static void ahead_rows(const wake_hpa_t *h, wake_hpa_ahead_t *a, const float *target, const float *gate, unsigned t0,
                       unsigned count, unsigned pos)
{
    const unsigned N = 1u << h->cfg.level, hz = h->cfg.horizon;
    const unsigned first_row = N + WAKE_HPA_AHEAD_TAPS - 1u + hz;
    /* every row held out: the solve takes <T, P> and <P, P> from b and G instead (ahead_held_out) */
    const unsigned held = wake_hpa_ahead_all_held(h, a) ? h->n : a->held;
    const float *ring = a->ring, *prev = a->prev;
    float *lag = a->lag, *rhs = a->rhs;
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
                a->tp += gate[q] * p;
                a->pp += p * p;
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
 * A function of its own (inlined: one call): a block's states kept apart by its count inside it (analyser).
 */
static void ahead_block(const wake_hpa_t *h, wake_hpa_ahead_t *a, unsigned t, unsigned count, unsigned pos)
{
    const unsigned N = 1u << h->cfg.level;
    const float centre = 0.5f * (float)(h->n - 1u), mean = h->mean, slope = h->slope;
    const wake_q15_t *x = h->work;
    float *ring = a->ring;
    const unsigned extra = h->gate_extra;
    float vol[AHEAD_BLOCK], y[AHEAD_BLOCK], gate[AHEAD_BLOCK];
    const float *scored = vol;
    unsigned q;
    /* the block reads only the elements it writes; zeroed all the same (stores, not a call: analyser) */
    for (q = 0; q < AHEAD_BLOCK; q += 2u) { /* wcet-loop: AHEAD_BLOCK / 2 */
        vol[q] = 0.0f;
        vol[q + 1u] = 0.0f;
        y[q] = 0.0f;
        y[q + 1u] = 0.0f;
    }
    ahead_voluntary(a->bin_osc, h->bins, count, vol);
    for (q = 0; q + 2u <= count; q += 2u) { /* wcet-loop: AHEAD_BLOCK / 2 */
        ahead_estimate2(a->fir, x, t + q, N, &y[q]);
    }
    if (q < count) {
        y[q] = ahead_estimate1(a->fir, x, t + q, N);
    }
    for (q = 0; q < count; ++q) { /* wcet-loop: AHEAD_BLOCK */
        const unsigned s = t + q, at = pos + 1u + q;
        ring[at < WAKE_HPA_AHEAD_RING ? at : at - WAKE_HPA_AHEAD_RING] = y[q];
        if (s < N + WAKE_HPA_AHEAD_TAPS) {
            a->head[s - N] = y[q];
        }
        vol[q] = (((float)x[s] - mean) - slope * ((float)s - centre)) - vol[q];
    }
    if (extra != 0u) {
        /* the gate's truth: T less the gate's bins above f_d (after the fit's in bin_osc) */
        for (q = 0; q < AHEAD_BLOCK; ++q) { /* wcet-loop: AHEAD_BLOCK */
            gate[q] = 0.0f;
        }
        ahead_voluntary(&a->bin_osc[3u * h->bins], extra, count, gate);
        for (q = 0; q < count; ++q) { /* wcet-loop: AHEAD_BLOCK */
            gate[q] = vol[q] - gate[q];
        }
        scored = gate;
    }
    ahead_rows(h, a, vol, scored, t, count, pos);
}

/**
 * The pass's samples start .. end - 1, a block of up to AHEAD_BLOCK samples at a time (ahead_block).  A function of its
 * own (inlined: one call): its blocks' states joined, not the chunk's ends (analyser).
 */
static void ahead_blocks(const wake_hpa_t *h, wake_hpa_ahead_t *a, unsigned start, unsigned end)
{
    unsigned t = start, pos = ahead_ring_pos(start, 1u << h->cfg.level);
    while (t < end) { /* wcet-loop: WAKE_HPA_SLICE_BUDGET / COST_AHEAD / (AHEAD_BLOCK / 2) */
        const unsigned left = end - t;   /* named once (analyser) */
        const unsigned count = left < AHEAD_BLOCK ? left : AHEAD_BLOCK;
        ahead_block(h, a, t, count, pos);
        pos += count;   /* < RING + AHEAD_BLOCK; the wrap tests pos itself (analyser) */
        pos = pos < WAKE_HPA_AHEAD_RING ? pos : pos - WAKE_HPA_AHEAD_RING;
        t += count;
    }
}

/** One chunk of the pass over t = N .. n-1 (ahead_blocks); the ring position of its end for the next chunk. */
int32_t wake_hpa_step_ahead_pass(wake_hpa_t *h, wake_hpa_ahead_t *a, int32_t budget)
{
    const unsigned N = 1u << h->cfg.level, n = h->n;
    const unsigned start = h->t, k = chunk_count(start, ahead_items(h, budget), n), end = chunk_end(start, k, n);
    ahead_blocks(h, a, start, end);
    if (end == n) {
        a->pos = (uint16_t)ahead_ring_pos(n, N);   /* of n, not end (analyser) */
        h->t = 0;
        h->d = 0;
        h->phase = STEP_AHEAD_SOLVE;
    } else {
        a->pos = (uint16_t)ahead_ring_pos(end, N);
        h->t = (uint16_t)end;
    }
    return COST_AHEAD_CHUNK + (int32_t)k * cost_ahead(h, k);   /* k = end - start, bounded by n - start */
}

/** y(k) of the pass's last rows (k within WAKE_HPA_AHEAD_RING of n - 1). */
static inline float ahead_tail(const wake_hpa_t *h, const wake_hpa_ahead_t *a, unsigned k)
{
    const unsigned back = (h->n - 1u) - k;
    return a->ring[a->pos >= back ? a->pos - back : a->pos + WAKE_HPA_AHEAD_RING - back];
}

/**
 * The previous predictor's held-out sums when every row is held out (the steady state: an HPA every L
 * samples), from the sums of the fit instead of a product per row: with P(k + h) = c_prev . u(k),
 *   <T, P> = sum_k T(k + h) c_prev . u(k) = c_prev . b,    <P, P> = c_prev' G c_prev
 * (G before its ridge, read from the upper triangle).
 */
static void ahead_held_out(wake_hpa_ahead_t *a)
{
    const unsigned P = WAKE_HPA_AHEAD_TAPS;
    const float *g = a->gram, *c = a->prev;
    float tp = 0.0f, pp = 0.0f;
    unsigned i, j;
    for (i = 0; i < P; ++i) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
        float gc = 0.0f;
        for (j = 0; j < P; ++j) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
            gc += (i <= j ? g[i * P + j] : g[j * P + i]) * c[j];
        }
        tp += c[i] * a->rhs[i];
        pp += c[i] * gc;
    }
    a->tp = tp;
    a->pp = pp;
}

/** Row i of G (upper triangle) from the lag sums and the rows' edges; after the last, the ridge (-1: nothing
 *  to fit). */
static void ahead_assemble(const wake_hpa_t *h, wake_hpa_ahead_t *a, unsigned i)
{
    const unsigned P = WAKE_HPA_AHEAD_TAPS, N = 1u << h->cfg.level, hz = h->cfg.horizon;
    const unsigned k0 = N + P - 1u;
    unsigned j, k;
    /* fewer than two rows: zeros (wake.ahead.fit_predictor) */
    if (h->n < k0 + hz + 2u) {
        a->ridge = -1.0f;
        return;
    }
    {
        const unsigned k1 = h->n - 1u - hz;
        for (j = i; j < P; ++j) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
            const unsigned d = j - i;
            float g = a->lag[d];
            for (k = k0 - i; k < k0; ++k) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
                g += a->head[k - N] * a->head[k - d - N];
            }
            for (k = k1 + 1u - i; k <= k1; ++k) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
                g -= ahead_tail(h, a, k) * ahead_tail(h, a, k - d);
            }
            a->gram[i * P + j] = g;
        }
    }
    if (i + 1u == P) {
        float trace = 0.0f;
        for (j = 0; j < P; ++j) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
            trace += a->gram[j * P + j];
        }
        /* no power: zeros */
        a->ridge = trace > 0.0f && is_finite(trace) ? 1e-3f * trace / (float)P : -1.0f;
        if (wake_hpa_ahead_all_held(h, a)) {
            ahead_held_out(a);
        }
    }
}

/**
 * Column j of (G + ridge I) = L D L' in place (no square root): D on the diagonal, L below it, G read
 * from the upper triangle; a pivot not positive and finite: nothing to fit (ridge -1).
 */
static void ahead_factor(wake_hpa_ahead_t *a, unsigned j)
{
    const unsigned P = WAKE_HPA_AHEAD_TAPS;
    float *g = a->gram;
    float dj;
    unsigned i, k;
    if (!(a->ridge > 0.0f)) {
        return;
    }
    /* d_j = M_jj + ridge - sum_k L_jk^2 d_k */
    dj = g[j * P + j] + a->ridge;
    for (k = 0; k < j; ++k) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
        dj -= g[j * P + k] * g[j * P + k] * g[k * P + k];
    }
    if (!(dj > 0.0f) || !is_finite(dj)) {
        a->ridge = -1.0f;
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
void wake_hpa_step_ahead_solve(wake_hpa_t *h, wake_hpa_ahead_t *a)
{
    float c[WAKE_HPA_AHEAD_TAPS], gain = 0.0f;
    unsigned i;
    if (h->d < WAKE_HPA_AHEAD_TAPS) {
        ahead_assemble(h, a, h->d);
        h->d = (uint16_t)(h->d + 1u);
        return;
    }
    if (h->d < AHEAD_SOLVE_LAST) {
        ahead_factor(a, h->d - WAKE_HPA_AHEAD_TAPS);
        h->d = (uint16_t)(h->d + 1u);
        return;
    }
    for (i = 0; i < WAKE_HPA_AHEAD_TAPS; ++i) { /* wcet-loop: WAKE_HPA_AHEAD_TAPS */
        c[i] = 0.0f;
    }
    if (a->ridge > 0.0f) {
        ahead_substitute(a->gram, a->rhs, c);
    }
    if (a->held < h->n && a->pp > 0.0f && is_finite(a->pp)) {
        gain = a->tp / a->pp;
        gain = gain > 1.0f ? 1.0f : (gain > 0.0f ? gain : 0.0f);   /* NaN: 0 */
    }
    /* wake.ahead.gate_target: no tremor peak, nothing to predict */
    if (h->flag == WAKE_HPA_NO_TREMOR_PEAK || h->flag == WAKE_HPA_SILENT) {
        gain = 0.0f;
    }
    wake_hpa_ahead_keep(h, a, c, gain);
    wake_hpa_publish(h);
}

