#!/bin/sh
# The C core through CMake, as a firmware project takes it (docs/reference/packaging.md):
#   1. host build of csrc/ with the firmware warning set as errors, its unit tests under ctest;
#   2. Cortex-M4 and Cortex-M0+ builds with csrc/cmake/arm-cortex-*.cmake, no forbidden symbol;
#   3. install to a prefix and build tests/cmake_consumer with find_package(wake), run it;
#   4. the same consumer with add_subdirectory(csrc).
# Usage: sh tests/cmake_check.sh [BUILD_DIR]   (from csrc/; CMAKE overrides the cmake command)
set -eu
CSRC=$(cd "$(dirname "$0")/.." && pwd)
OUT=${1:-$CSRC/build/cmake}
CMAKE=${CMAKE:-cmake}
FORBIDDEN='__aeabi_[fd]|__aeabi_[lu]*l?div|__aeabi_uldivmod|__aeabi_ldivmod|__(add|sub|mul|div)[sd]f3|^ *U (malloc|calloc|realloc|free|printf|abort|exit)$'
rm -rf "$OUT"
mkdir -p "$OUT"

"$CMAKE" -S "$CSRC" -B "$OUT/host" -DWAKE_WARNINGS_AS_ERRORS=ON >/dev/null
"$CMAKE" --build "$OUT/host" -j 2 >/dev/null
(cd "$OUT/host" && ctest --output-on-failure >/dev/null)
echo "cmake host: library built, ctest passed"

for cpu in m4 m0plus; do
    "$CMAKE" -S "$CSRC" -B "$OUT/$cpu" -DCMAKE_TOOLCHAIN_FILE="$CSRC/cmake/arm-cortex-$cpu.cmake" \
        -DWAKE_WARNINGS_AS_ERRORS=ON >/dev/null
    "$CMAKE" --build "$OUT/$cpu" -j 2 >/dev/null
    # the RTP core may not pull in soft-float, 64-bit division, allocation or stdio
    if arm-none-eabi-nm -u "$OUT/$cpu/libwake_rtp.a" | grep -E "$FORBIDDEN"; then
        echo "cmake $cpu: libwake_rtp.a references a forbidden symbol" >&2
        exit 1
    fi
    arm-none-eabi-size "$OUT/$cpu/libwake_rtp.a" | awk -v c="$cpu" 'NR == 2 {print "cmake " c ": libwake_rtp.a .text " $1 " B"}'
done
if arm-none-eabi-objdump -d "$OUT/m0plus/libwake_rtp.a" | grep -Eq '\s(umull|smull|smlal|umlal)\s'; then
    echo "cmake m0plus: a long multiply in the Cortex-M0+ build (WAKE_RTP_NO_LONG_MULTIPLY not applied?)" >&2
    exit 1
fi

"$CMAKE" --install "$OUT/host" --prefix "$OUT/prefix" >/dev/null
"$CMAKE" -S "$CSRC/tests/cmake_consumer" -B "$OUT/consumer-package" -DWAKE_CONSUME=package \
    -DCMAKE_PREFIX_PATH="$OUT/prefix" >/dev/null
"$CMAKE" --build "$OUT/consumer-package" >/dev/null
"$OUT/consumer-package/consumer"
"$CMAKE" -S "$CSRC/tests/cmake_consumer" -B "$OUT/consumer-subdir" -DWAKE_CONSUME=subdir \
    -DWAKE_CSRC_DIR="$CSRC" >/dev/null
"$CMAKE" --build "$OUT/consumer-subdir" >/dev/null
"$OUT/consumer-subdir/consumer"
echo "cmake: OK (host, Cortex-M4, Cortex-M0+, find_package and add_subdirectory consumers)"
