#!/bin/sh
# cobra run with a task chart stuck in an endless loop (test/apps/stuck.lua), on the lockstep clock
# and on the wall clock:
#  - with no Lua budget, SIGTERM must end the run through its clean path (the Lua hook notices the
#    interrupt, the run reports it and exits with a status), long before a generous bound;
#  - with the Supervisor's default budget, the run ends by itself: the Supervisor in Exception,
#    naming the chart's file:line.
# Usage: run_interrupt_test.sh COBRA ENTRY_FILE
set -u
cobra="$1"
app="$2"
out=$(mktemp)
budgeted=$(mktemp -d)
trap 'rm -rf "$out" "$budgeted"' EXIT
# The same application with the budget left at its default.
sed '/lua_budget = 0/d' "$app" >"$budgeted/stuck.lua"
cp "$(dirname "$app")/stuck_task.lua" "$budgeted/"

# Waits until $1 has ended (at most 10 s), then sets $status to its exit status.
await() {
  i=0
  while kill -0 "$1" 2>/dev/null; do
    sleep 0.05
    i=$((i + 1))
    if [ $i -gt 200 ]; then echo "$mode: still running after 10 s"; cat "$out"; kill -9 "$1"; exit 1; fi
  done
  wait "$1"
  status=$?
  if [ $status -ge 128 ]; then echo "$mode: ended by a signal (status $status)"; cat "$out"; exit 1; fi
}

for mode in lockstep realtime thread-per-component; do
  flag=""
  [ "$mode" = realtime ] && flag="--realtime"
  [ "$mode" = thread-per-component ] && flag="--realtime --thread-per-component"
  : >"$out"  # emptied before the start: the previous run's line must not be taken for this one's
  "$cobra" run "$app" $flag --time-limit 1000 >"$out" 2>&1 &
  pid=$!
  i=0
  while ! grep -q "stuck: looping" "$out"; do
    sleep 0.05
    i=$((i + 1))
    if [ $i -gt 600 ]; then echo "$mode: the chart never got stuck"; cat "$out"; kill -9 $pid; exit 1; fi
  done
  kill -TERM $pid
  await $pid
  if ! grep -q "stuck_task.lua:6: interrupted (Ctrl-C or SIGTERM) while component 'TaskSup' ran" "$out"; then
    echo "$mode: the chart's loop was not interrupted at its line"; cat "$out"; exit 1
  fi
  echo "$mode, SIGTERM: status $status"

  : >"$out"
  "$cobra" run "$budgeted/stuck.lua" $flag --time-limit 1000 >"$out" 2>&1 &
  await $!
  if ! grep -q "cobra run: component error: component 'TaskSup' is in Exception: .*stuck_task.lua:6: component 'TaskSup' ran past its budget of 0.005 s of CPU time" "$out"; then
    echo "$mode, budget: the run did not end with the Supervisor's Exception at the loop's line"; cat "$out"; exit 1
  fi
  echo "$mode, budget: status $status"
done
echo "cobra run ends cleanly on SIGTERM with a chart stuck in a loop, and by itself with a budget"
