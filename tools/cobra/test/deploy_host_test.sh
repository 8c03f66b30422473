#!/usr/bin/env bash
# `cobra deploy FILE --host NAME` on the puncturing task's placement (apps/puncturing/puncturing.lua:
# host needle runs the world and the I-SUR's controller, host probe the UR5's): only host needle's
# components are created and started, the link included; an unknown host is refused with a
# message naming the hosts that exist. In real time: with --sim the link would wait for host probe
# at the first clock meeting. DDS domain 139, this test's own (no host probe runs there).
# Usage: deploy_host_test.sh COBRA_TOOL PUNCTURING_ENTRY_FILE
set -euo pipefail
cobra="$1" entry="$2"
export COBRA_DDS_DOMAIN=139
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "deploy_host_test: $*" >&2; exit 1; }

"$cobra" deploy "$entry" --host needle --run-for 0.5 >"$work/out" 2>"$work/err" ||
  fail "host needle did not deploy: $(cat "$work/err")"
grep -Eq "^host 'needle' of the placement: [0-9]+ component\(s\) here; [1-9][0-9]* of other hosts, which run them$" \
  "$work/out" || fail "no host line: $(cat "$work/out")"
for component in Link ISUR Patient NeedleTaskSup NeedleAdmittance; do
  grep -Eq "^  $component +[A-Za-z]+ +Running " "$work/out" || fail "$component is not Running: $(cat "$work/out")"
done
grep -Eq "^  (UR5|Probe[A-Za-z]*) " "$work/out" && fail "host probe's components run here: $(cat "$work/out")"
grep -q "^ran 0\.5[0-9]* s of real time$" "$work/out" || fail "did not run 0.5 s: $(cat "$work/out")"

"$cobra" deploy "$entry" --host nedle --run-for 0.5 >"$work/out" 2>"$work/err" && fail "host nedle was accepted"
grep -Eq "puncturing.lua:[0-9]+: this process's host 'nedle' is not a host of the placement \(needle, probe\); did you mean 'needle'\? known hosts: needle, probe" \
  "$work/err" || fail "unexpected refusal: $(cat "$work/err")"
echo "cobra deploy --host runs one host's components and refuses an unknown host"
