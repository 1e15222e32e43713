/**
 * @file wake_bounds.h
 * @brief Bounds that exist for the analyser and the fuzzer: each keeps a value that only a corrupted
 * state can push out of its range within that range, so that no operation on it can overflow.  One line
 * of reason each; the argument is in docs/studies/verification.md, at the section named.  Internal.
 */
#ifndef WAKE_BOUNDS_H
#define WAKE_BOUNDS_H

/* ---- RTP ---------------------------------------------------------------------------------------- */

/** A prepared FIR sum h' window less its newest product, read back within +-2^52 (N <= 256 products < 2^44:
 * "Corrupted state"). */
#define WAKE_BOUND_RTP_PREPARED_FIR_BITS 52u
/** A prepared sum of the N taps (before the first sample), read back within +-2^39 ("Corrupted state"). */
#define WAKE_BOUND_RTP_PREPARED_TAP_SUM_BITS 39u
/** The tremor ahead's prepared seven products, read back within +-2^49 ("Corrupted state"). */
#define WAKE_BOUND_RTP_PREPARED_AHEAD_BITS 49u
/** z and z_s as the voluntary ahead reads them, within +-2^41 (z is kept within +-2^40: "Corrupted state"). */
#define WAKE_BOUND_RTP_VOLUNTARY_Z_BITS 41u

#endif /* WAKE_BOUNDS_H */
