#!/usr/bin/env bash
# End-to-end check of `cobra new component`: the generated skeleton compiles against cobra::core
# and its generated unit test passes, untouched.
# Usage: new_component_test.sh COBRA_TOOL CXX CORE_INCLUDE_DIR CORE_LIBRARY
set -euo pipefail
cobra="$1" cxx="$2" core_include="$3" core_library="$4"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$cobra" new component VariableAdmittance --role calculation --package my_control -o "$work/my_control" \
  --in ref_pose:Frame --in meas_wrench:Wrench --event-in tick:Event --out adm_pose:Frame --out adm_twist:Twist \
  --prop stiffness:double:N/m --prop damping:vector:N·s/m --prop joints:JntArray
"$cobra" new component ContactDetector --role decision --package my_control -o "$work/my_control" \
  --in force:double:N --prop threshold:double:N
grep -q "my_control_component(variable_admittance)" "$work/my_control/CMakeLists.txt"
grep -q "my_control_component(contact_detector)" "$work/my_control/CMakeLists.txt"

# Refusals: an existing component, a bad type.
if "$cobra" new component ContactDetector --role decision --package my_control -o "$work/my_control" 2>"$work/err"; then
  echo "expected a refusal for an existing component" >&2; exit 1
fi
grep -q "already exists" "$work/err"
if "$cobra" new component Bad --role calculation --package p -o "$work/p" --in x:Matrix 2>"$work/err"; then
  echo "expected a refusal for an unknown type" >&2; exit 1
fi
grep -q "unknown type 'Matrix'; the types are:" "$work/err"

"$cxx" -std=c++20 -I"$work/my_control/include" -I"$core_include" -isystem /usr/include/eigen3 \
  "$work"/my_control/src/*.cpp "$work"/my_control/test/*_test.cpp "$core_library" \
  -lgtest -lgtest_main -lorocos-kdl -lpthread -o "$work/generated_tests"
"$work/generated_tests"
echo "generated component skeletons build and pass their tests"
