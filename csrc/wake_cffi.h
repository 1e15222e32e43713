/*
 * wake_cffi.h: the declarations cffi reads for the Python extension wake._rtp (build_ffi.py).
 *
 * Written for cffi's cdef, not for a C compiler (no includes, no guards, no conditionals): the
 * types, constants and functions of wake_rtp.h, wake_hpa.h and wake_rate.h that the extension's
 * configuration compiles in (build_ffi.CONFIGURATION: the tremor ahead of the RTP and of the HPA, the
 * voluntary motion ahead, not the split step). The host-only evaluation loops declare themselves beside
 * their code (wake/eval/native/wake_eval_cffi.h), read after this file.
 * `#define NAME ...` takes the value from the compiled code; `[...]` takes an array's size from it.
 *
 * The build checks this file against the headers: cffi's API mode compiles every declaration
 * below against the real ones (each function's signature, each struct field's type, offset and the
 * struct's size), so a declaration that drifted from its header fails `python build_ffi.py`.
 * A change to a public header's declarations is made here too.
 */

/* ---- wake_rtp.h ------------------------------------------------------------------------------ */
#define WAKE_RTP_MAX_LEVEL ...
#define WAKE_RTP_KALMAN ...
#define WAKE_RTP_AHEAD ...
#define WAKE_RTP_SPLIT ...
#define WAKE_RTP_VOLUNTARY_AHEAD ...
#define WAKE_RTP_AHEAD_TAPS ...
#define WAKE_RTP_AHEAD_COEF_FRAC ...
#define WAKE_RTP_AHEAD_COEF_MAX ...
#define WAKE_RTP_GATE_FRAC ...
#define WAKE_RTP_GATE_ONE ...
#define WAKE_RTP_AHEAD_RAMP_DEFAULT ...
#define WAKE_RTP_MAX_TAPS ...
#define WAKE_RTP_P_FRAC ...
#define WAKE_RTP_SAMPLE_FRAC ...
#define WAKE_RTP_TAP_FRAC ...
#define WAKE_RTP_STATE_FRAC ...
#define WAKE_RTP_WEIGHT_FRAC ...
#define WAKE_RTP_WEIGHT_MAX ...
#define WAKE_RTP_TAP_ROW_ABS_MAX ...
#define WAKE_RTP_RATIO_FRAC ...
#define WAKE_RTP_DIR_FRAC ...
#define WAKE_RTP_MAGIC ...
typedef int16_t wake_q15_t;
typedef int32_t wake_q23_t;
typedef int32_t wake_q24_t;
typedef union {
    int32_t value;
    struct {
        uint16_t biased_hi;
        uint8_t mid;
        uint8_t lo;
    } parts;
} wake_fir_t;
typedef int32_t wake_cov_t;
typedef int32_t wake_ratio_t;
typedef enum {
    WAKE_RTP_OK = 0,
    WAKE_RTP_E_NULL = -1,
    WAKE_RTP_E_LEVEL = -2,
    WAKE_RTP_E_TAPS = -3,
    WAKE_RTP_E_WEIGHTS = -4,
    WAKE_RTP_E_NOISE = -5,
    WAKE_RTP_E_UNINIT = -6,
    WAKE_RTP_E_CORRUPT = -7,
    WAKE_RTP_E_STATE = -8,
    WAKE_RTP_E_NO_KALMAN = -9,
    WAKE_RTP_E_AHEAD = -10,
    WAKE_RTP_E_UNPREPARED = -11,
    WAKE_RTP_E_FEATURE = -12
} wake_rtp_status_t;
/* ---- wake_ahead.h ---- */
typedef struct {
    int32_t coef[...];
    wake_ratio_t goal;
    wake_ratio_t gate;
    wake_ratio_t ramp;
    uint32_t saturations;
    wake_q23_t predicted;
    wake_q23_t command;
    uint16_t head;
    uint16_t reserved;
    wake_q15_t line[...];
} wake_ahead_t;
typedef struct {
    int64_t dot;
    wake_ratio_t gate;
} wake_ahead_prepared_t;
wake_rtp_status_t wake_ahead_init(wake_ahead_t *a);
wake_rtp_status_t wake_ahead_reset(wake_ahead_t *a);
wake_rtp_status_t wake_ahead_check(const wake_ahead_t *a);
wake_rtp_status_t wake_ahead_set_model(wake_ahead_t *a, const int32_t *coefficients, wake_ratio_t goal);
wake_rtp_status_t wake_ahead_set_ramp(wake_ahead_t *a, wake_ratio_t ramp);
wake_rtp_status_t wake_ahead_load(wake_ahead_t *a, const wake_q15_t *line, wake_ratio_t gate);
wake_rtp_status_t wake_ahead_history(const wake_ahead_t *a, wake_q15_t *line);
wake_rtp_status_t wake_ahead_output(const wake_ahead_t *a, wake_q23_t *predicted, wake_ratio_t *gate,
                                    wake_q23_t *command);
void wake_ahead_step(wake_ahead_t *a, wake_q23_t tremor);
void wake_ahead_step_missing(wake_ahead_t *a);
void wake_ahead_prepare(const wake_ahead_t *a, wake_ahead_prepared_t *prepared);
void wake_ahead_finish(wake_ahead_t *a, const wake_ahead_prepared_t *prepared, wake_q23_t tremor,
                       wake_ratio_t gate);

/* ---- wake_voluntary_ahead.h ---- */
typedef struct {
    wake_q24_t weights[...];
    int64_t z_start;
    int64_t start;
    int32_t gain;
    wake_q23_t output;
    uint32_t saturations;
    uint16_t set;
    uint16_t reserved;
    wake_fir_t fir[...];
} wake_voluntary_ahead_t;
wake_rtp_status_t wake_voluntary_ahead_output(const wake_voluntary_ahead_t *v, wake_q23_t *output);

/* ---- wake_rtp.h (the instance) ---- */
typedef struct {
    uint32_t magic;
    uint32_t saturations;
    uint32_t steps;
    uint16_t level;
    uint16_t n_taps;
    uint16_t head;
    uint16_t primed;
    uint16_t inert;
    uint16_t reserved;
    const wake_q15_t *taps;
    wake_q24_t weights[...];
    wake_cov_t r;
    wake_cov_t q;
    wake_cov_t p0;
    wake_cov_t variance;
    int64_t q_omega;
    wake_q23_t last_output;
    int64_t s;
    int64_t z;
    wake_q23_t correction[...];
    wake_fir_t fir[...];
    wake_q15_t ring[...];
    wake_ahead_t ahead;
    wake_voluntary_ahead_t voluntary_ahead;
} wake_rtp_t;
wake_rtp_status_t wake_rtp_init(wake_rtp_t *s, int level, const wake_q15_t *taps,
                                const wake_q24_t *weights, wake_cov_t r, wake_cov_t q, wake_cov_t p0);
wake_rtp_status_t wake_rtp_set_weights(wake_rtp_t *s, const wake_q24_t *weights, wake_cov_t r, wake_cov_t q);
wake_rtp_status_t wake_rtp_reset(wake_rtp_t *s);
wake_rtp_status_t wake_rtp_step(wake_rtp_t *s, wake_q15_t sample, wake_q15_t *prediction);
wake_rtp_status_t wake_rtp_step_missing(wake_rtp_t *s, wake_q15_t *prediction);
wake_rtp_status_t wake_rtp_run(wake_rtp_t *s, const wake_q15_t *in, wake_q15_t *out, size_t n);
wake_rtp_status_t wake_rtp_run_outputs(wake_rtp_t *s, const wake_q15_t *in, const uint8_t *missing, size_t n,
                                       wake_q15_t *voluntary, wake_q23_t *tremor_ahead, wake_ratio_t *gate,
                                       wake_q23_t *command, wake_q23_t *voluntary_ahead);
wake_rtp_status_t wake_rtp_load_state(wake_rtp_t *s, const wake_q15_t *window,
                                      const wake_q23_t *correction, const wake_cov_t *covariance,
                                      wake_q23_t last_output);
wake_rtp_status_t wake_rtp_get_state(const wake_rtp_t *s, wake_q23_t *correction, wake_cov_t *covariance);
wake_rtp_status_t wake_rtp_set_ahead(wake_rtp_t *s, const int32_t *coefficients, wake_ratio_t goal);
wake_rtp_status_t wake_rtp_set_ahead_ramp(wake_rtp_t *s, wake_ratio_t ramp);
wake_rtp_status_t wake_rtp_ahead_output(const wake_rtp_t *s, wake_q23_t *predicted, wake_ratio_t *gate,
                                        wake_q23_t *command);
wake_rtp_status_t wake_rtp_load_ahead_state(wake_rtp_t *s, const wake_q15_t *line, wake_ratio_t gate);
wake_rtp_status_t wake_rtp_get_ahead_state(const wake_rtp_t *s, wake_q15_t *line);
wake_rtp_status_t wake_rtp_set_voluntary_ahead(wake_rtp_t *s, const wake_q24_t *weights_ahead);
wake_rtp_status_t wake_rtp_voluntary_ahead_output(const wake_rtp_t *s, wake_q23_t *output);
uint32_t wake_rtp_reciprocal(uint32_t x);

/* ---- wake_hpa.h ------------------------------------------------------------------------------ */
#define WAKE_HPA_MAX_WINDOW ...
#define WAKE_HPA_MAX_LEVEL ...
#define WAKE_HPA_MAX_ORDER ...
#define WAKE_HPA_MAX_PSD_BINS ...
#define WAKE_HPA_SLICE_BUDGET ...
#define WAKE_HPA_MAX_TAPS ...
#define WAKE_HPA_MAX_WARMUP ...
#define WAKE_HPA_HORIZON ...
#define WAKE_HPA_AHEAD ...
#define WAKE_HPA_AHEAD_TAPS ...
#define WAKE_HPA_MAX_AHEAD_HORIZON ...
#define WAKE_HPA_AHEAD_RING ...
#define WAKE_HPA_MAX_BINS ...
#define WAKE_HPA_PSD_GRID ...
#define WAKE_HPA_FLOOR_STRIDE ...
#define WAKE_HPA_WEIGHT_LIMIT ...
#define WAKE_HPA_RIDGE_STEPS ...
#define WAKE_HPA_MAGIC ...
#define WAKE_HPA_NOTE_REGULARISED ...
#define WAKE_HPA_NOTE_WEIGHTS_KEPT ...
#define WAKE_HPA_NOTE_CLIPPED ...
#define WAKE_HPA_NOTE_FULL_SCALE ...
#define WAKE_HPA_GLITCH_DIVISOR ...
typedef enum {
    WAKE_HPA_OK = 0,
    WAKE_HPA_RUNNING = 1,
    WAKE_HPA_DONE = 2,
    WAKE_HPA_STARTED = 3,
    WAKE_HPA_E_NULL = -1,
    WAKE_HPA_E_CONFIG = -2,
    WAKE_HPA_E_UNINIT = -3,
    WAKE_HPA_E_WINDOW = -4,
    WAKE_HPA_E_BUSY = -5,
    WAKE_HPA_E_IDLE = -6,
    WAKE_HPA_E_RTP = -7,
    WAKE_HPA_E_CORRUPT = -8
} wake_hpa_status_t;
typedef enum {
    WAKE_HPA_VALLEY = 0,
    WAKE_HPA_NO_TREMOR_PEAK = 1,
    WAKE_HPA_NO_VALLEY = 2,
    WAKE_HPA_SILENT = 3,
    WAKE_HPA_SHALLOW_VALLEY = 4,
    WAKE_HPA_FLOOR_VALLEY = 5
} wake_hpa_flag_t;
typedef enum {
    WAKE_HPA_RULE_PAPER = 0,
    WAKE_HPA_RULE_SHALLOW = 1,
    WAKE_HPA_RULE_FLOOR = 2
} wake_hpa_rule_t;
typedef enum {
    WAKE_HPA_RIDGE_GRAM = 0,
    WAKE_HPA_RIDGE_CENTRED = 1
} wake_hpa_ridge_scale_t;
typedef struct {
    float fs;
    float tremor_low;
    float tremor_high;
    float cutoff_low;
    float cutoff_high;
    float shallow_high;
    float default_cutoff;
    float min_depth_ratio;
    float floor_ratio;
    float edge_ratio;
    float ridge;
    float process_noise_ratio;
    float gate_cutoff;
    uint16_t window;
    uint16_t level;
    uint16_t ar_order;
    uint16_t rule;
    uint16_t clean_below;
    uint16_t horizon;
    uint16_t ridge_scale;
    uint16_t warmup[...];
} wake_hpa_config_t;
typedef struct {
    float weights[...];
    float cutoff;
    float measurement_noise;
    float fit_mse;
    float ridge;
    uint32_t index;
    uint16_t n;
    uint16_t flag;
    uint16_t notes;
    uint16_t reserved;
    float ahead[...];
    float ahead_goal;
} wake_hpa_result_t;
typedef struct {
    float bin_osc[...];
    int32_t fir[...];
    float ring[...];
    float head[...];
    float lag[...];
    float gram[...];
    float rhs[...];
    float coef[...];
    float prev[...];
    float tp, pp;
    float goal;
    float ridge;
    uint32_t prev_index;
    uint16_t has_prev;
    uint16_t pos;
    uint16_t held;
    uint16_t rail;
} wake_hpa_ahead_t;
typedef struct {
    uint32_t magic;
    uint32_t seal;
    wake_hpa_config_t cfg;
    uint32_t count;
    uint32_t runs;
    uint32_t overruns;
    uint32_t skipped;
    uint32_t gap_skipped;
    uint32_t base;
    uint16_t missing_run;
    uint16_t gap_len;
    wake_q15_t last_valid;
    uint16_t fill_len;
    uint16_t fill;
    uint16_t warmup_next;
    uint16_t ready;
    const wake_q15_t *work;
    uint32_t index;
    uint16_t phase;
    uint16_t n;
    uint16_t rows;
    uint16_t order;
    uint16_t lags;
    uint16_t d, t, m;
    uint16_t bins;
    uint16_t gate_extra;
    uint16_t psd_end;
    uint16_t peak;
    uint16_t pair;
    uint16_t flag;
    uint16_t psd_lo, psd_hi;
    uint16_t cut_lo, cut_hi;
    uint16_t cut_shallow;
    uint16_t floor_lo;
    uint16_t attempts;
    int16_t lo, hi;
    int64_t sum;
    int64_t prefix_rows;
    int64_t tsum;
    int64_t tsum_rows;
    int64_t prefix_lo;
    int64_t prefix_hi;
    int64_t suffix;
    int64_t acc_head, acc_tail;
    int64_t diag;
    float mean;
    float cutoff;
    float xr, xi, qr, qi;
    float lam[2];
    float gs[2], gd[2];
    float hs[2], hd[2];
    float rot[2];
    float ph[6];
    float power;
    float cross;
    float slope;
    float ramp_u;
    float prev1, prev2;
    float err;
    float den_peak;
    float den_floor;
    float yy;
    float noise;
    float scale;
    float factor;
    float gram[...];
    float rhs[...];
    float colall[...];
    float chol[...];
    float trial[...];
    float rowsum[...];
    float colsum[...];
    float sy, vv, trace;
    float trace_c;
    float yc2;
    float weights[...];
    float r[...];
    float a[...];
    float den[...];
    float tapf[...];
    float bank_rxx[...];
    float cxy[...];
    float wsum[...];
    float vhead[...];
    wake_hpa_ahead_t ahead;
    wake_hpa_result_t result;
    wake_q15_t buf[...];
} wake_hpa_t;
wake_hpa_status_t wake_hpa_default_config(wake_hpa_config_t *cfg);
wake_hpa_status_t wake_hpa_init(wake_hpa_t *h, const wake_hpa_config_t *cfg, const wake_q15_t *taps,
                                const float *weights);
wake_hpa_status_t wake_hpa_push(wake_hpa_t *h, wake_q15_t sample);
wake_hpa_status_t wake_hpa_push_missing(wake_hpa_t *h);
wake_hpa_status_t wake_hpa_start(wake_hpa_t *h, const wake_q15_t *window, uint16_t n, uint32_t index);
wake_hpa_status_t wake_hpa_slice(wake_hpa_t *h);
wake_hpa_status_t wake_hpa_run(wake_hpa_t *h);
wake_hpa_status_t wake_hpa_take(wake_hpa_t *h, wake_hpa_result_t *out);
wake_hpa_status_t wake_hpa_to_rtp(const wake_hpa_result_t *res, int level, float process_noise_ratio,
                                  wake_q24_t *weights, wake_cov_t *r, wake_cov_t *q);
wake_hpa_status_t wake_hpa_ahead_to_rtp(const wake_hpa_result_t *res, int32_t *coefficients, wake_ratio_t *goal);
wake_hpa_status_t wake_hpa_set_previous_ahead(wake_hpa_t *h, const float *coefficients, uint32_t index);
wake_hpa_status_t wake_hpa_apply(wake_hpa_t *h, wake_rtp_t *rtp);

/* ---- wake_rate.h ----------------------------------------------------------------------------- */
#define WAKE_RATE_MAX_FACTOR ...
#define WAKE_RATE_MAGIC ...
typedef enum {
    WAKE_RATE_OK = 0,
    WAKE_RATE_E_NULL = -1,
    WAKE_RATE_E_FACTOR = -2,
    WAKE_RATE_E_UNINIT = -3,
    WAKE_RATE_E_CORRUPT = -4,
    WAKE_RATE_E_RTP = -5
} wake_rate_status_t;
typedef enum {
    WAKE_RATE_OPEN = 0,
    WAKE_RATE_GROUP = 1,
    WAKE_RATE_MISSING = 2
} wake_rate_group_t;
typedef struct {
    uint32_t magic;
    int32_t sum;
    uint16_t factor;
    uint16_t phase;
    uint16_t present;
    uint16_t reserved;
} wake_rate_t;
wake_rate_status_t wake_rate_init(wake_rate_t *s, int factor);
wake_rate_status_t wake_rate_push(wake_rate_t *s, wake_q15_t sample, int present, wake_rate_group_t *group,
                                  wake_q15_t *mean);
