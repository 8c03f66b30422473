#!/usr/bin/env bash
# Renders the project's screenshots into docs/screenshots/ (PNG), one section per page. Each
# section runs what it shows (the tasks in simulation, lockstep) and shoots it in headless
# Chromium (Debian's, driven by playwright-core from studio/web/node_modules; ./do setup installs
# both). Usage: tools/screenshots.sh [BUILD_DIR]   (default build/release, with `cobra` built)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build/release}"
cobra="$build/tools/cobra/cobra"
out="$root/docs/screenshots"
[ -x "$cobra" ] || { echo "screenshots: $cobra: not built (./do build release cobra)" >&2; exit 2; }
mkdir -p "$out"
runs="$(mktemp -d)"
trap 'rm -rf "$runs"' EXIT

# --- The run reports (report.html of cobra run APP --report DIR), one per task.
for task in puncturing suturing puma260; do
  "$cobra" run "$root/apps/$task" --report "$runs/$task" --quiet > "$runs/$task.log" 2>&1 ||
    { cat "$runs/$task.log" >&2; echo "screenshots: cobra run apps/$task failed" >&2; exit 1; }
  node "$root/tools/screenshots/report.mjs" --page "$runs/$task/report.html" --out "$out/report_$task.png"
done

# --- Studio and editor pages: tools/screenshots/<page>.mjs sections follow here.
