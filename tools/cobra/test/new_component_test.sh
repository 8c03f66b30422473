#!/usr/bin/env bash
# End-to-end check of `cobra new component`: it writes a package folder built against an
# installed cobra, refuses what it must, and — given an install prefix — the package configures
# and builds with its own CMake against that prefix and its generated tests pass, untouched.
# With EDITOR_GENERATE (studio_editor_generate: the editor's generate route, as the page calls
# it), a third component is generated through the editor into the same package and built with it.
# Usage: new_component_test.sh COBRA_TOOL [INSTALL_PREFIX] [EDITOR_GENERATE]
set -euo pipefail
cobra="$1" prefix="${2:-}" editor_generate="${3:-}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
launcher=(); command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fail() { echo "new_component_test: $*" >&2; exit 1; }

"$cobra" new component VariableAdmittance --role calculation --package my_control -o "$work/my_control" \
  --in ref_pose:Frame --in meas_wrench:Wrench --event-in tick:Event --out adm_pose:Frame --out adm_twist:Twist \
  --prop stiffness:double:N/m --prop damping:vector:N·s/m --prop joints:JntArray >"$work/out"
grep -q "wrote .*my_control/CMakeLists.txt" "$work/out" || fail "first component did not write CMakeLists.txt"
grep -q "wrote .*my_control/src/package.cpp" "$work/out" || fail "first component did not write src/package.cpp"
"$cobra" new component ContactDetector --role decision --package my_control -o "$work/my_control" \
  --in force:double:N --prop threshold:double:N >"$work/out"
grep -q "CMakeLists.txt\|package.cpp" "$work/out" && fail "second component rewrote the package files: $(cat "$work/out")"

if [ -n "$editor_generate" ]; then
  "$editor_generate" "$work/my_control" my_control >"$work/out" || fail "the editor's generate route failed: $(cat "$work/out")"
  grep -q '^200 {"files":\[.*my_control/include/my_control/editor_made.hpp' "$work/out" || fail "$(cat "$work/out")"
  grep -q "^my_control_component(editor_made)" "$work/my_control/CMakeLists.txt" || fail "no line for editor_made"
  "$editor_generate" "$work/my_control" my_control >"$work/out" && fail "the editor generated EditorMade twice"
  grep -q '^400 {"error":".*editor_made.hpp already exists; remove it or choose another name"}' "$work/out" || fail "$(cat "$work/out")"
fi

cmake_file="$work/my_control/CMakeLists.txt" package="$work/my_control/src/package.cpp"
grep -q "^find_package(cobra 0.1 REQUIRED)" "$cmake_file" || fail "CMakeLists.txt does not find cobra"
grep -q "^cobra_add_package(my_control SOURCES src/package.cpp INSTALL)" "$cmake_file" || fail "no cobra_add_package"
grep -q "^my_control_component(variable_admittance)" "$cmake_file" || fail "no line for variable_admittance"
grep -q "^my_control_component(contact_detector)" "$cmake_file" || fail "no line for contact_detector"
grep -q 'package.component<my_control::VariableAdmittance>("VariableAdmittance"' "$package" || fail "VariableAdmittance not registered"
grep -q 'package.component<my_control::ContactDetector>("ContactDetector"' "$package" || fail "ContactDetector not registered"
grep -q '#include "my_control/contact_detector.hpp"' "$package" || fail "ContactDetector's header not included"

# Refusals, each before anything is written: an existing component, a bad type, a package.cpp
# without its markers.
if "$cobra" new component ContactDetector --role decision --package my_control -o "$work/my_control" 2>"$work/err"; then
  fail "expected a refusal for an existing component"
fi
grep -q "contact_detector.hpp already exists; remove it or choose another name" "$work/err" || fail "$(cat "$work/err")"
if "$cobra" new component Bad --role calculation --package p -o "$work/p" --in x:Matrix 2>"$work/err"; then
  fail "expected a refusal for an unknown type"
fi
grep -q "unknown type 'Matrix'; the types are:" "$work/err" || fail "$(cat "$work/err")"
mkdir -p "$work/edited/src"
printf 'extern "C" void cobra_register_package(cobra::deploy::PackageBuilder&) {}\n' >"$work/edited/src/package.cpp"
if "$cobra" new component Probe --role bridge --package edited -o "$work/edited" 2>"$work/err"; then
  fail "expected a refusal for a package.cpp without markers"
fi
grep -q "src/package.cpp has no line '// cobra new component: component headers above this line'" "$work/err" \
  || fail "$(cat "$work/err")"
[ ! -e "$work/edited/include" ] && [ ! -e "$work/edited/CMakeLists.txt" ] || fail "a refusal left files behind"

if [ -n "$prefix" ]; then
  cmake -S "$work/my_control" -B "$work/build" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" \
    ${launcher[@]+"${launcher[@]}"} >"$work/configure.log" 2>&1 || { cat "$work/configure.log"; fail "configure failed"; }
  cmake --build "$work/build" >"$work/build.log" 2>&1 || { cat "$work/build.log"; fail "build failed"; }
  ctest --test-dir "$work/build" --output-on-failure | tee "$work/ctest.log"
  if [ -n "$editor_generate" ]; then
    grep -q "editor_made" "$work/ctest.log" || fail "the component generated through the editor has no test that ran"
  fi
  echo "generated components build against $prefix and pass their tests"
fi
echo "cobra new component writes a package and refuses bad input"
