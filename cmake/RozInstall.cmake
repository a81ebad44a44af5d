# SPDX-License-Identifier: Apache-2.0
# Install rules: find_package(roz CONFIG) gives a consumer the same roz::
# targets, roz_generate(), roz_add_wasm_controller() and
# roz_add_rust_controller() that
# add_subdirectory(roz) does, and nothing in the prefix names the tree it
# was built in. What goes where (under the prefix):
#   include/roz/             the public headers (roz/features.h included)
#   include/roz/sdk/         the controller SDK (roz_controller.h), roz::sdk
#   include/roz/manifests/   the built-in manifests' generated headers
#   lib/                     the static libraries: the registered ports' and their
#                            rules' (cmake/RozPort.cmake; roz::dds and the DDS ports
#                            where Cyclone DDS was found: the package then needs it too)
#   lib/cmake/roz/           the package: rozConfig.cmake, targets, RozGenerate.cmake, RozWasm.cmake,
#                            RozRust.cmake, toolchains/ (the Cortex-M toolchain files)
#   lib/roz/python/          rozgen and its pinned dependencies (RozInstallRozgen.cmake)
#   bin/                     rozgen, rozrun, roz_manifest_json, roz_manifest_info
#   share/roz/sdk/rust/      the Rust controller SDK's crate (roz_controller)
#   share/roz/manifests/     the built-in manifests' robot.toml files
#   share/doc/roz/           licences
include(CMakePackageConfigHelpers)

set(ROZ_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/roz)
set(_roz_targets roz_core roz_hal roz_sdk)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/sdk/include/
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/roz/sdk FILES_MATCHING PATTERN "*.h")
install(FILES ${PROJECT_SOURCE_DIR}/lib/math/roz_math.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/roz/sdk)
# the built-in manifests, which `rozgen-nn deploy --robot <name>` reads
file(GLOB _roz_tomls ${PROJECT_SOURCE_DIR}/manifests/*.toml)
install(FILES ${_roz_tomls} DESTINATION ${CMAKE_INSTALL_DATADIR}/roz/manifests)
# the Rust controller SDK's crate (roz_add_rust_controller(), docs/rust.md)
set(ROZ_INSTALL_RUSTDIR ${CMAKE_INSTALL_DATADIR}/roz/sdk/rust)
install(FILES ${PROJECT_SOURCE_DIR}/sdk/rust/Cargo.toml DESTINATION ${ROZ_INSTALL_RUSTDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/sdk/rust/src DESTINATION ${ROZ_INSTALL_RUSTDIR}
        FILES_MATCHING PATTERN "*.rs")
install(DIRECTORY ${PROJECT_SOURCE_DIR}/hal/include/roz DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h")
# The ports' libraries, their rules' and the plumbing they share, with their
# headers, and what the package must find first for them: the registry's
# (roz_add_port(), roz_add_port_rules(), roz_port_export() in
# cmake/RozPort.cmake), below.
get_property(ROZ_PORT_PACKAGE_CONFIG GLOBAL PROPERTY ROZ_PORT_PACKAGE_CONFIG)
if(TARGET roz_wasm3)
  # Static roz_core links it PRIVATE, so a consumer's link line needs it.
  list(APPEND _roz_targets roz_wasm3)
  set_target_properties(roz_wasm3 PROPERTIES EXPORT_NAME wasm3)
endif()
# the host libraries, host/<name> as roz_<name> (gamepad: a Linux gamepad as
# the operator's remote, roz/gamepad.h)
foreach(_lib IN ITEMS toml run record gamepad)
  if(TARGET roz_${_lib})
    list(APPEND _roz_targets roz_${_lib})
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/host/${_lib}/include/roz
            DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
  endif()
endforeach()
if(TARGET roz_manifests)
  list(APPEND _roz_targets roz_manifests)
  target_include_directories(roz_manifests PUBLIC
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/roz/manifests>)
  install(DIRECTORY ${PROJECT_BINARY_DIR}/manifests/generated/
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/roz/manifests
          FILES_MATCHING PATTERN "*.h")
endif()

# Every registered port, what it exports with it, and the registry
# (roz_add_port(), cmake/RozPort.cmake, which installs their headers).
# A build for one firmware (ROZ_CONFIG_HEADER): its configuration, roz::config.
if(ROZ_CONFIG_HEADER AND TARGET roz_config)
  list(APPEND _roz_targets roz_config)
  install(FILES ${ROZ_CONFIG_HEADER} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/roz/config)
endif()
get_property(_roz_port_targets GLOBAL PROPERTY ROZ_PORT_EXPORTS)
list(APPEND _roz_targets ${_roz_port_targets})
list(REMOVE_DUPLICATES _roz_targets)
install(TARGETS ${_roz_targets} EXPORT rozTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/lib/include/roz DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h")
install(FILES ${PROJECT_BINARY_DIR}/lib/include/roz/features.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/roz)
install(EXPORT rozTargets NAMESPACE roz:: DESTINATION ${ROZ_INSTALL_CMAKEDIR})

# The host tools (tools/).
foreach(tool IN ITEMS rozrun roz_manifest_json roz_manifest_info)
  if(TARGET ${tool})
    install(TARGETS ${tool} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endforeach()
include(RozInstallRozgen)

set(ROZ_INSTALL_BINDIR ${CMAKE_INSTALL_BINDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/rozConfig.cmake.in
  ${PROJECT_BINARY_DIR}/rozConfig.cmake INSTALL_DESTINATION ${ROZ_INSTALL_CMAKEDIR}
  PATH_VARS ROZ_INSTALL_BINDIR ROZ_INSTALL_RUSTDIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/rozConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/rozConfig.cmake ${PROJECT_BINARY_DIR}/rozConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/RozGenerate.cmake ${PROJECT_SOURCE_DIR}/cmake/RozWasm.cmake
              ${PROJECT_SOURCE_DIR}/cmake/RozRust.cmake
        DESTINATION ${ROZ_INSTALL_CMAKEDIR})

# the Cortex-M toolchain files, for a firmware that finds this package
# (examples/firmware/CMakeLists.txt looks for them here)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/cmake/toolchains DESTINATION ${ROZ_INSTALL_CMAKEDIR})

install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR})
if(ROZ_WASM3_LICENSE_FILE)
  install(FILES ${ROZ_WASM3_LICENSE_FILE} DESTINATION ${CMAKE_INSTALL_DOCDIR}
          RENAME LICENSE.wasm3)
endif()
