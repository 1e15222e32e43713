/**
 * @file wake_rtp_split.c
 * @brief The RTP's split step (issue 33): wake_rtp_prepare computes what the next step does not need its
 * sample for, wake_rtp_finish / wake_rtp_finish_missing the rest, with the result of wake_rtp_step /
 * wake_rtp_step_missing bit for bit.
 *
 * A scheduling of the core's per-sample pieces (internal/wake_rtp_sample.h): the finish is the step's own
 * control flow (sample_flow) instantiated for a prepared step.  The prepared values live in the instance's
 * wake_rtp_split_t (wake_rtpi_split): a build without WAKE_RTP_SPLIT holds none, and there the entries
 * answer WAKE_RTP_E_FEATURE; a firmware that does not call
 * them does not link them.
 */
/* At -Os the split step keeps its own copies of the integer helpers (wake_fixed.h): its finish calls them
 * about ten times on its longest path, and calls within a module cost fewer instructions (the compiler
 * knows which registers they use) than calls of wake_rtp_fixed.c's copies; a split build pays their code. */
#define WAKE_FIXED_LOCAL_COPIES 1
#include "internal/wake_rtp_sample.h"

#if WAKE_RTP_KALMAN && WAKE_RTP_NO_LONG_MULTIPLY
kalman_gain_t wake_rtpi_kalman_gain(const wake_rtp_t *s, uint32_t *events)
{
    return kalman_gain(s, events);
}
#endif

/**
 * wake_rtp_prepare on a checked instance.  Everything below is what sample_flow computes before it
 * needs the sample, stored for its prepared case:
 *
 *   fir    = h' window(n) - h_{N-1} m(n)       the window after the next push, less its newest product
 *            (before the first sample: the sum of h, the first sample fills the window with itself)
 *   rho, s = the Kalman gain and (R/S) s + q|w|^2                           unless inert
 *   ahead  = c . line(n) - c_0 e(n);  gate towards the goal
 */
static void prepare_validated(wake_rtp_t *s, wake_rtp_split_t *p)
{
    const unsigned N = s->n_taps;
    /* after the next push the window is ring[head + 1 .. head + N - 1] and the new sample; the ring's
     * ring[head + N] (the copy of the oldest sample, which the push drops) takes the new sample's place
     * in fir_window and its product is taken off again: exact in int64, |.| < 2^52 */
    const wake_q15_t *older = &s->ring[s->head + 1u];
    uint32_t ev = 0u;
    if (s->primed != 0u) {
        p->fir = fir_window(s->fir, older, N) - fir_product(s->fir[N - 1u], older[N - 1u]);
    } else {
        p->fir = fir_sum(s->fir, N);
    }
    p->rho = 0;
    p->s = s->s;
#if WAKE_RTP_KALMAN
    if (!s->inert) {
        const kalman_gain_t g = gain_of(s, &ev);
        p->rho = g.rho;
        p->s = kalman_covariance(s, &g, &ev);
    }
#endif
    p->events = ev;
    features_prepare(s, p);
    p->ready = 1u;
}

/* A setter changed what a prepare read: prepare again if the instance was prepared (wake_rtpi_split_refresh). */
void wake_rtpi_split_prepare_again(wake_rtp_t *s)
{
    wake_rtp_split_t *const p = wake_rtpi_split(s);
    if ((p != NULL) && (p->ready != 0u)) {
        prepare_validated(s, p);
    }
}

/** sample_flow of a prepared step. */
WAKE_RTP_NOINLINE static wake_q15_t finish_validated(wake_rtp_t *s, wake_q15_t sample, int measured, uint32_t ev)
{
    return sample_flow(s, sample, measured, ev, 1);
}

/** wake_rtp_finish (@p measured 1) and wake_rtp_finish_missing (0): the checks, then the prepared step. */
static WAKE_RTP_ALWAYS_INLINE wake_rtp_status_t finish_checked(wake_rtp_t *s, wake_q15_t sample, int measured, wake_q15_t *prediction)
{
    uint32_t ev = 0u;
    wake_rtp_status_t st = WAKE_RTP_OK;
    if (sample_admitted(s, &sample, measured, prediction, 1, &ev, &st) != 0) {
        *prediction = finish_validated(s, sample, measured, ev);
    }
    return st;
}

wake_rtp_status_t wake_rtp_prepare(wake_rtp_t *s)
{
    wake_rtp_status_t st = wake_rtpi_check_structure(s);
    if (st == WAKE_RTP_OK) {
        wake_rtp_split_t *const p = wake_rtpi_split(s);
        st = wake_rtpi_feature(p);                         /* the instance may hold no split step */
        if (st == WAKE_RTP_OK) {
            prepare_validated(s, p);
        }
    }
    return st;
}

wake_rtp_status_t wake_rtp_finish(wake_rtp_t *s, wake_q15_t sample, wake_q15_t *prediction)
{
    return finish_checked(s, sample, 1, prediction);
}

wake_rtp_status_t wake_rtp_finish_missing(wake_rtp_t *s, wake_q15_t *prediction)
{
    return finish_checked(s, 0, 0, prediction);
}
