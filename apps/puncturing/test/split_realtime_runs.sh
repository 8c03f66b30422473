#!/bin/sh
# The puncturing task split over two hosts on the wall clock, N times in a row, the way a user
# starts it (README.md, "Two hosts"): `cobra run apps/puncturing --host needle --realtime` and
# `--host probe --realtime` on test/scenarios/one_vertical_needle, then one line per run and host:
# exit status, outcome, run time, wall time, placement, worst tracking, deadline misses. Not a
# ctest (minutes per run); it re-measures the figures README.md quotes for wall-clock split runs.
#   split_realtime_runs.sh COBRA DDS_PACKAGE_DIR [RUNS [WORK_FOLDER [DDS_DOMAIN]]]
# Exits 0 when every run completed on both hosts (exit status 0), 1 otherwise.
set -u
cobra=$1
export COBRA_PACKAGE_PATH=$2
runs=${3:-10}
work=${4:-/tmp/cobra_split_realtime_runs}
export COBRA_DDS_DOMAIN=${5:-232}
app=$(cd "$(dirname "$0")/.." && pwd)
scenario=$app/test/scenarios/one_vertical_needle
rm -rf "$work" && mkdir -p "$work"
failed=0
completed=0
i=1
while [ "$i" -le "$runs" ]; do
  dir=$work/run$i
  mkdir -p "$dir"
  start=$(date +%s.%N)
  timeout 600 "$cobra" run "$app" --scenario "$scenario" --host needle --realtime --report "$dir/needle" \
    >"$dir/needle.log" 2>&1 &
  needle=$!
  timeout 600 "$cobra" run "$app" --scenario "$scenario" --host probe --realtime --report "$dir/probe" \
    >"$dir/probe.log" 2>&1
  probe_status=$?
  wait $needle
  needle_status=$?
  wall=$(awk "BEGIN { print $(date +%s.%N) - $start }")
  for host in needle probe; do
    eval status=\$${host}_status
    log=$dir/$host.log
    ended=$(sed -n 's/^ *\([0-9.]*\) s  run ended: \([^:;]*\).*/\2 at \1 s/p' "$log" | tail -1)
    placed=$(sed -n 's/^placement error per needle: //p' "$log" | tail -1)
    tracking=$(sed -n 's/^\(I-SUR needle\|UR5 probe\): worst tracking \([0-9.]* mm\) at [0-9.]* s, \([0-9.]* deg\).*/\2, \3/p' "$log")
    misses=$(sed -n 's/^executor: .*; \([0-9]* deadline misses (longest run [0-9]*)\).*/\1/p' "$log")
    lost=$(grep -c "PEER LOST" "$log")
    printf 'run %2d %-6s exit %s: %s; wall %.1f s (both); placement %s; worst tracking %s; %s; peer lost lines %s\n' \
      "$i" "$host" "$status" "$ended" "$wall" "${placed:--}" "${tracking:--}" "${misses:--}" "$lost"
    if [ "$status" != 0 ]; then failed=1; fi
  done
  if [ "$needle_status" = 0 ] && [ "$probe_status" = 0 ]; then completed=$((completed + 1)); fi
  i=$((i + 1))
done
echo "$completed of $runs runs completed on both hosts"
exit $failed
