#!/bin/bash
# Packs what tools/bench/gpu_run.sh needs on a GPU machine that has a Vulkan
# driver but none of the project's libraries: the Vulkan test programs,
# bench_region and cmr from build/ (stripped), and every shared library they
# load beyond glibc and libstdc++ (OpenCASCADE, cairo, gmp, the Vulkan
# loader, ...), as .gpu/bundle.tar.xz. Run from the repository root after
# `tools/build.sh --tests`. EXTRA=.gpu/bench_region_old packs another
# build's bench_region too, for an A/B on the same GPU.
set -euo pipefail
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
programs=(build/tools/cmr build/tools/bench/bench_region build/tests/vk/*_test ${EXTRA:-})
mkdir -p "$stage/.gpu/lib"
for p in "${programs[@]}"; do
  mkdir -p "$stage/$(dirname "$p")"
  strip -o "$stage/$p" "$p"
done
ldd "${programs[@]}" 2>/dev/null | awk '/=> \// {print $3}' | sort -u |
  grep -v -E '/(libc|libm|libdl|libpthread|librt|libstdc\+\+|libgcc_s|ld-linux[^/]*)\.so' |
  while read -r lib; do cp -L "$lib" "$stage/.gpu/lib/"; done
pwd >"$stage/.gpu/source_dir"  # the tests read examples/ through this path
mkdir -p .gpu
tar -C "$stage" -cJf .gpu/bundle.tar.xz .
ls -l .gpu/bundle.tar.xz
