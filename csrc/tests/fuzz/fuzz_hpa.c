/**
 * @file fuzz_hpa.c
 * @brief libFuzzer harness for the single-precision HPA's public entry points (wake_hpa.h).
 *
 * The input is decoded as: a configuration (wake.WakeConfig's defaults with fields replaced by input
 * values, raw float bits included, so that init's refusals and the accepted configurations are both
 * reached), the filter bank and start weights, then a sequence of calls: push (one sample or a burst
 * of up to 255 generated ones, so that windows fill within one input), push_missing (bursts: long
 * gaps), slice (bursts), run, start on an input window, take, to_rtp, apply to an RTP instance,
 * "corrupt", which overwrites part of the checked fields with input bytes (the work pointer excepted),
 * and "scribble", which breaks start's contract: it overwrites the window the last accepted start
 * took, also while a run reads it.
 * Built with ASan and UBSan (csrc/Makefile, target fuzz).
 *
 * Properties checked beyond the sanitizers: every status is one the header lists; while the instance
 * has not been corrupted, every result taken has finite weights within WAKE_HPA_WEIGHT_LIMIT, a finite
 * cut-off and a finite measurement noise (no NaN or infinity from int16 input), non-negative unless a
 * window was scribbled on.
 *
 * Built with -DWAKE_HPA_AHEAD=1 (fuzz_hpa_ahead: the tremor-ahead fit, horizons 1..32 and the refused 0
 * and 33 from the configuration, the RTP with its ahead predictor), also: every result's predictor is
 * finite within +-8 (wake.ahead.COEFFICIENT_LIMIT) and its goal in [0, 1], 0 for a window without a
 * tremor peak, a silent one or one noted WAKE_HPA_NOTE_FULL_SCALE; wake_hpa_ahead_to_rtp's Q27 / Q30
 * values lie within the RTP's ranges; and wake_hpa_apply installs exactly those in the RTP.
 */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "wake_hpa.h"
#include "fuzz_input.h"

enum { OP_PUSH, OP_PUSH_BURST, OP_MISSING, OP_SLICE, OP_RUN, OP_START, OP_TAKE, OP_TO_RTP, OP_APPLY,
#if WAKE_HPA_AHEAD
       OP_AHEAD_TO_RTP,
#endif
       OP_CORRUPT, OP_SCRIBBLE, OP_COUNT };

static wake_q15_t taps[WAKE_HPA_MAX_LEVEL * WAKE_HPA_MAX_TAPS];
/* two caller windows: wake_hpa_start's window "must stay unchanged until the result is ready", so
   OP_START writes the one the last accepted start did not take (the only run that can still read a
   caller's window is the last accepted start's) */
static wake_q15_t windows[2][WAKE_HPA_MAX_WINDOW];
static wake_hpa_t hpa;
static wake_rtp_t rtp;

/**
 * The fields every call checks (check_instance in wake_hpa.c): the sealed configuration, the feeding
 * counters and the run's loop counters, all declared before wake_hpa_t::lo. The numeric work state
 * after them (int64 sums, floats) is the run's own output and is trusted, not re-checked
 * (docs/studies/verification.md, "Corrupted state"): the harness corrupts only the checked part.
 */
#define CHECKED_BYTES offsetof(wake_hpa_t, lo)

static int status_known(wake_hpa_status_t st)
{
    return st <= WAKE_HPA_STARTED && st >= WAKE_HPA_E_CORRUPT;
}

static float fuzz_f32(fuzz_input_t *in)
{
    float v;
    fuzz_bytes(in, &v, sizeof v);
    return v;
}

/** Replace the default configuration's fields the input selects (a bit per field group). */
static void read_config(fuzz_input_t *in, wake_hpa_config_t *c)
{
    const uint16_t mask = fuzz_u16(in);
    unsigned k;
    (void)wake_hpa_default_config(c);
    if (mask & 1u) {
        c->level = (uint16_t)(fuzz_u8(in) % (WAKE_HPA_MAX_LEVEL + 2u));
    }
    if (mask & 2u) {
        c->window = (uint16_t)(fuzz_u16(in) % (WAKE_HPA_MAX_WINDOW + 64u));
    }
    if (mask & 4u) {
        c->ar_order = (uint16_t)(fuzz_u8(in) % (WAKE_HPA_MAX_ORDER + 2u));
    }
    if (mask & 8u) {
        c->rule = (uint16_t)(fuzz_u8(in) % 4u);
    }
    if (mask & 16u) {
        c->clean_below = fuzz_u16(in);
        c->horizon = (uint16_t)(fuzz_u8(in) % (WAKE_HPA_MAX_AHEAD_HORIZON + 2u));
    }
    if (mask & 32u) {
        for (k = 0; k < WAKE_HPA_MAX_WARMUP; ++k) {
            c->warmup[k] = (uint16_t)(fuzz_u16(in) % (WAKE_HPA_MAX_WINDOW + 1u));
        }
    }
    if (mask & 64u) {                      /* the rates: a scale factor or raw bits */
        c->fs = (mask & 128u) ? fuzz_f32(in) : c->fs * (float)(fuzz_u8(in) + 1u) / 64.0f;
    }
    if (mask & 256u) {
        c->tremor_low = fuzz_f32(in);
        c->tremor_high = fuzz_f32(in);
    }
    if (mask & 512u) {
        c->cutoff_low = fuzz_f32(in);
        c->cutoff_high = fuzz_f32(in);
        c->default_cutoff = fuzz_f32(in);
        c->shallow_high = fuzz_f32(in);
    }
    if (mask & 1024u) {
        c->min_depth_ratio = fuzz_f32(in);
        c->floor_ratio = fuzz_f32(in);
        c->edge_ratio = fuzz_f32(in);
    }
    if (mask & 2048u) {
        c->ridge = fuzz_f32(in);
        c->process_noise_ratio = fuzz_f32(in);
    }
    if (mask & 4096u) {                    /* issue 46's settings: any gate cut-off bits, the ridge's scale */
        c->gate_cutoff = (mask & 8192u) ? fuzz_f32(in) : (float)fuzz_u8(in) / 16.0f;
        c->ridge_scale = (uint16_t)(fuzz_u8(in) % 3u);
    }
}

/**
 * A result's ranges.  @p consistent: no window was scribbled on during a run; the noise is then >= 0
 * (it is a sum of squares about a fitted line, exact in int64 for one window's content, and may come
 * out negative when the content changed between the passes that sum it).
 */
static void check_result(const wake_hpa_result_t *r, unsigned level, int consistent)
{
    unsigned j;
    for (j = 0; j < level; ++j) {
        FUZZ_REQUIRE(isfinite(r->weights[j]) && fabsf(r->weights[j]) <= (float)WAKE_HPA_WEIGHT_LIMIT);
    }
    FUZZ_REQUIRE(isfinite(r->cutoff) && isfinite(r->measurement_noise));
    FUZZ_REQUIRE(!consistent || r->measurement_noise >= 0.0f);
#if WAKE_HPA_AHEAD
    for (j = 0; j < WAKE_HPA_AHEAD_TAPS; ++j) {
        FUZZ_REQUIRE(isfinite(r->ahead[j]) && fabsf(r->ahead[j]) <= 8.0f);
    }
    FUZZ_REQUIRE(r->ahead_goal >= 0.0f && r->ahead_goal <= 1.0f);   /* false for NaN */
    if (r->flag == WAKE_HPA_NO_TREMOR_PEAK || r->flag == WAKE_HPA_SILENT ||
        (r->notes & WAKE_HPA_NOTE_FULL_SCALE) != 0u) {
        FUZZ_REQUIRE(r->ahead_goal == 0.0f);
    }
#endif
}

#if WAKE_HPA_AHEAD
/** wake_hpa_ahead_to_rtp of a result: the RTP's ranges (|c| <= 8 in Q27, goal in [0, 1] in Q30). */
static void check_ahead_to_rtp(const wake_hpa_result_t *r, int32_t *c, wake_ratio_t *goal)
{
    unsigned j;
    FUZZ_REQUIRE(wake_hpa_ahead_to_rtp(r, c, goal) == WAKE_HPA_OK);
    for (j = 0; j < WAKE_HPA_AHEAD_TAPS; ++j) {
        FUZZ_REQUIRE(c[j] >= -(INT32_C(1) << 30) && c[j] <= (INT32_C(1) << 30));
    }
    FUZZ_REQUIRE(*goal >= 0 && *goal <= (INT32_C(1) << 30));
}
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input_t in = {data, size, 0u};
    wake_hpa_config_t cfg;
    wake_hpa_result_t res;
    wake_hpa_status_t st;
    float weights[WAKE_HPA_MAX_LEVEL];
    wake_q24_t w24[WAKE_RTP_MAX_LEVEL];
    wake_cov_t r, q;
    unsigned i, n, level, ops = 0, corrupted = 0, scribbled = 0, taken = 0;
    uint8_t shift;

    read_config(&in, &cfg);
    level = cfg.level >= 1u && cfg.level <= WAKE_HPA_MAX_LEVEL ? cfg.level : 1u;
    shift = (uint8_t)(fuzz_u8(&in) % 17u);
    for (i = 0; i < (level << level); ++i) {
        taps[i] = (wake_q15_t)(fuzz_i16(&in) >> shift);
    }
    for (i = 0; i < WAKE_HPA_MAX_LEVEL; ++i) {
        weights[i] = (fuzz_u8(&in) & 1u) ? fuzz_f32(&in) : (float)fuzz_i16(&in) / 1024.0f;
        w24[i] = 0;
    }
    memset(&hpa, 0x5A, sizeof hpa);                 /* init takes any content */
    st = wake_hpa_init(&hpa, &cfg, taps, weights);
    FUZZ_REQUIRE(status_known(st));
    /* the RTP apply hands results to: the same level and bank when that is a valid RTP */
    (void)wake_rtp_init(&rtp, (int)level, taps, w24, 1, 0, 0);

    while (fuzz_more(&in) && ops++ < 256u) {
        const unsigned op = fuzz_u8(&in) % OP_COUNT;
        switch (op) {
        case OP_PUSH:
            st = wake_hpa_push(&hpa, fuzz_i16(&in));
            break;
        case OP_PUSH_BURST: {              /* a deterministic tone + noise burst */
            const unsigned count = (unsigned)fuzz_u8(&in) + 1u;
            uint32_t lcg = fuzz_u16(&in);
            const int amplitude = (int)fuzz_u8(&in) << 7;
            for (i = 0; i < count; ++i) {
                lcg = lcg * 1664525u + 1013904223u;
                st = wake_hpa_push(&hpa, (wake_q15_t)((int)((lcg >> 16) % 2001u) - 1000
                                                      + ((i / 8u) & 1u ? amplitude : -amplitude)));
                FUZZ_REQUIRE(status_known(st));
            }
            break;
        }
        case OP_MISSING:
            n = (unsigned)fuzz_u8(&in) + 1u;
            for (i = 0; i < n; ++i) {
                st = wake_hpa_push_missing(&hpa);
                FUZZ_REQUIRE(status_known(st));
            }
            break;
        case OP_SLICE:
            n = (unsigned)fuzz_u8(&in) + 1u;
            for (i = 0; i < n; ++i) {
                st = wake_hpa_slice(&hpa);
                FUZZ_REQUIRE(status_known(st));
            }
            break;
        case OP_RUN:
            st = wake_hpa_run(&hpa);
            break;
        case OP_START: {
            wake_q15_t *const free_window = windows[1u - taken];
            n = fuzz_u16(&in) % (WAKE_HPA_MAX_WINDOW + 1u);
            fuzz_bytes(&in, free_window, n * sizeof free_window[0]);
            st = wake_hpa_start(&hpa, free_window, (uint16_t)n, (uint32_t)fuzz_i32(&in));
            if (st == WAKE_HPA_OK) {
                taken = 1u - taken;
            }
            break;
        }
        case OP_SCRIBBLE: {   /* a contract violation: results keep their ranges, all but the noise's sign */
            const size_t offset = fuzz_u16(&in) % WAKE_HPA_MAX_WINDOW;
            size_t len = (size_t)fuzz_u8(&in) + 1u;
            if (len > WAKE_HPA_MAX_WINDOW - offset) {
                len = WAKE_HPA_MAX_WINDOW - offset;
            }
            fuzz_bytes(&in, windows[taken] + offset, len * sizeof windows[0][0]);
            scribbled = 1;
            st = WAKE_HPA_OK;
            break;
        }
        case OP_TAKE:
            st = wake_hpa_take(&hpa, &res);
            if (st == WAKE_HPA_OK && !corrupted) {
                check_result(&res, hpa.cfg.level, !scribbled);
            }
            break;
        case OP_TO_RTP:
            if (hpa.magic == WAKE_HPA_MAGIC && !corrupted) {
                st = wake_hpa_to_rtp(&hpa.result, (int)level, fuzz_f32(&in), w24, &r, &q);
            } else {
                st = WAKE_HPA_OK;
            }
            break;
        case OP_APPLY: {
#if WAKE_HPA_AHEAD
            int32_t c[WAKE_HPA_AHEAD_TAPS];
            wake_ratio_t goal = 0;
            const int check = !corrupted && hpa.magic == WAKE_HPA_MAGIC && hpa.ready != 0u;   /* a result to apply */
            if (check) {
                check_result(&hpa.result, hpa.cfg.level, !scribbled);
                check_ahead_to_rtp(&hpa.result, c, &goal);
            }
#endif
            st = wake_hpa_apply(&hpa, &rtp);
#if WAKE_HPA_AHEAD
            if (st == WAKE_HPA_OK && check) {   /* the RTP holds exactly the converted predictor and goal */
                FUZZ_REQUIRE(memcmp(rtp.ahead.coef, c, sizeof c) == 0 && rtp.ahead.goal == goal);
            }
#endif
            break;
        }
#if WAKE_HPA_AHEAD
        case OP_AHEAD_TO_RTP:
            if (hpa.magic == WAKE_HPA_MAGIC && !corrupted) {
                int32_t c[WAKE_HPA_AHEAD_TAPS];
                wake_ratio_t goal;
                check_ahead_to_rtp(&hpa.result, c, &goal);
            }
            st = WAKE_HPA_OK;
            break;
#endif
        default: {   /* OP_CORRUPT: overwrite up to 16 bytes of the checked fields, keep the work pointer */
            const wake_q15_t *keep = hpa.work;
            const size_t offset = (size_t)fuzz_i32(&in) % CHECKED_BYTES;
            size_t len = (size_t)(fuzz_u8(&in) % 16u) + 1u;
            if (len > CHECKED_BYTES - offset) {
                len = CHECKED_BYTES - offset;
            }
            fuzz_bytes(&in, (uint8_t *)&hpa + offset, len);
            hpa.work = keep;
            corrupted = 1;
            st = WAKE_HPA_OK;
            break;
        }
        }
        FUZZ_REQUIRE(status_known(st));
    }
    return 0;
}
