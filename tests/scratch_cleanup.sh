#!/bin/sh
# The scratch fixture's cleanup (tests/CMakeLists.txt): every test ran with
# TMPDIR=$1. A process still running with that in its environment 5 s after
# the last test ended was left by a test (an Xvfb, a server): name it, stop it
# and fail. (xvfb-run signals its Xvfb and returns without waiting for it to
# exit, so a server may still be going for a moment after its test passed.)
# Then remove $1, with whatever files the tests left in it.
dir=$1
left=""
for env in /proc/[0-9]*/environ; do
  pid=${env#/proc/}
  pid=${pid%/environ}
  if tr '\0' '\n' 2>/dev/null <"$env" | grep -qxF "TMPDIR=$dir"; then
    left="$left $pid"
  fi
done
# Up to 5 s for the ones already on their way out.
tries=0
while [ -n "$left" ] && [ $tries -lt 50 ]; do
  still=""
  for pid in $left; do
    [ -d /proc/"$pid" ] && [ "$(cut -d' ' -f3 /proc/"$pid"/stat 2>/dev/null)" != Z ] && still="$still $pid"
  done
  left=$still
  [ -n "$left" ] && sleep 0.1
  tries=$((tries + 1))
done
status=0
for pid in $left; do
  echo "scratch_cleanup: a test left process $pid running: $(tr '\0' ' ' </proc/"$pid"/cmdline 2>/dev/null)"
  kill "$pid" 2>/dev/null
  status=1
done
files=$(find "$dir" -mindepth 1 2>/dev/null | wc -l)
rm -rf "$dir"
echo "scratch_cleanup: removed $dir ($files entries the tests left there)"
exit $status
