/**
 * @file wake_rtp.h
 * @brief Fixed-point real-time prediction (RTP) core of WAKE.
 *
 * One ::wake_rtp_t is one channel of the WAKE real-time predictor: a ring of
 * the newest 2^J samples, a J-level wavelet filter bank and a J-state Kalman
 * correction observed through the HPA weights w.  The float64 oracle
 * `wake/rtp/reference.py` runs that recursion literally:
 *
 * @code
 *   e    = m(n) - y(n-1)            innovation
 *   u    = P w,  S = w' u + R
 *   d    = d + u e / S              correction state (J values)
 *   P    = P - u u' / S + q I       F = I
 *   y(n) = w' (B window + d)        prediction of the voluntary motion at n + 1
 * @endcode
 *
 * A weight change restarts the covariance isotropic at its variance along
 * the old w, P = (w'Pw / |w|^2) I (docs/studies/design.md, "Covariance at a weight
 * change").  From such a restart u = P w stays parallel to w, and this core
 * evaluates the same recursion in an algebraically equivalent, constant-time
 * form (docs/studies/fixed_point.md proves the equivalence and bounds the error):
 *
 * @code
 *   h    = B' w                     2^J FIR taps, rebuilt by set_weights
 *   y(n) = h' window + z,           z = w' d
 *   S = s + R;  rho = s / S;        s = w' P w  (u = (s / |w|^2) w)
 *   z   += rho e                    w' d
 *   s    = (R / S) s + q |w|^2
 * @endcode
 *
 * d and P themselves are formed from the restart (lambda, d_s) and these
 * scalars only in wake_rtp_set_weights and wake_rtp_get_state; the
 * per-sample path has no data-dependent loop and no rare slow path.
 *
 * Portable C99, integer arithmetic only, no allocation, no global state: any
 * number of instances may live side by side.  Every narrowing saturates (and
 * is counted in wake_rtp_t::saturations); nothing wraps.
 *
 * @par Number formats
 * A value "Qf of X" is the integer round(v / X * 2^f).  FS is the full-scale
 * value chosen by the caller (the Python wrapper's `full_scale`).
 *
 * | quantity                        | C type            | format                     | range              |
 * |---------------------------------|-------------------|----------------------------|--------------------|
 * | sample m, prediction y (I/O)    | ::wake_q15_t      | Q15 of FS                  | [-1, 1) FS         |
 * | filter-bank taps B              | ::wake_q15_t      | Q15                        | row sum of abs < 2 |
 * | HPA weights w                   | ::wake_q24_t      | Q24                        | [-64, 64]          |
 * | FIR taps h = B'w                | ::wake_fir_t      | Q(WAKE_RTP_FIR_FRAC)       | < 64 J             |
 * | d, z, e, y(n-1)                 | ::wake_q23_t      | Q23 of FS                  | [-256, 256) FS     |
 * | P, lambda, R, q, p0, s          | ::wake_cov_t      | Q(WAKE_RTP_P_FRAC) of FS^2 | default Q32: [-0.5, 0.5) FS^2 |
 * | rho = s/S, tau = R/S            | ::wake_ratio_t    | Q30                        | [-2, 2)            |
 * | ahead coefficients c            | int32_t           | Q27                        | [-8, 8]            |
 * | tremor estimate e (delay line)  | ::wake_q15_t      | Q15 of FS                  | [-1, 1) FS         |
 * | ahead P(n), command g P(n)      | ::wake_q23_t      | Q23 of FS                  | [-256, 256) FS     |
 * | gate g, goal, ramp alpha        | ::wake_ratio_t    | Q30                        | [0, 1]             |
 */
#ifndef WAKE_RTP_H
#define WAKE_RTP_H

#include <stddef.h>
#include <stdint.h>

#include "wake_rtp_types.h"
#include "wake_ahead.h"
#include "wake_voluntary_ahead.h"

#ifdef __cplusplus
extern "C" {
#endif


/**
 * 1 (default): the Kalman update is compiled in.  0: a build for firmware
 * whose Kalman stays inert (q = 0 and p0 = 0, the WakeFilter default) leaves
 * the covariance code out (about half of the code); init, set_weights and
 * load_state then refuse q > 0, p0 > 0 or a non-zero d or P with
 * WAKE_RTP_E_NO_KALMAN.  The predictions of an inert configuration are the
 * same, bit for bit, in both builds.
 */
#ifndef WAKE_RTP_KALMAN
#define WAKE_RTP_KALMAN 1
#endif

/**
 * 1 (default): the tremor-ahead predictor and gate (issue 32) are compiled in:
 * each step also takes the tremor estimate e(n) = m(n) - y(n-1) into a delay
 * line of WAKE_RTP_AHEAD_TAPS values, predicts the tremor h samples ahead,
 * P(n) = c . line (c fitted per horizon by the HPA, wake_rtp_set_ahead),
 * ramps the gate g += (goal - g) alpha and makes the command g P
 * (wake_rtp_ahead_output).  The float twin is wake/ahead.py (AheadStep).
 * 0: the core is exactly the one without it (same struct, code and cost);
 * the voluntary prediction is the same, bit for bit, in both builds.
 */
#ifndef WAKE_RTP_AHEAD
#define WAKE_RTP_AHEAD 1
#endif

/**
 * 0 (default): the core as above.  1: also the split step (issue 33):
 * wake_rtp_prepare does everything of the next step that does not need its
 * sample (the FIR over the older 2^J - 1 samples of the window, the Kalman
 * gain and covariance update, the older seven products of the tremor ahead,
 * the gate) and wake_rtp_finish / wake_rtp_finish_missing the rest, with the
 * result of wake_rtp_step / wake_rtp_step_missing bit for bit.  Behind a
 * decimating front end (wake_rate.h, wake_rate_step) the prepare runs on an
 * input sample that only pushes, so no input sample pays for a whole step.
 * The struct grows by the prepared values (wake_rtp_split_t: 48 bytes on a
 * Cortex-M4 with the tremor ahead, 32 without) and the code by the two halves;
 * wake_rtp_step is the same function in both builds (it also forgets a
 * prepared step).  The split step's module (wake_rtp_split.c) compiles in
 * every build: a firmware that uses it links its entries
 * (wake.firmware.sources.FEATURE_ENTRIES), one that does not leaves them out.
 * Every translation unit of a firmware must see the same value.
 */
#ifndef WAKE_RTP_SPLIT
#define WAKE_RTP_SPLIT 0
#endif

/**
 * 0 (default): the core as above.  1: also the voluntary motion h samples
 * ahead (issue 32): a second weight vector w_h from the HPA
 * (wake_rtp_set_voluntary_ahead) and, per step, v_h(n) = w_h' (a + d) from the
 * state of the one-step prediction (wake_rtp_voluntary_ahead_output): a second
 * 2^J-tap FIR h_h = B' w_h over the same window plus one product, since d
 * moves along w only (the constant-time form above):
 *
 * @code
 *   w_h' d = w_h' d_s + k (z - z_s),    k = w_h' w / |w|^2
 * @endcode
 *
 * The float twin is wake/rtp/reference.py (ReferenceRTP.last_voluntary_ahead).
 * Until a w_h is installed the output is y(n), the one-step prediction held.
 * The struct grows by w_h, the second FIR and four scalars; the one-step
 * prediction and every other output are the same, bit for bit, in both builds.
 * The host extension (build_ffi.py) and the standalone firmware build with 1; a
 * firmware that does not use it leaves it 0, so its state, code, cost and static
 * bounds do not move (its module, wake_rtp_voluntary.c, compiles in every build;
 * such a firmware does not link its entries).  Not with WAKE_RTP_SPLIT 1 (the
 * split step has no second FIR): that combination does not compile.
 */
#ifndef WAKE_RTP_VOLUNTARY_AHEAD
#define WAKE_RTP_VOLUNTARY_AHEAD 0
#endif

#if WAKE_RTP_VOLUNTARY_AHEAD && WAKE_RTP_SPLIT
#error "WAKE_RTP_VOLUNTARY_AHEAD 1 and WAKE_RTP_SPLIT 1 together are not supported: the split step has no second FIR for w_h"
#endif


/**
 * What wake_rtp_prepare computed for the next finish (the split step, WAKE_RTP_SPLIT 1 builds embed one as
 * wake_rtp_t::split; its module, wake_rtp_split.c, compiles in every build and answers WAKE_RTP_E_FEATURE
 * where the instance holds none).
 */
typedef struct {
    int64_t fir;               /**< h' window less the newest sample's product, Q(FIR + 15), exact, |.| < 2^52 */
    int64_t s;                 /**< s after the next measurement update, Q(P_FRAC) of FS^2 */
    wake_ratio_t rho;          /**< rho = s / S of the next measurement update, Q30 */
    uint32_t events;           /**< saturations of the prepared measurement update */
    uint16_t ready;            /**< 1 from wake_rtp_prepare to the next step, else 0 */
    uint16_t reserved;         /**< 0 */
#if WAKE_RTP_AHEAD
    wake_ahead_prepared_t ahead;   /**< the tremor ahead's part of the next step (wake_ahead_prepare) */
#endif
} wake_rtp_split_t;

/**
 * One channel's complete state.  Treat the fields as read-only; change them
 * through the functions below.
 *
 * @par Scaling and overflow
 * See each field.  The struct holds no pointer except the taps, which the
 * caller owns (typically a `const` table in flash) and must keep alive; they
 * are read by init and set_weights only.  Any value of the per-sample fields
 * is safe for wake_rtp_step (every operation on them saturates), so a
 * corrupted number can give a wrong prediction but never undefined behaviour;
 * the structural fields and the weights are re-checked by every call.
 */
typedef struct {
    uint32_t magic;            /**< WAKE_RTP_MAGIC when initialised */
    uint32_t saturations;      /**< narrowings that saturated since init/reset (sticks at UINT32_MAX) */
    uint32_t steps;            /**< samples since the last restart (sticks at UINT32_MAX); P gains steps * q I */
    uint16_t level;            /**< J, 1..WAKE_RTP_MAX_LEVEL */
    uint16_t n_taps;           /**< N = 2^J */
    uint16_t head;             /**< ring index of the oldest sample, 0..N-1 */
    uint16_t primed;           /**< 0 until the first sample, then 1 */
    uint16_t inert;            /**< 1 only while q == 0 and s == 0 (the Kalman update is then the
                                    identity and is skipped); set by every restart */
    uint16_t reserved;         /**< 0 */
    const wake_q15_t *taps;    /**< J x N taps B, row-major, oldest sample first, Q15 (caller-owned) */
    wake_q24_t weights[WAKE_RTP_MAX_LEVEL];  /**< HPA weights w, Q24, |w| <= 64 */
    wake_cov_t r;              /**< measurement noise R, > 0 */
    wake_cov_t q;              /**< process noise q (Q = q I), >= 0 */
    wake_cov_t p0;             /**< initial covariance P(0) = p0 I, >= 0 */
    wake_cov_t variance;       /**< lambda >= 0: P = lambda I at the last restart (reset, set_weights,
                                    load_state) */
    int64_t q_omega;           /**< q |w|^2, Q(P_FRAC) of FS^2 in int64 */
    wake_q23_t last_output;    /**< y(n-1) (saturated to int32) */
    /* per-sample Kalman state: since the restart u = P w = (s / |w|^2) w, so d moves along w only */
    int64_t s;                 /**< w' P w, Q(P_FRAC) of FS^2 in int64 (with |w| up to 64 it leaves the
                                    int32 range of P); kept within +-2^50 */
    int64_t z;                 /**< w' d, Q23 of FS in int64 (w'a and w'd may each leave the int32
                                    range while y = w'(a + d) does not); kept within +-2^40 */
    wake_q23_t correction[WAKE_RTP_MAX_LEVEL];   /**< d_s, d at the last restart */
    wake_fir_t fir[WAKE_RTP_MAX_TAPS];           /**< h = B' w, oldest sample first */
    wake_q15_t ring[2 * WAKE_RTP_MAX_TAPS];      /**< the newest N samples, each stored twice (at k and
                                                      k + N) so that the window, oldest first, is the
                                                      contiguous ring[head .. head + N - 1] */
#if WAKE_RTP_AHEAD
    wake_ahead_t ahead;        /**< the tremor ahead (wake_ahead.h): set by wake_rtp_set_ahead, fed by every step */
#endif
#if WAKE_RTP_VOLUNTARY_AHEAD
    wake_voluntary_ahead_t voluntary_ahead;  /**< the voluntary motion ahead (wake_voluntary_ahead.h): w_h set by
                                                  wake_rtp_set_voluntary_ahead, rebuilt by every restart */
#endif
#if WAKE_RTP_SPLIT
    wake_rtp_split_t split;    /**< the split step's prepared values (wake_rtp_prepare): the setters recompute
                                    them when they are ready, any step forgets them */
#endif
} wake_rtp_t;

/**
 * @brief Initialise one channel.
 * @param[out] s        instance (any content)
 * @param[in]  level    J, 1..WAKE_RTP_MAX_LEVEL
 * @param[in]  taps     J x 2^J taps, row-major, oldest sample first, Q15;
 *                      kept by pointer (not copied): must outlive @p s
 * @param[in]  weights  J weights, Q24 (copied)
 * @param[in]  r        R, Q(P_FRAC) of FS^2, > 0
 * @param[in]  q        q, Q(P_FRAC) of FS^2, >= 0
 * @param[in]  p0       P(0) = p0 I, Q(P_FRAC) of FS^2, >= 0
 * @return WAKE_RTP_OK, or WAKE_RTP_E_NULL / _LEVEL / _TAPS / _WEIGHTS / _NOISE.
 *         On any error other than a NULL @p s, only the magic of @p s is
 *         written (cleared): every other call then refuses @p s with
 *         WAKE_RTP_E_UNINIT.
 *
 * @par Scaling and overflow
 * A tap row whose sum of |taps| exceeds 65535 (2.0 - 2^-15 in Q15) is
 * rejected, and |w| <= 64; so |h_i| = |sum_j B_ji w_j| < 64 J and the
 * window sum h' window stays below 2^47 in its int64 accumulator (exact).
 * The FIR taps are the exact int64 sums rounded once to
 * Q(WAKE_RTP_FIR_FRAC).  See wake_rtp_set_weights for the restart of P and d.
 */
wake_rtp_status_t wake_rtp_init(wake_rtp_t *s, int level, const wake_q15_t *taps,
                                const wake_q24_t *weights, wake_cov_t r, wake_cov_t q, wake_cov_t p0);

/**
 * @brief Install new HPA weights, R and q between two samples.
 *
 * Glitch-free: the ring, d and the last output are untouched; the covariance
 * restarts as P = (w'Pw / |w|^2) I with the old w (its variance along the
 * direction it observed; the largest P_ii when w = 0); the next step uses
 * the new values.
 * @param[in,out] s        initialised instance
 * @param[in]     weights  J weights, Q24, |w| <= 64
 * @param[in]     r        R, Q(P_FRAC) of FS^2, > 0
 * @param[in]     q        q, Q(P_FRAC) of FS^2, >= 0
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT, _CORRUPT, _WEIGHTS or _NOISE
 *         (on error nothing changes).
 *
 * @par Scaling and overflow
 * d = d_s + ((z - z_s) / |w|^2) w and lambda = s / |w|^2 (docs/studies/fixed_point.md):
 * each division by |w|^2 (Q24, < 2^40) is an exact restoring long division
 * (63 + frac turns, no division instruction) rounded once and clamped to
 * +-2^50, then narrowed to int32 with saturation; s = lambda |w|^2 and
 * q |w|^2 are exact in int64; w'd sums J products < 2^60 after a floor
 * shift by 3.
 */
wake_rtp_status_t wake_rtp_set_weights(wake_rtp_t *s, const wake_q24_t *weights, wake_cov_t r, wake_cov_t q);

/**
 * @brief Forget every sample; keep taps, weights, R, q and p0.
 *
 * Ring and d are zeroed, P = p0 I, the instance is unprimed and the
 * saturation counter restarts from zero.
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT or _CORRUPT.
 * @par Scaling and overflow
 * s = p0 |w|^2, exact in int64.
 */
wake_rtp_status_t wake_rtp_reset(wake_rtp_t *s);

/**
 * @brief Take sample m(n); return the predicted voluntary motion at n + 1.
 * @param[in,out] s           initialised instance
 * @param[in]     sample      m(n), Q15 of FS
 * @param[out]    prediction  y(n), Q15 of FS (saturated)
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT or _CORRUPT (then
 *         @p prediction is not written and the state is untouched).
 *
 * Constant time: no loop but the 2^J-tap FIR (and, on the first sample
 * only, the fill of the ring), no data-dependent branch but saturation.
 *
 * @par Scaling and overflow
 * FIR: h' window, int32 x int16 products into an int64 accumulator (exact,
 * < 2^47; on cores without a 64-bit multiply the same sum from split taps in
 * 32-bit parts, see wake_fir_t), rounded once to Q23.  e = m - y(n-1) in
 * Q23, saturated.  S = s + R in [1, 2^32) (clamped to >= 1); 1/S from a
 * 31-bit mantissa by four Newton-Raphson steps (the first two on its top 16
 * bits with 32-bit products, the last two with 32 x 32 -> 64-bit products;
 * relative error <= 2^-29).  rho = s/S and tau = 1 - rho in Q30, b/S in Q24: one product
 * with the reciprocal each, rounded once and saturated.  Every update
 * (z, d_dir, acc_vv, s, b) is one 32 x 32 -> 64-bit product
 * rounded once and added with int32 saturation.  y(n) = FIR + z, saturated
 * to int32 Q23 (stored) and to Q15 (returned).  While wake_rtp_t::inert is
 * set the Kalman part is skipped: it would change nothing.
 */
wake_rtp_status_t wake_rtp_step(wake_rtp_t *s, wake_q15_t sample, wake_q15_t *prediction);

/**
 * @brief No measurement at n (dropped packet, NaN).
 *
 * The last prediction (rounded to Q15, saturated) enters the ring as the
 * sample, the measurement update is skipped, P += q I still happens, then the
 * prediction is made.  Before the first sample: *prediction = 0 and nothing
 * changes.
 * @return as wake_rtp_step.
 * @par Scaling and overflow
 * As wake_rtp_step; the time update is s += q|w|^2, saturating.
 */
wake_rtp_status_t wake_rtp_step_missing(wake_rtp_t *s, wake_q15_t *prediction);

/**
 * @brief Run a block: out[k] = prediction after in[k], k = 0..n-1.
 *
 * Same result and cost per sample as n calls of wake_rtp_step (it makes
 * them: the instance is validated before the first sample and by every step).
 * @p in and @p out may be the same array.  n = 0 is allowed (pointers may
 * then be NULL).
 * @return as wake_rtp_step.
 * @par Scaling and overflow
 * As wake_rtp_step.
 */
wake_rtp_status_t wake_rtp_run(wake_rtp_t *s, const wake_q15_t *in, wake_q15_t *out, size_t n);


/**
 * @brief Set the full state (hand-over from a float warm-up).
 * @param[in,out] s           initialised instance
 * @param[in]     window      N = 2^J samples, oldest first, Q15 of FS
 * @param[in]     correction  J values d, Q23 of FS
 * @param[in]     covariance  J x J values P, row-major, Q(P_FRAC) of FS^2;
 *                            the core keeps w'Pw: P restarts as (w'Pw / |w|^2) I
 *                            (the largest P_ii when w = 0), as at a weight change
 * @param[in]     last_output y(n-1), Q23 of FS
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT, _CORRUPT or _STATE (a
 *         negative diagonal entry; nothing changes).
 *
 * The instance is primed afterwards; the saturation counter is kept.  Until
 * the next weight change only w'Pw and the direction of P w enter the
 * recursion; for a P from the same recursion (P w parallel to w) the
 * predictions are those of the full P.
 * @par Scaling and overflow
 * w'Pw = sum_i (P w)_i w_i: J products per row < 2^60 after a floor shift by
 * 3, each row rounded once; then as wake_rtp_set_weights.
 */
wake_rtp_status_t wake_rtp_load_state(wake_rtp_t *s, const wake_q15_t *window,
                                      const wake_q23_t *correction, const wake_cov_t *covariance,
                                      wake_q23_t last_output);

/**
 * @brief Read the Kalman state P and d (what the literal recursion holds).
 * @param[in]  s           initialised instance (not modified)
 * @param[out] correction  J values d, Q23 of FS
 * @param[out] covariance  J x J values P, row-major, Q(P_FRAC) of FS^2
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT or _CORRUPT.
 * @par Scaling and overflow
 * P = Lambda I - c w w' with Lambda = lambda + steps q and
 * c = (Lambda - s / |w|^2) / |w|^2: two long divisions as in
 * wake_rtp_set_weights, c carried with 16 extra fraction bits so that the
 * products w_i w_j (up to 2^12) do not amplify its rounding; the upper
 * triangle is computed and mirrored; entries beyond int32 saturate (not
 * counted: the instance is const).
 */
wake_rtp_status_t wake_rtp_get_state(const wake_rtp_t *s, wake_q23_t *correction, wake_cov_t *covariance);

/* The split step (wake_rtp_split.c): compiled in every build, linked by a firmware that calls it.  In a
 * build without WAKE_RTP_SPLIT the instance holds no prepared values: wake_rtp_prepare and the finishes
 * return WAKE_RTP_E_FEATURE once the instance is checked, changing nothing. */
/**
 * @brief The part of the next step that does not need its sample (WAKE_RTP_SPLIT builds).
 *
 * Reads the instance and stores the prepared values in it; the observable
 * state (ring, Kalman scalars, outputs, counters) is untouched.  Call it
 * any number of times between two steps (each recomputes); the setters
 * (set_weights, reset, load_state, the tremor-ahead setters) recompute a
 * prepared step themselves; wake_rtp_step, wake_rtp_step_missing, wake_rtp_run
 * (of one sample or more: a run of none steps nothing) and the finishes forget it.
 * @param[in,out] s  initialised instance
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT or _CORRUPT.
 *
 * @par Scaling and overflow
 * The FIR over the window the next push leaves, less its newest product:
 * h' (ring[head+1 .. head+N]) - h_{N-1} ring[head+N], both exact int64 sums
 * (< 2^52), so finish adds h_{N-1} m(n) and has wake_rtp_step's sum exactly;
 * before the first sample the sum of the taps (< 2^39, exact), which the
 * first sample multiplies (three 32-bit products).
 * The Kalman gain rho = s/S (Q30) and the new s = tau s + q|w|^2 exactly as
 * wake_rtp_step computes them, their saturations counted when the finish
 * applies them (a first or missing sample's finish makes its time update
 * s + q|w|^2 itself).  The tremor
 * ahead's c . line less c_0 times the estimate it drops (Q42, exact) and the
 * gate's next value towards the goal, as in wake_rtp_step.
 */
wake_rtp_status_t wake_rtp_prepare(wake_rtp_t *s);

/**
 * @brief Take sample m(n) into a prepared instance; as wake_rtp_step, bit for bit.
 * @param[in,out] s           initialised instance, prepared since its last step
 * @param[in]     sample      m(n), Q15 of FS
 * @param[out]    prediction  y(n), Q15 of FS (saturated)
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT, _CORRUPT or _UNPREPARED
 *         (then nothing changes and @p prediction is not written).
 *
 * The first sample of a stream fills the window with itself and multiplies
 * the prepared sum of the taps by it; every other sample adds one FIR
 * product, the correction z += rho e, one tremor-ahead product and the
 * command.
 *
 * @par Scaling and overflow
 * acc = prepared sum + h_{N-1} m(n), exact in int64 (the prepared sum is
 * clamped to +-2^52 first, so a corrupted one cannot overflow), then as
 * wake_rtp_step: e = m - y(n-1) saturated to int32 Q23, z += round(rho e /
 * 2^30) clamped to +-2^40, y(n) rounded once to Q23 and to Q15 with
 * saturation; the ahead's P = prepared (clamped to +-2^49) + c_0 e(n), Q42,
 * rounded once to Q23, and g P as wake_rtp_step.
 */
wake_rtp_status_t wake_rtp_finish(wake_rtp_t *s, wake_q15_t sample, wake_q15_t *prediction);

/**
 * @brief No measurement at n, on a prepared instance; as wake_rtp_step_missing, bit for bit.
 * @return as wake_rtp_finish.
 * @par Scaling and overflow
 * As wake_rtp_finish with the last prediction (rounded to Q15, saturated)
 * as the sample and the prepared time update s + q|w|^2 (saturating).
 */
wake_rtp_status_t wake_rtp_finish_missing(wake_rtp_t *s, wake_q15_t *prediction);

/* The tremor ahead of the instance (wake_rtp_t::ahead): each function below forwards to its wake_ahead.h
 * counterpart after checking the instance.  In a build without it (WAKE_RTP_AHEAD 0) the instance has none
 * and each returns WAKE_RTP_E_FEATURE once the instance is checked, changing nothing. */
/**
 * @brief Install an HPA's tremor-ahead predictor and the gate's goal between two samples.
 *
 * The delay line and the gate's value carry over; the gate ramps from its
 * value towards @p goal.  (wake.ahead.AheadStep.set_model)
 * @param[in,out] s             initialised instance
 * @param[in]     coefficients  WAKE_RTP_AHEAD_TAPS values c, newest estimate first, Q27, |c| <= 8
 * @param[in]     goal          the gate's goal, Q30, in [0, 2^30]
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT, _CORRUPT or _AHEAD (on
 *         error nothing changes).
 * @par Scaling and overflow
 * Copies only; the ranges are what wake_rtp_step's bounds assume.
 */
wake_rtp_status_t wake_rtp_set_ahead(wake_rtp_t *s, const int32_t *coefficients, wake_ratio_t goal);

/**
 * @brief Set the gate's ramp coefficient alpha = 1 / max(1, 0.3 fs) (init sets 1/30, fs = 100 Hz).
 * @param[in,out] s     initialised instance
 * @param[in]     ramp  alpha, Q30, in [1, 2^30]
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT, _CORRUPT or _AHEAD.
 * @par Scaling and overflow
 * A copy; alpha <= 2^30 keeps every gate step within [0, 1].
 */
wake_rtp_status_t wake_rtp_set_ahead_ramp(wake_rtp_t *s, wake_ratio_t ramp);

/**
 * @brief The tremor ahead made by the last step: P(n), g(n) and g(n) P(n).
 *
 * Before the first step (and after reset) all three are 0.
 * @param[in]  s          initialised instance (not modified)
 * @param[out] predicted  P(n), the tremor predicted for n + h, Q23 of FS (may be NULL)
 * @param[out] gate       g(n), the confidence, Q30 in [0, 2^30] (may be NULL)
 * @param[out] command    g(n) P(n), Q23 of FS (may be NULL)
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT or _CORRUPT.
 * @par Scaling and overflow
 * Reads only.
 */
wake_rtp_status_t wake_rtp_ahead_output(const wake_rtp_t *s, wake_q23_t *predicted, wake_ratio_t *gate,
                                        wake_q23_t *command);

/**
 * @brief Set the tremor-ahead state (hand-over from a float warm-up or another full scale).
 * @param[in,out] s     initialised instance
 * @param[in]     line  WAKE_RTP_AHEAD_TAPS tremor estimates, newest first, Q15 of FS
 * @param[in]     gate  the gate's value, Q30, in [0, 2^30]
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT, _CORRUPT or _AHEAD (nothing changes).
 *         The coefficients and the goal are wake_rtp_set_ahead's.
 * @par Scaling and overflow
 * Copies only.
 */
wake_rtp_status_t wake_rtp_load_ahead_state(wake_rtp_t *s, const wake_q15_t *line, wake_ratio_t gate);

/**
 * @brief Read the tremor-ahead state: the delay line newest first (Q15 of FS).
 * @param[in]  s     initialised instance (not modified)
 * @param[out] line  WAKE_RTP_AHEAD_TAPS tremor estimates, newest first
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT or _CORRUPT.
 * @par Scaling and overflow
 * Reads only.
 */
wake_rtp_status_t wake_rtp_get_ahead_state(const wake_rtp_t *s, wake_q15_t *line);

/* The voluntary motion ahead of the instance (wake_rtp_t::voluntary_ahead, wake_rtp_voluntary.c): compiled in
 * every build, linked by a firmware that calls it.  In a build without WAKE_RTP_VOLUNTARY_AHEAD the instance
 * holds none: wake_rtp_set_voluntary_ahead and wake_rtp_voluntary_ahead_output return WAKE_RTP_E_FEATURE once
 * the instance is checked, changing nothing. */
/**
 * @brief Install w_h, the HPA's weights of the voluntary motion h samples ahead, between two samples.
 *
 * The ring, d, P and the one-step prediction are untouched: from the next step
 * on the core also outputs v_h(n) = w_h' (a + d) (ReferenceRTP.set_weights_ahead).
 * Weights, R and q installed later (wake_rtp_set_weights) keep this w_h.
 * @param[in,out] s              initialised instance
 * @param[in]     weights_ahead  J weights w_h, Q24, |w_h| <= 64
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT, _CORRUPT or _WEIGHTS (on
 *         error nothing changes).
 *
 * @par Scaling and overflow
 * The FIR taps h_h = B' w_h as wake_rtp_init's h = B' w (exact int64, Q39,
 * rounded once to Q(WAKE_RTP_FIR_FRAC)).  w_h' d_s and z_s = w' d_s: J
 * products < 2^60 after a floor shift by 3, rounded once to Q23 (|.| < 2^41).
 * k = w_h' w / |w|^2: the J products Q48 (< 2^60 after the floor shift by 3)
 * over |w|^2 (Q24, < 2^40) by the exact long division of set_weights, rounded
 * once to Q24 and narrowed to int32 with saturation ([-128, 128), counted in
 * voluntary_ahead.saturations); 0 when w = 0 (d = d_s then).
 */
wake_rtp_status_t wake_rtp_set_voluntary_ahead(wake_rtp_t *s, const wake_q24_t *weights_ahead);

/**
 * @brief The voluntary motion h samples ahead made by the last step: v_h(n) = w_h' (a + d).
 *
 * y(n), the one-step prediction, while no w_h is installed; 0 before the first
 * step and after reset.
 * @param[in]  s       initialised instance (not modified)
 * @param[out] output  v_h(n), Q23 of FS
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL, _UNINIT or _CORRUPT.
 * @par Scaling and overflow
 * Reads only.  Per step (wake_rtp_step, wake_rtp_step_missing, wake_rtp_run):
 * v_h = round(h_h' window / 2^(FIR + 15 - 23)) + w_h' d_s + round(k (z - z_s) / 2^24):
 * the FIR exact in int64 (< 2^47) as y's; z - z_s clamped to +-2^41, its
 * product with k (Q24) from two 32 x 32 -> 64-bit products (< 2^62), rounded
 * once; the sum (< 2^49) narrowed once to int32 Q23 with saturation (counted in
 * voluntary_ahead.saturations).
 */
wake_rtp_status_t wake_rtp_voluntary_ahead_output(const wake_rtp_t *s, wake_q23_t *output);

/**
 * @brief Run a block and collect every per-sample output: after in[k], k = 0..n-1,
 * voluntary[k] = y(n) (wake_rtp_step's prediction), tremor_ahead[k], gate[k]
 * and command[k] = P(n), g(n) and g(n) P(n) (wake_rtp_ahead_output), and
 * voluntary_ahead[k] = v_h(n) (wake_rtp_voluntary_ahead_output).
 * Same result, state and cost per sample as n calls of wake_rtp_step, or of
 * wake_rtp_step_missing where missing[k] is non-zero, each followed by the
 * reads of its outputs: one call per block of a batch caller.
 * @param[in,out] s                initialised instance
 * @param[in]     in               n samples m, Q15 of FS (in[k] is not read where missing[k] != 0)
 * @param[in]     missing          n flags, non-zero: no measurement at k; NULL: every sample measured
 * @param[in]     n                samples; 0 is allowed (pointers may then be NULL)
 * @param[out]    voluntary        n values y, Q15 of FS (may be NULL)
 * @param[out]    tremor_ahead     n values P, Q23 of FS (may be NULL)
 * @param[out]    gate             n values g, Q30 in [0, 2^30] (may be NULL)
 * @param[out]    command          n values g P, Q23 of FS (may be NULL)
 * @param[out]    voluntary_ahead  n values v_h, Q23 of FS (may be NULL)
 * In a build without WAKE_RTP_AHEAD the three tremor-ahead outputs are 0
 * (nothing predicted, the gate shut).  The arrays must not overlap.
 * In a build without WAKE_RTP_VOLUNTARY_AHEAD, voluntary_ahead[k] is y(n)
 * in Q23 (what the voluntary ahead outputs while no w_h is installed).
 * The host's block entry: a firmware's block of predictions is wake_rtp_run,
 * and a firmware that does not call this one does not link it.
 * @return WAKE_RTP_OK, WAKE_RTP_E_NULL (@p in NULL with n > 0), _UNINIT or
 *         _CORRUPT (checked before the first sample; then nothing is written
 *         and the state is untouched).
 * @par Scaling and overflow
 * As wake_rtp_step and wake_rtp_step_missing; the outputs are copies of the
 * values each step stores.
 */
wake_rtp_status_t wake_rtp_run_outputs(wake_rtp_t *s, const wake_q15_t *in, const uint8_t *missing, size_t n,
                                       wake_q15_t *voluntary, wake_q23_t *tremor_ahead, wake_ratio_t *gate,
                                       wake_q23_t *command, wake_q23_t *voluntary_ahead);

/**
 * @brief 2^61 / x for x in [2^30, 2^31), by Newton-Raphson (no division).
 *
 * Exposed for testing.  The result lies in [2^30, 2^31]; its error is at
 * most 2^-29 relative (measured over 2e5 arguments: 1 unit of 2^-30).
 * @par Scaling and overflow
 * x is Q31 of [0.5, 1), the result Q30 of (1, 2]; 32 x 32 -> 64-bit
 * unsigned products only, each below 2^62.
 */
uint32_t wake_rtp_reciprocal(uint32_t x);

#ifdef __cplusplus
}
#endif

#endif /* WAKE_RTP_H */
