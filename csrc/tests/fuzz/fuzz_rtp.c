/**
 * @file fuzz_rtp.c
 * @brief libFuzzer harness for the fixed-point RTP's public entry points (wake_rtp.h).
 *
 * The input is decoded as: an init (level, taps, weights, R, q, p0, each either raw or scaled into
 * the range the API accepts, so that both the refusals and the accepted configurations are reached),
 * then a sequence of calls: step, step_missing, run, set_weights, reset, load_state (arbitrary bytes),
 * get_state, the tremor ahead's set_ahead (coefficients raw or scaled into +-8), set_ahead_ramp,
 * ahead_output, load_ahead_state and get_ahead_state, and "corrupt", which overwrites part of the instance with input bytes (the caller-owned
 * taps pointer excepted: no check can validate a pointer) before the calls that must then refuse it
 * or run without undefined behaviour (the Kalman accumulators excepted, see keep_accumulators_in_range). Built with ASan and UBSan (csrc/Makefile, target fuzz).
 *
 * Properties checked beyond the sanitizers: every status is one the header lists; a call that
 * fails leaves the instance byte for byte unchanged where the header promises it (step,
 * step_missing, set_weights, load_state).
 */
#include <stdint.h>
#include <string.h>

#include "wake_rtp.h"
#include "fuzz_input.h"
#include "fuzz_rtp_input.h"

enum { OP_STEP, OP_MISSING, OP_RUN, OP_SET_WEIGHTS, OP_RESET, OP_LOAD_STATE, OP_GET_STATE,
#if WAKE_RTP_AHEAD
       OP_SET_AHEAD, OP_SET_AHEAD_RAMP, OP_AHEAD_OUTPUT, OP_LOAD_AHEAD, OP_GET_AHEAD,
#endif
       OP_CORRUPT, OP_COUNT };

static wake_q15_t taps[WAKE_RTP_MAX_LEVEL * WAKE_RTP_MAX_TAPS];

static int status_known(wake_rtp_status_t st)
{
    return st <= WAKE_RTP_OK && st >= WAKE_RTP_E_AHEAD;
}

static void check_unchanged_on_error(wake_rtp_status_t st, const wake_rtp_t *before, const wake_rtp_t *after)
{
    FUZZ_REQUIRE(status_known(st));
    if (st != WAKE_RTP_OK) {
        FUZZ_REQUIRE(memcmp(before, after, sizeof *before) == 0);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static wake_rtp_t rtp, copy;
    fuzz_input_t in = {data, size, 0u};
    wake_q24_t w[WAKE_RTP_MAX_LEVEL];
    wake_q23_t correction[WAKE_RTP_MAX_LEVEL];
    wake_cov_t covariance[WAKE_RTP_MAX_LEVEL * WAKE_RTP_MAX_LEVEL];
    wake_q15_t window[WAKE_RTP_MAX_TAPS];
    wake_q15_t block[64];
#if WAKE_RTP_AHEAD
    wake_q15_t line[WAKE_RTP_AHEAD_TAPS];
#endif
    wake_q15_t prediction;
    wake_rtp_status_t st;
    unsigned level, n, i, ops = 0;
    uint8_t shift;

    /* init: level 0..MAX+1 (both ends refused), taps raw or scaled so that each row's sum of |taps|
       stays below 2.0 (a row of 2^J taps each below 2^(15-J)) */
    level = fuzz_u8(&in) % (WAKE_RTP_MAX_LEVEL + 2u);
    shift = (uint8_t)(fuzz_u8(&in) % 17u);
    n = (level >= 1u && level <= WAKE_RTP_MAX_LEVEL) ? level << level : 0u;
    for (i = 0; i < n; ++i) {
        taps[i] = (wake_q15_t)(fuzz_i16(&in) >> shift);
    }
    memset(&rtp, 0xA5, sizeof rtp);            /* init takes any content */
    read_weights(&in, w, level <= WAKE_RTP_MAX_LEVEL ? level : WAKE_RTP_MAX_LEVEL);
    {
        const wake_cov_t r = read_noise(&in), q = read_noise(&in), p0 = read_noise(&in);
        const int kalman = fuzz_u8(&in) & 1u;   /* half the inits are inert (q = p0 = 0) */
        st = wake_rtp_init(&rtp, (int)level, taps, w, r, kalman ? q : 0, kalman ? p0 : 0);
    }
    FUZZ_REQUIRE(status_known(st));

    while (fuzz_more(&in) && ops++ < 4096u) {
        const unsigned op = fuzz_u8(&in) % OP_COUNT;
        memcpy(&copy, &rtp, sizeof rtp);
        switch (op) {
        case OP_STEP:
            st = wake_rtp_step(&rtp, fuzz_i16(&in), &prediction);
            check_unchanged_on_error(st, &copy, &rtp);
            break;
        case OP_MISSING:
            st = wake_rtp_step_missing(&rtp, &prediction);
            check_unchanged_on_error(st, &copy, &rtp);
            break;
        case OP_RUN:
            n = fuzz_u8(&in) % 65u;
            for (i = 0; i < n; ++i) {
                block[i] = fuzz_i16(&in);
            }
            st = wake_rtp_run(&rtp, block, block, n);   /* in place, as the header allows */
            FUZZ_REQUIRE(status_known(st));
            break;
        case OP_SET_WEIGHTS:
            read_weights(&in, w, WAKE_RTP_MAX_LEVEL);
            {
                const wake_cov_t r = read_noise(&in), q = read_noise(&in);
                st = wake_rtp_set_weights(&rtp, w, r, q);
            }
            check_unchanged_on_error(st, &copy, &rtp);
            break;
        case OP_RESET:
            st = wake_rtp_reset(&rtp);
            FUZZ_REQUIRE(status_known(st));
            break;
        case OP_LOAD_STATE:
            fuzz_bytes(&in, window, sizeof window);
            fuzz_bytes(&in, correction, sizeof correction);
            fuzz_bytes(&in, covariance, sizeof covariance);
            st = wake_rtp_load_state(&rtp, window, correction, covariance, fuzz_i32(&in));
            check_unchanged_on_error(st, &copy, &rtp);
            break;
        case OP_GET_STATE:
            st = wake_rtp_get_state(&rtp, correction, covariance);
            FUZZ_REQUIRE(status_known(st));
            FUZZ_REQUIRE(memcmp(&copy, &rtp, sizeof rtp) == 0);   /* const */
            break;
#if WAKE_RTP_AHEAD
        case OP_SET_AHEAD: {
            int32_t c[WAKE_RTP_AHEAD_TAPS];
            const int scaled = (fuzz_u8(&in) & 1u) == 0u;   /* raw, or |c| <= 2^30 (8.0 in Q27) */
            for (i = 0; i < (unsigned)WAKE_RTP_AHEAD_TAPS; ++i) {
                const int32_t raw = fuzz_i32(&in);
                c[i] = scaled ? raw / 2 : raw;
            }
            st = wake_rtp_set_ahead(&rtp, c, fuzz_i32(&in));
            check_unchanged_on_error(st, &copy, &rtp);
            break;
        }
        case OP_SET_AHEAD_RAMP:
            st = wake_rtp_set_ahead_ramp(&rtp, fuzz_i32(&in));
            check_unchanged_on_error(st, &copy, &rtp);
            break;
        case OP_AHEAD_OUTPUT: {
            wake_q23_t predicted, command;
            wake_ratio_t gate;
            st = wake_rtp_ahead_output(&rtp, &predicted, &gate, &command);
            FUZZ_REQUIRE(status_known(st));
            FUZZ_REQUIRE(memcmp(&copy, &rtp, sizeof rtp) == 0);   /* const */
            break;
        }
        case OP_LOAD_AHEAD:
            fuzz_bytes(&in, line, sizeof line);
            st = wake_rtp_load_ahead_state(&rtp, line, fuzz_i32(&in));
            check_unchanged_on_error(st, &copy, &rtp);
            break;
        case OP_GET_AHEAD:
            st = wake_rtp_get_ahead_state(&rtp, line);
            FUZZ_REQUIRE(status_known(st));
            FUZZ_REQUIRE(memcmp(&copy, &rtp, sizeof rtp) == 0);   /* const */
            break;
#endif
        default: {   /* OP_CORRUPT: overwrite up to 16 bytes at an offset, keep the taps pointer */
            const wake_q15_t *keep = rtp.taps;
            const size_t offset = fuzz_u16(&in) % sizeof rtp;
            size_t len = (size_t)(fuzz_u8(&in) % 16u) + 1u;
            if (len > sizeof rtp - offset) {
                len = sizeof rtp - offset;
            }
            fuzz_bytes(&in, (uint8_t *)&rtp + offset, len);
            rtp.taps = keep;
            keep_accumulators_in_range(&rtp);
            break;
        }
        }
    }
    return 0;
}
