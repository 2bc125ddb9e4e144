#!/bin/bash
# The GPU check of issue 39, for a machine lent by the device tool (NVIDIA
# driver, no project libraries): unpacks .gpu/bundle.tar.xz (made here by
# tools/bench/gpu_bundle.sh), names the device, runs every Vulkan test
# program on it, then bench_region: every cell at 512 and 1024, the Vulkan
# backend with each share of the work up to 2048, (when packed) an older
# bench_region's Vulkan column on the same cells, the cubic Bezier's whole
# region at 2048 and the one-shot `cmr region` times. Writes each log to $OUT
# as it goes, so a run cut short still returns what it measured.
# Run from the repository root: OUT=/tmp/gpu tools/bench/gpu_run.sh
set -u
root=$(pwd)
out=${OUT:-/tmp/gpu_out}
mkdir -p "$out"
tar -xJf .gpu/bundle.tar.xz
# The NVIDIA Vulkan driver needs libglvnd (libGLdispatch), which a bare
# machine may lack: Debian's .debs in .gl/ (the device tool's notes say how
# to fetch them), unpacked over /.
if ls .gl/*.deb >/dev/null 2>&1; then
  for f in .gl/*.deb; do dpkg -x "$f" /; done
  ldconfig
fi
# The tests read examples/ through the source path they were built with.
built_in=$(cat .gpu/source_dir)
if [ ! -e "$built_in" ]; then mkdir -p "$(dirname "$built_in")" && ln -s "$root" "$built_in"; fi
export LD_LIBRARY_PATH=$root/.gpu/lib
if [ -z "${VK_DRIVER_FILES:-}" ]; then
  for f in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json /usr/share/vulkan/icd.d/nvidia_icd.json \
    /etc/vulkan/icd.d/nvidia_icd.json; do
    if [ -e "$f" ]; then export VK_DRIVER_FILES=$f; break; fi
  done
fi
{
  date -u
  nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv 2>&1
  nproc
  grep -m1 'model name' /proc/cpuinfo
  uname -r
  echo "VK_DRIVER_FILES=${VK_DRIVER_FILES:-}"
} >"$out/device.txt" 2>&1
step() { echo "== $*" >>"$out/run.log"; }
step tests
for t in build/tests/vk/*_test; do
  if [ "$(basename "$t")" = cmr_vk_no_device_test ]; then
    env -u VK_DRIVER_FILES timeout 100 "$t" --gtest_brief=1 >>"$out/tests.log" 2>&1
  else
    timeout 100 "$t" --gtest_brief=1 >>"$out/tests.log" 2>&1
  fi
  echo "$(basename "$t") rc $?" | tee -a "$out/run.log" >>"$out/tests.log"
done
step bench
export PATH=$root/build/tools:$PATH
b=build/tools/bench/bench_region
timeout 200 $b 3 "" all 512,1024 >"$out/bench_all.txt" 2>&1; echo "bench all rc $?" >>"$out/run.log"
# The Vulkan backend alone with each share of the work (vk::DeviceShare),
# and the whole share as an fp32-then-fp64 cascade, up to 2048.
for mode in vk-culled vk-whole vk-cascade; do
  timeout 45 $b 10 "10 " $mode 512,1024,2048 >"$out/bench_$mode.txt" 2>&1; echo "bench $mode rc $?" >>"$out/run.log"
done
if [ -x .gpu/bench_region_old ]; then
  for x in .gpu/bench_region_old $b; do
    echo "# $x" >>"$out/bench_ab.txt"
    timeout 45 $x 10 "10 " vk >>"$out/bench_ab.txt" 2>&1
  done
  echo "bench ab done" >>"$out/run.log"
fi
timeout 40 $b 3 "cubic Bezier, P1 whole region 10" all 2048 >"$out/bench_2048.txt" 2>&1
echo "bench 2048 rc $?" >>"$out/run.log"
timeout 30 tools/bench/oneshot_region.sh 10 build/tools/cmr >"$out/oneshot.txt" 2>&1
echo "oneshot rc $?" >>"$out/run.log"
