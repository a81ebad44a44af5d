# SPDX-License-Identifier: Apache-2.0
# The port registry. Each port's CMakeLists.txt registers its library once:
#
#   roz_add_port(NAME socketcan TARGET roz_port_socketcan HEADER roz/port/socketcan.h
#                TYPE roz_socketcan_t CONSTRUCTOR roz_socketcan_port
#                DOCS docs/ports/socketcan.md [more pages ...]
#                [OPS roz_socketcan_ops] [EXPORT roz_extra_target ...])
#
# DOCS: its pages, from the top of the source tree (the first its own): the
# registry carries them, so the docs test and the ports index need no list.
#
# which gives the target its roz::port_<NAME> alias (when it has none yet),
# installs its include/ folder and exports it (with the EXPORT targets: its
# generated IDL types, say) in rozTargets. roz_ports_generate(), called
# once after every port, writes roz/ports.h and ports.c (generated, do not
# edit) into the build tree: the registered ports, each with its ops,
# sizeof and alignment of its instance and a function that constructs it
# in caller storage; and the library roz_ports (roz::ports) that holds that
# table and links every registered port. rozrun, the conformance suite, the
# benchmarks and the consumer tests enumerate ports from it.
# The port's constructor has the one shape every port has:
#   roz_port_t CONSTRUCTOR(TYPE *self, roz_log_fn log, void *log_ctx);

# roz__require(WHO PREFIX KEY...): fails, naming WHO, unless each of the
# caller's <PREFIX>_<KEY> (cmake_parse_arguments) is set.
function(roz__require who prefix)
  foreach(k IN LISTS ARGN)
    if(NOT ${prefix}_${k})
      message(FATAL_ERROR "${who}: ${k} is required")
    endif()
  endforeach()
endfunction()

# roz__register_once(WHO PROPERTY NAME): appends NAME to the global list
# PROPERTY; fails, naming WHO, where it is there already.
function(roz__register_once who property name)
  get_property(names GLOBAL PROPERTY ${property})
  if(name IN_LIST names)
    message(FATAL_ERROR "${who}: ${name} registered twice")
  endif()
  set_property(GLOBAL APPEND PROPERTY ${property} ${name})
endfunction()

# A port's rules of its own [hardware] keys, in a library without any
# transport (so that roz_manifest_json, and through it rozgen, runs them):
#
#   roz_add_port_rules(PORT socketcan TARGET roz_can HEADER roz/port/can_config.h
#                      FUNCTION roz_can_config_check RULE_IDS roz_can_rule_ids
#                      [FILES_FUNCTION fn])
#
# PORT is the name robot.toml's [hardware] port gives; FUNCTION has the shape
#   int FUNCTION(const roz_manifest_t *m, roz_port_rules_report_fn report, void *ctx);
# and reports every problem (report(ctx, rule id, text after the file name))
# of a manifest that passed the robot.toml rules, returning ROZ_OK or
# ROZ_EINVAL. RULE_IDS names the port's rule ids and what each refuses,
# beside its rules:
#   const char *const RULE_IDS[] = { "can-id\tsocketcan port: two joints ...", ..., NULL };
# (roz_manifest_json --list-rules prints them; rozgen --list-rules and
# rozgen's rule ids take them from there). FILES_FUNCTION, for a port whose keys name files (the mujoco
# port's model), runs after it passed, with the robot.toml's path:
#   int FILES_FUNCTION(const roz_manifest_t *m, const char *robot_toml,
#                      roz_port_rules_report_fn report, void *ctx);
# roz_port_rules_generate() writes the table, roz/port_rules.h (library
# roz_port_rules). The rules library is installed and exported (rozTargets)
# with the calling folder's include/roz headers, whether the port is built
# or not.
#
# A port folder's other libraries (the plumbing ports share: roz::dds,
# roz::ros2, ...) are installed and exported the same way:
#
#   roz_port_export(TARGETS roz_dds [CONFIG "find_dependency(CycloneDDS CONFIG)"])
#
# CONFIG: what the installed package's rozConfig.cmake runs before it
# includes the targets (a dependency they link). cmake/RozInstall.cmake
# names no port.
function(roz_port_export)
  cmake_parse_arguments(E "" "CONFIG" "TARGETS" ${ARGN})
  set_property(GLOBAL APPEND PROPERTY ROZ_PORT_EXPORTS ${E_TARGETS})
  if(E_CONFIG)
    set_property(GLOBAL APPEND_STRING PROPERTY ROZ_PORT_PACKAGE_CONFIG "${E_CONFIG}\n")
  endif()
  _roz_port_install_headers()
endfunction()

function(_roz_port_install_headers)
  if(ROZ_INSTALL AND EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/include/roz)
    install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/roz
            DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
  endif()
endfunction()

function(roz_add_port_rules)
  cmake_parse_arguments(R "" "PORT;TARGET;HEADER;FUNCTION;FILES_FUNCTION;RULE_IDS" "" ${ARGN})
  if(NOT R_FILES_FUNCTION)
    set(R_FILES_FUNCTION NULL)
  endif()
  roz__require(roz_add_port_rules R PORT TARGET HEADER FUNCTION RULE_IDS)
  roz__register_once(roz_add_port_rules ROZ_PORT_RULES_PORTS ${R_PORT})
  set_property(GLOBAL APPEND PROPERTY ROZ_PORT_RULES_ENTRIES
               "${R_PORT}|${R_TARGET}|${R_HEADER}|${R_FUNCTION}|${R_FILES_FUNCTION}|${R_RULE_IDS}")
  roz_port_export(TARGETS ${R_TARGET})
endfunction()

# Writes the table of the port rules registered so far: roz/port_rules.h and
# port_rules.c in the build tree, and the library roz_port_rules.
function(roz_port_rules_generate)
  get_property(entries GLOBAL PROPERTY ROZ_PORT_RULES_ENTRIES)
  set(dir ${PROJECT_BINARY_DIR}/ports/generated_rules)
  set(banner "generated by cmake/RozPort.cmake (roz_port_rules_generate()) from the roz_add_port_rules() calls of this build; do not edit")
  set(includes "")
  set(rows "")
  set(libs "")
  foreach(e IN LISTS entries)
    string(REPLACE "|" ";" e "${e}")
    list(GET e 0 port)
    list(GET e 1 target)
    list(GET e 2 header)
    list(GET e 3 fn)
    list(GET e 4 files_fn)
    list(GET e 5 ids)
    list(APPEND libs ${target})
    string(APPEND includes "#include \"${header}\"\n")
    string(APPEND rows "    { \"${port}\", ${fn}, ${files_fn}, ${ids} },\n")
  endforeach()
  string(APPEND rows "    { NULL, NULL, NULL, NULL },\n")
  file(CONFIGURE OUTPUT ${dir}/include/roz/port_rules.h @ONLY CONTENT [=[
/* SPDX-License-Identifier: Apache-2.0 */
/* @banner@ */
/**
 * @file roz/port_rules.h
 * @brief The ports' rules of their own [hardware] keys that this build
 *        holds (roz_add_port_rules()): what roz_manifest_json, and so
 *        rozgen, checks after the robot.toml rules.
 */
#ifndef ROZ_PORT_RULES_H
#define ROZ_PORT_RULES_H

#include "roz/config.h"

#include <stddef.h>

#include "roz/manifest.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Called once per problem: a rule id ("can-id") and the text after the
 *  file name (": hardware.params: ..."). */
typedef void (*roz_port_rules_report_fn)(void *ctx, const char *rule, const char *text);

/** One port's rules. */
typedef struct roz_port_rules {
    const char *port; /**< [hardware] port = "..." */
    /** ROZ_OK, or ROZ_EINVAL with every problem reported. Context: start-up
     *  or host tools; no heap. */
    int (*check_hardware)(const roz_manifest_t *m, roz_port_rules_report_fn report, void *ctx);
    /** The rules on the files its keys name (a model), run once
     *  check_hardware() passed; @p robot_toml is the file @p m was read
     *  from (paths are relative to its folder; NULL: the working
     *  directory). ROZ_OK, or ROZ_EINVAL with the problem reported. NULL:
     *  none. Context: host tools; may allocate. */
    int (*check_files)(const roz_manifest_t *m, const char *robot_toml,
                       roz_port_rules_report_fn report, void *ctx);
    /** Its rule ids and what each refuses, "<id>\t<what>", NULL-ended. */
    const char *const *rule_ids;
} roz_port_rules_t;

/** @brief The rules of the port @p port names; NULL when it has none here
 *  (its keys are then checked by the port alone, at open). Context: any. */
const roz_port_rules_t *roz_port_rules_find(const char *port);

/** @brief The @p i-th port's rules, in registration order; NULL past the
 *  last. Context: any. */
const roz_port_rules_t *roz_port_rules_at(size_t i);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORT_RULES_H */
]=])
  file(CONFIGURE OUTPUT ${dir}/port_rules.c @ONLY CONTENT [=[
/* SPDX-License-Identifier: Apache-2.0 */
/* @banner@ */
#include "roz/port_rules.h"

#include <string.h>

@includes@
static const roz_port_rules_t rules[] = {
@rows@};

const roz_port_rules_t *roz_port_rules_find(const char *port)
{
    for (size_t i = 0; port != NULL && rules[i].port != NULL; i++) {
        if (strcmp(rules[i].port, port) == 0)
            return &rules[i];
    }
    return NULL;
}

const roz_port_rules_t *roz_port_rules_at(size_t i)
{
    return i < sizeof rules / sizeof rules[0] - 1 ? &rules[i] : NULL;
}
]=])
  add_library(roz_port_rules STATIC EXCLUDE_FROM_ALL ${dir}/port_rules.c)
  set_target_properties(roz_port_rules PROPERTIES C_STANDARD 11 C_STANDARD_REQUIRED ON
                        C_EXTENSIONS OFF POSITION_INDEPENDENT_CODE ${ROZ_PIC})
  target_include_directories(roz_port_rules PUBLIC $<BUILD_INTERFACE:${dir}/include>)
  target_link_libraries(roz_port_rules PUBLIC ${libs} roz_core)
  roz_target_warnings(roz_port_rules)
endfunction()

function(roz_add_port)
  cmake_parse_arguments(P "" "NAME;TARGET;HEADER;TYPE;CONSTRUCTOR;OPS" "EXPORT;DOCS" ${ARGN})
  roz__require(roz_add_port P NAME TARGET HEADER TYPE CONSTRUCTOR DOCS)
  if(NOT TARGET ${P_TARGET})
    message(FATAL_ERROR "roz_add_port(${P_NAME}): no target ${P_TARGET}")
  endif()
  if(NOT P_OPS)
    set(P_OPS roz_${P_NAME}_ops)
  endif()
  roz__register_once(roz_add_port ROZ_PORT_NAMES ${P_NAME})
  foreach(p IN LISTS P_DOCS)
    if(NOT EXISTS ${PROJECT_SOURCE_DIR}/${p})
      message(FATAL_ERROR "roz_add_port(${P_NAME}): DOCS ${p}: no such page")
    endif()
  endforeach()
  list(JOIN P_DOCS " " P_DOCS)
  foreach(k IN ITEMS TARGET HEADER TYPE CONSTRUCTOR OPS DOCS)
    set_property(GLOBAL PROPERTY ROZ_PORT_${P_NAME}_${k} ${P_${k}})
  endforeach()
  if(NOT TARGET roz::port_${P_NAME})
    add_library(roz::port_${P_NAME} ALIAS ${P_TARGET})
  endif()
  # install and export (cmake/RozInstall.cmake installs rozTargets)
  foreach(t IN LISTS P_EXPORT)
    string(REGEX REPLACE "^roz_" "" exported ${t})
    set_target_properties(${t} PROPERTIES EXPORT_NAME ${exported})
  endforeach()
  roz_port_export(TARGETS ${P_EXPORT} ${P_TARGET})
endfunction()

# Writes the registry of the ports registered so far and defines roz_ports.
function(roz_ports_generate)
  get_property(names GLOBAL PROPERTY ROZ_PORT_NAMES)
  set(dir ${PROJECT_BINARY_DIR}/ports/generated)
  set(banner "generated by cmake/RozPort.cmake (roz_ports_generate()) from the roz_add_port() calls of this build; do not edit")
  set(includes "")
  set(constructors "")
  set(entries "")
  set(libs "")
  list(LENGTH names count)
  foreach(n IN LISTS names)
    foreach(k IN ITEMS TARGET HEADER TYPE CONSTRUCTOR OPS DOCS)
      get_property(${k} GLOBAL PROPERTY ROZ_PORT_${n}_${k})
    endforeach()
    list(APPEND libs ${TARGET})
    string(APPEND includes "#include \"${HEADER}\"\n")
    string(APPEND constructors
      "static roz_port_t construct_${n}(void *storage, roz_log_fn log, void *log_ctx)\n"
      "{\n    return ${CONSTRUCTOR}((${TYPE} *)storage, log, log_ctx);\n}\n\n")
    string(APPEND entries
      "    { \"${n}\", &${OPS}, sizeof(${TYPE}), _Alignof(${TYPE}), construct_${n},\n"
      "      \"${DOCS}\" },\n")
  endforeach()
  if(count EQUAL 0)
    set(entries "    { NULL, NULL, 0, 0, NULL, NULL }, /* none: the table is never empty */\n")
  endif()

  file(CONFIGURE OUTPUT ${dir}/include/roz/ports.h @ONLY CONTENT [=[
/* SPDX-License-Identifier: Apache-2.0 */
/* @banner@ */
/**
 * @file roz/ports.h
 * @brief The ports this build of roz holds (library roz::ports): one entry
 *        per roz_add_port(), in registration order. A consumer finds a port
 *        by name, allocates its instance (size, align) once at start-up and
 *        constructs it there, without naming the port.
 */
#ifndef ROZ_PORTS_H
#define ROZ_PORTS_H

#include "roz/config.h"

#include <stddef.h>

#include "roz/log.h"
#include "roz/port.h"

#ifdef __cplusplus
extern "C" {
#endif

/** How many ports this build holds. */
#define ROZ_PORTS_COUNT @count@u

/** One registered port. */
typedef struct roz_port_entry {
    const char           *id;    /**< its roz_add_port() NAME: "unitree_g1" */
    const roz_port_ops_t *ops;   /**< its ops; ops->name is what --port takes */
    size_t                size;  /**< sizeof its instance */
    size_t                align; /**< the alignment its instance needs */
    /** A roz_port_t over @p storage (size bytes, aligned to align, owned by
     *  the caller, zeroed or a closed instance), not yet open. Context:
     *  start-up. */
    roz_port_t (*construct)(void *storage, roz_log_fn log, void *log_ctx);
    /** its documentation: pages from the top of roz's source tree,
     *  separated by spaces, its own first ("docs/ports/ros2.md docs/ports/dds.md") */
    const char *docs;
} roz_port_entry_t;

/** The registered ports, ROZ_PORTS_COUNT of them. */
extern const roz_port_entry_t roz_ports[];

/** @brief The port whose ops name (or id) is @p name; NULL when this build
 *  holds none. Context: any. */
const roz_port_entry_t *roz_ports_find(const char *name);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORTS_H */
]=])
  file(CONFIGURE OUTPUT ${dir}/ports.c @ONLY CONTENT [=[
/* SPDX-License-Identifier: Apache-2.0 */
/* @banner@ */
#include "roz/ports.h"

#include <string.h>

@includes@
@constructors@const roz_port_entry_t roz_ports[] = {
@entries@};

const roz_port_entry_t *roz_ports_find(const char *name)
{
    for (size_t i = 0; i < sizeof roz_ports / sizeof roz_ports[0]; i++) {
        if (roz_ports[i].ops != NULL &&
            (strcmp(roz_ports[i].ops->name, name) == 0 || strcmp(roz_ports[i].id, name) == 0))
            return &roz_ports[i];
    }
    return NULL;
}
]=])

  add_library(roz_ports STATIC ${dir}/ports.c)
  add_library(roz::ports ALIAS roz_ports)
  set_target_properties(roz_ports PROPERTIES C_STANDARD 11 C_STANDARD_REQUIRED ON
                        C_EXTENSIONS OFF EXPORT_NAME ports POSITION_INDEPENDENT_CODE ${ROZ_PIC})
  target_include_directories(roz_ports PUBLIC
    $<BUILD_INTERFACE:${dir}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(roz_ports PUBLIC ${libs} roz_core)
  roz_target_warnings(roz_ports)
  set_property(GLOBAL APPEND PROPERTY ROZ_PORT_EXPORTS roz_ports)
  if(ROZ_INSTALL)
    install(FILES ${dir}/include/roz/ports.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/roz)
  endif()
endfunction()
