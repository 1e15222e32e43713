/* Specifications of the GCC builtins wake_rtp.c uses, for Frama-C (make prove includes this file
   first). Frama-C's gcc machdep knows __builtin_memcpy but not __builtin_assume_aligned, which
   returns its argument (the alignment is a promise to the optimiser, checked at compile time by
   wake_rtp.c's static assertion on the ring's offset). */
#include <stddef.h>
/*@ assigns \result \from p;
    ensures \result == p; */
void *__builtin_assume_aligned(const void *p, size_t align);
/* __builtin_memcpy as the libc memcpy, whose Frama-C specification requires valid, separated
   source and destination (so Eva checks prime_window's stores). */
#include <string.h>
#define __builtin_memcpy memcpy
