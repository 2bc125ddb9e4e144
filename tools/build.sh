#!/usr/bin/env bash
# Configures and builds cmr in ./build (Release, Ninja). Safe to rerun.
# tools/build.sh PREFIX also installs cmr into PREFIX/bin (cmake --install),
# e.g. tools/build.sh /usr/local puts it on the PATH.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
if [[ $# -ge 1 ]]; then
  cmake --install build --prefix "$1"
fi
