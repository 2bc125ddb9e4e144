#!/usr/bin/env bash
# Configures and builds cmr in ./build (Release, Ninja). Safe to rerun.
# tools/build.sh PREFIX also installs cmr into PREFIX/bin (cmake --install),
# e.g. tools/build.sh /usr/local puts it on the PATH. With the environment
# variable CI set, warnings are errors (-DCMR_WERROR=ON).
set -euo pipefail
cd "$(dirname "$0")/.."
# Under CI (.ci/run runs with CI=true) a new compiler warning fails the build.
werror=OFF
if [[ -n "${CI:-}" ]]; then werror=ON; fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMR_WERROR="$werror" >/dev/null
cmake --build build -j"$(nproc)"
if [[ $# -ge 1 ]]; then
  cmake --install build --prefix "$1"
fi
