/**
 * @file wake_rtp_fixed.c
 * @brief The one copy of the RTP's out-of-line integer helpers (wake_fixed.h) in an -Os build; nothing at
 * any other level, where every module inlines them.
 */
#define WAKE_FIXED_DEFINE 1
#include "wake_rtp.h"   /* the configuration: a build without the Kalman needs no clamp */
#include "wake_fixed.h"
