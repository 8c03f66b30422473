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
  # -O1: the build type is Debug (assertions on), but unoptimised code under ASan made the
  # procedure tests several times slower; -O1 keeps every report (and the stacks, with frame
  # pointers) and brings the whole sanitized suite within the CI's budget (.ci/run).
  target_compile_options(cobra_build_flags INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer
    -fno-sanitize-recover=undefined -O1 ${COBRA_EIGEN_AS_KDL})
  target_link_options(cobra_build_flags INTERFACE -fsanitize=address,undefined)
elseif(COBRA_SANITIZER STREQUAL "thread")
  target_compile_options(cobra_build_flags INTERFACE -fsanitize=thread -fno-omit-frame-pointer)
  target_link_options(cobra_build_flags INTERFACE -fsanitize=thread)
  # The lock of glibc's pthread_mutex_clocklock made visible to TSan (see the file): Fast DDS's
  # timed mutexes are locked through it.
  target_sources(cobra_build_flags INTERFACE
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/test_support/tsan/pthread_mutex_clocklock.cpp>)
elseif(COBRA_SANITIZER STREQUAL "fuzzer")
  # Coverage instrumentation for libFuzzer everywhere, plus ASan/UBSan to turn bugs into crashes.
  target_compile_options(cobra_build_flags INTERFACE -fsanitize=fuzzer-no-link,address,undefined
    -fno-omit-frame-pointer -fno-sanitize-recover=undefined ${COBRA_EIGEN_AS_KDL})
  target_link_options(cobra_build_flags INTERFACE -fsanitize=address,undefined)
elseif(NOT COBRA_SANITIZER STREQUAL "")
  message(FATAL_ERROR "COBRA_SANITIZER must be '', 'address', 'thread' or 'fuzzer', not '${COBRA_SANITIZER}'")
endif()

# The test properties of every test that loads Fast DDS (a dds test, a procedure split over
# processes, a `cobra` command whose deployment loads the package cobra_dds): under ASan they run
# with new_delete_type_mismatch=0, and only they. Debian's Fast DDS 2.9.1 frees every RTPS
# endpoint's statistics data through a base class without a virtual destructor
# (fastdds::statistics::StatisticsReaderImpl / StatisticsWriterImpl, whatever the QoS), and ASan's
# new-delete-type-mismatch report cannot be suppressed by frame. fast_dds_statistics_probe
# (dds/test) shows the report still comes without the option: that test fails once Fast DDS is
# fixed, and then this goes. Appended to the ASAN_OPTIONS `./do test --asan` gives.
set(COBRA_FAST_DDS_TEST_PROPERTIES)
if(COBRA_SANITIZER STREQUAL "address")
  set(COBRA_FAST_DDS_TEST_PROPERTIES ENVIRONMENT_MODIFICATION "ASAN_OPTIONS=string_append::new_delete_type_mismatch=0")
endif()

# cobra_uses_std_regex(<source>...): GCC 12 at -O1 with ASan warns -Wmaybe-uninitialized inside
# libstdc++'s <regex> (the std::function of its NFA states: a false positive in the library's
# header, which the -O2 release build does not show). The translation units of the calling
# directory that include <regex> name themselves here; under ASan they go without that warning.
function(cobra_uses_std_regex)
  if(COBRA_SANITIZER STREQUAL "address")
    set_source_files_properties(${ARGN} PROPERTIES COMPILE_OPTIONS -Wno-maybe-uninitialized)
  endif()
endfunction()

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

# The linker: mold when it is installed (`./do` installs it). cobra links about 250 executables,
# each test with the whole runtime it exercises, in each of the CI's four builds; GNU ld took
# 13.9 s of wall time for puncturing_procedure_test on the loaded 2-core machine where mold took
# 3.0 s (gold 6.3 s). COBRA_LINKER=default keeps the compiler's own linker.
set(COBRA_LINKER "mold" CACHE STRING "Linker of every target: mold (when found) or default")
if(COBRA_LINKER STREQUAL "mold")
  find_program(COBRA_MOLD_PROGRAM NAMES ld.mold mold)
  if(COBRA_MOLD_PROGRAM)
    add_link_options(-fuse-ld=mold)
  else()
    message(STATUS "cobra: mold not found, linking with the compiler's default linker")
  endif()
endif()

# A slice of the tests (the CI's sanitizer slice): only tests labelled with one of these are built
# by the `selected_tests` target and registered with CTest; the others stay out of `all`.
set(COBRA_TEST_LABELS "" CACHE STRING "Build and register only the tests with one of these labels (empty: all)")

# cobra_add_test(<name> SOURCES ... LIBS ... [LABELS l...] [TEST_PROPERTIES k v ...]): one
# executable per unit, registered with CTest; TEST_PROPERTIES are set on each of its tests (e.g.
# RUN_SERIAL). With several labels (e.g. "dds;concurrency") it belongs to every slice one of them selects.
function(cobra_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS;LABELS;TEST_PROPERTIES" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} cobra::test_support GTest::gtest GTest::gtest_main cobra_build_flags)
  # A test's own sources at -O1 in the optimised builds (the code under test, in the libraries,
  # keeps the build's -O2): measured on port_test.cpp, 5.3 s of CPU instead of 7.2 at -O2, and
  # test sources are most of a build's compile time (the CI's budget, .ci/run).
  target_compile_options(${name} PRIVATE $<$<CONFIG:RelWithDebInfo,Release>:-O1>)
  set(selected OFF)
  foreach(label IN LISTS ARG_LABELS)
    if(label IN_LIST COBRA_TEST_LABELS)
      set(selected ON)
    endif()
  endforeach()
  if(COBRA_TEST_LABELS AND NOT selected)
    set_target_properties(${name} PROPERTIES EXCLUDE_FROM_ALL ON)
    return()
  endif()
  set(first_label "")
  if(ARG_LABELS)
    list(GET ARG_LABELS 0 first_label)
  endif()
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "${first_label}" ${ARG_TEST_PROPERTIES})
  list(LENGTH ARG_LABELS label_count)
  if(label_count GREATER 1)
    # gtest_discover_tests passes its PROPERTIES on as separate words, which splits a list value:
    # the discovered tests (listed in ${name}_TESTS by its script) get their labels from a script
    # of ours that ctest includes after it.
    set(labels_script ${CMAKE_CURRENT_BINARY_DIR}/${name}_labels.cmake)
    file(WRITE ${labels_script} "if(${name}_TESTS)\n  set_tests_properties(\${${name}_TESTS} PROPERTIES LABELS \"${ARG_LABELS}\")\nendif()\n")
    set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${labels_script})
  endif()
  set_property(GLOBAL APPEND PROPERTY COBRA_SELECTED_TESTS ${name})
endfunction()

# cobra_add_unit_tests(<prefix> LIBS ... [LABELS label...] [THREADED unit...]): one test
# executable per test/<unit>_test.cpp of the calling directory, named <prefix>_<unit>_test. The
# THREADED units (e.g. server_test) run threads: also labelled concurrency (the TSan slice).
function(cobra_add_unit_tests prefix)
  cmake_parse_arguments(ARG "" "" "LIBS;LABELS;THREADED" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/test/*_test.cpp)
  foreach(source IN LISTS sources)
    get_filename_component(unit ${source} NAME_WE)
    set(labels ${ARG_LABELS})
    if(unit IN_LIST ARG_THREADED)
      list(APPEND labels concurrency)
    endif()
    cobra_add_test(${prefix}_${unit} SOURCES ${source} LIBS ${ARG_LIBS} LABELS ${labels})
    target_compile_definitions(${prefix}_${unit} PRIVATE COBRA_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  endforeach()
endfunction()
