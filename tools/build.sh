#!/usr/bin/env bash
# Configures and builds cmr in ./build (Release, Ninja). Safe to rerun.
#   tools/build.sh            builds the program only: cmr (with the editor,
#                             `cmr edit`, and everything `cmr figures` needs)
#   tools/build.sh --python   cmr and the Python module (build/python/cmr)
#   tools/build.sh --tests    builds everything: cmr, the tests, benchmarks,
#                             examples and the Python module (what ctest runs)
#   tools/build.sh PREFIX     also installs cmr into PREFIX/bin (cmake --install),
#                             e.g. tools/build.sh /usr/local puts it on the PATH
# With the environment variable CI set, warnings are errors (-DCMR_WERROR=ON).
set -euo pipefail
cd "$(dirname "$0")/.."
tests=0
targets=(cmr)
prefix=""
for arg in "$@"; do
  case "$arg" in
    --tests) tests=1 ;;
    --python) targets+=(_cmr) ;;
    -*)
      echo "tools/build.sh: unknown option $arg (usage: tools/build.sh [--tests] [--python] [PREFIX])" >&2
      exit 2
      ;;
    *) prefix=$arg ;;
  esac
done
# Under CI (.ci/run exports CI=true) a new compiler warning fails the build.
werror=OFF
if [[ -n "${CI:-}" ]]; then werror=ON; fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMR_WERROR="$werror" >/dev/null
if ((tests)); then
  cmake --build build -j"$(nproc)"
else
  cmake --build build -j"$(nproc)" --target "${targets[@]}"
fi
if [[ -n "$prefix" ]]; then
  cmake --install build --prefix "$prefix"
fi
