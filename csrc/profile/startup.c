/**
 * @file startup.c
 * @brief Minimal Cortex-M vector table and reset handler for the profiling image.
 *
 * Copies .data, zeroes .bss, runs main() and reports its return value through
 * semihosting (SYS_EXIT_EXTENDED), which QEMU turns into its exit status.
 */
#include <stdint.h>

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;
int main(void);
void Reset_Handler(void);
void Fault_Handler(void);

/** Semihosting exit with status @p code (0 = success). */
__attribute__((noreturn)) void semihost_exit(int code)
{
    /* ADP_Stopped_ApplicationExit and the exit code */
    static uint32_t block[2];
    register uint32_t r0 __asm("r0") = 0x20u;                 /* SYS_EXIT_EXTENDED */
    register uint32_t *r1 __asm("r1") = block;
    block[0] = 0x20026u;
    block[1] = (uint32_t)code;
    __asm volatile("bkpt #0xab" : : "r"(r0), "r"(r1) : "memory");
    for (;;) {
    }
}

void Reset_Handler(void)
{
    uint32_t *src = &_sidata;
    uint32_t *dst = &_sdata;
#if defined(__ARM_FP)
    /* hard-float image: give CP10 and CP11 (the FPU) full access before any float instruction */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm volatile("dsb\n\tisb" ::: "memory");
#endif
    while (dst < &_edata) {
        *dst++ = *src++;
    }
    for (dst = &_sbss; dst < &_ebss; ++dst) {
        *dst = 0u;
    }
    semihost_exit(main());
}

void Fault_Handler(void)
{
    semihost_exit(100);
}

/* Initial SP, reset, NMI, HardFault, MemManage, BusFault, UsageFault. */
__attribute__((section(".isr_vector"), used)) void (*const g_vectors[16])(void) = {
    (void (*)(void))(uintptr_t)&_estack,
    Reset_Handler,
    Fault_Handler,
    Fault_Handler,
    Fault_Handler,
    Fault_Handler,
    Fault_Handler,
};
