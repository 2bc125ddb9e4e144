#!/usr/bin/env bash
# Do two cmr binaries write the same report.json, JUnit and SARIF?
# Usage: tools/bench/same_outputs.sh OLD_CMR NEW_CMR REPORT_ARGS...
# Runs `cmr report REPORT_ARGS --quiet --out D/o --junit D/j.xml --sarif D/s.sarif`
# with each binary and compares the three files byte for byte, after blanking
# what is measured, not computed: JUnit's timestamp and time attributes and
# report.json's "seconds" (a certified fix's search time). Exit 0: the same.
set -euo pipefail
old=$1 new=$2; shift 2
d=$(mktemp -d)
trap 'rm -rf "$d"' EXIT
for b in old new; do
  bin=$old; [[ $b == new ]] && bin=$new
  set +e
  "$bin" report "$@" --quiet --out "$d/$b/o" --junit "$d/$b/j.xml" --sarif "$d/$b/s.sarif" >/dev/null 2>"$d/$b.err"
  echo "$b: exit $?"
  set -e
  sed -E -i 's/ (timestamp|time)="[^"]*"/ \1=""/g' "$d/$b/j.xml"
  sed -E -i 's/"seconds": ?[0-9.e+-]+/"seconds":0/g' "$d/$b/o/report.json"
done
rc=0
for f in o/report.json j.xml s.sarif; do
  if cmp -s "$d/old/$f" "$d/new/$f"; then echo "same: $f ($(stat -c %s "$d/new/$f") bytes)"; else echo "DIFFERENT: $f"; rc=1; fi
done
exit $rc
