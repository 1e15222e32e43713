# Toolchain file: Cortex-M0+ with arm-none-eabi-gcc (bare metal, static libraries only).
#   cmake -S csrc -B build-m0plus -DCMAKE_TOOLCHAIN_FILE=csrc/cmake/arm-cortex-m0plus.cmake
# The M0+ has no 32 x 32 -> 64-bit multiply instruction: WAKE_RTP_NO_LONG_MULTIPLY defaults to ON
# (split FIR taps and 16 x 16-bit partial products, bit-identical results; docs/studies/fixed_point.md).
set(WAKE_ARM_CPU_FLAGS "-mcpu=cortex-m0plus -mthumb")
set(WAKE_RTP_NO_LONG_MULTIPLY ON CACHE BOOL "Cortex-M0+ arithmetic: no 32 x 32 -> 64-bit multiply")
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi.cmake)
