# SPDX-License-Identifier: Apache-2.0
# roz_idl_library(<target> <file.idl>...): compiles IDL with Cyclone's idlc at
# build time into a static library of the generated C (types and topic
# descriptors), its headers on the include path of whoever links it. The
# generated code is Cyclone's, built without roz's warning flags.
function(roz_idl_library target)
  find_program(ROZ_IDLC idlc DOC "Cyclone DDS's IDL compiler (Debian: cyclonedds-tools)")
  if(NOT ROZ_IDLC)
    message(FATAL_ERROR "idlc not found: apt-get install cyclonedds-tools")
  endif()
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${target})
  file(MAKE_DIRECTORY ${out})
  set(sources "")
  foreach(idl IN LISTS ARGN)
    get_filename_component(abs ${idl} ABSOLUTE)
    get_filename_component(name ${idl} NAME_WE)
    add_custom_command(OUTPUT ${out}/${name}.c ${out}/${name}.h
                       COMMAND ${ROZ_IDLC} -Wno-implicit-extensibility -o ${out} ${abs}
                       DEPENDS ${abs}
                       COMMENT "idlc ${idl}")
    list(APPEND sources ${out}/${name}.c)
  endforeach()
  add_library(${target} STATIC ${sources})
  set_target_properties(${target} PROPERTIES C_STANDARD 11 POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${out}>)
  target_link_libraries(${target} PUBLIC CycloneDDS::ddsc)
  if(ROZ_SANITIZE_FLAGS)
    target_compile_options(${target} PRIVATE ${ROZ_SANITIZE_FLAGS})
  endif()
endfunction()
