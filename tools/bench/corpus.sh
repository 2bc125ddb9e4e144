#!/usr/bin/env bash
# Corpus benchmark of `cmr report` (docs/qa-corpus.md): the Latin glyphs
# (U+0021-U+017F) of every font of Debian's fonts-noto-core (TrueType) and
# fonts-texgyre (CFF), judged by the type gates, without thumbnails and with
# the pages' thumbnails; wall time, glyphs per second and peak memory
# (/usr/bin/time -v), and per font the share of glyphs with findings
# (tools/bench/corpus_stats.py, which also draws docs/qa-corpus.svg).
#
# Usage: tools/bench/corpus.sh [CMR] [OUT]   (CMR default build/tools/cmr, OUT /tmp/cmr-corpus)
# Environment: SUBSET=N  only the first N fonts of each family (sorted), for a quick run;
#              PAGES=0   skip the run with thumbnails (drawn, no handle-move search: --no-fixes);
#              FIXES=1   also run with the move search (slow: each candidate re-reports its contour).
set -euo pipefail
cmr=${1:-build/tools/cmr}
out=${2:-/tmp/cmr-corpus}
here=$(cd "$(dirname "$0")" && pwd)

# The corpus: Debian packages, installed when missing (root or sudo).
missing=()
for p in fonts-noto-core fonts-texgyre time; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=(); ((EUID == 0)) || sudo=(sudo)
  echo "corpus: installing ${missing[*]}"
  DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
noto=/usr/share/fonts/truetype/noto
texgyre=/usr/share/texmf/fonts/opentype/public/tex-gyre

rm -rf "$out"
mkdir -p "$out/fonts"
# The fonts, as links in one folder (a SUBSET of each family when asked).
n=${SUBSET:-100000}
for f in $(ls "$noto"/*.ttf | sort | head -n "$n") $(ls "$texgyre"/*.otf | sort | head -n "$n"); do
  ln -s "$f" "$out/fonts/$(basename "$f")"
done
fonts=$(ls "$out/fonts" | wc -l)
gates=curvature-extrema-at-nodes:runs,curvature-extrema-at-nodes,g2-at-smooth-nodes
echo "corpus: $fonts fonts; cmr $("$cmr" --version 2>/dev/null || echo '?'); $(nproc) cores: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"

run() {  # NAME ARGS...
  local name=$1; shift
  set +e
  /usr/bin/time -v -o "$out/$name.time" "$cmr" report "$out/fonts" --glyphs U+0021-U+017F --require "$gates" \
      --quiet --out "$out/$name" --junit "$out/$name.junit.xml" --sarif "$out/$name.sarif" "$@" >"$out/$name.log" 2>"$out/$name.err"
  local rc=$?
  set -e
  if ((rc != 0 && rc != 1)); then echo "corpus: $name failed ($rc)"; cat "$out/$name.err"; exit 1; fi
  local wall rss
  wall=$(grep 'Elapsed (wall clock)' "$out/$name.time" | awk '{print $NF}')
  rss=$(grep 'Maximum resident set size' "$out/$name.time" | awk '{print $NF}')
  echo "corpus: $name: $(cat "$out/$name.log")"
  echo "corpus: $name: wall $wall, peak memory $((rss / 1024)) MiB, pages $(du -sh --exclude=report.json "$out/$name" | cut -f1), report.json $(du -sh "$out/$name/report.json" | cut -f1)"
}
run nothumb --no-thumbnails
if [[ ${PAGES:-1} != 0 ]]; then run pages --no-fixes; fi
if [[ ${FIXES:-0} != 0 ]]; then run fixes; fi
python3 "$here/corpus_stats.py" "$out/nothumb.junit.xml" "$out/nothumb.sarif" "$out/stats.md" "$out/qa-corpus.svg"
echo "corpus: per-font table $out/stats.md, plot $out/qa-corpus.svg"
