#!/usr/bin/env bash
# Installs every Debian package cmr needs to build, test and run.
# Idempotent: packages already installed are skipped, and apt is not touched
# at all when nothing is missing. Run as root on Debian 12 (or with sudo).
# clang + libclang-rt-14-dev (libFuzzer, ASan, UBSan runtimes; only a
# Recommends of clang, so named here) are for fuzz/run.sh.
# libocct-data-exchange-dev (OpenCASCADE's STEP reader; it pulls in the other
# libocct-*-dev packages) and libtbb-dev (a library OCCT's CMake targets name)
# are for the STEP importer (step/); without them cmr builds without it.
# python3-fonttools, python3-ufolib2 and fontmake make and build the test
# UFOs of tests/report/ufo_source_test.py (tools/make_test_ufo.py).
# pybind11-dev and python3-dev build the Python module (python/, import cmr);
# python3-numpy, python3-pytest and python3-fonttools run it and its tests
# (tests/python); python3-matplotlib is for cmr.plot and examples/python.
# python3-yaml: tests/docs/ci_workflow.py reads examples/ci/cmr-qa.yml.
# time: /usr/bin/time, which tools/bench/scale.sh (quoted in the README) runs.
# Progress: apt's output is condensed to a line per 25 packages downloaded
# and per 25 set up (a first install is several hundred packages, minutes).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config python3 python3-yaml
  libglm-dev nlohmann-json3-dev libcli11-dev libgmp-dev
  libcairo2-dev libpng-dev libxml2-dev
  libgtest-dev libgmock-dev
  libvulkan-dev mesa-vulkan-drivers glslang-tools
  chromium fonts-dejavu-core
  libglfw3-dev libimgui-dev xvfb xauth libxext-dev
  libopenmesh-dev
  libocct-data-exchange-dev libtbb-dev
  libfreetype-dev fonts-urw-base35
  libpugixml-dev
  fonts-noto-core fonts-texgyre fonts-inter-variable
  strace time valgrind
  clang libclang-rt-14-dev
  pybind11-dev python3-dev python3-numpy python3-pytest python3-fonttools python3-matplotlib
  python3-ufolib2 fontmake
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

sudo=()
if ((EUID != 0)); then sudo=(sudo); fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
echo "setup: apt-get update"
"${sudo[@]}" apt-get update -qq
echo "setup: apt-get install (with their dependencies; this takes minutes on a first install)"
"${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}" | awk '
  / newly installed/ { total = $3; print "setup: " total " packages to download and set up"; fflush() }
  /^Get:/ { got++; if (got % 25 == 0 || got == total) { print "setup: downloaded " got " of " total; fflush() } }
  /^Setting up / { set++; if (set % 25 == 0 || set == total) { print "setup: set up " set " of " total; fflush() } }'
echo "setup: done"
