#!/bin/sh
# `cobra run apps/puncturing --host needle` and `--host probe`, the way a user starts the split
# task (README.md, "Two hosts"): each process loads its half (the run table's entries of the
# other host dropped, its studio robots included), each says its peer joined (they meet over
# DDS) and both stop at the time limit, 1 s simulated.
#   run_two_hosts_test.sh COBRA APP_FOLDER WORK_FOLDER DDS_DOMAIN
set -u
cobra=$1 app=$2 work=$3
export COBRA_DDS_DOMAIN=$4
rm -rf "$work" && mkdir -p "$work"
timeout 600 "$cobra" run "$app" --host needle --time-limit 1 --report "$work/needle" >"$work/needle.log" 2>&1 &
needle=$!
timeout 600 "$cobra" run "$app" --host probe --time-limit 1 --report "$work/probe" >"$work/probe.log" 2>&1
probe_status=$?
wait $needle
needle_status=$?
failed=0
for host in needle probe; do
  eval status=\$${host}_status
  if [ "$status" != 1 ]; then echo "host $host exited with $status, expected 1 (the time limit)"; failed=1; fi
  if ! grep -q "cobra run: time limit: time limit 1.000 s reached" "$work/$host.log"; then
    echo "host $host did not stop at its time limit"; failed=1
  fi
  if [ $host = needle ]; then peer=probe; else peer=needle; fi
  if ! grep -q "peer '$peer' joined" "$work/$host.log"; then echo "host $host never said its peer joined"; failed=1; fi
done
if [ $failed != 0 ]; then
  for host in needle probe; do echo "--- $host.log"; cat "$work/$host.log"; done
fi
exit $failed
