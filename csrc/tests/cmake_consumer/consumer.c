/* The smallest program that takes the WAKE C core through CMake: the HPA's default configuration
   and one RTP instance stepped once. Exit status 0 when both report success. */
#include <stdio.h>
#include "wake_hpa.h"

int main(void)
{
    static const wake_q15_t taps[2] = {16384, 16384};   /* level 1: the mean of the last 2 samples, Q15 */
    static const wake_q24_t weights[1] = {1 << 24};     /* 1.0 in Q24 */
    wake_hpa_config_t cfg;
    wake_rtp_t rtp;
    wake_q15_t prediction = 0;
    int ok = wake_hpa_default_config(&cfg) == WAKE_HPA_OK
             && wake_rtp_init(&rtp, 1, taps, weights, 1, 0, 0) == WAKE_RTP_OK
             && wake_rtp_step(&rtp, 1000, &prediction) == WAKE_RTP_OK;
    printf("consumer: %s (WAKE_RTP_MAX_LEVEL %d)\n", ok ? "OK" : "FAILED", WAKE_RTP_MAX_LEVEL);
    return ok ? 0 : 1;
}
