/**
 * @file wake_bounds.h
 * @brief Bounds that exist for the analyser (Frama-C Eva) and the fuzzer, which give a struct any contents:
 *        clamps that never change a value of a real input or a state the code itself computed, so that a value
 *        analysis sees an invariant it cannot derive and a corrupted value cannot overflow what follows.  One line
 *        each; the argument that a bound never fires is written once: the HPA's in docs/reference/verification.md
 *        ("The analyser's bounds"), the RTP's in docs/studies/verification.md ("Corrupted state").
 */
#ifndef WAKE_BOUNDS_H
#define WAKE_BOUNDS_H

/* ---- RTP ---------------------------------------------------------------------------------------- */

/** The split step's prepared FIR sum (h' window less its newest product), read within +-2^52. */
#define WAKE_BOUND_RTP_PREPARED_FIR_BITS 52u
/** The split step's prepared sum of the taps (before the first sample), read within +-2^39. */
#define WAKE_BOUND_RTP_PREPARED_TAP_SUM_BITS 39u
/** The split step's prepared seven products of the tremor ahead, read within +-2^49. */
#define WAKE_BOUND_RTP_PREPARED_AHEAD_BITS 49u
/** z, z_s and w_h' d_s as the voluntary ahead reads them, within +-2^41 (z itself is kept within +-2^40). */
#define WAKE_BOUND_RTP_VOLUNTARY_Z_BITS 41u

#endif /* WAKE_BOUNDS_H */

/* The HPA's bounds depend on its sizes: defined in a unit that has included wake_hpa.h first (its internal header
 * does); a second inclusion defines them again with the same replacement lists, which C allows. */
#if defined(WAKE_HPA_MAX_WINDOW)

/* ---- the HPA (csrc/wake_hpa_*.c) ------------------------------------------------------------------------------
 * Analyser shapes: besides these clamps, a few expressions are written so that an interval analysis keeps a
 * bound it would otherwise lose (a chunk's count from limit - t, an end tested as step >= rest, a test on a
 * value itself rather than on a copy): docs/reference/verification.md#analyser-shapes lists them.
 * Where a comment in the HPA's sources says "(analyser)", this is what it means. */

/** |n^2 Rxx(i, i + d)| < n^3 2^32: the Rxx diagonal's exact int64 value, clamped where a chunk loads it
 *  (docs/reference/verification.md#bound-diag). */
#if WAKE_HPA_MAX_WINDOW <= 512
#define DIAG_MAX INT64_C(1152921504606846976)    /* 2^60 */
#else
#define DIAG_MAX INT64_C(4611686018427387904)    /* 2^62 */
#endif

/** The Reinsch states s, d of a DFT pass, clamped every REINSCH_BLOCK samples
 *  (docs/reference/verification.md#bound-reinsch). */
#if WAKE_HPA_MAX_WINDOW <= 512
#define REINSCH_S_MAX 8589934592.0f     /* 2^33 */
#define REINSCH_D_MAX 17179869184.0f    /* 2^34 */
#else
#define REINSCH_S_MAX 34359738368.0f    /* 2^35 */
#define REINSCH_D_MAX 68719476736.0f    /* 2^36 */
#endif
/** Samples between two clamps of the Reinsch states: an interval grows at most 5.9-fold per sample, 2^41 over 16. */
#define REINSCH_BLOCK 16u

/** Every part of a bin slide's phasors, clamped every SLIDE_BLOCK rows
 *  (docs/reference/verification.md#bound-slide). */
#define PHASOR_MAX 1.00390625f              /* 1 + 2^-8 */
/** Q_m(i) of a bin slide, clamped with the phasors (docs/reference/verification.md#bound-slide). */
#define SLIDE_Q_MAX (4.0f * REINSCH_D_MAX)
/** Rows of a slide between two clamps of its phasors (5 would let vhead's interval reach 2^36 at n = 64). */
#define SLIDE_BLOCK 4u

/** The tremor-ahead pass's oscillators (v, e), clamped after each run of samples
 *  (docs/reference/verification.md#bound-ahead-osc). */
#define AHEAD_V_MAX 34359738368.0f      /* 2^35 */
#define AHEAD_E_MAX 68719476736.0f      /* 2^36 */

#endif /* WAKE_HPA_MAX_WINDOW */
