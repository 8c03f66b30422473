#!/usr/bin/env bash
# Renders the project's screenshots into docs/screenshots/ (PNG), one section per page. Each
# section runs what it shows (the tasks in simulation, lockstep) and shoots it in headless
# Chromium (Debian's, driven by playwright-core from studio/web/node_modules; ./do setup installs
# both). Usage: tools/screenshots.sh [BUILD_DIR]   (default build/release, with `cobra` and `studio_web` built;
# `./do screenshots` builds them and runs this)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$(realpath -m "${1:-$root/build/release}")"
cobra="$build/tools/cobra/cobra"
out="$root/docs/screenshots"
[ -x "$cobra" ] || { echo "screenshots: $cobra: not built (./do build release cobra)" >&2; exit 2; }
[ -f "$build/studio/web/dist/index.html" ] ||
  { echo "screenshots: $build/studio/web/dist: the studio page is not built (./do build release studio_web)" >&2; exit 2; }
mkdir -p "$out"
cd "$root"  # the pages name the application as given: apps/TASK
runs="$(mktemp -d)"
edit=""  # cobra edit's process while its page is shot
trap '[ -z "$edit" ] || kill "$edit" 2>/dev/null; rm -rf "$runs"' EXIT

# --- Per task: the run report (report.html of cobra run APP --report DIR) and cobra studio's
# page of the same run folder (studio/index.html: its scene and signals, replayed at mid-run).
for task in puncturing suturing puma260; do
  "$cobra" run "apps/$task" --report "$runs/$task" --quiet > "$runs/$task.log" 2>&1 ||
    { cat "$runs/$task.log" >&2; echo "screenshots: cobra run apps/$task failed" >&2; exit 1; }
  node "$root/tools/screenshots/report.mjs" --page "$runs/$task/report.html" --out "$out/report_$task.png"
  node "$root/tools/screenshots/studio.mjs" "file://$runs/$task/studio/index.html" "$out/studio-$task.png"
done

# --- The deployment editor (cobra edit's page on apps/puncturing, served until it is shot).
"$cobra" edit apps/puncturing > "$runs/edit.log" 2>&1 & edit=$!
until grep -q '^editor: ' "$runs/edit.log"; do
  kill -0 "$edit" 2>/dev/null || { cat "$runs/edit.log" >&2; echo "screenshots: cobra edit failed" >&2; exit 1; }
  sleep 0.2
done
node "$root/tools/screenshots/editor.mjs" "$(sed -n 's/^editor: //p' "$runs/edit.log")" "$out/editor-puncturing.png"
kill "$edit"; edit=""
