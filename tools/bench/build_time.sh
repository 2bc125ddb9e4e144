#!/usr/bin/env bash
# Times the README's two build commands in a fresh clone of HEAD (packages
# already installed, tools/setup.sh not run): first `tools/build.sh` (cmr
# only), then `tools/build.sh --tests` (the rest), and counts their build
# steps. Cold by default (CCACHE_DISABLE=1); --ccache keeps ccache on (then
# the times are those of a warm cache, not a newcomer's). Prints the load
# average (/proc/loadavg: 1, 5 and 15 minutes) before and after each command:
# a time is that of an idle machine only where the load stays near 0.
#   bash tools/bench/build_time.sh [--ccache]
set -euo pipefail
cd "$(dirname "$0")/../.."
dir=$(mktemp -d /tmp/cmr_build_time.XXXXXX)
trap 'rm -rf "$dir"' EXIT
git clone -q --no-hardlinks . "$dir/cmr"
cd "$dir/cmr"
if [[ "${1:-}" == "--ccache" ]]; then
  export CCACHE_BASEDIR="$dir/cmr"
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  echo "build_time: ccache on (warm-cache times)"
else
  export CCACHE_DISABLE=1
  launcher=()
fi
# tools/build.sh configures the same way; configuring first adds the launcher.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" >/dev/null
echo "build_time: $(nproc) cores, $(ninja -C build -t commands tools/cmr | wc -l) steps for cmr," \
  "$(ninja -C build -t commands | wc -l) for everything"
load() { echo "build_time: load $(cut -d' ' -f1-3 /proc/loadavg) $1"; }
load "before tools/build.sh"
t0=$(date +%s)
bash tools/build.sh >/dev/null
t1=$(date +%s)
load "after it ($((t1 - t0)) s)"
bash tools/build.sh --tests >/dev/null
t2=$(date +%s)
load "after tools/build.sh --tests"
echo "build_time: tools/build.sh $((t1 - t0)) s; then tools/build.sh --tests $((t2 - t1)) s more"
