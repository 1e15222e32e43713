/**
 * @file wake_rtp_internal.h
 * @brief What the RTP's modules share, and what the verification layer (unit tests, proofs, fuzz
 * harnesses) may reach: not part of the public API (wake_rtp.h).
 *
 * The RTP by concern (docs/reference/architecture.md, "The C core's files"):
 *
 * | file                       | concern                                                              |
 * |----------------------------|----------------------------------------------------------------------|
 * | wake_rtp.c                 | the core step: bank + Kalman + one-step prediction (wake_rtp_step)    |
 * | wake_rtp_state.c           | init, reset, weights, state load/save; the covariance form           |
 * | wake_rtp_split.c           | the split step (prepare / finish): the same per-sample flow, scheduled |
 * | wake_rtp_ahead.c           | the tremor ahead (predictor + gate): its step, fed the core's tremor estimate, and its setters |
 * | wake_rtp_voluntary.c       | the voluntary motion ahead (w_h): its restart, its step, its setter  |
 * | wake_rtp_block.c           | the block entries (wake_rtp_run, wake_rtp_run_outputs)               |
 * | wake_rtp_fixed.c           | at -Os, the one copy of the integer helpers (wake_fixed.h)           |
 * | internal/wake_rtp_sample.h | the per-sample pieces and their control flow, written once           |
 * | internal/wake_bounds.h     | the bounds that exist for a corrupted state                          |
 *
 * A feature module's hook is its function when the feature's switch is on and a `static inline`
 * no-op when it is off, so that the modules that call it carry no feature switch.
 */
#ifndef WAKE_RTP_INTERNAL_H
#define WAKE_RTP_INTERNAL_H

#include "../wake_rtp.h"
#include "../wake_fixed.h"

#include <string.h>

/* The FIR reads its taps split in parts (wake_fir_t) where that avoids 64-bit
 * sums; its 32-bit sums hold up to 64 taps. */
#if WAKE_RTP_NO_LONG_MULTIPLY && WAKE_RTP_MAX_LEVEL <= 6
#define WAKE_RTP_SPLIT_FIR 1
#else
#define WAKE_RTP_SPLIT_FIR 0
#endif

/* Functions kept out of line so that `wake profile` can bound the step with
 * and without them (the Kalman update is skipped while inert; the window fill
 * runs on the first sample only). */
#if defined(__GNUC__)
#define WAKE_RTP_NOINLINE __attribute__((noinline))
#else
#define WAKE_RTP_NOINLINE
#endif

/* Functions that run once per HPA, reset or state load, never per sample.
 * clang optimises them for size: at -O2 it unrolls their loops over the J
 * levels into about twice gcc's code (bench/clang_cost.py); gcc builds them
 * as the rest.  The per-sample path is not marked. */
#if defined(__clang__)
#define WAKE_RTP_COLD __attribute__((minsize))
#else
#define WAKE_RTP_COLD
#endif

/* The ring is 4-byte aligned inside the struct (wake_rtpi_prime_window stores words). */
typedef char wake_rtp_ring_is_aligned[(offsetof(wake_rtp_t, ring) % 4u == 0u) ? 1 : -1];

#define P_FRAC WAKE_RTP_P_FRAC
#define RATIO_ONE (INT32_C(1) << WAKE_RTP_RATIO_FRAC)
/* Q15 sample -> Q23 signal: 8 guard bits */
#define SIGNAL_GUARD_BITS (WAKE_RTP_STATE_FRAC - WAKE_RTP_SAMPLE_FRAC)
/* Q(FIR) x Q15 -> Q23 */
#define FIR_TO_SIGNAL_SHIFT (WAKE_RTP_FIR_FRAC + WAKE_RTP_SAMPLE_FRAC - WAKE_RTP_STATE_FRAC)

/* Functions inlined even at -Os: the parts of the per-sample control flow (internal/wake_rtp_sample.h), each of
 * which one caller instantiates for a constant case (a copy per case is what a hand-written copy of the flow
 * would hold). */
#if defined(__GNUC__)
#define WAKE_RTP_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define WAKE_RTP_ALWAYS_INLINE inline
#endif

#if WAKE_RTP_KALMAN /* the ranges of the Kalman's scalars */
/** v clamped to +-2^40 (the range of z = w'd); adds 1 to *events when it clamps. */
static inline int64_t clamp_wide(int64_t v, uint32_t *events)
{
    return clamp_symmetric(v, 40u, events);
}

/** v clamped to +-2^50 (the range of s); adds 1 to *events when it clamps. */
static inline int64_t clamp_cov_wide(int64_t v, uint32_t *events)
{
    return clamp_symmetric(v, 50u, events);
}

#endif

/* ---------------------------------------------------------------------- */
/* Checks (wake_rtp.c: the structure; wake_rtp_state.c: the instance)      */
/* ---------------------------------------------------------------------- */

/** The structural fields: what wake_rtp_step indexes with or branches on. */
wake_rtp_status_t wake_rtpi_check_structure(const wake_rtp_t *s);

/** wake_rtpi_check_structure plus the weights' range, the variance's sign and each feature's fields (every
 * function but the per-sample ones). */
wake_rtp_status_t wake_rtpi_check_instance(const wake_rtp_t *s);

/** After the RTP instance's check: WAKE_RTP_E_FEATURE when the feature's embedded instance, @p embedded, is absent
 * (NULL: a build without the feature), else WAKE_RTP_OK.  Every RTP entry of a feature answers through it. */
static inline wake_rtp_status_t wake_rtpi_feature(const void *embedded)
{
    return (embedded == NULL) ? WAKE_RTP_E_FEATURE : WAKE_RTP_OK;
}

/** 0 when the tremor ahead's line index is out of range (the step indexes the line with it). */
static inline int wake_rtpi_ahead_structure_ok(const wake_rtp_t *s)
{
#if WAKE_RTP_AHEAD
    return (s->ahead.head < (unsigned)WAKE_RTP_AHEAD_TAPS) ? 1 : 0;
#else
    (void)s;
    return 1;
#endif
}

/** 1 when every one of the @p level weights lies within +-64 (Q24). */
static inline int weights_in_range(const wake_q24_t *weights, unsigned level)
{
    unsigned j;
    for (j = 0; j < level; ++j) {
        if (weights[j] > WAKE_RTP_WEIGHT_MAX || weights[j] < -WAKE_RTP_WEIGHT_MAX) {
            return 0;
        }
    }
    return 1;
}

/** A tap as fir_window reads it (see wake_fir_t). */
WAKE_RTP_INLINE_UNLESS_OS wake_fir_t fir_tap(int32_t h)
{
    wake_fir_t t;
#if WAKE_RTP_SPLIT_FIR
    const uint32_t bits = (uint32_t)h;
    t.parts.biased_hi = (uint16_t)((bits >> 16) ^ 0x8000u);   /* top half, top bit flipped: floor(h/2^16) + 2^15 */
    t.parts.mid = (uint8_t)((bits >> 8) & 0xFFu);
    t.parts.lo = (uint8_t)(bits & 0xFFu);
#else
    t.value = h;
#endif
    return t;
}

#if WAKE_RTP_KALMAN
/**
 * round(a 2^frac / x) clamped to +-2^50, for |a| < 2^62, 1 <= x < 2^62 and
 * frac <= 40: restoring long division, one quotient bit per turn.  Exact
 * (one rounding), a fixed number of turns; it runs in the restart and in
 * get_state only, never per sample.
 */
WAKE_RTP_COLD static inline int64_t divide_wide(int64_t a, uint64_t x, unsigned frac, uint32_t *events)
{
    const uint64_t cap = UINT64_C(1) << 52;                 /* twice 2^50 and more: clamps below */
    uint64_t mag = (uint64_t)(a < 0 ? -a : a), rem = 0, q = 0;
    unsigned k;
    /* the numerator mag 2^(frac + 1), bit by bit from the top: the 62 bits of mag, then zeros */
    for (k = 0; k < 63u + frac; ++k) {
        uint64_t take;
        rem = (rem << 1) | (mag >> 61);                                     /* < 2 x < 2^63 */
        mag = (mag << 1) & ((UINT64_C(1) << 62) - 1u);
        take = (rem >= x) ? 1u : 0u;
        rem -= x & (UINT64_C(0) - take);                                 /* no multiply */
        q = (q << 1) | take;                                                /* <= 2^53 + 1 */
        q = (q > cap) ? cap : q;
    }
    q = (q + 1u) >> 1;                                      /* one extra bit: round half up */
    return clamp_cov_wide(a < 0 ? -(int64_t)q : (int64_t)q, events);
}

/** |w|^2 in Q24 (exact sum of Q48 squares, rounded once): < 2^40. */
static inline uint64_t weight_norm2(const wake_q24_t *w, unsigned J)
{
    unsigned j;
    uint64_t acc = 0;
    for (j = 0; j < J; ++j) {
        acc += (uint64_t)((int64_t)w[j] * w[j]);           /* < 2^60, J <= 8 terms */
    }
    return (acc + (UINT64_C(1) << 23)) >> 24;
}

/** w'x for x in Q23 (d) or Q(P) (a row of P): J products Q(f + 24) rounded once to Q(f); |.| < 2^41
 * (wake_rtp_state.c). */
int64_t wake_rtpi_weighted_sum(const wake_q24_t *w, const int32_t *x, unsigned J);
#endif

/* ---------------------------------------------------------------------- */
/* The feature modules' hooks                                              */
/* ---------------------------------------------------------------------- */

/* The tremor ahead (wake_ahead.h, wake_rtp_ahead.c): the rules its public functions and the RTP's hooks share. */

/** 1 when every coefficient lies within +-8 (Q27). */
static inline int ahead_coefficients_in_range(const int32_t *c)
{
    unsigned i;
    for (i = 0; i < (unsigned)WAKE_RTP_AHEAD_TAPS; ++i) {
        if (c[i] > WAKE_RTP_AHEAD_COEF_MAX || c[i] < -WAKE_RTP_AHEAD_COEF_MAX) {
            return 0;
        }
    }
    return 1;
}

/** 1 when v lies in [lo, 2^30] (a gate, goal or ramp in Q30). */
static inline int gate_in_range(wake_ratio_t v, wake_ratio_t lo)
{
    return (v >= lo && v <= WAKE_RTP_GATE_ONE) ? 1 : 0;
}

/** The fields every function but the per-sample ones checks (the step indexes with head only). */
static inline int ahead_consistent(const wake_ahead_t *a)
{
    return ahead_coefficients_in_range(a->coef) && gate_in_range(a->goal, 0)
           && gate_in_range(a->gate, 0) && gate_in_range(a->ramp, 1);
}

/** A new instance: the default ramp; coefficients, goal, gate and line 0. */
static inline void ahead_init(wake_ahead_t *a)
{
    (void)memset(a, 0, sizeof(*a));
    a->ramp = WAKE_RTP_AHEAD_RAMP_DEFAULT;
}

/** The instance forgets its samples and shuts; its coefficients and ramp stay. */
static inline void ahead_reset(wake_ahead_t *a)
{
    memset(a->line, 0, sizeof(a->line));
    a->head = 0u;
    a->goal = 0;
    a->gate = 0;
    a->predicted = 0;
    a->command = 0;
    a->saturations = 0u;
}

/** A sample without a measurement: the held-out gain needs a window's worth of samples again. */
static inline void ahead_shut(wake_ahead_t *a)
{
    a->goal = 0;
}

/* ---------------------------------------------------------------------- */
/* The composition: which feature instances an RTP instance holds          */
/* ---------------------------------------------------------------------- */

#if WAKE_RTP_AHEAD
/** The instance's tremor ahead. */
static inline wake_ahead_t *wake_rtpi_ahead(wake_rtp_t *s)
{
    return &s->ahead;
}
/** The instance's tremor ahead, read only. */
static inline const wake_ahead_t *wake_rtpi_ahead_of(const wake_rtp_t *s)
{
    return &s->ahead;
}
#else
static inline wake_ahead_t *wake_rtpi_ahead(wake_rtp_t *s)
{
    (void)s;
    return NULL;                    /* none: its functions answer WAKE_RTP_E_NULL */
}
static inline const wake_ahead_t *wake_rtpi_ahead_of(const wake_rtp_t *s)
{
    (void)s;
    return NULL;
}
#endif

#if WAKE_RTP_AHEAD
/** The tremor ahead's outputs of the last step: P(n), g(n) and g(n) P(n). */
static inline void wake_rtpi_ahead_outputs(const wake_rtp_t *s, wake_q23_t *predicted, wake_ratio_t *gate,
                                           wake_q23_t *command)
{
    *predicted = s->ahead.predicted;
    *gate = s->ahead.gate;
    *command = s->ahead.command;
}
static inline int wake_rtpi_ahead_consistent(const wake_rtp_t *s)
{
    return ahead_consistent(&s->ahead);
}
static inline void wake_rtpi_ahead_reset(wake_rtp_t *s)
{
    ahead_reset(&s->ahead);
}
static inline void wake_rtpi_ahead_init(wake_rtp_t *s)
{
    s->ahead.ramp = WAKE_RTP_AHEAD_RAMP_DEFAULT;        /* the rest is init's memset */
}
#else
static inline void wake_rtpi_ahead_outputs(const wake_rtp_t *s, wake_q23_t *predicted, wake_ratio_t *gate,
                                           wake_q23_t *command)
{
    (void)s;
    *predicted = 0;                 /* nothing predicted, the gate shut */
    *gate = 0;
    *command = 0;
}
static inline int wake_rtpi_ahead_consistent(const wake_rtp_t *s)
{
    (void)s;
    return 1;
}
static inline void wake_rtpi_ahead_reset(wake_rtp_t *s)
{
    (void)s;
}
static inline void wake_rtpi_ahead_init(wake_rtp_t *s)
{
    (void)s;
}
#endif

/* The voluntary motion ahead (wake_voluntary_ahead.h, wake_rtp_voluntary.c) on instance v of RTP s. */
/** 1 when w_h and its flag are consistent. */
int wake_rtpi_voluntary_consistent_on(const wake_rtp_t *s, const wake_voluntary_ahead_t *v);
/** The output and counter back to 0; w_h stays. */
void wake_rtpi_voluntary_reset_on(wake_voluntary_ahead_t *v);
/** The restart for the current w and d_s. */
void wake_rtpi_voluntary_restart_on(wake_rtp_t *s, wake_voluntary_ahead_t *v);

#if WAKE_RTP_VOLUNTARY_AHEAD
/** The instance's voluntary motion ahead. */
static inline wake_voluntary_ahead_t *wake_rtpi_voluntary(wake_rtp_t *s)
{
    return &s->voluntary_ahead;
}
/** The instance's voluntary motion ahead, read only. */
static inline const wake_voluntary_ahead_t *wake_rtpi_voluntary_of(const wake_rtp_t *s)
{
    return &s->voluntary_ahead;
}
/** The voluntary motion ahead's output of the last step, v_h(n). */
static inline wake_q23_t wake_rtpi_voluntary_output(const wake_rtp_t *s)
{
    return s->voluntary_ahead.output;
}
static inline int wake_rtpi_voluntary_consistent(const wake_rtp_t *s)
{
    return wake_rtpi_voluntary_consistent_on(s, &s->voluntary_ahead);
}
static inline void wake_rtpi_voluntary_reset(wake_rtp_t *s)
{
    wake_rtpi_voluntary_reset_on(&s->voluntary_ahead);
}
static inline void wake_rtpi_voluntary_restart(wake_rtp_t *s)
{
    wake_rtpi_voluntary_restart_on(s, &s->voluntary_ahead);
}
#else
static inline wake_voluntary_ahead_t *wake_rtpi_voluntary(wake_rtp_t *s)
{
    (void)s;
    return NULL;                    /* none: its functions answer WAKE_RTP_E_NULL */
}
static inline const wake_voluntary_ahead_t *wake_rtpi_voluntary_of(const wake_rtp_t *s)
{
    (void)s;
    return NULL;
}
static inline wake_q23_t wake_rtpi_voluntary_output(const wake_rtp_t *s)
{
    return s->last_output;          /* none: the one-step prediction held, as before a w_h is installed */
}
static inline int wake_rtpi_voluntary_consistent(const wake_rtp_t *s)
{
    (void)s;
    return 1;
}
static inline void wake_rtpi_voluntary_reset(wake_rtp_t *s)
{
    (void)s;
}
static inline void wake_rtpi_voluntary_restart(wake_rtp_t *s)
{
    (void)s;
}
#endif

/** Prepare again if the instance was prepared (wake_rtp_split.c). */
void wake_rtpi_split_prepare_again(wake_rtp_t *s);

#if WAKE_RTP_SPLIT
/** A setter changed what a prepare read: prepare again if the instance was prepared. */
static inline void wake_rtpi_split_refresh(wake_rtp_t *s)
{
    wake_rtpi_split_prepare_again(s);
}
/** A step forgets a prepared step (it changes what the prepare read). */
static inline void wake_rtpi_split_forget(wake_rtp_t *s)
{
    s->split.ready = 0u;
}
/** The instance's split step: what wake_rtp_prepare computed for the next finish. */
static inline wake_rtp_split_t *wake_rtpi_split(wake_rtp_t *s)
{
    return &s->split;
}
/** The instance's split step, read only. */
static inline const wake_rtp_split_t *wake_rtpi_split_of(const wake_rtp_t *s)
{
    return &s->split;
}
#else
static inline void wake_rtpi_split_refresh(wake_rtp_t *s)
{
    (void)s;                        /* nothing prepared: nothing to refresh */
}
static inline void wake_rtpi_split_forget(wake_rtp_t *s)
{
    (void)s;
}
static inline wake_rtp_split_t *wake_rtpi_split(wake_rtp_t *s)
{
    (void)s;
    return NULL;                    /* none: the split entries answer WAKE_RTP_E_FEATURE */
}
static inline const wake_rtp_split_t *wake_rtpi_split_of(const wake_rtp_t *s)
{
    (void)s;
    return NULL;
}
#endif

#endif /* WAKE_RTP_INTERNAL_H */
