/*
 * Standalone WAKE firmware: the whole algorithm on the device, no host.
 *
 * Per sensor sample: the RTP predicts the voluntary motion of the next
 * sample, the sample goes into the HPA's window buffer, and the HPA does one
 * bounded slice of work; a finished HPA is installed in the RTP between two
 * samples.  That is the bare-metal super-loop of wake_hpa.h; an RTOS would
 * run wake_hpa_run() in a low-priority task instead of the slices.
 *
 * The sensor and the actuator are files here, so that the same program runs
 * on the host (stdio) and on a Cortex-M4F under QEMU (Arm semihosting):
 *   input        int16 little-endian Q15 samples
 *   predictions  int16 little-endian, one per sample (the voluntary motion of the next sample)
 *   weights      one record per installed HPA: uint32 sample count, then J int32 Q24 weights, R, q
 * `make -C csrc standalone-check` runs both builds on one recording and
 * compares the two outputs byte for byte.
 *
 * The configuration header is what `wake export-header` writes (WakeConfig's
 * defaults: sym3, J = 5, 100 Hz, L = 500).
 */
#include <stddef.h>
#include <stdint.h>

#include "wake_rtp.h"
#include "wake_hpa.h"
#include "wake_config.h"

/* ---- I/O: stdio on the host, semihosting on the target ------------------- */
#if defined(__arm__)
static int32_t semihost(uint32_t op, const void *args)
{
    register uint32_t r0 __asm("r0") = op;
    register const void *r1 __asm("r1") = args;
    __asm volatile("bkpt #0xab" : "+r"(r0) : "r"(r1) : "memory");
    return (int32_t)r0;
}

static int32_t io_open(const char *name, int write)
{
    size_t len = 0;
    uint32_t args[3];
    while (name[len] != '\0') {
        ++len;
    }
    args[0] = (uint32_t)(uintptr_t)name;
    args[1] = write ? 5u : 1u;              /* "wb" / "rb" */
    args[2] = (uint32_t)len;
    return semihost(0x01u, args);           /* SYS_OPEN */
}

/* bytes transferred */
static size_t io_transfer(int32_t fd, void *buf, size_t n, int write)
{
    uint32_t args[3];
    args[0] = (uint32_t)fd;
    args[1] = (uint32_t)(uintptr_t)buf;
    args[2] = (uint32_t)n;
    return n - (size_t)semihost(write ? 0x05u : 0x06u, args); /* SYS_WRITE / SYS_READ: returns bytes not done */
}

static void io_close(int32_t fd)
{
    uint32_t args[1];
    args[0] = (uint32_t)fd;
    (void)semihost(0x02u, args);            /* SYS_CLOSE */
}
#else
#include <stdio.h>

static FILE *files[3];

static int32_t io_open(const char *name, int write)
{
    int32_t k;
    for (k = 0; k < 3; ++k) {
        if (files[k] == NULL) {
            files[k] = fopen(name, write ? "wb" : "rb");
            return files[k] != NULL ? k : -1;
        }
    }
    return -1;
}

static size_t io_transfer(int32_t fd, void *buf, size_t n, int write)
{
    return write ? fwrite(buf, 1, n, files[fd]) : fread(buf, 1, n, files[fd]);
}

static void io_close(int32_t fd)
{
    fclose(files[fd]);
    files[fd] = NULL;
}
#endif

/* ---- the device ------------------------------------------------------------ */
static wake_rtp_t rtp;
static wake_hpa_t hpa;

#define BLOCK 64

int main(void)
{
    static int16_t in[BLOCK], out[BLOCK];
    int32_t fin, fpred, fw;
    uint32_t count = 0;
    size_t got, k;

    if (wake_config_init(&rtp) != WAKE_RTP_OK || wake_config_hpa_init(&hpa) != WAKE_HPA_OK) {
        return 2;
    }
    /* the RTP starts from the start-up weights, the designed one-step-ahead predictor */
    if (wake_rtp_set_weights(&rtp, wake_config_start_weights, WAKE_CONFIG_R, WAKE_CONFIG_Q) != WAKE_RTP_OK) {
        return 2;
    }
    fin = io_open("input.q15", 0);
    fpred = io_open("predictions.q15", 1);
    fw = io_open("weights.bin", 1);
    if (fin < 0 || fpred < 0 || fw < 0) {
        return 3;
    }
    while ((got = io_transfer(fin, in, sizeof in, 0) / sizeof in[0]) > 0) {
        for (k = 0; k < got; ++k) {
            /* one sample period */
            if (wake_rtp_step(&rtp, in[k], &out[k]) != WAKE_RTP_OK) {
                return 4;
            }
            ++count;
            (void)wake_hpa_push(&hpa, in[k]);      /* starts an HPA when a window is complete */
            if (wake_hpa_slice(&hpa) < 0) {        /* one bounded piece of it */
                return 5;
            }
            if (wake_hpa_apply(&hpa, &rtp) == WAKE_HPA_OK) {  /* between this sample and the next */
                int32_t rec[2 + WAKE_CONFIG_LEVEL + 1];
                int j;
                rec[0] = (int32_t)count;
                for (j = 0; j < WAKE_CONFIG_LEVEL; ++j) {
                    rec[1 + j] = rtp.weights[j];
                }
                rec[1 + WAKE_CONFIG_LEVEL] = rtp.r;
                rec[2 + WAKE_CONFIG_LEVEL] = rtp.q;
                if (io_transfer(fw, rec, sizeof rec, 1) != sizeof rec) {
                    return 6;
                }
            }
        }
        if (io_transfer(fpred, out, got * sizeof out[0], 1) != got * sizeof out[0]) {
            return 6;
        }
    }
    io_close(fin);
    io_close(fpred);
    io_close(fw);
    return (hpa.overruns == 0u && hpa.runs > 0u) ? 0 : 7;
}
