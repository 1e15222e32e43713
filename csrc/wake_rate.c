/**
 * @file wake_rate.c
 * @brief Decimating front end of WAKE (see wake_rate.h).
 */
#include "wake_rate.h"

/* 1: the mean by a 16-turn restoring division (cores without a divide instruction: Cortex-M0/M0+,
 * whose `/` would call a libgcc helper); 0: by `/` (Cortex-M3/M4/M7 UDIV, hosts). */
#ifndef WAKE_RATE_SOFT_DIVIDE
#if defined(__arm__) && !defined(__ARM_FEATURE_IDIV)
#define WAKE_RATE_SOFT_DIVIDE 1
#else
#define WAKE_RATE_SOFT_DIVIDE 0
#endif
#endif

/** floor(num / (2 den)) = round(|sum| / den), halves up, for num = 2|sum| + den < 2^26; quotient < 2^16. */
static inline uint32_t divide_small(uint32_t num, uint32_t den)
{
#if WAKE_RATE_SOFT_DIVIDE
    /* restoring division, one quotient bit per turn, most significant first:
     * q = floor(num / (2 den)) = round(|sum| / den), halves up                */
    const uint32_t twice = den << 1u;           /* 2 den <= 2000 */
    uint32_t rem = num;
    uint32_t q = 0u;
    int bit;
    for (bit = 15; bit >= 0; --bit) {                   /* wcet-loop: 16 */
        const uint32_t step = twice << (uint32_t)bit;   /* < 2000 2^15 < 2^26 */
        if (rem >= step) {
            rem -= step;
            q |= UINT32_C(1) << (uint32_t)bit;
        }
    }
    return q;
#else
    return num / (den << 1u);
#endif
}

/** The fields a push relies on: the phase inside the group, the sum within present Q15 samples. */
static int consistent(const wake_rate_t *s)
{
    const int32_t present = (int32_t)s->present;
    return (s->factor >= 1u) && (s->factor <= (uint16_t)WAKE_RATE_MAX_FACTOR) && (s->phase < s->factor)
           && (s->present <= s->phase) && (s->reserved == 0u)
           && (s->sum <= (present * INT32_C(32767))) && (s->sum >= (present * INT32_C(-32768)));
}

wake_rate_status_t wake_rate_init(wake_rate_t *s, int factor)
{
    wake_rate_status_t status = WAKE_RATE_OK;
    if (s == NULL) {
        status = WAKE_RATE_E_NULL;
    } else if ((factor < 1) || (factor > WAKE_RATE_MAX_FACTOR)) {
        s->magic = 0u;
        status = WAKE_RATE_E_FACTOR;
    } else {
        s->sum = 0;
        s->factor = (uint16_t)factor;
        s->phase = 0u;
        s->present = 0u;
        s->reserved = 0u;
        s->magic = WAKE_RATE_MAGIC;
    }
    return status;
}

/** The mean of the closing group, then an empty group.  present > 0 when called. */
static wake_q15_t close_group(wake_rate_t *s)
{
    /* g = round(sum / present), halves away from zero                        Q15 of FS */
    const uint32_t magnitude = (s->sum < 0) ? (uint32_t)(-s->sum) : (uint32_t)s->sum;
    const uint32_t q = divide_small((magnitude << 1u) + (uint32_t)s->present, (uint32_t)s->present);
    const wake_q15_t mean = (s->sum < 0) ? (wake_q15_t)(-(int32_t)q) : (wake_q15_t)q;
    s->sum = 0;
    return mean;
}

/** The state's status: WAKE_RATE_OK, _UNINIT or _CORRUPT (@p s is not NULL). */
static wake_rate_status_t check(const wake_rate_t *s)
{
    wake_rate_status_t status = WAKE_RATE_OK;
    if (s->magic != WAKE_RATE_MAGIC) {
        status = WAKE_RATE_E_UNINIT;
    } else if (consistent(s) == 0) {
        status = WAKE_RATE_E_CORRUPT;
    } else {
        status = WAKE_RATE_OK;
    }
    return status;
}

/** One input sample into a checked front end: the group sum, and at the group's end its mean. */
static inline void push_checked(wake_rate_t *s, wake_q15_t sample, int present, wake_rate_group_t *group,
                                wake_q15_t *mean)
{
    /* sum += x(n); present += 1 for a present sample                      Q15 of FS, exact */
    if (present != 0) {
        s->sum += (int32_t)sample;
        s->present = (uint16_t)(s->present + 1u);
    }
    s->phase = (uint16_t)(s->phase + 1u);
    if (s->phase == s->factor) {
        if (s->present == 0u) {
            *group = WAKE_RATE_MISSING;
        } else {
            *mean = close_group(s);
            *group = WAKE_RATE_GROUP;
        }
        s->sum = 0;
        s->phase = 0u;
        s->present = 0u;
    }
}

wake_rate_status_t wake_rate_push(wake_rate_t *s, wake_q15_t sample, int present, wake_rate_group_t *group,
                                  wake_q15_t *mean)
{
    wake_rate_status_t status = WAKE_RATE_OK;
    if (group != NULL) {
        *group = WAKE_RATE_OPEN;
    }
    if (mean != NULL) {
        *mean = 0;
    }
    if ((s == NULL) || (group == NULL) || (mean == NULL)) {
        status = WAKE_RATE_E_NULL;
    } else {
        status = check(s);
    }
    if (status == WAKE_RATE_OK) {
        push_checked(s, sample, present, group, mean);
    }
    return status;
}

wake_rate_status_t wake_rate_step(wake_rate_t *s, wake_rtp_t *rtp, wake_q15_t sample, int present,
                                  wake_q15_t *prediction)
{
    wake_rate_status_t status = WAKE_RATE_OK;
    if ((s == NULL) || (rtp == NULL) || (prediction == NULL)) {
        status = WAKE_RATE_E_NULL;
    } else {
        status = check(s);
    }
    if ((status == WAKE_RATE_OK) && (s->factor < 2u)) {
        status = WAKE_RATE_E_FACTOR;                /* D = 1: no group to prepare in; wake_rtp_step */
    }
    if (status == WAKE_RATE_OK) {
        wake_rate_group_t group = WAKE_RATE_OPEN;
        wake_q15_t mean = 0;
        wake_rtp_status_t rtp_status = WAKE_RTP_OK;
        push_checked(s, sample, present, &group, &mean);
        if (group == WAKE_RATE_GROUP) {
            rtp_status = wake_rtp_finish(rtp, mean, prediction);
        } else if (group == WAKE_RATE_MISSING) {
            rtp_status = wake_rtp_finish_missing(rtp, prediction);
        } else if (((uint32_t)s->phase + 1u) == (uint32_t)s->factor) {
            rtp_status = wake_rtp_prepare(rtp);         /* the next input sample ends the group */
        } else {
            rtp_status = WAKE_RTP_OK;                   /* the group stays open: nothing for the RTP */
        }
        if (rtp_status != WAKE_RTP_OK) {
            status = WAKE_RATE_E_RTP;
        }
    }
    return status;
}
