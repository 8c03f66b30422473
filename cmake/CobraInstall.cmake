# `cmake --install`: cobra's libraries, public headers, the `cobra` tool, the reusable charts and a
# CMake package (find_package(cobra) -> cobra::core, cobra::deploy, ..., cobra_add_package()).
# Included last from the top-level CMakeLists.txt, once every library target exists.
#
# The installed libraries are the framework's static archives. A component package is a MODULE
# that links none of them (cobra_add_package): it uses the cobra of the process that dlopens it,
# so the type registry, the package registry and every other singleton exist once. That process
# (the `cobra` tool, or a program linked with cobra_link_package_host) links every archive whole and
# exports its symbols, so a package may call any public function of any cobra library.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(COBRA_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/cobra CACHE STRING "Where cobraConfig.cmake is installed")
set(COBRA_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/cobra)
set(COBRA_INSTALL_PACKAGEDIR ${CMAKE_INSTALL_LIBDIR}/cobra/packages)

# cobra::deploy finds the installed data and packages relative to the running tool
# (install_layout.hpp): relocatable, no absolute path is compiled in.
file(RELATIVE_PATH cobra_data_from_bin ${CMAKE_INSTALL_FULL_BINDIR} ${CMAKE_INSTALL_FULL_DATADIR}/cobra)
file(RELATIVE_PATH cobra_packages_from_bin ${CMAKE_INSTALL_FULL_BINDIR} ${CMAKE_INSTALL_FULL_LIBDIR}/cobra/packages)
set_source_files_properties(${PROJECT_SOURCE_DIR}/deploy/src/install_layout.cpp DIRECTORY ${PROJECT_SOURCE_DIR}/deploy
  PROPERTIES COMPILE_DEFINITIONS
  "COBRA_DATA_DIR_FROM_BIN=\"${cobra_data_from_bin}\";COBRA_PACKAGE_DIR_FROM_BIN=\"${cobra_packages_from_bin}\"")
# cobra's charts, installed together in <prefix>/share/cobra/charts (COBRA_CHARTS in deployment
# files; on every Supervisor chart's package.path): the deployment and configuration supervisors
# (components/coordination/charts) and the steps of a task chart (components/task/charts).
set(COBRA_CHART_FOLDERS ${PROJECT_SOURCE_DIR}/components/coordination/charts ${PROJECT_SOURCE_DIR}/components/task/charts)
# The build tree mirrors the installed data beside the tool, so the tool built here finds it too:
# a charts folder of links to the charts' sources.
get_target_property(cobra_tool_dir cobra BINARY_DIR)
get_filename_component(cobra_build_data_dir ${cobra_tool_dir}/${cobra_data_from_bin} ABSOLUTE)
if(IS_SYMLINK ${cobra_build_data_dir}/charts)  # a build tree of before: one link to one folder
  file(REMOVE ${cobra_build_data_dir}/charts)
endif()
file(MAKE_DIRECTORY ${cobra_build_data_dir}/charts)
foreach(folder IN LISTS COBRA_CHART_FOLDERS)
  file(GLOB cobra_charts CONFIGURE_DEPENDS ${folder}/*.lua)
  foreach(chart IN LISTS cobra_charts)
    get_filename_component(chart_name ${chart} NAME)
    file(CREATE_LINK ${chart} ${cobra_build_data_dir}/charts/${chart_name} SYMBOLIC)
  endforeach()
endforeach()

# Every library target of the framework: those defined outside the applications, examples, tests,
# benchmarks and the tool's own sources. A library added later is installed too.
function(cobra_collect_libraries dir out)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  set(found)
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    if(NOT target MATCHES "^cobra_" OR NOT type MATCHES "^(STATIC_LIBRARY|SHARED_LIBRARY|INTERFACE_LIBRARY)$")
      continue()
    endif()
    file(RELATIVE_PATH where ${PROJECT_SOURCE_DIR} ${dir})
    if(where MATCHES "^(apps|examples|bench|fuzz|test_support|tools/cobra)(/|$)" OR where MATCHES "(^|/)test$")
      continue()
    endif()
    list(APPEND found ${target})
  endforeach()
  foreach(subdir IN LISTS subdirs)
    cobra_collect_libraries(${subdir} below)
    list(APPEND found ${below})
  endforeach()
  set(${out} ${found} PARENT_SCOPE)
endfunction()
cobra_collect_libraries(${PROJECT_SOURCE_DIR} COBRA_LIBRARIES)
# The tests' helpers (the counting operator new) serve packages' tests too.
if(TARGET cobra_test_support)
  list(APPEND COBRA_LIBRARIES cobra_test_support)
endif()

# The DDS type support fastddsgen generates (dds/CMakeLists.txt), installed as cobra::dds_types with
# its headers, so that a package can register its own types for DDS (cobra::types::registerType<T>
# with cobra_add_package(... USES cobra::dds): cobra/dds headers include the generated messages').
if(TARGET dds_generated_types)
  list(APPEND COBRA_LIBRARIES dds_generated_types)
  get_directory_property(cobra_dds_generated_dir DIRECTORY ${PROJECT_SOURCE_DIR}/dds DEFINITION COBRA_DDS_GENERATED_DIR)
  set(cobra_dds_generated_installed ${CMAKE_INSTALL_INCLUDEDIR}/cobra_dds_generated)
  install(DIRECTORY ${cobra_dds_generated_dir}/ DESTINATION ${cobra_dds_generated_installed}
    COMPONENT cobra_development FILES_MATCHING PATTERN "*.h" PATTERN "*.hpp")
  # The generated files include each other by bare name ("Point.h"): each message package's folder
  # is on the include path, as in the build tree.
  get_target_property(cobra_dds_generated_includes dds_generated_types INTERFACE_INCLUDE_DIRECTORIES)
  string(REGEX MATCHALL "\\$<BUILD_INTERFACE:[^>]+>" cobra_dds_generated_includes "${cobra_dds_generated_includes}")
  foreach(item IN LISTS cobra_dds_generated_includes)
    string(REGEX REPLACE "^\\$<BUILD_INTERFACE:(.+)>$" "\\1" dir "${item}")
    file(RELATIVE_PATH relative ${cobra_dds_generated_dir} ${dir})
    target_include_directories(dds_generated_types INTERFACE
      "$<INSTALL_INTERFACE:${cobra_dds_generated_installed}/${relative}>")
  endforeach()
endif()

# A library that links one of the left-out targets (an application's, the tool's) is left out too,
# until none is left: an installed library may depend only on installed ones.
set(cobra_dropping ON)
while(cobra_dropping)
  set(cobra_dropping OFF)
  foreach(target IN LISTS COBRA_LIBRARIES)
    get_target_property(links ${target} LINK_LIBRARIES)
    get_target_property(interface_links ${target} INTERFACE_LINK_LIBRARIES)
    foreach(link IN LISTS links interface_links)
      if(NOT TARGET "${link}")
        continue()
      endif()
      get_target_property(aliased ${link} ALIASED_TARGET)
      if(aliased)
        set(link ${aliased})
      endif()
      get_target_property(imported ${link} IMPORTED)
      if(NOT imported AND NOT link IN_LIST COBRA_LIBRARIES)
        message(STATUS "cobra: not installed: ${target} (it links ${link}, which is not installed)")
        list(REMOVE_ITEM COBRA_LIBRARIES ${target})
        set(cobra_dropping ON)
        break()
      endif()
    endforeach()
  endforeach()
endwhile()

# Lua and OMPL are found as paths, not imported targets: the installed targets name them through
# cobra::lua and cobra::ompl instead, which cobraConfig.cmake makes from the consumer's own
# find_package, so that no absolute path of this machine is installed.
get_directory_property(cobra_lua_libraries DIRECTORY ${PROJECT_SOURCE_DIR}/script DEFINITION LUA_LIBRARIES)
get_directory_property(cobra_ompl_library DIRECTORY ${PROJECT_SOURCE_DIR}/planning DEFINITION COBRA_OMPL_LIBRARY)
get_directory_property(cobra_ompl_includes DIRECTORY ${PROJECT_SOURCE_DIR}/planning DEFINITION OMPL_INCLUDE_DIRS)
# In <property> of <target>, the items among <paths> become build-only; <installed> (if not "")
# takes their place in the installed package.
function(cobra_install_through target property paths installed)
  get_target_property(items ${target} ${property})
  if(NOT items)
    return()
  endif()
  set(result)
  set(replaced OFF)
  foreach(item IN LISTS items)
    if(item IN_LIST paths)
      list(APPEND result "$<BUILD_INTERFACE:${item}>")
      set(replaced ON)
    else()
      list(APPEND result "${item}")
    endif()
  endforeach()
  if(replaced AND installed)
    list(APPEND result "$<INSTALL_INTERFACE:${installed}>")
  endif()
  set_target_properties(${target} PROPERTIES ${property} "${result}")
endfunction()
foreach(target IN LISTS COBRA_LIBRARIES)
  cobra_install_through(${target} INTERFACE_LINK_LIBRARIES "${cobra_lua_libraries}" cobra::lua)
  cobra_install_through(${target} INTERFACE_LINK_LIBRARIES "${cobra_ompl_library}" cobra::ompl)
  cobra_install_through(${target} INTERFACE_INCLUDE_DIRECTORIES "${cobra_ompl_includes}" "")
  cobra_install_through(${target} INTERFACE_SYSTEM_INCLUDE_DIRECTORIES "${cobra_ompl_includes}" "")
endforeach()

# Installed names follow the in-tree aliases: cobra_core -> cobra::core,
# cobra_components_signal -> cobra::components::signal, cobra_build_flags -> cobra::build_flags.
set(COBRA_EXPORTED_NAMES)
set(COBRA_HOST_TARGETS)
# Not linked into the hosts (COBRA_HOST_LIBRARIES, cobra_link_package_host), so neither the `cobra`
# tool nor a host program links cobra::dds or Fast DDS: the transport is the package cobra_dds
# (libcobra_dds.so, loaded RTLD_LOCAL, the one part of an install that needs the Fast DDS runtime),
# and a package that registers a type for DDS links the dds archives itself (cobra_add_package(...
# USES cobra::dds)); the two meet in core::TypeFacets. cobra::types is built without DDS and is an
# ordinary host library (architecture_tool_links_no_dds_test checks the tool).
set(COBRA_NOT_HOST_TARGETS cobra_dds dds_generated_types)
foreach(target IN LISTS COBRA_LIBRARIES)
  string(REGEX REPLACE "^cobra_" "" name ${target})
  string(REGEX REPLACE "^components_" "components::" name ${name})
  if(target STREQUAL "dds_generated_types")
    set(name dds_types)
  endif()
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  list(APPEND COBRA_EXPORTED_NAMES cobra::${name})
  get_target_property(type ${target} TYPE)
  if(NOT type STREQUAL "INTERFACE_LIBRARY" AND NOT target IN_LIST COBRA_NOT_HOST_TARGETS)
    list(APPEND COBRA_HOST_TARGETS cobra::${name})
  endif()
  # Public headers: the include folder of the target's build interface, as is.
  get_target_property(includes ${target} INTERFACE_INCLUDE_DIRECTORIES)
  if(includes)
    string(REGEX MATCHALL "\\$<BUILD_INTERFACE:[^>]+>" build_includes "${includes}")
    foreach(item IN LISTS build_includes)
      string(REGEX REPLACE "^\\$<BUILD_INTERFACE:(.+)>$" "\\1" include_dir "${item}")
      # (Not the build tree's generated headers, dds_types' above, though it may lie in the source tree.)
      if(include_dir MATCHES "^${PROJECT_SOURCE_DIR}/" AND NOT include_dir MATCHES "^${PROJECT_BINARY_DIR}/")
        install(DIRECTORY ${include_dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT cobra_development)
      endif()
    endforeach()
  endif()
endforeach()

install(TARGETS ${COBRA_LIBRARIES} EXPORT cobraTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT cobraTargets NAMESPACE cobra:: DESTINATION ${COBRA_INSTALL_CMAKEDIR} FILE cobraTargets.cmake)

# The `cobra` tool hosts packages: every library whole, symbols exported.
set(COBRA_HOST_TARGETS_IN_TREE)
foreach(name IN LISTS COBRA_HOST_TARGETS)
  string(REGEX REPLACE "^cobra::components::" "cobra_components_" target ${name})
  string(REGEX REPLACE "^cobra::" "cobra_" target ${target})
  list(APPEND COBRA_HOST_TARGETS_IN_TREE ${target})
endforeach()
cobra_link_package_host(cobra ${COBRA_HOST_TARGETS_IN_TREE})
install(TARGETS cobra RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

# Data the tool and deployment files use at run time, found relative to the tool
# (cobra::deploy::dataDirectory): <prefix>/share/cobra/charts.
foreach(folder IN LISTS COBRA_CHART_FOLDERS)
  install(DIRECTORY ${folder}/ DESTINATION ${COBRA_INSTALL_DATADIR}/charts)
endforeach()
install(FILES ${PROJECT_SOURCE_DIR}/cmake/CobraPackage.cmake DESTINATION ${COBRA_INSTALL_CMAKEDIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/cobraConfig.cmake.in
  ${PROJECT_BINARY_DIR}/cobraConfig.cmake INSTALL_DESTINATION ${COBRA_INSTALL_CMAKEDIR}
  PATH_VARS COBRA_INSTALL_DATADIR COBRA_INSTALL_PACKAGEDIR CMAKE_INSTALL_BINDIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/cobraConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/cobraConfig.cmake ${PROJECT_BINARY_DIR}/cobraConfigVersion.cmake
  DESTINATION ${COBRA_INSTALL_CMAKEDIR})

# Installs into a temporary prefix, builds examples/06_package and a `cobra new component` package
# against it with their own CMake, and runs them (the generated code is built plainly: not in
# sanitizer builds).
if(COBRA_BUILD_TESTS AND COBRA_SANITIZER STREQUAL "")
  add_test(NAME install_out_of_tree_package
    COMMAND ${PROJECT_SOURCE_DIR}/cmake/install_test.sh ${PROJECT_BINARY_DIR} ${PROJECT_SOURCE_DIR})
  set_tests_properties(install_out_of_tree_package PROPERTIES LABELS install TIMEOUT 600
    PASS_REGULAR_EXPRESSION "installed cobra builds and runs an out-of-tree package")
endif()
