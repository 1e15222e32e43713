/**
 * @file wake_fixed.h
 * @brief The integer helpers of the fixed-point core: shifts, roundings, saturations, wide products.
 *
 * `static inline` functions only, no state, no macros in place of functions (libfixmath style); each
 * compiles to the same instructions in every translation unit that uses it, and a unit that does not
 * use one pays nothing for it.  Integer arithmetic only, no division, no libc.
 *
 * Conventions: no signed overflow, no left shift of a negative value.  Right shifts of negative
 * values go through shift_right_floor(), written with non-negative operands only, so the code does
 * not rely on the implementation-defined behaviour of `>>` on negative numbers (compilers still emit
 * one arithmetic shift).
 *
 * The one arithmetic variant: WAKE_RTP_NO_LONG_MULTIPLY 1 assembles every 32 x 32 -> 64-bit product
 * from 16 x 16-bit ones (cores without the long multiply instruction, ARMv6-M and ARMv8-M baseline,
 * where it is the default), so that no __aeabi_lmul call is made.
 */
#ifndef WAKE_FIXED_H
#define WAKE_FIXED_H

#include <stdint.h>

/* Cores without a 32 x 32 -> 64-bit multiply instruction (ARMv6-M, ARMv8-M
 * baseline): 64-bit products are assembled from 16 x 16-bit ones, so no
 * __aeabi_lmul call is made. */
#ifndef WAKE_RTP_NO_LONG_MULTIPLY /* the host tests also build it with 1, to run the Cortex-M0+ arithmetic */
#if defined(__ARM_ARCH_6M__) || defined(__ARM_ARCH_8M_BASE__)
#define WAKE_RTP_NO_LONG_MULTIPLY 1
#else
#define WAKE_RTP_NO_LONG_MULTIPLY 0
#endif
#endif

/* Helpers that an -Os build keeps out of line.  gcc's size heuristics inline
 * them at every call site, where each copy of their 64-bit arithmetic costs
 * more than the call (docs/studies/profiling.md, "Code at -Os").  Other levels inline
 * them as before: the -O2 code that the cost targets bound is unchanged.
 * (Marked unused at -Os, so that a unit that does not call one is not warned
 * about it.) */
#if defined(__GNUC__) && defined(__OPTIMIZE_SIZE__)
#define WAKE_RTP_OUTLINE_AT_OS __attribute__((noinline))
#define WAKE_RTP_INLINE_UNLESS_OS static __attribute__((noinline, unused))
#else
#define WAKE_RTP_OUTLINE_AT_OS
#define WAKE_RTP_INLINE_UNLESS_OS static inline
#endif

/* The helpers every RTP module calls (shift_right_round to clamp_symmetric below): `static inline` at every
 * level but -Os, where each is compiled once, in wake_rtp_fixed.c (WAKE_FIXED_DEFINE), and every module calls
 * that copy (a copy per module would cost more code than the modules' split saves), under a prefixed
 * symbol; a module that defines WAKE_FIXED_LOCAL_COPIES (the split step, for its cost) keeps its own,
 * out of line.  The body of each is written once, here. */
#if defined(WAKE_FIXED_LOCAL_COPIES) && (WAKE_FIXED_LOCAL_COPIES == 1)
#define WAKE_FIXED_OUTLINE 0            /* this module's own copies */
#elif defined(__GNUC__) && defined(__OPTIMIZE_SIZE__)
#define WAKE_FIXED_OUTLINE 1
#else
#define WAKE_FIXED_OUTLINE 0
#endif
#if WAKE_FIXED_OUTLINE
int64_t shift_right_round(int64_t v, unsigned sh) __asm__("wake_fixed_shift_right_round");
int32_t narrow_saturate(int64_t v, uint32_t *events) __asm__("wake_fixed_narrow_saturate");
int16_t narrow_saturate16(int32_t v, uint32_t *events) __asm__("wake_fixed_narrow_saturate16");
int64_t clamp_symmetric(int64_t v, unsigned bits, uint32_t *events) __asm__("wake_fixed_clamp_symmetric");
#endif
#if !WAKE_FIXED_OUTLINE
#define WAKE_FIXED_HELPER WAKE_RTP_INLINE_UNLESS_OS
#elif defined(WAKE_FIXED_DEFINE) && (WAKE_FIXED_DEFINE == 1)
#define WAKE_FIXED_HELPER               /* wake_rtp_fixed.c at -Os: the one external copy of each */
#endif

/** Add n events to a counter that sticks at UINT32_MAX (no branch on the data). */
static inline void count_events(uint32_t *counter, uint32_t n)
{
    uint32_t sum = *counter + n;
    *counter = (sum < n) ? UINT32_MAX : sum;
}

/** floor(v / 2^sh) for 0 <= sh <= 63, without shifting a negative value. */
static inline int64_t shift_right_floor(int64_t v, unsigned sh)
{
    if (v >= 0) {
        return v >> sh;
    }
    /* v < 0: -1 - v is in [0, INT64_MAX]; floor(v/2^k) = -1 - floor((-1-v)/2^k) */
    return -1 - ((-1 - v) >> sh);
}

/** floor(v / 2^sh) for 0 <= sh <= 31, in 32 bits (one arithmetic shift), without shifting a negative value. */
static inline int32_t shift_right_floor32(int32_t v, unsigned sh)
{
    return (v >= 0) ? (v >> sh) : (-1 - ((-1 - v) >> sh));
}

#if defined(WAKE_FIXED_HELPER)
/** round(v / 2^sh), halves up, for 1 <= sh <= 62 and |v| <= 2^62 (cannot overflow). */
WAKE_FIXED_HELPER int64_t shift_right_round(int64_t v, unsigned sh)
{
    return shift_right_floor(v + (INT64_C(1) << (sh - 1u)), sh);
}

/** Narrow int64 to int32, saturating; adds 1 to *events when it saturates. */
WAKE_FIXED_HELPER int32_t narrow_saturate(int64_t v, uint32_t *events)
{
    /* v + 2^31 in [0, 2^32) exactly when v fits: one 64-bit add and a test of the top word */
    const uint32_t over = (uint32_t)(((uint64_t)v + UINT64_C(0x80000000)) >> 32) != 0u;
    *events += over;
    return over ? ((v < 0) ? INT32_MIN : INT32_MAX) : (int32_t)v;
}

/** Narrow int32 to int16, saturating; adds 1 to *events when it saturates. */
WAKE_FIXED_HELPER int16_t narrow_saturate16(int32_t v, uint32_t *events)
{
    *events += (uint32_t)((v > INT16_MAX) | (v < INT16_MIN));
    return (int16_t)((v > INT16_MAX) ? INT16_MAX : (v < INT16_MIN) ? INT16_MIN : v);
}

#if !(defined(WAKE_FIXED_DEFINE) && (WAKE_FIXED_DEFINE == 1) && defined(WAKE_RTP_KALMAN) && !WAKE_RTP_KALMAN)   /* only the Kalman clamps */
/** v clamped to +-2^bits, 1 <= bits <= 62; adds 1 to *events when it clamps. */
WAKE_FIXED_HELPER int64_t clamp_symmetric(int64_t v, unsigned bits, uint32_t *events)
{
    const int64_t top = INT64_C(1) << bits;
    *events += (uint32_t)((v > top) | (v < -top));
    return (v > top) ? top : (v < -top) ? -top : v;
}
#endif
#endif

/** a * b exactly, for int32 operands (a 32 x 32 -> 64-bit multiply). */
static inline int64_t multiply_wide(int32_t a, int32_t b)
{
#if WAKE_RTP_NO_LONG_MULTIPLY
    /* a = ah 2^16 + al, b = bh 2^16 + bl with al, bl in [0, 2^16): four 16 x 16-bit products */
    int32_t ah = (int32_t)shift_right_floor(a, 16u), bh = (int32_t)shift_right_floor(b, 16u);
    int32_t al = (int32_t)((uint32_t)a & 0xFFFFu), bl = (int32_t)((uint32_t)b & 0xFFFFu);
    int64_t cross = (int64_t)(ah * bl) + (int64_t)(al * bh);       /* each |.| < 2^31 */
    return (int64_t)(ah * bh) * 4294967296 + cross * 65536 + (int64_t)((uint32_t)al * (uint32_t)bl);
#else
    return (int64_t)a * b;
#endif
}

/** a * b exactly, for uint32 operands. */
static inline uint64_t multiply_wide_unsigned(uint32_t a, uint32_t b)
{
#if WAKE_RTP_NO_LONG_MULTIPLY
    uint32_t ah = a >> 16, al = a & 0xFFFFu, bh = b >> 16, bl = b & 0xFFFFu;
    uint64_t cross = (uint64_t)(ah * bl) + (uint64_t)(al * bh);
    return ((uint64_t)(ah * bh) << 32) + (cross << 16) + (uint64_t)(al * bl);
#else
    return (uint64_t)a * b;
#endif
}

/**
 * round(a b / 2^sh) for |a| <= 2^50, 20 <= sh <= 31: a = hi 2^31 + lo with
 * lo in [0, 2^31), so a b = hi b 2^31 + lo b from two 32 x 32 -> 64-bit products.
 * |result| < 2^62.
 */
static inline int64_t multiply_wide_by32(int64_t a, int32_t b, unsigned sh)
{
    int64_t hi = shift_right_floor(a, 31u);                                /* |hi| <= 2^19 */
    int32_t lo = (int32_t)(a - hi * (INT64_C(1) << 31));                   /* [0, 2^31) */
    return multiply_wide((int32_t)hi, b) * (INT64_C(1) << (31u - sh)) + shift_right_round(multiply_wide(lo, b), sh);
}

/** Number of significant bits of v >= 1, portable. */
static inline unsigned bit_length64(uint64_t v)
{
#if defined(__GNUC__) && defined(__ARM_FEATURE_CLZ)
    /* CLZ (Cortex-M3/M4/M7): no branch on the data, so the step's worst path is its usual one */
    return 64u - (unsigned)__builtin_clzll(v);
#else
    unsigned n = 0;
    if (v >> 32) { v >>= 32; n += 32; }
    if (v >> 16) { v >>= 16; n += 16; }
    if (v >> 8) { v >>= 8; n += 8; }
    if (v >> 4) { v >>= 4; n += 4; }
    if (v >> 2) { v >>= 2; n += 2; }
    if (v >> 1) { v >>= 1; n += 1; }
    return n + (unsigned)v;
#endif
}

#endif /* WAKE_FIXED_H */
