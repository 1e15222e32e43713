/**
 * @file wake_eval.c
 * @brief The baselines' per-sample loops (see wake_eval.h); host-only, double precision.
 */
#include "wake_eval.h"

#include <math.h>
#include <string.h>

#define TWO_PI (2.0 * 3.141592653589793)

/* The factorisation's row updates are independent axpys: on x86-64 Linux with GCC, a copy for AVX2 as well
 * (picked at load time; -ffp-contract=off keeps every product and sum as written, so both copies round alike). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define WAKE_EVAL_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define WAKE_EVAL_CLONES
#endif

static double dot(const double *a, const double *b, size_t n)
{
    double s = 0.0;
    size_t j;
    for (j = 0; j < n; ++j) {
        s += a[j] * b[j];
    }
    return s;
}

void wake_eval_bmflc(const double *phi, size_t n, size_t m, const double *x, double two_mu, double two_mu_bias,
                     const long *horizons, size_t n_horizons, double *w, double *vol, double *bank, double *ahead)
{
    double b = 0.0;
    size_t i, j, k;
    for (i = 0; i < n; ++i) {
        const double *f = phi + i * m;
        double t = dot(f, w, m);
        double e;
        vol[i] = b;
        bank[i] = t;
        e = x[i] - t - b;
        for (j = 0; j < m; ++j) {
            w[j] += two_mu * (f[j] * e);
        }
        b = b + two_mu_bias * e;
        for (k = 0; k < n_horizons; ++k) {
            ahead[k * n + i] = dot(phi + (i + (size_t)horizons[k]) * m, w, m);
        }
    }
}

/* u := the upper Cholesky factor of the upper triangle of g (g = u' u), outer-product form: every inner loop
 * runs along a row. */
WAKE_EVAL_CLONES
static void cholesky_upper(const double *g, double *u, size_t p)
{
    size_t i, j, k;
    for (i = 0; i < p; ++i) {
        memcpy(u + i * p + i, g + i * p + i, (p - i) * sizeof(double));
    }
    for (i = 0; i < p; ++i) {
        double *ui = u + i * p;
        double d = sqrt(ui[i]);
        ui[i] = d;
        for (j = i + 1; j < p; ++j) {
            ui[j] /= d;
        }
        for (j = i + 1; j < p; ++j) {
            double s = ui[j];
            double *uj = u + j * p;
            for (k = j; k < p; ++k) {
                uj[k] -= s * ui[k];
            }
        }
    }
}

/* w := (u' u)^-1 r, y scratch (overwritten). */
static void cholesky_solve(const double *u, const double *r, double *w, double *y, size_t p)
{
    size_t i, j;
    memcpy(y, r, p * sizeof(double));
    for (i = 0; i < p; ++i) {  /* u' y = r, column by column of u' (rows of u) */
        const double *ui = u + i * p;
        double v = y[i] / ui[i];
        y[i] = v;
        for (j = i + 1; j < p; ++j) {
            y[j] -= ui[j] * v;
        }
    }
    for (i = p; i-- > 0;) {    /* u w = y */
        const double *ui = u + i * p;
        w[i] = (y[i] - dot(ui + i + 1, w + i + 1, p - i - 1)) / ui[i];
    }
}

WAKE_EVAL_CLONES
void wake_eval_ebmflc(const double *phi, size_t n, size_t p, size_t nv, const double *x, double rho, double delta,
                      double leak, const long *horizons, size_t n_horizons, double *g, double *u, double *r,
                      double *w, double *y, double *vol, double *pred, double *ahead)
{
    size_t i, j, k;
    memset(g, 0, p * p * sizeof(double));
    memset(u, 0, p * p * sizeof(double));
    for (j = 0; j < p; ++j) {
        g[j * p + j] = delta;
        r[j] = 0.0;
        w[j] = 0.0;
        y[j] = 0.0;
    }
    for (i = 0; i < n; ++i) {
        const double *f = phi + i * p;
        pred[i] = dot(f, w, p);
        vol[i] = dot(f, w, nv);
        /* G = rho G + f f' + leak I, in the Python loop's order: scale, add the outer product, add the leak */
        for (j = 0; j < p; ++j) {
            double *gj = g + j * p;
            double fj = f[j];
            for (k = j; k < p; ++k) {
                gj[k] = gj[k] * rho + fj * f[k];
            }
            gj[j] += leak;
            r[j] = r[j] * rho + f[j] * x[i];
        }
        cholesky_upper(g, u, p);
        cholesky_solve(u, r, w, y, p);
        for (k = 0; k < n_horizons; ++k) {
            const double *fh = phi + (i + (size_t)horizons[k]) * p;
            ahead[k * n + i] = dot(fh + nv, w + nv, p - nv);
        }
    }
}

void wake_eval_wflc(const double *x, size_t n, size_t m, double fs, double omega0, double lo, double hi,
                    double two_mu, double two_mu_bias, double two_mu0, double beta, const long *horizons,
                    size_t n_horizons, double *a, double *c, double *sn, double *cs, double *vol, double *bank,
                    double *freq, double *ahead)
{
    double omega = omega0, theta = 0.0, b = 0.0, power = 0.0;
    size_t i, j, k;
    for (j = 0; j < m; ++j) {
        a[j] = 0.0;
        c[j] = 0.0;
    }
    for (i = 0; i < n; ++i) {
        double t = 0.0, z = 0.0, e, dev;
        for (j = 0; j < m; ++j) {
            double arg = (double)(j + 1) * theta;
            sn[j] = sin(arg);
            cs[j] = cos(arg);
            t += a[j] * sn[j] + c[j] * cs[j];
        }
        vol[i] = b;
        bank[i] = t;
        freq[i] = omega * fs / TWO_PI;
        e = x[i] - t - b;
        dev = x[i] - b;
        power = (i == 0) ? dev * dev : power + beta * (dev * dev - power);
        for (j = 0; j < m; ++j) {
            z += (double)(j + 1) * (a[j] * cs[j] - c[j] * sn[j]);
        }
        omega = omega + two_mu0 * e * z / (power + 1e-300);
        omega = omega < lo ? lo : (omega > hi ? hi : omega);
        for (j = 0; j < m; ++j) {
            a[j] += two_mu * sn[j] * e;
            c[j] += two_mu * cs[j] * e;
        }
        b = b + two_mu_bias * e;
        theta = fmod(theta + omega, TWO_PI);
        for (k = 0; k < n_horizons; ++k) {  /* the phase advanced by the frequency now in use */
            double ph = theta + (double)(horizons[k] - 1) * omega;
            double s = 0.0;
            for (j = 0; j < m; ++j) {
                double arg = (double)(j + 1) * ph;
                s += a[j] * sin(arg) + c[j] * cos(arg);
            }
            ahead[k * n + i] = s;
        }
    }
}

/* The Python loop's order throughout: the estimate from the weights before the update, the frequency step from
 * them too, the Kalman update (P + Q, P phi, phi' P phi + 1, the gain, w, P), then the phase. */
void wake_eval_ehwflc(const double *x, size_t n, size_t m, double fs, double omega0, double lo, double hi,
                      double two_mu0, double beta, double p0, double q_bias, double q_tremor, const long *horizons,
                      size_t n_horizons, double *w, double *p, double *phi, double *pphi, double *vol, double *bank,
                      double *freq, double *ahead)
{
    size_t dim = 1 + 2 * m;
    double omega = omega0, theta = 0.0, power = 0.0;
    size_t i, j, k;
    memset(p, 0, dim * dim * sizeof(double));
    for (j = 0; j < dim; ++j) {
        w[j] = 0.0;
        p[j * dim + j] = p0;
    }
    phi[0] = 1.0;
    for (i = 0; i < n; ++i) {
        double b = w[0], t = 0.0, z = 0.0, e, dev, s;
        for (j = 0; j < m; ++j) {
            double arg = (double)(j + 1) * theta;
            phi[1 + 2 * j] = sin(arg);
            phi[2 + 2 * j] = cos(arg);
            t += w[1 + 2 * j] * phi[1 + 2 * j] + w[2 + 2 * j] * phi[2 + 2 * j];
        }
        vol[i] = b;
        bank[i] = t;
        freq[i] = omega * fs / TWO_PI;
        e = x[i] - t - b;
        dev = x[i] - b;
        power = (i == 0) ? dev * dev : power + beta * (dev * dev - power);
        for (j = 0; j < m; ++j) {
            z += (double)(j + 1) * (w[1 + 2 * j] * phi[2 + 2 * j] - w[2 + 2 * j] * phi[1 + 2 * j]);
        }
        p[0] += q_bias;
        for (j = 1; j < dim; ++j) {
            p[j * dim + j] += q_tremor;
        }
        for (j = 0; j < dim; ++j) {
            pphi[j] = dot(p + j * dim, phi, dim);
        }
        s = dot(phi, pphi, dim) + 1.0;
        for (j = 0; j < dim; ++j) {  /* the gain K_j = (P phi)_j / s; row j of P loses K_j (P phi)' */
            double kj = pphi[j] / s;
            double *pj = p + j * dim;
            w[j] += kj * e;
            for (k = 0; k < dim; ++k) {
                pj[k] -= kj * pphi[k];
            }
        }
        omega = omega + two_mu0 * e * z / (power + 1e-300);
        omega = omega < lo ? lo : (omega > hi ? hi : omega);
        theta = fmod(theta + omega, TWO_PI);
        for (k = 0; k < n_horizons; ++k) {  /* the phase advanced by the frequency now in use */
            double ph = theta + (double)(horizons[k] - 1) * omega;
            double a = 0.0;
            for (j = 0; j < m; ++j) {
                double arg = (double)(j + 1) * ph;
                a += w[1 + 2 * j] * sin(arg) + w[2 + 2 * j] * cos(arg);
            }
            ahead[k * n + i] = a;
        }
    }
}
