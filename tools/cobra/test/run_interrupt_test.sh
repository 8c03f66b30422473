#!/bin/sh
# cobra run with a task chart stuck in an endless loop and no Lua budget (test/apps/stuck.lua):
# SIGTERM must end the run through its clean path (the Lua hook notices the interrupt, the run
# reports it and exits with a status), long before a generous bound, on the lockstep clock and
# on the wall clock. Usage: run_interrupt_test.sh COBRA APP
set -u
cobra="$1"
app="$2"
out=$(mktemp)
trap 'rm -f "$out"' EXIT
for mode in lockstep realtime; do
  flag=""
  [ "$mode" = realtime ] && flag="--realtime"
  : >"$out"  # emptied before the start: the previous mode's line must not be taken for this one's
  "$cobra" run "$app" $flag --time-limit 1000 >"$out" 2>&1 &
  pid=$!
  i=0
  while ! grep -q "stuck: looping" "$out"; do
    sleep 0.05
    i=$((i + 1))
    if [ $i -gt 600 ]; then echo "$mode: the chart never got stuck"; cat "$out"; kill -9 $pid; exit 1; fi
  done
  kill -TERM $pid
  i=0
  while kill -0 $pid 2>/dev/null; do
    sleep 0.05
    i=$((i + 1))
    if [ $i -gt 200 ]; then echo "$mode: still running 10 s after SIGTERM"; cat "$out"; kill -9 $pid; exit 1; fi
  done
  wait $pid
  status=$?
  if [ $status -ge 128 ]; then echo "$mode: ended by a signal (status $status)"; cat "$out"; exit 1; fi
  if ! grep -q "interrupted" "$out"; then echo "$mode: the run did not say it was interrupted"; cat "$out"; exit 1; fi
  echo "$mode: status $status"
  grep "cobra run:" "$out"
done
echo "cobra run ends cleanly on SIGTERM with a chart stuck in a loop"
