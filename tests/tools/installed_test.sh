#!/usr/bin/env bash
# An installed cmr stands alone: `cmake --install` into a fresh prefix copies
# bin/cmr and nothing else but, in a build with OpenCASCADE, the STEP
# importer's plugin (lib/cmr/cmr_step_plugin.so, docs/space.md), neither of
# which names the source tree or the example files, and, run from an empty
# folder with the source tree moved out of reach, it does every command the
# README's tour shows (figures, segments, analyze, region of a point and of
# a weight, fix, report, import of a font, of an SVG and of a STEP model,
# knots, sweep, kcurve, and the editor under Xvfb).
#
# "Moved out of reach": the commands run in a private mount namespace where
# an empty tmpfs is mounted over SOURCE_DIR (unshare -m, as root), so nothing
# under it can be read; every file they are given was copied out before.
# Where mount namespaces are not allowed (an unprivileged container), strace
# records every path the commands open instead, and the test fails if one
# lies under SOURCE_DIR. With neither available the test is skipped (exit 77)
# and says why.
# Usage: installed_test.sh CMAKE BUILD_DIR SOURCE_DIR
set -euo pipefail
cmake_cmd=$1 build=$2 source=$(cd "$3" && pwd -P)
# The scratch folder must lie outside SOURCE_DIR, which gets hidden: ctest's
# TMPDIR (build/test-scratch) may be under it, so then /tmp is used.
base=${TMPDIR:-/tmp}
case "$(cd "$base" && pwd -P)/" in "$source"/*) base=/tmp ;; esac
tmp=$(mktemp -d -p "$base")
trap 'rm -rf "$tmp"' EXIT
fail() { echo "installed_test: $*" >&2; exit 1; }

"$cmake_cmd" --install "$build" --prefix "$tmp/prefix" >/dev/null
files=$(cd "$tmp/prefix" && find . -type f | sort)
step_model=$build/tools/cmr_step_model  # built where OpenCASCADE was found (step/CMakeLists.txt)
# bin/cmr, and the STEP plugin under the library folder (lib/cmr/, or
# lib/<multiarch>/cmr/ for a /usr prefix) where this build reads STEP.
others=$(grep -v -x './bin/cmr' <<<"$files" || true)
[[ $files == *./bin/cmr* ]] || fail "the install holds no bin/cmr: $files"
if [[ -x $step_model ]]; then
  [[ $others =~ ^\./lib(/[^/]+)?/cmr/cmr_step_plugin\.so$ ]] ||
    fail "the install holds more than bin/cmr and the STEP plugin, or no plugin: $files"
else
  [[ -z $others ]] || fail "the install holds more than bin/cmr: $files"
fi
for f in $files; do
  n=$(grep -c -F "$source" "$tmp/prefix/$f" || true)
  [[ $n == 0 ]] || fail "$f names the source tree $source ($n times)"
  n=$(grep -c -F "examples/figures" "$tmp/prefix/$f" || true)
  [[ $n == 0 ]] || fail "$f names examples/figures ($n times): it would read the source tree"
done

# Everything the commands read travels by path, copied out of the tree.
data=$tmp/data
mkdir "$tmp/empty" "$data"
cp "$source/examples/figures/fig8.json" "$data/fig8.json"
cp "$source/examples/uniform.json" "$data/uniform.json"
cp "$source/examples/kcurve/points.json" "$data/points.json"
cp "$source/examples/report/arch.json" "$data/arch.json"
cat >"$data/drop.svg" <<'SVG'
<svg xmlns="http://www.w3.org/2000/svg"><path d="M 0 0 C 10 0 20 10 20 20 S 10 40 0 40"/></svg>
SVG
printf 'select 3\ndrag 3 1.2 -3.5 4\n' >"$data/edit.txt"
step_import=":"  # the STEP model's import, where this build reads STEP
if [[ -x $step_model ]]; then
  "$step_model" "$data/model.step" >/dev/null
  step_import="\"\$cmr\" import \"$data/model.step\" --out \"\$o/step_curves\" >\"\$o/import_step.txt\""
fi
: >"$tmp/xauthority"  # xvfb-run -f: its own X authority file, so no folder of its own to fail to remove
font=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf  # fonts-dejavu-core (tools/setup.sh)

# The commands, as the README's tour shows them, into $tmp/out.
cat >"$tmp/commands.sh" <<EOF
set -euo pipefail
cd "$tmp/empty"
cmr=$tmp/prefix/bin/cmr
o=$tmp/out
mkdir -p "\$o"
step() { echo "\$*" >"\$o/step"; }
step figures;  "\$cmr" figures --out "\$o/figs" --size 64 --backend cpu >"\$o/figures.txt"
step segments; "\$cmr" segments "$data/fig8.json" >"\$o/segments.txt"
step analyze;  "\$cmr" analyze "$data/fig8.json" >"\$o/analyze.json"
step region;   "\$cmr" region "$data/fig8.json" --point 3 --size 32x32 --backend cpu --png "\$o/r.png" --labels "\$o/r.pgm" >"\$o/region.json"
step weight;   "\$cmr" region "$data/fig8.json" --weight 2 --from 0.2 --to 3 --plot "\$o/w.png" >"\$o/weight.json"
step fix;      "\$cmr" fix "$data/fig8.json" --require cmrwi --out "\$o/fixed.json" --png "\$o/fix.png" >"\$o/fix.json"
step report;   "\$cmr" report "$data/arch.json" --out "\$o/qa" --no-thumbnails >"\$o/report.txt"
step import-font; "\$cmr" import "$font" --glyphs O,a --out "\$o/glyphs" >"\$o/import.txt"
step import-svg;  "\$cmr" import "$data/drop.svg" --out "\$o/svg" >"\$o/import_svg.txt"
step import-step; $step_import
step knots;    "\$cmr" knots "$data/uniform.json" insert 3.5 >"\$o/knots.json"
step sweep;    "\$cmr" sweep "$data/fig8.json" --point 3 --knot 3 --from 2.1 --to 3.9 --steps 3 --size 32x32 --backend cpu --out-dir "\$o/sweep" >"\$o/sweep.txt"
step kcurve;   "\$cmr" kcurve "$data/points.json" --cubic --out "\$o/cubic.json" >"\$o/kcurve.txt"
step edit;     xvfb-run -a -f "$tmp/xauthority" "\$cmr" edit "$data/fig8.json" --script "$data/edit.txt" --screenshot "\$o/edit.png" >"\$o/edit.txt"
step done
EOF

# A sanitizer build's runtime settings (tools/sanitize.sh) pass through; its
# suppression file lives in the source tree, which is hidden: a copy.
sanitizer_env=()
for v in ASAN_OPTIONS UBSAN_OPTIONS; do
  [[ -n ${!v:-} ]] && sanitizer_env+=("$v=${!v}")
done
if [[ -n ${LSAN_OPTIONS:-} ]]; then
  supp=""  # the suppressions= option (not print_suppressions=)
  IFS=: read -ra lsan_parts <<<"$LSAN_OPTIONS"
  for part in "${lsan_parts[@]}"; do
    if [[ $part == suppressions=* ]]; then supp=${part#suppressions=}; fi
  done
  if [[ -n $supp && -f $supp ]]; then
    cp "$supp" "$tmp/lsan.supp"
    sanitizer_env+=("LSAN_OPTIONS=${LSAN_OPTIONS//"$supp"/$tmp/lsan.supp}")
  else
    sanitizer_env+=("LSAN_OPTIONS=$LSAN_OPTIONS")
  fi
fi

# A bare environment: no source path, no build path; Vulkan's driver file
# (lavapipe, a system file) for the editor.
run_bare() {
  env -i PATH=/usr/bin:/bin HOME="$tmp/empty" \
    VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json "${sanitizer_env[@]}" "$@"
}
if unshare -m true 2>/dev/null; then
  how="with $source hidden under an empty tmpfs"
  run_bare unshare -m bash -c 'mount -t tmpfs none "$1" && [[ -z $(ls -A "$1") ]] && exec bash "$2"' _ \
    "$source" "$tmp/commands.sh" 2>"$tmp/stderr" ||
    fail "step '$(cat "$tmp/out/step" 2>/dev/null)' failed $how: $(tail -3 "$tmp/stderr")"
elif command -v strace >/dev/null && strace -f -o /dev/null true 2>/dev/null; then
  how="under strace (no mount namespace here)"
  run_bare strace -f -qq -e trace=%file -o "$tmp/trace" bash "$tmp/commands.sh" 2>"$tmp/stderr" ||
    fail "step '$(cat "$tmp/out/step" 2>/dev/null)' failed $how: $(tail -3 "$tmp/stderr")"
  # (getcwd reports where ctest started the script, before `cd`: not a read.)
  if grep -F "\"$source" "$tmp/trace" | grep -v -e "getcwd(" -e "\"$tmp" >"$tmp/touched"; then
    fail "a command opened a path under the source tree: $(head -3 "$tmp/touched")"
  fi
else
  echo "installed_test: skipped: neither a mount namespace (unshare -m) nor strace is available here"
  exit 77
fi

o=$tmp/out
[[ $(cat "$o/step") == done ]] || fail "the commands stopped at $(cat "$o/step")"
[[ -s $o/figs/index.html ]] || fail "cmr figures wrote no index.html"
ls "$o/figs"/*.png >/dev/null 2>&1 || fail "cmr figures wrote no PNG"
grep -q '"cmrwi"' "$o/analyze.json" || fail "cmr analyze printed no verdict"
grep -q '"points"' "$o/region.json" || fail "cmr region printed no summary"
[[ -s $o/r.png && -s $o/r.pgm && -s $o/w.png ]] || fail "cmr region wrote no picture, label map or weight plot"
[[ -s $o/fixed.json && -s $o/fix.png ]] || fail "cmr fix wrote no fixed spline or picture"
[[ -s $o/qa/index.html && -s $o/qa/report.json ]] || fail "cmr report wrote no report"
ls "$o/glyphs"/*.json >/dev/null 2>&1 || fail "cmr import wrote no glyph contour"
ls "$o/svg"/*.json >/dev/null 2>&1 || fail "cmr import wrote no SVG path"
if [[ -x $step_model ]]; then
  ls "$o/step_curves"/*.json >/dev/null 2>&1 || fail "cmr import wrote no STEP curve"
fi
grep -q '"knots"' "$o/knots.json" || fail "cmr knots printed no spline"
ls "$o/sweep"/*.png >/dev/null 2>&1 || fail "cmr sweep wrote no frame"
[[ -s $o/cubic.json ]] || fail "cmr kcurve wrote no spline"
[[ -s $o/edit.png ]] || fail "cmr edit wrote no screenshot"
[[ -z $(ls -A "$tmp/empty") ]] || fail "a command wrote into the working folder: $(ls -A "$tmp/empty")"
echo "installed cmr stands alone ($how): $(( $(grep -c '^step ' "$tmp/commands.sh") - 1 )) commands"
