/**
 * @file wake_bounds.h
 * @brief Bounds that exist for the analyser and the fuzzer, which give a struct any contents: each reads a
 * value of the state within the range its own computation keeps, so that a corrupted value cannot overflow
 * what follows.  One line each; the argument is in docs/studies/verification.md, "Corrupted state".
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
