#!/usr/bin/env bash
# cobra used from outside its tree (label "install"): installs the build into a temporary prefix,
# builds examples/06_package with its own CMake against it, runs its deployment with the installed
# tool (which dlopens the package) and checks the filtered force; then `cobra new component`
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

# An installed package is found without COBRA_PACKAGE_PATH.
cmake --install "$work/example" --prefix "$prefix" >/dev/null
"$prefix/bin/cobra" deploy "$deployment" --sim --run-for 0.01 | grep -Eq "^  Filter +Calculation +Running" \
  || fail "the package installed in $prefix/lib/cobra/packages was not found"

# The editor's generate route builds too (studio_editor_generate is built with the tests).
editor_generate="$build/studio/studio_editor_generate"
[ -x "$editor_generate" ] || editor_generate=""
"$source/tools/cobra/test/new_component_test.sh" "$prefix/bin/cobra" "$prefix" "$editor_generate"
echo "installed cobra builds and runs an out-of-tree package"
