# The applications of cobra's tree (apps/) and the tests that run them.
#
# An application's C++ is a loadable package, built as an out-of-tree package is
# (CobraPackage.cmake: a MODULE that links no cobra library) and written where the `cobra` tool
# built here finds packages: the build tree mirrors the install layout beside the tool
# (<bin>/../lib/cobra/packages; its data, cobra's charts, in <bin>/../share/cobra). No cobra
# library, tool or test outside apps/ links an application's target or includes its headers
# (architecture_dependency_direction_test checks it).
include(GNUInstallDirs)
file(RELATIVE_PATH cobra_apps_packages_from_bin ${CMAKE_INSTALL_FULL_BINDIR} ${CMAKE_INSTALL_FULL_LIBDIR}/cobra/packages)
file(RELATIVE_PATH cobra_apps_data_from_bin ${CMAKE_INSTALL_FULL_BINDIR} ${CMAKE_INSTALL_FULL_DATADIR}/cobra)
get_filename_component(COBRA_BUILD_PACKAGE_DIR ${PROJECT_BINARY_DIR}/tools/cobra/${cobra_apps_packages_from_bin} ABSOLUTE)
get_filename_component(COBRA_BUILD_DATA_DIR ${PROJECT_BINARY_DIR}/tools/cobra/${cobra_apps_data_from_bin} ABSOLUTE)

# The cobra libraries whose code the applications' packages call (beyond the headers they
# include): a program that loads those packages links them whole and exports them.
set(COBRA_APP_PACKAGE_HOST_LIBRARIES cobra_core cobra_deploy cobra_trajectory cobra_task cobra_components_motion
    cobra_components_task cobra_planning cobra_task_planning cobra_components_planning)

# cobra_app_package(<name> SOURCES <file>... [USES <cobra target>...] [LIBS <library>...])
#   The application package lib<name>.so, written beside the tool's packages (the tool depends on
#   it, so `cobra run apps/X` finds it without COBRA_PACKAGE_PATH).
function(cobra_app_package name)
  cobra_add_package(${name} ${ARGN} OUTPUT_DIRECTORY ${COBRA_BUILD_PACKAGE_DIR})
  target_link_libraries(${name} PRIVATE cobra_build_flags)
  add_dependencies(cobra ${name})
endfunction()

# cobra_host_app_packages(<test target> <package>...)
#   Test executable <test target> loads the applications' packages <package>... as `cobra run`
#   does: it links the libraries they call whole and exports them (cobra_link_package_host), is
#   built after them, and its tests find them and cobra's charts as the tool does
#   (COBRA_PACKAGE_PATH, COBRA_DATA_DIR: the build tree's mirror of the install layout).
function(cobra_host_app_packages target)
  if(NOT TARGET ${target})
    return()
  endif()
  cobra_link_package_host(${target} ${COBRA_APP_PACKAGE_HOST_LIBRARIES})
  if(ARGN)
    add_dependencies(${target} ${ARGN})
  endif()
  cobra_app_test_environment(${target})
endfunction()

# cobra_app_test_environment(<test target>)
#   The tests of <test target> (gtest_discover_tests: the list ${target}_TESTS) find the build's
#   packages and cobra's charts as the tool built here does. Through a script ctest includes after
#   the discovered tests (PROPERTIES of gtest_discover_tests would split the list).
function(cobra_app_test_environment target)
  set(script ${CMAKE_CURRENT_BINARY_DIR}/${target}_app_environment.cmake)
  file(WRITE ${script}
    "if(${target}_TESTS)\n"
    "  set_tests_properties(\${${target}_TESTS} PROPERTIES ENVIRONMENT_MODIFICATION\n"
    "    \"COBRA_PACKAGE_PATH=set:${COBRA_BUILD_PACKAGE_DIR};COBRA_DATA_DIR=set:${COBRA_BUILD_DATA_DIR}\")\n"
    "endif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${script})
endfunction()
