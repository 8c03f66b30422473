#!/usr/bin/env bash
# cobra used from outside its tree (label "install"): installs the build into a temporary prefix,
# builds examples/06_package with its own CMake against it, runs its deployment with the installed
# tool (which dlopens the package) and checks the filtered force and the package's own type
# (example.ForceSample: CSV columns with units, a property set from Lua, two processes over DDS,
# recorded, plotted and offered to the studio by `cobra run`);
# then `cobra new component`
# writes a package that builds against the prefix and whose generated tests pass.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$1" source="$2"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
launcher=(); command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fail() { echo "install_test: $*" >&2; exit 1; }
# Quick on a second run: paths relative to the temporary folder make ccache hits, and programs
# that link cobra's archives whole skip their debug information (a 9 s link becomes 2 s).
export CCACHE_BASEDIR="$work" LDFLAGS="-Wl,--strip-debug"
unset COBRA_DATA_DIR COBRA_PACKAGE_PATH  # the installed layout alone must find data and packages

# Installed elsewhere, then moved: the installation must not depend on where it was put.
cmake --install "$build" --prefix "$work/installed" >"$work/install.log" || { cat "$work/install.log"; fail "install failed"; }
mv "$work/installed" "$work/prefix"
prefix="$work/prefix"
if grep -rl -e "$build" -e "$source" "$prefix/lib/cmake" "$prefix/share" "$prefix/include"; then
  fail "installed files name the build or source tree (above)"
fi
# The installed tool runs without Fast DDS: DDS is the package cobra_dds, loaded when a
# deployment asks for it (architecture's tool_links_no_dds_test checks the build tree's tool).
if readelf -d "$prefix/bin/cobra" | grep -q 'libfastrtps'; then
  fail "the installed cobra tool links Fast DDS (it must load it with the package cobra_dds only)"
fi
# Nor this machine's paths of third-party libraries: the consumer's find_package finds them.
if grep -n '"/[^"]' "$prefix"/lib/cmake/cobra/cobraTargets*.cmake; then
  fail "the installed targets name absolute paths (above)"
fi

cmake -S "$source/examples/06_package" -B "$work/example" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" \
  ${launcher[@]+"${launcher[@]}"} >"$work/configure.log" 2>&1 || { cat "$work/configure.log"; fail "configure failed"; }
cmake --build "$work/example" >"$work/build.log" 2>&1 || { cat "$work/build.log"; fail "build failed"; }

deployment="$source/examples/06_package/force_filter.lua"
COBRA_PACKAGE_PATH="$work/example" "$prefix/bin/cobra" deploy "$deployment" --sim --run-for 1 | tee "$work/deploy.out"
grep -Eq "^  Filter +Calculation +Running" "$work/deploy.out" || fail "the package's component did not run"
grep -q "ran 1.000 s of simulated time" "$work/deploy.out" || fail "the deployment did not run 1 s"

# The filter's output after 1 s of a 10 N step at fc = 0.5 Hz: 10·(1 - exp(-π)) N, to one
# 1 ms step (≈1.4 mN): the component computed, not just ran.
printf 'read Filter.force_out\nstep 1\nread Filter.force_out\nlua print(COBRA_CHARTS)\n' |
  COBRA_PACKAGE_PATH="$work/example" "$prefix/bin/cobra" console "$deployment" --sim | tee "$work/console.out"
force=$(sed -n 's/^Filter.force_out = \([0-9.e+-]*\) \[N\]$/\1/p' "$work/console.out")
[ -n "$force" ] || fail "no value read from Filter.force_out"
awk -v y="$force" 'BEGIN { e = 10 * (1 - exp(-3.141592653589793)); d = y - e; exit !(d < 0.005 && d > -0.005) }' \
  || fail "Filter.force_out = $force N after 1 s; expected 10·(1 - e^-π) = 9.568 N within 5 mN"
# The reusable charts are found in the moved prefix, not in the source tree.
grep -qx "$prefix/share/cobra/charts/" "$work/console.out" || fail "COBRA_CHARTS is not the installed charts folder"
# A deployment supervisor runs the installed chart (which requires its sibling switch_supervisor.lua).
cat >"$work/supervisor.lua" <<'LUA'
packages_list = { "cobra_coordination" }
components_list = { { peer_name = "DepSup", component_type = "Supervisor" } }
initConfigurator(packages_list, components_list)
getReferences()
DepSup.fsm_path = COBRA_CHARTS .. "deployment_supervisor.lua"
setActivities({ { peer_name = "DepSup", period = 0.01, priority = 50, scheduler = rtt.globals.ORO_SCHED_RT } })
configureComponents({ "DepSup" })
startComponents({ "DepSup" })
LUA
"$prefix/bin/cobra" deploy "$work/supervisor.lua" --sim --run-for 0.1 | grep -Eq "^  DepSup +Supervision +Running" \
  || fail "a Supervisor did not run the installed deployment_supervisor.lua"

# The package's own type, example.ForceSample, registered with cobra::types::registerType<T>():
# recorded to CSV, one column per field with its unit ...
samples="$source/examples/06_package/force_sample.lua"
FORCE_SAMPLE_CSV="$work/force_sample.csv" COBRA_PACKAGE_PATH="$work/example" \
  "$prefix/bin/cobra" deploy "$samples" --sim --run-for 1 >"$work/samples.out" || { cat "$work/samples.out"; fail "force_sample.lua did not run"; }
header="time [s],Filter.force_out [N],Filter.sample_out.force [N],Filter.sample_out.filtered [N],Filter.sample_out.count"
[ "$(head -1 "$work/force_sample.csv")" = "$header" ] ||
  fail "the CSV header is '$(head -1 "$work/force_sample.csv")', expected '$header'"
# The row at 0.9 s: 10 N read, 10·(1 - e^(-0.9π)) N written (within a step), the 901st update.
awk -F, '$1 == "0.9" { e = 10 * (1 - exp(-0.9 * 3.141592653589793)); d = $4 - e; found = 1
                      ok = $3 == 10 && $4 == $2 && d < 0.005 && d > -0.005 && $5 == 901 }
         END { exit !(found && ok) }' "$work/force_sample.csv" ||
  { cat "$work/force_sample.csv"; fail "the CSV's row at 0.9 s is not the filter's sample (above)"; }
# ... a property of that type set from Lua (the deployment file, then the console's Lua), read back.
printf 'get Hold.sample\nlua Hold.sample = {force = 7, filtered = 8.5, count = 9}\nlua print(Hold.sample.filtered + Hold.sample.count)\nget Hold.sample\n' |
  FORCE_SAMPLE_CSV="$work/force_sample_console.csv" COBRA_PACKAGE_PATH="$work/example" \
  "$prefix/bin/cobra" console "$samples" --sim | tee "$work/samples_console.out"
grep -qx "Hold.sample = {force = 1.5, filtered = 2.25, count = 3}" "$work/samples_console.out" ||
  fail "Hold.sample is not the example.ForceSample force_sample.lua sets"
grep -qx "17.5" "$work/samples_console.out" || fail "Lua did not read Hold.sample's fields back"
grep -qx "Hold.sample = {force = 7, filtered = 8.5, count = 9}" "$work/samples_console.out" ||
  fail "Hold.sample set from the console's Lua is not read back"
# ... and between two processes over DDS (the transport is the package cobra_dds; the type is
# found through core::TypeFacets): one writes the filter's samples, the other records them.
# Domain 212, this test's own; the reader starts first and outlives the writer.
dds_samples="$source/examples/06_package/force_sample_dds.lua"
COBRA_DDS_DOMAIN=212 FORCE_SAMPLE_ROLE=reader FORCE_SAMPLE_CSV="$work/force_sample_dds.csv" COBRA_PACKAGE_PATH="$work/example" \
  timeout 120 "$prefix/bin/cobra" deploy "$dds_samples" --run-for 5 >"$work/dds_reader.out" 2>&1 &
reader=$!
COBRA_DDS_DOMAIN=212 FORCE_SAMPLE_ROLE=writer COBRA_PACKAGE_PATH="$work/example" \
  timeout 120 "$prefix/bin/cobra" deploy "$dds_samples" --run-for 3 >"$work/dds_writer.out" 2>&1 ||
  { cat "$work/dds_writer.out"; fail "the DDS writer did not run"; }
wait "$reader" || { cat "$work/dds_reader.out"; fail "the DDS reader did not run"; }
header="time [s],Hold.sample_out.force [N],Hold.sample_out.filtered [N],Hold.sample_out.count"
[ "$(head -1 "$work/force_sample_dds.csv")" = "$header" ] || { cat "$work/dds_reader.out"; fail "the DDS reader's CSV header is '$(head -1 "$work/force_sample_dds.csv")'"; }
# Received: the writer's samples of 10 N, after more than 1 s of its updates (its filter > 9 N).
tail -1 "$work/force_sample_dds.csv" | awk -F, '{ exit !($2 == 10 && $3 > 9 && $3 < 10 && $4 > 1000) }' ||
  { tail -3 "$work/force_sample_dds.csv"; cat "$work/dds_reader.out"; fail "the reader did not receive the writer's example.ForceSample over DDS"; }

# ... and in a run of the installed `cobra run` (force_sample_run.lua): its fields are the run's
# signals.csv columns with their units, its report plots them, and cobra studio's recording of the
# run offers the filtered force as a signal in N, with its values.
COBRA_PACKAGE_PATH="$work/example" "$prefix/bin/cobra" run "$source/examples/06_package/force_sample_run.lua" \
  --report "$work/run" --quiet >"$work/run.out" 2>&1 || { cat "$work/run.out"; fail "force_sample_run.lua did not run to its done state"; }
header="time [s],Filter.sample_out.force [N],Filter.sample_out.filtered [N],Filter.sample_out.count"
[ "$(head -1 "$work/run/signals.csv")" = "$header" ] ||
  fail "the run's signals.csv header is '$(head -1 "$work/run/signals.csv")', expected '$header'"
# The row at 0.9 s: the sample of the 900th update (those at 0 ... 0.899 s; the run's row is read
# between two instants of the clock), 10·(1 - e^(-0.9π)) N within a step.
awk -F, '$1 == "0.900" { e = 10 * (1 - exp(-0.9 * 3.141592653589793)); d = $3 - e; found = 1
                         ok = $2 == 10 && d < 0.005 && d > -0.005 && $4 == 900 }
         END { exit !(found && ok) }' "$work/run/signals.csv" ||
  { cat "$work/run/signals.csv"; fail "the run's signals.csv row at 0.9 s is not the filter's sample (above)"; }
grep -q "Filter.sample_out.filtered" "$work/run/report.html" || fail "the run's report does not plot Filter.sample_out.filtered"
recording="$work/run/studio/recording.json"
grep -q '"signals":\[{"name":"Filter.sample_out.filtered","unit":"N"}\]' "$recording" ||
  fail "the studio's recording does not offer the signal Filter.sample_out.filtered [N]"
filtered=$(grep -o '"Filter.sample_out.filtered":[0-9.e+-]*' "$recording" | tail -1 | cut -d: -f2)
awk -v y="$filtered" 'BEGIN { exit !(y > 9.5 && y < 10) }' ||
  fail "the studio's last value of Filter.sample_out.filtered is '$filtered'; expected 10·(1 - e^-π) ≈ 9.57 N"

# An installed package is found without COBRA_PACKAGE_PATH.
cmake --install "$work/example" --prefix "$prefix" >/dev/null
"$prefix/bin/cobra" deploy "$deployment" --sim --run-for 0.01 | grep -Eq "^  Filter +Calculation +Running" \
  || fail "the package installed in $prefix/lib/cobra/packages was not found"

# The editor's generate route builds too (studio_editor_generate is built with the tests).
editor_generate="$build/studio/studio_editor_generate"
[ -x "$editor_generate" ] || editor_generate=""
"$source/tools/cobra/test/new_component_test.sh" "$prefix/bin/cobra" "$prefix" "$editor_generate"
echo "installed cobra builds and runs an out-of-tree package"
