# The applications of cobra's tree (apps/) and the tests that run them.
#
# An application's C++ is a loadable package, built as an out-of-tree package is
# (CobraPackage.cmake: a MODULE that links no cobra library) and written where the `cobra` tool
# built here finds packages: the build tree mirrors the install layout beside the tool
# (<bin>/../lib/cobra/packages; its data, cobra's charts, in <bin>/../share/cobra). No cobra
# library links an application's target (apps_depend_on_no_library_test checks it).
include(GNUInstallDirs)
file(RELATIVE_PATH cobra_apps_packages_from_bin ${CMAKE_INSTALL_FULL_BINDIR} ${CMAKE_INSTALL_FULL_LIBDIR}/cobra/packages)
file(RELATIVE_PATH cobra_apps_data_from_bin ${CMAKE_INSTALL_FULL_BINDIR} ${CMAKE_INSTALL_FULL_DATADIR}/cobra)
get_filename_component(COBRA_BUILD_PACKAGE_DIR ${PROJECT_BINARY_DIR}/tools/cobra/${cobra_apps_packages_from_bin} ABSOLUTE)
get_filename_component(COBRA_BUILD_DATA_DIR ${PROJECT_BINARY_DIR}/tools/cobra/${cobra_apps_data_from_bin} ABSOLUTE)

# The cobra libraries whose code the applications' packages call (beyond the headers they
# include): a program that loads those packages links them whole and exports them.
set(COBRA_APP_PACKAGE_HOST_LIBRARIES cobra_core cobra_deploy cobra_trajectory cobra_task cobra_components_motion
    cobra_components_task)

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

# cobra_check_libraries_know_no_app(): called once every target exists. The test
# libraries_know_no_app fails when a target of cobra's libraries, tools or their tests links a
# target defined under apps/, or when a source file of theirs includes a header of an application
# (an include folder under apps/). What it found at configure is in libraries_linking_apps.txt.
function(cobra_check_libraries_know_no_app)
  set(library_folders core statechart trajectory kinematics control planning sim fieldbus script deploy run
      components task text dds bridges studio tools test_support)
  # Every folder of the build, below the top one.
  function(cobra_folders_below dir out)
    get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
    set(found ${subdirs})
    foreach(subdir IN LISTS subdirs)
      cobra_folders_below(${subdir} below)
      list(APPEND found ${below})
    endforeach()
    set(${out} ${found} PARENT_SCOPE)
  endfunction()
  cobra_folders_below(${PROJECT_SOURCE_DIR} folders)
  # Every target under apps/, by name.
  set(app_targets "")
  foreach(part IN LISTS folders)
    file(RELATIVE_PATH where ${PROJECT_SOURCE_DIR} ${part})
    if(where MATCHES "^apps(/|$)")
      get_property(targets DIRECTORY ${part} PROPERTY BUILDSYSTEM_TARGETS)
      list(APPEND app_targets ${targets})
    endif()
  endforeach()
  set(violations "")
  foreach(part IN LISTS folders)
    file(RELATIVE_PATH where ${PROJECT_SOURCE_DIR} ${part})
    string(REGEX REPLACE "/.*" "" top "${where}")
    if(NOT top IN_LIST library_folders)
      continue()
    endif()
    get_property(targets DIRECTORY ${part} PROPERTY BUILDSYSTEM_TARGETS)
    foreach(target IN LISTS targets)
      get_target_property(links ${target} LINK_LIBRARIES)
      get_target_property(interface_links ${target} INTERFACE_LINK_LIBRARIES)
      foreach(link IN LISTS links interface_links)
        if(TARGET "${link}")
          get_target_property(aliased ${link} ALIASED_TARGET)
          if(aliased)
            set(link ${aliased})
          endif()
          if(link IN_LIST app_targets)
            string(APPEND violations "${target} (${where}) links ${link}, an application's target\n")
          endif()
        endif()
      endforeach()
    endforeach()
  endforeach()
  file(WRITE ${PROJECT_BINARY_DIR}/libraries_linking_apps.txt "${violations}")
  if(COBRA_BUILD_TESTS)
    add_test(NAME libraries_know_no_app
      COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${PROJECT_SOURCE_DIR} -DLINKS=${PROJECT_BINARY_DIR}/libraries_linking_apps.txt
              "-DFOLDERS=${library_folders}" -P ${PROJECT_SOURCE_DIR}/cmake/check_libraries_know_no_app.cmake)
    set_tests_properties(libraries_know_no_app PROPERTIES LABELS apps
      PASS_REGULAR_EXPRESSION "no library knows an application")
  endif()
endfunction()
