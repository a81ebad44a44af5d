# SPDX-License-Identifier: Apache-2.0
# roz_idl_library(<target> <file.idl>... [USES <idl-target>...]): compiles IDL
# with Cyclone's idlc at build time into a static library of the generated C
# (types and topic descriptors), its headers on the include path of whoever
# links it. USES names roz_idl_library targets whose IDL these files
# #include (ROS 2's standard messages): their folders are on idlc's include
# path, their types are compiled there once and linked, not again here. The
# generated code is Cyclone's, built without roz's warning flags.
function(roz_idl_library target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "USES")
  find_program(ROZ_IDLC idlc DOC "Cyclone DDS's IDL compiler (Debian: cyclonedds-tools)")
  if(NOT ROZ_IDLC)
    message(FATAL_ERROR "idlc not found: apt-get install cyclonedds-tools")
  endif()
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${target})
  file(MAKE_DIRECTORY ${out})
  set(includes "")
  set(depends "")
  foreach(dep IN LISTS arg_USES)
    get_target_property(dep_idl ${dep} ROZ_IDL_FILES)
    foreach(f IN LISTS dep_idl)
      get_filename_component(dir ${f} DIRECTORY)
      list(APPEND includes -I${dir})
      list(APPEND depends ${f})
    endforeach()
  endforeach()
  list(REMOVE_DUPLICATES includes)
  set(sources "")
  set(idls "")
  foreach(idl IN LISTS arg_UNPARSED_ARGUMENTS)
    get_filename_component(abs ${idl} ABSOLUTE)
    get_filename_component(name ${idl} NAME_WE)
    add_custom_command(OUTPUT ${out}/${name}.c ${out}/${name}.h
                       COMMAND ${ROZ_IDLC} -Wno-implicit-extensibility ${includes} -o ${out} ${abs}
                       DEPENDS ${abs} ${depends}
                       COMMENT "idlc ${idl}")
    list(APPEND sources ${out}/${name}.c)
    list(APPEND idls ${abs})
  endforeach()
  add_library(${target} STATIC ${sources})
  set_target_properties(${target} PROPERTIES C_STANDARD 11 POSITION_INDEPENDENT_CODE ON
                                             ROZ_IDL_FILES "${idls}")
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${out}>)
  target_link_libraries(${target} PUBLIC CycloneDDS::ddsc ${arg_USES})
  if(ROZ_SANITIZE_FLAGS)
    target_compile_options(${target} PRIVATE ${ROZ_SANITIZE_FLAGS})
  endif()
endfunction()
