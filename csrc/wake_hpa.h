/**
 * @file wake_hpa.h
 * @brief The WAKE hyper-parameter adjustment (HPA) in portable single-precision C.
 *
 * A port of the Python reference `wake.hpa.run_hpa` (causal fit) for firmware
 * that re-fits its own weights with no host.  One HPA run takes a window of
 * the newest n <= L samples (the RTP's int16 Q15 input) and produces what
 * wake_rtp_set_weights() takes:
 * @code
 *   S1  r(k) = sum x_c(t) x_c(t+k)          exact in int64 (x_c = x - mean)
 *       a, sigma^2 = Levinson-Durbin(r)      AR(p), float
 *       D(f) = |1 + sum a_k e^{-j 2 pi f k / fs}|^2 on f = k fs / 1022
 *   S2  f_d = the valley rule on PSD = sigma^2 / D (dB tests as ratios of D); rule floor
 *       (the default) also compares the dip with the noise floor, max D over fs/2 and every
 *       8th bin below it above the tremor band (wake.hpa.find_cutoff)
 *   GT  v(t) = mean + (2/n) Re sum_{m: m fs/n <= f_d} X_m e^{j 2 pi m t / n}
 *       (the sharp FFT high-pass's voluntary part, from the bins below f_d only,
 *       each X_m by Reinsch's form of the Goertzel recursion, two bins per pass)
 *   S4  w = argmin |A w - v(+1)|^2 + lambda |w|^2 over the causal bank outputs A
 *       G = A'A = B Rxx B' + mean terms,  b = A'v(+1) = B Cxy + mean terms
 *       R = var(x - v), floored at 1e-6 var(x)
 * @endcode
 * docs/studies/hpa_c.md derives each rearrangement and records its agreement with the
 * Python HPA.
 *
 * Single precision only (`float`, no double: builds with -Wdouble-promotion),
 * no libm (cosines from a polynomial on an exact integer angle, dB tests as
 * ratios), no allocation, no global state.  Every buffer lives in one
 * caller-owned ::wake_hpa_t.  Build with `-ffp-contract=off` (the Makefile
 * does): the evaluation order is then fixed and the same image gives the same
 * bits on every IEEE-754 single-precision machine (checked: host x86-64
 * against a Cortex-M4F under QEMU).
 *
 * @par Two ways to run it
 * - RTOS task or main loop: wake_hpa_start() (or wake_hpa_push() when a window
 *   fills) then wake_hpa_run(), which returns when the result is ready.
 * - Bare-metal super-loop: one wake_hpa_slice() after each wake_rtp_step().
 *   A slice does a bounded amount of work (#WAKE_HPA_SLICE_BUDGET by a cost
 *   model, or one indivisible step); `wake profile` reports the largest slice
 *   in instructions.  wake_hpa_apply() hands the result to the RTP between two
 *   samples.
 *
 * @par Double buffering
 * wake_hpa_push() fills one window buffer while the HPA reads the other; the
 * buffers swap every L samples.  A warm-up HPA (a sample count in
 * wake_hpa_config_t::warmup) reads the prefix of the buffer being filled,
 * which pushes never overwrite until the swap.
 *
 * @par Memory
 * sizeof(wake_hpa_t) is a compile-time constant, with W = WAKE_HPA_MAX_WINDOW,
 * J = WAKE_HPA_MAX_LEVEL, p = WAKE_HPA_MAX_ORDER, B = WAKE_HPA_MAX_PSD_BINS, about
 *   4 W (the two int16 windows) + (8 J + 12) 2^J (the bank as floats, Rxx B',
 *   three 2^J sums) + 8 p + 4 B + 8 J^2 + 24 J + 400 bytes;
 * 4,832 bytes with -DWAKE_HPA_MAX_WINDOW=500 -DWAKE_HPA_MAX_LEVEL=5
 * -DWAKE_HPA_MAX_ORDER=17 -DWAKE_HPA_MAX_PSD_BINS=64 (`wake profile --hpa`
 * measures it on the target).  Stack: about 200 bytes on a Cortex-M4F, 400 on
 * a Cortex-M0+ (its soft-float calls); no recursion, no arrays on the stack.
 */
#ifndef WAKE_HPA_H
#define WAKE_HPA_H

#include <stddef.h>
#include <stdint.h>

#include "wake_rtp.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Largest window L (samples) the struct has room for; at most 1024 (int64 sums stay exact). */
#ifndef WAKE_HPA_MAX_WINDOW
#define WAKE_HPA_MAX_WINDOW 512
#endif
/** Largest level J (filter bank of 2^J taps). */
#ifndef WAKE_HPA_MAX_LEVEL
#define WAKE_HPA_MAX_LEVEL WAKE_RTP_MAX_LEVEL
#endif
/** Largest AR order p. */
#ifndef WAKE_HPA_MAX_ORDER
#define WAKE_HPA_MAX_ORDER 24
#endif
/** PSD bins kept for the valley search: bins k with k fs / 1022 <= cutoff_high (62 at 100 Hz, 6 Hz). */
#ifndef WAKE_HPA_MAX_PSD_BINS
#define WAKE_HPA_MAX_PSD_BINS 128
#endif
/**
 * Work one wake_hpa_slice() may do, in Cortex-M4F instructions of the cost
 * model in wake_hpa.c (1: one loop item or one indivisible step per slice,
 * which is how `python -m wake.firmware.hpa_cost --calibrate` measures the model).
 */
#ifndef WAKE_HPA_SLICE_BUDGET
#define WAKE_HPA_SLICE_BUDGET 1600
#endif

#if WAKE_HPA_MAX_WINDOW < 4 || WAKE_HPA_MAX_WINDOW > 1024
#error "WAKE_HPA_MAX_WINDOW must lie in 4..1024"
#endif
#if WAKE_HPA_MAX_LEVEL < 1 || WAKE_HPA_MAX_LEVEL > WAKE_RTP_MAX_LEVEL
#error "WAKE_HPA_MAX_LEVEL must lie in 1..WAKE_RTP_MAX_LEVEL"
#endif
#if WAKE_HPA_MAX_ORDER < 1 || WAKE_HPA_MAX_ORDER > 255
#error "WAKE_HPA_MAX_ORDER must lie in 1..255"
#endif
#if WAKE_HPA_MAX_PSD_BINS < 4 || WAKE_HPA_MAX_PSD_BINS > 512
#error "WAKE_HPA_MAX_PSD_BINS must lie in 4..512"
#endif
#if WAKE_HPA_SLICE_BUDGET < 1 || WAKE_HPA_SLICE_BUDGET > 1000000
#error "WAKE_HPA_SLICE_BUDGET must lie in 1..1000000"
#endif

/** Filter-bank taps for the largest level. */
#define WAKE_HPA_MAX_TAPS (1 << WAKE_HPA_MAX_LEVEL)
/** Warm-up HPA points the configuration can hold. */
#define WAKE_HPA_MAX_WARMUP 8
/** The fit target: the voluntary motion this many samples after the newest filter-bank input
 *  (wake.target.PredictionTarget.horizon); the fit rows pair a(t) with v(t + WAKE_HPA_HORIZON). */
#define WAKE_HPA_HORIZON 1u
/**
 * 1: the instance holds the tremor-ahead fit's state (wake_hpa_ahead_t) and a run also fits the predictor and
 * its gate's goal (wake_hpa_ahead.c; issue 32; needs WAKE_RTP_AHEAD), which wake_hpa_apply() installs; 0
 * (default): it does not (the result's ahead fields are zero), nothing calls wake_hpa_ahead.c (a firmware need
 * not link it), and its code, RAM and cost are those without it.  Off by default because of its cost:
 * docs/studies/hpa_c.md, "The tremor ahead".
 */
#ifndef WAKE_HPA_AHEAD
#define WAKE_HPA_AHEAD 0
#endif
/** Taps of the tremor-ahead predictor the HPA fits (wake.ahead.TAPS; the RTP's WAKE_RTP_AHEAD_TAPS). */
#define WAKE_HPA_AHEAD_TAPS 8u
/** Largest |coefficient| of the tremor-ahead predictor (wake.ahead.COEFFICIENT_LIMIT). */
#define WAKE_HPA_AHEAD_COEF_LIMIT 8.0f
/** Largest tremor-ahead horizon wake_hpa_config_t::horizon may ask for, samples. */
#define WAKE_HPA_MAX_AHEAD_HORIZON 32u
/** Estimates the tremor-ahead pass keeps: a row's 8 lags h samples before its target, and the 7 rows before
 *  the last row (the Gram's edge terms). */
#define WAKE_HPA_AHEAD_RING (2u * WAKE_HPA_AHEAD_TAPS + WAKE_HPA_MAX_AHEAD_HORIZON)
/** DFT bins the voluntary truth can hold (m fs / n <= cutoff_high < (B - 1) fs / 1022, so m < L (B - 1) / 1022). */
#define WAKE_HPA_MAX_BINS ((WAKE_HPA_MAX_WINDOW * (WAKE_HPA_MAX_PSD_BINS - 1)) / WAKE_HPA_PSD_GRID + 1)
/** FFT length of the Python AR spectrum: 512 frequencies on [0, fs/2]. */
#define WAKE_HPA_PSD_GRID 1022

/** Rule floor: the noise floor is the lowest PSD over fs/2 and every 8th bin below it, above the tremor
 *  band (wake.hpa.cutoff.FLOOR_STRIDE; 0.78 Hz apart at 100 Hz, where an AR spectrum is smooth). */
#define WAKE_HPA_FLOOR_STRIDE 8u
/** Largest |weight| the fit returns (the ridge rises until every weight is within it). */
#define WAKE_HPA_WEIGHT_LIMIT 32
/** Times the ridge may rise tenfold. */
#define WAKE_HPA_RIDGE_STEPS 16
/** Value of wake_hpa_t::magic once initialised ("HPAW"). */
#define WAKE_HPA_MAGIC 0x48504157u

/** wake_hpa_result_t::notes: the ridge was raised to keep the weights within the limit. */
#define WAKE_HPA_NOTE_REGULARISED 1
/** wake_hpa_result_t::notes: a silent window; the previous weights are kept. */
#define WAKE_HPA_NOTE_WEIGHTS_KEPT 2
/** wake_hpa_result_t::notes: no ridge kept the weights within the limit; they were clipped. */
#define WAKE_HPA_NOTE_CLIPPED 4
/**
 * wake_hpa_result_t::notes (WAKE_HPA_AHEAD builds): more than n / WAKE_HPA_GLITCH_DIVISOR samples of the
 * window sit at full scale (INT16_MAX or INT16_MIN): the tremor estimate the predictor reads was cut, and
 * its held-out gain measured on it, so the gate's goal is 0 until the next HPA (wake.ahead.installed_goal).
 */
#define WAKE_HPA_NOTE_FULL_SCALE 8
/**
 * A window is clipped when more than n / WAKE_HPA_GLITCH_DIVISOR of its n samples sit at full scale
 * (wake.rtp.full_scale.GLITCH_SHARE = 1 / this; wake.hpa.c_port.c_mirror_problems checks it).
 */
#define WAKE_HPA_GLITCH_DIVISOR 100u

/** Status codes: zero is success, positive values report progress, errors are negative. */
typedef enum {
    WAKE_HPA_OK = 0,            /**< success; for slice/run: nothing to do */
    WAKE_HPA_RUNNING = 1,       /**< slice (run: never, see wake_hpa_run): more work remains */
    WAKE_HPA_DONE = 2,          /**< slice/run: the result just became ready */
    WAKE_HPA_STARTED = 3,       /**< push: a window was complete and an HPA started */
    WAKE_HPA_E_NULL = -1,       /**< a required pointer is NULL */
    WAKE_HPA_E_CONFIG = -2,     /**< a configuration value out of range (see wake_hpa_init) */
    WAKE_HPA_E_UNINIT = -3,     /**< the struct was never initialised (bad magic) */
    WAKE_HPA_E_WINDOW = -4,     /**< start: n outside [2 * 2^J, L] */
    WAKE_HPA_E_BUSY = -5,       /**< start: an HPA is still running */
    WAKE_HPA_E_IDLE = -6,       /**< result/apply: no new result */
    WAKE_HPA_E_RTP = -7,        /**< apply: the RTP refused (level mismatch or its own status) */
    WAKE_HPA_E_CORRUPT = -8     /**< magic present but fields inconsistent */
} wake_hpa_status_t;

/** How the cut-off was found (the keys of wake.hpa.CUTOFF_FLAGS). */
typedef enum {
    WAKE_HPA_VALLEY = 0,          /**< the PSD minimum between voluntary content and tremor peak */
    WAKE_HPA_NO_TREMOR_PEAK = 1,  /**< no local PSD maximum in the tremor band: default cut-off */
    WAKE_HPA_NO_VALLEY = 2,       /**< no dip min_depth below both sides: default cut-off */
    WAKE_HPA_SILENT = 3,          /**< constant window (or zero AR error): default cut-off */
    WAKE_HPA_SHALLOW_VALLEY = 4,  /**< rules "shallow", "floor": the PSD minimum below the peak and shallow_high */
    WAKE_HPA_FLOOR_VALLEY = 5     /**< rule "floor": a valley at the noise floor; f_d at the floor's low edge */
} wake_hpa_flag_t;

/** Cut-off rules (wake.registry, in registration order). */
typedef enum {
    WAKE_HPA_RULE_PAPER = 0,
    WAKE_HPA_RULE_SHALLOW = 1,
    WAKE_HPA_RULE_FLOOR = 2       /**< the default: the PSD also on every 8th bin from fs/2 down to the tremor
                                       band, for the noise floor (about 45 bins more at 100 Hz) */
} wake_hpa_rule_t;

/** What the weight fit's relative ridge is relative to (wake.config.RIDGE_SCALES, in that order;
 *  wake.hpa.fit.ridge_scale_of). */
typedef enum {
    WAKE_HPA_RIDGE_GRAM = 0,      /**< the default: trace(G) / J */
    WAKE_HPA_RIDGE_CENTRED = 1    /**< the trace of the centred Gram matrix (each column's mean out), which an
                                       offset such as gravity does not inflate, floored at 1e-6 trace(G), over J */
} wake_hpa_ridge_scale_t;

/** The settings of wake.WakeConfig the HPA reads (`wake export-c` writes them). */
typedef struct {
    float fs;                   /**< sampling rate, Hz, > 0 */
    float tremor_low;           /**< tremor band, Hz: 0 < low < high <= fs/2 */
    float tremor_high;
    float cutoff_low;           /**< where f_d may lie, Hz: 0 < low <= default <= high < fs/2 */
    float cutoff_high;
    float shallow_high;         /**< rules shallow, floor: the highest f_d taken from a shallow dip, Hz, >= cutoff_low (4; capped
                                     at cutoff_high) */
    float default_cutoff;       /**< the fallback f_d, Hz */
    float min_depth_ratio;      /**< 10^(-min_depth_db / 10), in (0, 1): 0.5011872 for 3 dB */
    float floor_ratio;          /**< rule floor: 10^(-floor_margin_db / 10), in (0, 1): 0.031622777 for 15 dB */
    float edge_ratio;           /**< rule floor: 10^(-edge_db / 10), in (0, 1): 0.5011872 for 3 dB */
    float ridge;                /**< relative ridge, >= 0 (1e-6) */
    float process_noise_ratio;  /**< q = ratio * R when applied to the RTP, >= 0 */
    float gate_cutoff;          /**< the tremor ahead's gate scores the previous predictor against the window's tremor
                                     above max(f_d, gate_cutoff), Hz (wake.hpa.run.gate_truth); 0 (default): above
                                     f_d.  0, or 0 < gate_cutoff < fs/2 with gate_cutoff 1022 / fs <
                                     WAKE_HPA_MAX_PSD_BINS - 1 (the truth's bins); read by WAKE_HPA_AHEAD builds */
    uint16_t window;            /**< L, samples: 2 * 2^J <= L <= WAKE_HPA_MAX_WINDOW, L > 2 p */
    uint16_t level;             /**< J, 1..WAKE_HPA_MAX_LEVEL */
    uint16_t ar_order;          /**< p, 1..WAKE_HPA_MAX_ORDER */
    uint16_t rule;              /**< a ::wake_hpa_rule_t */
    uint16_t clean_below;       /**< a window shorter than this (samples; 0: none) installs its fit only with
                                     a clean valley (flag valley or floor_valley), else keeps the weights
                                     (wake.hpa.run.CLEAN_ONLY_BELOW_S: 2 s) */
    uint16_t horizon;           /**< the tremor ahead's horizon h, samples, 1..WAKE_HPA_MAX_AHEAD_HORIZON (default 1):
                                     the predictor maps the estimate up to k onto the tremor at k + h */
    uint16_t ridge_scale;       /**< a ::wake_hpa_ridge_scale_t (default WAKE_HPA_RIDGE_GRAM) */
    uint16_t warmup[WAKE_HPA_MAX_WARMUP]; /**< sample counts of warm-up HPAs before the first full
                                               window, increasing, each in [2 * 2^J, L); 0 ends the list */
} wake_hpa_config_t;

/** What one HPA run produced (the C image of wake.hpa.HPAUpdate). */
typedef struct {
    float weights[WAKE_HPA_MAX_LEVEL];  /**< w, |w_j| <= WAKE_HPA_WEIGHT_LIMIT */
    float cutoff;                       /**< f_d, Hz */
    float measurement_noise;            /**< R in LSB^2 of the Q15 input (R / FS^2 = this / 2^30) */
    float fit_mse;                      /**< e_L^2 in LSB^2 */
    float ridge;                        /**< the ridge factor finally used */
    uint32_t index;                     /**< samples received when the window closed */
    uint16_t n;                         /**< window length */
    uint16_t flag;                      /**< a ::wake_hpa_flag_t */
    uint16_t notes;                     /**< WAKE_HPA_NOTE_* bits */
    uint16_t reserved;
    float ahead[WAKE_HPA_AHEAD_TAPS];   /**< the tremor-ahead predictor c, newest estimate first, |c| <= 8
                                             (wake.ahead.fit_predictor; scale-free) */
    float ahead_goal;                   /**< the gate's goal in [0, 1] (wake.ahead.gate_target of the
                                             previous predictor's held-out gain; 0 after the first HPA) */
} wake_hpa_result_t;

/**
 * The tremor-ahead fit's state (csrc/wake_hpa_ahead.c): the truth's low bins and the estimate's lags.  An
 * instance holds one when it is configured with the tremor ahead (WAKE_HPA_AHEAD 1).
 */
typedef struct {
    float bin_osc[3 * WAKE_HPA_MAX_BINS];       /**< per voluntary-truth bin: v_m(t) = (2/n) Re X'_m e^{j w t},
                                                     v_m(t) - v_m(t-1), and Reinsch's lambda = -4 sin^2(w/2) */
    int32_t fir[WAKE_HPA_MAX_TAPS];             /**< w' B in Q20: the estimate's voluntary prediction as one FIR,
                                                     oldest first */
    float ring[WAKE_HPA_AHEAD_RING];            /**< the estimate y(t) at ring[(t - 2^J) mod RING] */
    float head[WAKE_HPA_AHEAD_TAPS];            /**< y(2^J) .. y(2^J + 7): the Gram's first edge terms */
    float lag[WAKE_HPA_AHEAD_TAPS];             /**< sum_k y(k) y(k - d) over the fit rows, d = 0..7 */
    float gram[WAKE_HPA_AHEAD_TAPS * WAKE_HPA_AHEAD_TAPS]; /**< Y'Y (upper triangle), then L D L' */
    float rhs[WAKE_HPA_AHEAD_TAPS];             /**< Y'T(+h) */
    float coef[WAKE_HPA_AHEAD_TAPS];            /**< this run's predictor */
    float prev[WAKE_HPA_AHEAD_TAPS];            /**< the previous HPA's predictor */
    float tp, pp;                               /**< <T, P>, <P, P> of the previous predictor over the new targets */
    float goal;                                 /**< this run's gate goal */
    float ridge;                                /**< the predictor's ridge 1e-3 trace(G) / 8 (-1: nothing to fit) */
    uint32_t prev_index;                        /**< the previous HPA's index (samples received) */
    uint16_t has_prev;                          /**< 1 once an HPA has produced a predictor */
    uint16_t pos;                               /**< ring index of the newest estimate */
    uint16_t held;                              /**< first window index scored by the held-out gain (n: none) */
    uint16_t rail;                              /**< samples of the window at full scale (STEP_SUMS counts them) */
} wake_hpa_ahead_t;

/**
 * One channel's HPA: configuration, both window buffers and every work array.
 * Treat the fields as read-only.
 */
typedef struct {
    uint32_t magic;               /**< WAKE_HPA_MAGIC once initialised */
    uint32_t seal;                /**< hash of cfg and the bins derived from it (a changed field: _E_CORRUPT) */
    wake_hpa_config_t cfg;        /**< validated copy */
    /* feeding */
    uint32_t count;               /**< samples pushed (sticks at UINT32_MAX) */
    uint32_t runs;                /**< HPAs started */
    uint32_t overruns;            /**< full-window HPAs abandoned unfinished after L more samples */
    uint32_t skipped;             /**< warm-up HPAs not run or not finished: a warm-up point that found an
                                       HPA running, or a warm-up HPA superseded by the full window */
    uint32_t gap_skipped;         /**< HPA points that fell inside a long gap (not run) */
    uint32_t base;                /**< the count the schedule runs from: 0, or the last sample of the latest
                                       long gap */
    uint16_t missing_run;         /**< missing samples in a row up to now (saturates at 65535) */
    uint16_t gap_len;             /**< a long gap: at least this many missing samples in a row, ceil(L / 5)
                                       (set by init) */
    wake_q15_t last_valid;        /**< the newest sample pushed (a missing sample is held at it) */
    uint16_t fill_len;            /**< samples in the buffer being filled */
    uint16_t fill;                /**< which buffer is being filled (0 or 1) */
    uint16_t warmup_next;         /**< next warm-up point to check */
    uint16_t ready;               /**< 1 while ::result holds a result not yet taken */
    /* the job */
    const wake_q15_t *work;       /**< the window being analysed (oldest first) */
    uint32_t index;               /**< its sample count */
    uint16_t phase;               /**< 0 idle, else the step being worked on */
    uint16_t n;                   /**< window length */
    uint16_t rows;                /**< causal fit rows, n - 2^J */
    uint16_t order;               /**< AR order used, min(p, (n - 1) / 2) */
    uint16_t lags;                /**< correlation lags computed, max(order + 1, 2^J) */
    uint16_t d, t, m;             /**< loop counters of the current step */
    uint16_t bins;                /**< DFT bins at or below f_d */
    uint16_t gate_extra;          /**< DFT bins above f_d at or below cfg.gate_cutoff (bins + 1 .. bins +
                                       gate_extra): they only feed the gate's truth (WAKE_HPA_AHEAD builds; else 0).
                                       Held as a count above bins, not a last bin, so that "no gate bins" is a
                                       value of one field (an analyser tracks no relation between two) */
    uint16_t psd_end;             /**< last PSD bin evaluated */
    uint16_t peak;                /**< tremor peak bin (0xFFFF: none yet) */
    uint16_t pair;                /**< bins in the current DFT pass (1 or 2) */
    uint16_t flag;                /**< cut-off flag of this run */
    uint16_t psd_lo, psd_hi;      /**< PSD bins of the tremor band (set by init) */
    uint16_t cut_lo, cut_hi;      /**< PSD bins of the cut-off range (set by init) */
    uint16_t cut_shallow;         /**< last PSD bin rule shallow may take, <= cut_hi (set by init) */
    uint16_t floor_lo;            /**< rule floor: first PSD bin above tremor_high (WAKE_HPA_PSD_GRID / 2 + 1:
                                       none, no floor test; set by init) */
    uint16_t attempts;            /**< ridge rises so far */
    int16_t lo, hi;               /**< smallest and largest sample */
    int64_t sum;                  /**< S = sum x */
    int64_t prefix_rows;          /**< sum of x[0 .. rows-1] */
    int64_t tsum;                 /**< T = sum t x(t) (the end-point line's cross term) */
    int64_t tsum_rows;            /**< sum t x(t) over t < rows */
    int64_t prefix_lo;            /**< P(d) = sum x[0 .. d-1] */
    int64_t prefix_hi;            /**< P(rows + d) */
    int64_t suffix;               /**< sum x[n-d .. n-1] */
    int64_t acc_head, acc_tail;   /**< the lag sum being accumulated (t < rows, t >= rows) */
    int64_t diag;                 /**< n^2 Rxx(i, i + d) on the diagonal being walked */
    float mean;                   /**< S / n */
    float cutoff;                 /**< f_d of this run */
    float xr, xi, qr, qi;         /**< X_m of the bin being slid, and Q_m(i) */
    float lam[2];                 /**< Reinsch's -4 sin^2(w/2) of the pass's bins */
    float gs[2], gd[2];           /**< their Reinsch states s, d */
    float hs[2], hd[2];           /**< the states at t = rows */
    float rot[2];                 /**< cos w, sin w of the bin being slid */
    float ph[6];                  /**< its phasors e^{j w (N - i)}, e^{j w i}, e^{j w (rows + i)} */
    float power;                  /**< sum over bins of |X'_m|^2 (X' = X - slope R: the line taken out) */
    float cross;                  /**< sum over bins of Re(X'_m conj(R_m)), R_m = sum t e^{-j w t} */
    float slope;                  /**< (x(n-1) - x(0)) / (n - 1): the window's end-point line, LSB per sample */
    float ramp_u;                 /**< STEP_RAMP's U(i) between slices */
    float prev1, prev2;           /**< D of the two previous PSD bins */
    float err;                    /**< Levinson prediction error */
    float den_peak;               /**< D at the tremor peak */
    float den_floor;              /**< rule floor: largest D above tremor_high (the PSD's floor), 0 if none */
    float yy;                     /**< sum of the squared fit targets */
    float noise;                  /**< R of this run, LSB^2 */
    float scale;                  /**< the ridge's scale: trace(G) / J, or (WAKE_HPA_RIDGE_CENTRED) max(trace(G_c),
                                       1e-6 trace(G)) / J */
    float factor;                 /**< the ridge factor being tried */
    float gram[WAKE_HPA_MAX_LEVEL * WAKE_HPA_MAX_LEVEL]; /**< G = A'A, J x J row-major (WAKE_HPA_RIDGE_CENTRED: G_c,
                                                     A less its column means) */
    float rhs[WAKE_HPA_MAX_LEVEL];              /**< b = A'v(+1) (WAKE_HPA_RIDGE_CENTRED: b_c, the centred A's) */
    float colall[WAKE_HPA_MAX_LEVEL];           /**< z = A'1 = c + rows mu s, the columns' sums */
    float chol[WAKE_HPA_MAX_LEVEL * WAKE_HPA_MAX_LEVEL]; /**< L of (G + lambda I) = L D L' */
    float trial[WAKE_HPA_MAX_LEVEL];            /**< the weights of the current ridge */
    float rowsum[WAKE_HPA_MAX_LEVEL];           /**< s = B 1 */
    float colsum[WAKE_HPA_MAX_LEVEL];           /**< c = B wsum = A_c' 1 */
    float sy, vv, trace;                        /**< sum of the centred targets, of v_c(t < 2^J)^2, trace G */
    float trace_c;                              /**< trace of the centred Gram matrix G_c */
    float yc2;                                  /**< sum of the squared targets less their mean, y_c'y_c - sy^2 / rows */
    float weights[WAKE_HPA_MAX_LEVEL];          /**< the newest weights (a silent window keeps them) */
    float r[WAKE_HPA_MAX_ORDER + 1];            /**< autocorrelation (scaled by n^3) */
    float a[WAKE_HPA_MAX_ORDER + 1];            /**< AR polynomial, a[0] = 1 */
    float den[WAKE_HPA_MAX_PSD_BINS];           /**< D(f_k) for the valley search */
    float tapf[WAKE_HPA_MAX_TAPS * WAKE_HPA_MAX_LEVEL]; /**< the bank B as floats, B[l][i] at [i MAX_LEVEL + l] */
    float bank_rxx[WAKE_HPA_MAX_TAPS * WAKE_HPA_MAX_LEVEL]; /**< Rxx B', 2^J rows of stride WAKE_HPA_MAX_LEVEL */
    float cxy[WAKE_HPA_MAX_TAPS];               /**< sum x_c(t + i) v_c(t + 2^J) over the fit rows */
    float wsum[WAKE_HPA_MAX_TAPS];              /**< sum x_c(t + i) over the fit rows */
    float vhead[WAKE_HPA_MAX_TAPS];             /**< v_c(t), t < 2^J */
#if WAKE_HPA_AHEAD
    wake_hpa_ahead_t ahead;                     /**< the tremor-ahead fit's state (wake_hpa_ahead.c) */
#endif
    wake_hpa_result_t result;                   /**< the newest result */
    wake_q15_t buf[2 * WAKE_HPA_MAX_WINDOW];    /**< the two window buffers */
} wake_hpa_t;

/**
 * @brief Fill @p cfg with wake.WakeConfig's defaults (100 Hz, L = 500, J = 5, p = 17,
 *        tremor band 2.5..15 Hz, cut-off 0.5..6 Hz, default 2 Hz, 3 dB, ridge 1e-6,
 *        warm-up at 200, 300 and 400 samples).
 * @return WAKE_HPA_OK or WAKE_HPA_E_NULL.
 */
wake_hpa_status_t wake_hpa_default_config(wake_hpa_config_t *cfg);

/**
 * @brief Initialise one channel's HPA.
 * @param[out] h        instance (any content)
 * @param[in]  cfg      configuration (copied); every field is checked
 * @param[in]  taps     the RTP's J x 2^J Q15 filter bank (copied, as floats)
 * @param[in]  weights  the J start weights (kept by a silent first window); finite, |w| <= 32
 * @return WAKE_HPA_OK, WAKE_HPA_E_NULL or WAKE_HPA_E_CONFIG (then @p h is left
 *         uninitialised: every other call refuses it).
 */
wake_hpa_status_t wake_hpa_init(wake_hpa_t *h, const wake_hpa_config_t *cfg, const wake_q15_t *taps,
                                const float *weights);

/**
 * @brief Store one sample; start an HPA when a window is complete.
 * @return WAKE_HPA_OK, WAKE_HPA_STARTED, or WAKE_HPA_E_NULL / _UNINIT / _CORRUPT.
 *         A full window abandons an HPA still running (a full-window one
 *         counts in wake_hpa_t::overruns, a warm-up one in
 *         wake_hpa_t::skipped); a warm-up point that finds one running is
 *         skipped (wake_hpa_t::skipped).
 * @par Scaling and overflow
 * Q15 in; nothing is computed here.
 */
wake_hpa_status_t wake_hpa_push(wake_hpa_t *h, wake_q15_t sample);

/**
 * @brief A missing sample (the RTP's wake_rtp_step_missing()): the window holds
 *        the last sample pushed in its place.
 *
 * A run of at least ::wake_hpa_t::gap_len missing samples (20 % of L) is a
 * long gap: HPA points inside it are skipped (::wake_hpa_t::gap_skipped), and
 * at its end the schedule starts again, warm-up points first, in a fresh
 * buffer, as after init (docs/studies/design.md, "Missing samples"; the host
 * interpolates a short gap linearly where this holds the last sample).
 * @return as wake_hpa_push().
 */
wake_hpa_status_t wake_hpa_push_missing(wake_hpa_t *h);

/**
 * @brief Start an HPA on a caller-owned window (oldest first), which must stay
 *        unchanged until the result is ready.
 * @return WAKE_HPA_OK, WAKE_HPA_E_NULL / _UNINIT / _CORRUPT, _WINDOW (n outside
 *         [2 * 2^J, L]) or _BUSY.
 */
wake_hpa_status_t wake_hpa_start(wake_hpa_t *h, const wake_q15_t *window, uint16_t n, uint32_t index);

/**
 * @brief Do one bounded piece of the running HPA.
 * @return WAKE_HPA_OK (idle), WAKE_HPA_RUNNING, WAKE_HPA_DONE, or an error.
 * @par Scaling and overflow
 * Sums of samples and of products of centred samples are exact in int64
 * (n <= 1024, |x| <= 2^15: |n x - S| < 2^26, every partial sum < 2^62);
 * everything after them is IEEE single precision.
 */
wake_hpa_status_t wake_hpa_slice(wake_hpa_t *h);

/**
 * @brief Run the current HPA to the end.
 *
 * One call spends at most INT32_MAX / 2 units of the slices' cost model (about 1.07e9), far above what a whole
 * run spends in any configuration this header admits (2.2e7 measured at its limits; docs/studies/verification.md,
 * "Termination"): a bound that makes the call's end a proven property, never reached by a run.  Should it be
 * (WAKE_HPA_RUNNING), the run stays where it stopped and a further call or slice goes on from there.
 * @return WAKE_HPA_DONE, WAKE_HPA_OK (nothing was running), WAKE_HPA_RUNNING (the run is not done after
 *         INT32_MAX / 2 cost units: never within this header's limits) or an error.
 */
wake_hpa_status_t wake_hpa_run(wake_hpa_t *h);

/**
 * @brief Take the newest result (once).
 * @return WAKE_HPA_OK, WAKE_HPA_E_NULL / _UNINIT / _CORRUPT, or _IDLE (no new result).
 */
wake_hpa_status_t wake_hpa_take(wake_hpa_t *h, wake_hpa_result_t *out);

/**
 * @brief Convert a result into the RTP's formats.
 * @param[in]  res       a result
 * @param[in]  level     J
 * @param[in]  process_noise_ratio  q = ratio * R
 * @param[out] weights   J weights, Q24
 * @param[out] r, q      R and q, Q(WAKE_RTP_P_FRAC) of FS^2; R at least 1 LSB
 * @return WAKE_HPA_OK or WAKE_HPA_E_NULL.
 * @par Scaling and overflow
 * R is in LSB^2 of Q15, so R / FS^2 = R 2^-30 and the Q(P_FRAC) value is
 * R 2^(P_FRAC - 30), rounded and clamped to [1, INT32_MAX]; q likewise
 * clamped to [0, INT32_MAX]; weights rounded to Q24 and clamped to +-64.
 */
wake_hpa_status_t wake_hpa_to_rtp(const wake_hpa_result_t *res, int level, float process_noise_ratio,
                                  wake_q24_t *weights, wake_cov_t *r, wake_cov_t *q);

/**
 * @brief Convert a result's tremor-ahead predictor and goal into what wake_rtp_set_ahead() takes.
 * @param[in]  res           a result
 * @param[out] coefficients  WAKE_HPA_AHEAD_TAPS coefficients, Q27, newest estimate first
 * @param[out] goal          the gate's goal, Q30
 * @return WAKE_HPA_OK or WAKE_HPA_E_NULL.
 * @par Scaling and overflow
 * c in [-8, 8] times 2^27, rounded and clamped to [-2^30, 2^30] (WAKE_RTP_AHEAD_COEF_MAX); the goal in
 * [0, 1] times 2^30, rounded and clamped to [0, 2^30]; NaN becomes the lower bound.
 */
wake_hpa_status_t wake_hpa_ahead_to_rtp(const wake_hpa_result_t *res, int32_t *coefficients, wake_ratio_t *goal);

/**
 * @brief Give an idle instance the previous HPA's tremor-ahead predictor, which the next run scores on the
 *        samples since that HPA (its held-out gain, the gate's goal), as the instance that ran that HPA holds it.
 *
 * A fresh instance per window (a host that runs each window on its own instance) calls this before
 * wake_hpa_start(); an instance that ran the previous HPA already holds its predictor.
 * @param[in] h             an initialised instance with no run in progress
 * @param[in] coefficients  WAKE_HPA_AHEAD_TAPS coefficients, newest estimate first, each finite and within
 *                          [-8, 8] (wake.ahead.COEFFICIENT_LIMIT, what a run produces)
 * @param[in] index         the previous HPA's index (samples received when its window closed)
 * @return WAKE_HPA_OK; WAKE_HPA_E_NULL / _UNINIT / _CORRUPT; WAKE_HPA_E_BUSY (a run in progress: unchanged);
 *         WAKE_HPA_E_CONFIG (a coefficient not finite or outside [-8, 8], or an instance built without the
 *         tremor ahead, WAKE_HPA_AHEAD 0: unchanged).
 */
wake_hpa_status_t wake_hpa_set_previous_ahead(wake_hpa_t *h, const float *coefficients, uint32_t index);

/**
 * @brief Install the newest result in the RTP between two samples.
 * @return WAKE_HPA_OK, WAKE_HPA_E_IDLE (no new result: the RTP is untouched),
 *         WAKE_HPA_E_NULL / _UNINIT / _CORRUPT, or WAKE_HPA_E_RTP (the RTP
 *         refused: it is unchanged and the result stays ready).
 */
wake_hpa_status_t wake_hpa_apply(wake_hpa_t *h, wake_rtp_t *rtp);

#ifdef __cplusplus
}
#endif

#endif /* WAKE_HPA_H */
