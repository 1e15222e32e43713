# Toolchain file: Cortex-M4 with arm-none-eabi-gcc (bare metal, static libraries only).
#   cmake -S csrc -B build-m4 -DCMAKE_TOOLCHAIN_FILE=csrc/cmake/arm-cortex-m4.cmake
# Soft-float ABI by default, as csrc/Makefile's `cross` builds (the RTP uses no float). A firmware with
# the FPU and the HPA sets WAKE_ARM_FLOAT_FLAGS, e.g. "-mfloat-abi=hard -mfpu=fpv4-sp-d16".
set(WAKE_ARM_CPU_FLAGS "-mcpu=cortex-m4 -mthumb")
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi.cmake)
