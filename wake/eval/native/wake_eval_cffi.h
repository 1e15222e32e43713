/* The cffi declarations of the host-only evaluation loops (wake_eval.h beside this file), read by build_ffi.py
 * after csrc/wake_cffi.h: written for cffi as that file is (no conditionals, no includes). */
void wake_eval_bmflc(const double *phi, size_t n, size_t m, const double *x, double two_mu, double two_mu_bias,
                     const long *horizons, size_t n_horizons, double *w, double *vol, double *bank, double *ahead);
void wake_eval_ebmflc(const double *phi, size_t n, size_t p, size_t nv, const double *x, double rho, double delta,
                      double leak, const long *horizons, size_t n_horizons, double *g, double *u, double *r,
                      double *w, double *y, double *vol, double *pred, double *ahead);
void wake_eval_wflc(const double *x, size_t n, size_t m, double fs, double omega0, double lo, double hi,
                    double two_mu, double two_mu_bias, double two_mu0, double beta, const long *horizons,
                    size_t n_horizons, double *a, double *c, double *sn, double *cs, double *vol, double *bank,
                    double *freq, double *ahead);
void wake_eval_ehwflc(const double *x, size_t n, size_t m, double fs, double omega0, double lo, double hi,
                      double two_mu0, double beta, double p0, double q_bias, double q_tremor, const long *horizons,
                      size_t n_horizons, double *w, double *p, double *phi, double *pphi, double *vol, double *bank,
                      double *freq, double *ahead);
