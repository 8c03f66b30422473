# Building component packages for cobra: used in cobra's tree and installed with the CMake package
# (find_package(cobra) includes it).
#
# A package is a MODULE library `lib<name>.so` that a deployment names in `packages_list`; the
# deployer dlopens it and calls its `cobra_register_package` (cobra/deploy/package_registry.hpp).
# It links no cobra library: it uses the cobra of the process that loads it (the `cobra` tool or
# a program linked with cobra_link_package_host), so cobra's registries exist once.

# cobra_add_package(<name> SOURCES <file>... [USES <cobra target>...] [LIBS <library>...]
#                   [OUTPUT_DIRECTORY <dir>] [INSTALL])
#   Builds the loadable package lib<name>.so from SOURCES.
#   USES: the cobra libraries whose headers the package includes beyond cobra::core and
#         cobra::deploy (e.g. cobra::kinematics); their code comes from the loading process.
#         Except cobra::dds: the loading process (the `cobra` tool, a host program) links no DDS;
#         the transport is a package of its own (cobra_dds). So a package that registers its
#         types for DDS (cobra::types::registerType<T>() with cobra::dds in USES: the dds headers
#         on its include path compile the DDS side of registerType<T>() in) links the dds
#         archives and Fast DDS itself; the transport finds the types through core::TypeFacets.
#         Without cobra::dds, registerType<T>() registers core, Lua and CSV only.
#   LIBS: other libraries the package links itself (e.g. a device's vendor library).
#   OUTPUT_DIRECTORY: where lib<name>.so is written (default: CMake's usual place).
#   INSTALL: `cmake --install` puts it in <prefix>/lib/cobra/packages (COBRA_INSTALL_PACKAGEDIR),
#            where the installed `cobra` tool finds packages without COBRA_PACKAGE_PATH when both
#            share a prefix.
function(cobra_add_package name)
  cmake_parse_arguments(ARG "INSTALL" "OUTPUT_DIRECTORY" "SOURCES;USES;LIBS" ${ARGN})
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "cobra_add_package(${name}): no SOURCES; a package needs at least the file that defines "
                        "cobra_package_abi() and cobra_register_package()")
  endif()
  add_library(${name} MODULE ${ARG_SOURCES})
  foreach(used IN ITEMS cobra::core cobra::deploy LISTS ARG_USES)
    if(NOT TARGET ${used})
      message(FATAL_ERROR "cobra_add_package(${name}): USES ${used}: no such cobra target")
    endif()
    # Headers and definitions only: the symbols are the loading process's.
    target_include_directories(${name} SYSTEM PRIVATE $<TARGET_PROPERTY:${used},INTERFACE_INCLUDE_DIRECTORIES>)
    target_compile_definitions(${name} PRIVATE $<TARGET_PROPERTY:${used},INTERFACE_COMPILE_DEFINITIONS>)
  endforeach()
  if(cobra::dds IN_LIST ARG_USES)
    # The archives' files, not the targets: the targets would bring cobra::core's archive too (a
    # second core in the package). Fast DDS is a shared library: one in the process.
    foreach(used IN ITEMS cobra::dds_types)
      target_include_directories(${name} SYSTEM PRIVATE $<TARGET_PROPERTY:${used},INTERFACE_INCLUDE_DIRECTORIES>)
    endforeach()
    target_link_libraries(${name} PRIVATE $<TARGET_FILE:cobra::dds> $<TARGET_FILE:cobra::dds_types> fastrtps fastcdr)
  endif()
  target_link_libraries(${name} PRIVATE ${ARG_LIBS})
  target_compile_features(${name} PRIVATE cxx_std_20)
  # `packages_list = { "<name>" }` looks for lib<name>.so whatever the platform's module prefix.
  set_target_properties(${name} PROPERTIES PREFIX "lib" SUFFIX ".so")
  if(ARG_OUTPUT_DIRECTORY)
    set_target_properties(${name} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${ARG_OUTPUT_DIRECTORY})
  endif()
  if(ARG_INSTALL)
    # The installed tool's folder, relative to the prefix (cobraConfig.cmake sets it).
    set(destination ${COBRA_INSTALL_PACKAGEDIR})
    if(NOT destination)
      include(GNUInstallDirs)
      set(destination ${CMAKE_INSTALL_LIBDIR}/cobra/packages)
    endif()
    install(TARGETS ${name} LIBRARY DESTINATION ${destination})
  endif()
endfunction()

# cobra_link_package_host(<target> [<cobra library>...])
#   Makes executable <target> able to load packages: links the given cobra libraries (default:
#   all of them, COBRA_HOST_LIBRARIES) whole, so that every public function a package may call
#   is in the executable, and exports the executable's symbols to the packages it dlopens.
function(cobra_link_package_host target)
  set(libraries ${ARGN})
  if(NOT libraries)
    set(libraries ${COBRA_HOST_LIBRARIES})
  endif()
  set(archives)
  foreach(library IN LISTS libraries)
    string(APPEND archives " $<TARGET_FILE:${library}>")
  endforeach()
  # As link options, the whole archives come before the objects and libraries of the link line:
  # every object of each archive is in, and a later mention of the same archive adds nothing
  # (linked whole after an ordinary mention, its objects would be defined twice).
  target_link_options(${target} PRIVATE "SHELL:-Wl,--whole-archive${archives} -Wl,--no-whole-archive")
  target_link_libraries(${target} PRIVATE ${libraries})
  set_target_properties(${target} PROPERTIES ENABLE_EXPORTS ON)
endfunction()

# cobra_add_package_test(<name> PACKAGE <package> SOURCES <file>... [LIBS <library>...])
#   A GoogleTest executable that loads <package> as a deployment would (PackageRegistry, dlopen),
#   registered with CTest. It sees COBRA_PACKAGE_DIR (the folder of lib<package>.so) and
#   COBRA_PACKAGE_NAME as compile definitions, and cobra's test helpers
#   (cobra/test_support/counting_new.hpp: prove that an update allocates nothing, in the package
#   too). Needs find_package(GTest) first.
function(cobra_add_package_test name)
  cmake_parse_arguments(ARG "" "PACKAGE" "SOURCES;LIBS" ${ARGN})
  if(NOT ARG_PACKAGE OR NOT TARGET ${ARG_PACKAGE})
    message(FATAL_ERROR "cobra_add_package_test(${name}): PACKAGE must name a cobra_add_package() target")
  endif()
  if(NOT TARGET cobra::test_support)
    message(FATAL_ERROR "cobra_add_package_test(${name}): cobra::test_support is missing (cobra was built "
                        "with COBRA_BUILD_TESTS=OFF, which leaves out its test helpers)")
  endif()
  add_executable(${name} ${ARG_SOURCES})
  cobra_link_package_host(${name})
  target_link_libraries(${name} PRIVATE cobra::test_support GTest::gtest GTest::gtest_main ${ARG_LIBS})
  target_compile_definitions(${name} PRIVATE COBRA_PACKAGE_DIR="$<TARGET_FILE_DIR:${ARG_PACKAGE}>"
                                             COBRA_PACKAGE_NAME="${ARG_PACKAGE}")
  add_dependencies(${name} ${ARG_PACKAGE})
  add_test(NAME ${name} COMMAND ${name})
endfunction()
