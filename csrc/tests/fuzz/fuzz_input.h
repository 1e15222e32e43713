/**
 * @file fuzz_input.h
 * @brief Reading a libFuzzer input as a sequence of typed values (shared by the harnesses).
 *
 * Every read past the end returns zeros: a short input is a valid input whose
 * remaining calls see zero bytes, so the fuzzer never wastes an execution.
 */
#ifndef WAKE_FUZZ_INPUT_H
#define WAKE_FUZZ_INPUT_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct {
    const uint8_t *data;
    size_t size;
    size_t pos;
} fuzz_input_t;

static void fuzz_bytes(fuzz_input_t *in, void *out, size_t n)
{
    size_t avail = in->pos < in->size ? in->size - in->pos : 0u;
    size_t take = n < avail ? n : avail;
    memset(out, 0, n);
    if (take > 0u) {
        memcpy(out, in->data + in->pos, take);
    }
    in->pos += take;
}

static uint8_t fuzz_u8(fuzz_input_t *in)
{
    uint8_t v;
    fuzz_bytes(in, &v, sizeof v);
    return v;
}

static uint16_t fuzz_u16(fuzz_input_t *in)
{
    uint16_t v;
    fuzz_bytes(in, &v, sizeof v);
    return v;
}

static int16_t fuzz_i16(fuzz_input_t *in)
{
    int16_t v;
    fuzz_bytes(in, &v, sizeof v);
    return v;
}

static int32_t fuzz_i32(fuzz_input_t *in)
{
    int32_t v;
    fuzz_bytes(in, &v, sizeof v);
    return v;
}

static int fuzz_more(const fuzz_input_t *in)
{
    return in->pos < in->size;
}

/** Trap (a libFuzzer crash with the input saved) when a documented property fails. */
#define FUZZ_REQUIRE(cond) do { if (!(cond)) { __builtin_trap(); } } while (0)

#endif /* WAKE_FUZZ_INPUT_H */
