"""cffi (API mode) build script for ``wake._rtp``, the fixed-point C core.

Used by ``setup.py`` (``cffi_modules``); for development it can also be run
directly (``python build_ffi.py``) to compile the extension in place.
"""

import os

from cffi import FFI

HERE = os.path.dirname(os.path.abspath(__file__))

ffibuilder = FFI()

ffibuilder.cdef(
    """
    #define WAKE_RTP_MAX_LEVEL ...
    #define WAKE_RTP_MAX_TAPS ...
    #define WAKE_RTP_P_FRAC ...
    #define WAKE_RTP_SAMPLE_FRAC ...
    #define WAKE_RTP_TAP_FRAC ...
    #define WAKE_RTP_STATE_FRAC ...
    #define WAKE_RTP_WEIGHT_FRAC ...
    #define WAKE_RTP_WEIGHT_MAX ...
    #define WAKE_RTP_TAP_ROW_ABS_MAX ...

    typedef enum {
        WAKE_RTP_OK,
        WAKE_RTP_E_NULL,
        WAKE_RTP_E_LEVEL,
        WAKE_RTP_E_TAPS,
        WAKE_RTP_E_WEIGHTS,
        WAKE_RTP_E_NOISE,
        WAKE_RTP_E_UNINIT,
        WAKE_RTP_E_CORRUPT,
        WAKE_RTP_E_STATE,
        ...
    } wake_rtp_status_t;

    typedef struct {
        uint32_t magic;
        uint32_t saturations;
        uint32_t guard_events;
        uint16_t level;
        uint16_t n_taps;
        uint16_t head;
        uint16_t primed;
        int32_t weights[...];
        int32_t r;
        int32_t q;
        int32_t p0;
        int32_t last_output;
        int32_t correction[...];
        int32_t covariance[...];
        int16_t ring[...];
        ...;
    } wake_rtp_t;

    wake_rtp_status_t wake_rtp_init(wake_rtp_t *s, int level, const int16_t *taps,
                                    const int32_t *weights, int32_t r, int32_t q, int32_t p0);
    wake_rtp_status_t wake_rtp_set_weights(wake_rtp_t *s, const int32_t *weights,
                                           int32_t r, int32_t q);
    wake_rtp_status_t wake_rtp_reset(wake_rtp_t *s);
    wake_rtp_status_t wake_rtp_step(wake_rtp_t *s, int16_t sample, int16_t *prediction);
    wake_rtp_status_t wake_rtp_step_missing(wake_rtp_t *s, int16_t *prediction);
    wake_rtp_status_t wake_rtp_run(wake_rtp_t *s, const int16_t *in, int16_t *out, size_t n);
    wake_rtp_status_t wake_rtp_load_state(wake_rtp_t *s, const int16_t *window,
                                          const int32_t *correction, const int32_t *covariance,
                                          int32_t last_output);
    uint32_t wake_rtp_reciprocal(uint32_t x);
    """
)

ffibuilder.set_source(
    "wake._rtp",
    '#include "wake_rtp.h"',
    sources=["csrc/wake_rtp.c"],
    include_dirs=["csrc"],
)

if __name__ == "__main__":
    os.chdir(HERE)
    ffibuilder.compile(verbose=False)
    # ffibuilder.compile() writes wake/_rtp*.so relative to the cwd: the repo top.
