/**
 * @file wake_eval.h
 * @brief The per-sample loops of the evaluation's baselines (BMFLC, E-BMFLC, WFLC, eHWFLC-KF), for the host only.
 *
 * wake.eval.baselines runs these loops in one C call per channel instead of
 * numpy (or scipy) calls per sample; each mirrors the Python loop kept beside
 * it in wake/eval/baselines.py and wake/eval/ehwflc.py (the fallback when the C core is not built),
 * operation by operation, so its outputs agree with the loop's within
 * rounding (tests/eval/test_baselines_c.py pins 1e-12 of the largest output).
 *
 * Host code in double precision with libm (sin, cos, sqrt, fmod): not part of
 * the real-time path and not linked into any firmware build: it lives with the
 * evaluation (wake/eval/native), outside the firmware tree csrc/, and only
 * build_ffi.py compiles it, into the host extension wake._rtp. No allocation:
 * the caller passes every buffer, zeroed where noted.
 *
 * Arrays are row-major. @p phi holds the regressor rows of samples
 * 0 .. n + max(h) - 1; @p ahead holds one row of n values per horizon.
 */
#ifndef WAKE_EVAL_H
#define WAKE_EVAL_H

#include <stddef.h>

/** BMFLC (Veluvolu et al.): LMS on a sine/cosine bank of @p m columns and a bias.
 *  @p w (m values) zeroed by the caller; writes vol[i] = b(i-1), bank[i] = phi[i] . w(i-1). */
void wake_eval_bmflc(const double *phi, size_t n, size_t m, const double *x, double two_mu, double two_mu_bias,
                     const long *horizons, size_t n_horizons, double *w, double *vol, double *bank, double *ahead);

/** E-BMFLC (Atashzar et al.): exponentially weighted least squares over @p p regressors, solved every sample
 *  by a Cholesky factorisation of the information matrix G (upper triangle kept, p x p), the first @p nv
 *  regressors voluntary. @p g: p*p (filled here), @p u: p*p scratch, @p r, @p w, @p y: p values each (zeroed
 *  here). Writes pred[i] = phi[i] . w(i-1) and vol[i] (its voluntary part). */
void wake_eval_ebmflc(const double *phi, size_t n, size_t p, size_t nv, const double *x, double rho, double delta,
                      double leak, const long *horizons, size_t n_horizons, double *g, double *u, double *r,
                      double *w, double *y, double *vol, double *pred, double *ahead);

/** WFLC (Riviere et al.): @p m harmonics of an adapted frequency with an accumulated phase, and a bias.
 *  @p a, @p c, @p sn, @p cs: m values each (scratch, zeroed here). Writes vol[i] = b(i-1), bank[i] (the
 *  harmonics' sum) and freq[i] (the frequency used at i, Hz). */
void wake_eval_wflc(const double *x, size_t n, size_t m, double fs, double omega0, double lo, double hi,
                    double two_mu, double two_mu_bias, double two_mu0, double beta, const long *horizons,
                    size_t n_horizons, double *a, double *c, double *sn, double *cs, double *vol, double *bank,
                    double *freq, double *ahead);

/** eHWFLC-KF (Zhou et al.): @p m harmonics of an adapted frequency whose weights and bias, the state
 *  w = [b, a_1, c_1, ..., a_m, c_m] (dim = 1 + 2m), a Kalman filter tracks (random-walk variances @p q_bias,
 *  @p q_tremor, initial variance @p p0, all relative to a unit measurement variance). @p w, @p phi, @p pphi:
 *  dim values each, @p p: dim*dim (scratch, set here). Writes vol[i] = b(i-1), bank[i] (the harmonics' sum)
 *  and freq[i] (the frequency used at i, Hz). */
void wake_eval_ehwflc(const double *x, size_t n, size_t m, double fs, double omega0, double lo, double hi,
                      double two_mu0, double beta, double p0, double q_bias, double q_tremor, const long *horizons,
                      size_t n_horizons, double *w, double *p, double *phi, double *pphi, double *vol, double *bank,
                      double *freq, double *ahead);

#endif /* WAKE_EVAL_H */
