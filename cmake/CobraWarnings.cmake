# Warning and sanitizer flags shared by every cobra target.
add_library(cobra_build_flags INTERFACE)
target_compile_options(cobra_build_flags INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
  -Wno-sign-conversion -Wnon-virtual-dtor -Woverloaded-virtual)
if(COBRA_WARNINGS_AS_ERRORS)
  target_compile_options(cobra_build_flags INTERFACE -Werror)
endif()
# Under ASan, Eigen stops trusting malloc's 16-byte alignment and switches to its own aligned
# allocator, while Debian's liborocos-kdl (built without ASan) frees with free(): their inline
# functions then disagree and KDL's solvers crash. glibc's and ASan's malloc both align to 16 on
# 64-bit targets, so cobra keeps Eigen's normal allocation path in sanitizer builds.
set(COBRA_EIGEN_AS_KDL -DEIGEN_MALLOC_ALREADY_ALIGNED=1)
if(COBRA_SANITIZER STREQUAL "address")
  target_compile_options(cobra_build_flags INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer
    -fno-sanitize-recover=undefined ${COBRA_EIGEN_AS_KDL})
  target_link_options(cobra_build_flags INTERFACE -fsanitize=address,undefined)
elseif(COBRA_SANITIZER STREQUAL "thread")
  target_compile_options(cobra_build_flags INTERFACE -fsanitize=thread -fno-omit-frame-pointer)
  target_link_options(cobra_build_flags INTERFACE -fsanitize=thread)
elseif(COBRA_SANITIZER STREQUAL "fuzzer")
  # Coverage instrumentation for libFuzzer everywhere, plus ASan/UBSan to turn bugs into crashes.
  target_compile_options(cobra_build_flags INTERFACE -fsanitize=fuzzer-no-link,address,undefined
    -fno-omit-frame-pointer -fno-sanitize-recover=undefined ${COBRA_EIGEN_AS_KDL})
  target_link_options(cobra_build_flags INTERFACE -fsanitize=address,undefined)
elseif(NOT COBRA_SANITIZER STREQUAL "")
  message(FATAL_ERROR "COBRA_SANITIZER must be '', 'address', 'thread' or 'fuzzer', not '${COBRA_SANITIZER}'")
endif()

# Debug information: line tables only (-g1: function names, files and lines for debuggers,
# sanitizer reports and backtraces, without variable and type descriptions), compressed in objects
# and executables. Full -g made each test executable linking the whole runtime ~130 MB (a release
# build ~6 GB), which filled the CI machine's disk before its sanitizer builds; -g1 with
# compression keeps a build under 1 GB. Set COBRA_DEBUG_INFO=-g for full debug info.
set(COBRA_DEBUG_INFO "-g1" CACHE STRING "Debug information level of every build (-g1, -g, -g0)")
if(NOT COBRA_DEBUG_INFO STREQUAL "-g0")
  # Every target of the build (not only those linking cobra_build_flags); after the build type's
  # own -g, and the last -g option wins.
  add_compile_options(${COBRA_DEBUG_INFO} -gz)
  add_link_options(-Wl,--compress-debug-sections=zlib)
endif()

# A slice of the tests (the CI's sanitizer slice): only tests labelled with one of these are built
# by the `selected_tests` target and registered with CTest; the others stay out of `all`.
set(COBRA_TEST_LABELS "" CACHE STRING "Build and register only the tests with one of these labels (empty: all)")

# cobra_add_test(<name> SOURCES ... LIBS ... [LABELS l] [TEST_PROPERTIES k v ...]): one executable
# per unit, registered with CTest; TEST_PROPERTIES are set on each of its tests (e.g. RUN_SERIAL).
function(cobra_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS;LABELS;TEST_PROPERTIES" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} cobra::test_support GTest::gtest GTest::gtest_main cobra_build_flags)
  if(COBRA_TEST_LABELS AND NOT "${ARG_LABELS}" IN_LIST COBRA_TEST_LABELS)
    set_target_properties(${name} PROPERTIES EXCLUDE_FROM_ALL ON)
    return()
  endif()
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "${ARG_LABELS}" ${ARG_TEST_PROPERTIES})
  set_property(GLOBAL APPEND PROPERTY COBRA_SELECTED_TESTS ${name})
endfunction()

# cobra_add_unit_tests(<prefix> LIBS ... [LABELS label]): one test executable per
# test/<unit>_test.cpp of the calling directory, named <prefix>_<unit>_test.
function(cobra_add_unit_tests prefix)
  cmake_parse_arguments(ARG "" "LABELS" "LIBS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/test/*_test.cpp)
  foreach(source IN LISTS sources)
    get_filename_component(unit ${source} NAME_WE)
    cobra_add_test(${prefix}_${unit} SOURCES ${source} LIBS ${ARG_LIBS} LABELS ${ARG_LABELS})
    target_compile_definitions(${prefix}_${unit} PRIVATE COBRA_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  endforeach()
endfunction()
