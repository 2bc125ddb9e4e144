#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer,
# in build-asan (one command):
#   tools/sanitize.sh [CTEST ARGS...]     e.g. tools/sanitize.sh -R 'ImportSvg|OutputSet'
# Builds every target (or, with -R, still every target: ctest needs them)
# and runs ctest; any sanitizer report fails the test that triggered it.
# The Python module is built too (it is left out of sanitizer builds by
# default): its tests run Debian's python3 with the sanitizer runtimes
# preloaded and LeakSanitizer off for the interpreter (python/CMakeLists.txt).
# -O1 -g, as ASan's documentation suggests. Not part of CI (.ci/run): the
# build and the run take hours on the 2-core VM (docs/outputs.md).
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g -DNDEBUG" \
  -DCMR_SANITIZER_BUILD=ON -DCMR_WITH_PYTHON=ON "${launcher[@]}" \
  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
ninja -C build-asan -j"${CMR_JOBS:-2}" ${CMR_SANITIZE_TARGETS:-}
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
# Third-party caches that live as long as the process (tools/lsan.supp says
# which); print_suppressions=0 keeps the "Suppressions used" table off stderr,
# where the tests hold cmr to one line.
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tools/lsan.supp:print_suppressions=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export VK_DRIVER_FILES=${VK_DRIVER_FILES:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}
ctest --test-dir build-asan --output-on-failure -j"${CMR_JOBS:-2}" "$@"
