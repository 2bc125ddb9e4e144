#!/usr/bin/env bash
# Configures and builds cmr in ./build (Release, Ninja). Safe to rerun.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
