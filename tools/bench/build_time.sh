#!/usr/bin/env bash
# Times the README's two commands in a fresh clone of HEAD, with the
# packages already installed: first the main command exactly as the README
# gives it (`bash tools/setup.sh && bash tools/build.sh && build/tools/cmr
# figures`: configure, build cmr only, the paper's figures), then
# `tools/build.sh --tests` (the rest of the build; ctest is not run), and
# counts their build steps. Cold by default (CCACHE_DISABLE=1); --ccache
# keeps ccache on (the build folder is configured with it first, so the
# times are those of a warm cache, not a newcomer's). Prints the load
# average (/proc/loadavg: 1, 5 and 15 minutes) before and after each
# command: a time is that of an idle machine only where the load stays near 0
# (the build's own jobs raise it to about the number of cores).
# --main stops after the main command.
#   bash tools/bench/build_time.sh [--ccache] [--main]
set -euo pipefail
cd "$(dirname "$0")/../.."
dir=$(mktemp -d /tmp/cmr_build_time.XXXXXX)
trap 'rm -rf "$dir"' EXIT
git clone -q --no-hardlinks . "$dir/cmr"
cd "$dir/cmr"
ccache=0 main_only=0
for arg in "$@"; do
  case "$arg" in
    --ccache) ccache=1 ;;
    --main) main_only=1 ;;
    *) echo "build_time.sh: unknown option $arg (usage: build_time.sh [--ccache] [--main])" >&2; exit 2 ;;
  esac
done
if ((ccache)); then
  export CCACHE_BASEDIR="$dir/cmr"
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache >/dev/null
  echo "build_time: ccache on (warm-cache times)"
else
  export CCACHE_DISABLE=1
fi
load() { echo "build_time: load $(cut -d' ' -f1-3 /proc/loadavg) $1"; }
load "before the main command"
t0=$(date +%s)
bash tools/setup.sh >/dev/null && bash tools/build.sh >/dev/null && build/tools/cmr figures >/dev/null
t1=$(date +%s)
load "after it ($((t1 - t0)) s)"
echo "build_time: $(nproc) cores, $(ninja -C build -t commands tools/cmr | wc -l) steps for cmr," \
  "$(ninja -C build -t commands | wc -l) for everything"
if ((main_only)); then
  echo "build_time: main command (setup, build cmr, figures) $((t1 - t0)) s"
  exit 0
fi
bash tools/build.sh --tests >/dev/null
t2=$(date +%s)
load "after tools/build.sh --tests"
echo "build_time: main command (setup, build cmr, figures) $((t1 - t0)) s; then tools/build.sh --tests $((t2 - t1)) s more"
