#!/usr/bin/env bash
# Before and after in one run: builds one bench at an older revision and at the working tree, then
# runs the two executables in turn on the same machine and prints each benchmark's median and
# worst case side by side. The bench source is the working tree's, copied into the older
# revision (so both measure the same code paths; the bench must use only APIs both revisions
# have, as type_paths_bench.cpp does).
#
# Usage: bench/compare_revisions.sh REVISION [BENCH] [ROUNDS]
#   REVISION  the "before" revision (a commit, tag or branch of this repository)
#   BENCH     the bench's name (default type_paths_bench; bench/<BENCH>.cpp)
#   ROUNDS    how many times each executable runs, alternating (default 3; the table keeps, per
#             benchmark, the median of the rounds' medians and the largest of their maxima)
# Builds into build/before/src/build/release (a detached worktree of REVISION, kept for the next
# run; `git worktree remove build/before/src` removes it) and build/release.
set -euo pipefail
cd "$(dirname "$0")/.."
revision=${1:?usage: bench/compare_revisions.sh REVISION [BENCH] [ROUNDS]}
bench=${2:-type_paths_bench}
rounds=${3:-3}
[ -f "bench/$bench.cpp" ] || { echo "compare_revisions: no bench/$bench.cpp" >&2; exit 2; }
git rev-parse --verify --quiet "$revision^{commit}" >/dev/null ||
  { echo "compare_revisions: '$revision' is not a revision of this repository" >&2; exit 2; }

before=build/before
# The older revision's worktree and build are kept for the next comparison of the same revision.
if [ -d "$before/src" ] && [ "$(git -C "$before/src" rev-parse HEAD)" != "$(git rev-parse "$revision^{commit}")" ]; then
  git worktree remove --force "$before/src"
fi
mkdir -p "$before"
[ -d "$before/src" ] || git worktree add --detach --quiet "$before/src" "$revision"
git -C "$before/src" checkout --quiet -- bench/CMakeLists.txt  # the stanza below is appended afresh
cp "bench/$bench.cpp" bench/median_and_worst.hpp "$before/src/bench/"
# The bench's own CMake stanza (its libraries), appended to the older bench/CMakeLists.txt.
sed -n "/^# The type paths bench/,\$p" bench/CMakeLists.txt >>"$before/src/bench/CMakeLists.txt"

echo "[compare] building $bench at $(git rev-parse --short "$revision") (before) and at the working tree (after)"
cmake -S "$before/src" -B "$before/src/build/release" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >"$before/configure.log"
cmake --build "$before/src/build/release" --target "$bench" -j2 >"$before/build.log"
./do build release "bench/$bench" >/dev/null

mkdir -p build/compare
for ((r = 1; r <= rounds; ++r)); do
  for side in before after; do
    if [ $side = before ]; then exe="$before/src/build/release/bench/$bench"; else exe="build/release/bench/$bench"; fi
    echo "[compare] round $r: $side"
    "$exe" --benchmark_format=json >"build/compare/$side.$r.json" 2>/dev/null
  done
done

python3 - "$rounds" <<'EOF'
import json, statistics, sys
rounds = int(sys.argv[1])
def load(side):
    table = {}
    for r in range(1, rounds + 1):
        for b in json.load(open(f"build/compare/{side}.{r}.json"))["benchmarks"]:
            name, agg = b["run_name"], b.get("aggregate_name")
            if agg in ("median", "max"):
                table.setdefault(name, {}).setdefault(agg, []).append(b["real_time"])
    return {n: (statistics.median(v["median"]), max(v["max"])) for n, v in table.items()}
before, after = load("before"), load("after")
print(f"{'benchmark':40s} {'before median':>14s} {'after median':>13s} {'after/before':>12s} {'before max':>11s} {'after max':>10s}   (ns)")
for name in before:
    if name not in after: continue
    (bm, bx), (am, ax) = before[name], after[name]
    print(f"{name:40s} {bm:14.1f} {am:13.1f} {am / bm:12.2f} {bx:11.1f} {ax:10.1f}")
EOF
