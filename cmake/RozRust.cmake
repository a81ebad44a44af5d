# SPDX-License-Identifier: Apache-2.0
#
# roz_add_rust_controller(<name> SOURCE <main.rs>
#                         [MANIFEST <robot.toml>...] [SOURCE_ROOT <dir>]
#                         [DEPENDS <file>...] [RUSTFLAGS <flag>...])
#
# Builds <name>.wasm into CMAKE_CURRENT_BINARY_DIR as the target
# roz_wasm_<name>, part of roz_controllers (built by default), like
# roz_add_wasm_controller() does for C: rustc compiles the crate whose root
# is SOURCE for wasm32-unknown-unknown as a cdylib against the Rust
# controller SDK (the crate roz_controller, sdk/rust, built once per build
# tree), with the linker flags roz needs (docs/rust.md):
#   -z stack-size=16384   rustc's default stack of 1 MiB alone is more linear
#                         memory than roz allows (ROZ_CFG_WASM_MAX_PAGES)
#   --strip-all           as the C controllers (custom sections stay)
# rustc itself links a cdylib without an entry point and exports the
# #[no_mangle] functions (roz_controller::process!). -C opt-level=2 as -O2.
#
# MANIFEST runs rozgen on each robot.toml into
# ${CMAKE_CURRENT_BINARY_DIR}/roz_generated/rust_<name> and passes that folder
# as OUT_DIR, so the source includes the robot's module as a cargo build
# script's output would be:
#   include!(concat!(env!("OUT_DIR"), "/<robot_id>_channels.rs"));
# The generated files name the manifest relative to SOURCE_ROOT (default:
# the project's source folder). DEPENDS adds files to rebuild on (the other
# files of a crate of several); RUSTFLAGS extra rustc flags.
#
# rustc: ROZ_RUSTC when set, else the first rustc on PATH whose sysroot has
# the wasm32-unknown-unknown target's core library (Debian 12:
# apt-get install rustc libstd-rust-dev-wasm32; rustup: rustup target add
# wasm32-unknown-unknown). Without one, ROZ_RUSTC is ROZ_RUSTC-NOTFOUND and
# roz_add_rust_controller() stops with what to install.
#
# Available after find_package(roz) and after add_subdirectory(roz).
if(NOT COMMAND roz__rozgen_command)
  include(${CMAKE_CURRENT_LIST_DIR}/RozGenerate.cmake)
endif()
# The SDK's sources: an installed package sets ROZ_RUST_SDK_DIR
# (rozConfig.cmake); a source tree has them beside this file.
# Kept in a global property: roz_add_rust_controller() may be called from
# a folder that does not see this file's variables (roz as a subproject).
if(NOT ROZ_RUST_SDK_DIR)
  set(ROZ_RUST_SDK_DIR ${CMAKE_CURRENT_LIST_DIR}/../sdk/rust)
endif()
cmake_path(ABSOLUTE_PATH ROZ_RUST_SDK_DIR NORMALIZE)
set_property(GLOBAL PROPERTY ROZ_RUST_SDK_DIR ${ROZ_RUST_SDK_DIR})

# Whether rustc @p exe can build for wasm32-unknown-unknown: its target
# library folder holds libcore.
function(roz__rustc_has_wasm32 exe out)
  set(${out} FALSE PARENT_SCOPE)
  execute_process(COMMAND ${exe} --print target-libdir --target wasm32-unknown-unknown
                  OUTPUT_VARIABLE libdir ERROR_QUIET RESULT_VARIABLE rc
                  OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(rc EQUAL 0 AND IS_DIRECTORY "${libdir}")
    file(GLOB core "${libdir}/libcore-*.rlib")
    if(core)
      set(${out} TRUE PARENT_SCOPE)
    endif()
  endif()
endfunction()

if(ROZ_RUSTC)
  roz__rustc_has_wasm32(${ROZ_RUSTC} _roz_ok)
  if(NOT _roz_ok)
    message(FATAL_ERROR "ROZ_RUSTC=${ROZ_RUSTC} has no wasm32-unknown-unknown target "
                        "(its --print target-libdir has no libcore)")
  endif()
else()
  # every rustc on PATH in order: rustup's proxy often comes first, without
  # the target
  set(_roz_found "")
  set(_roz_tried "")
  set(_roz_path "$ENV{PATH}")
  string(REPLACE ":" ";" _roz_path "${_roz_path}")
  foreach(_roz_dir IN LISTS _roz_path)
    if(_roz_dir AND EXISTS "${_roz_dir}/rustc" AND NOT IS_DIRECTORY "${_roz_dir}/rustc")
      roz__rustc_has_wasm32("${_roz_dir}/rustc" _roz_ok)
      if(_roz_ok)
        set(_roz_found "${_roz_dir}/rustc")
        break()
      endif()
      list(APPEND _roz_tried "${_roz_dir}/rustc")
    endif()
  endforeach()
  if(_roz_found)
    set(ROZ_RUSTC "${_roz_found}" CACHE FILEPATH
        "rustc with the wasm32-unknown-unknown target, for Rust controllers")
    message(STATUS "Rust controllers: ${ROZ_RUSTC}")
  else()
    set(ROZ_RUSTC ROZ_RUSTC-NOTFOUND)
    if(_roz_tried)
      set(_roz_tried " (without it: ${_roz_tried})")
    endif()
    message(STATUS "Rust controllers: no rustc with the wasm32-unknown-unknown target "
                   "on PATH${_roz_tried}")
  endif()
endif()

# The SDK crate as an rlib, once per build folder (a custom command's output
# is known in its own folder only); sets @p out to its path.
function(roz__rust_sdk out)
  get_property(sdk_dir GLOBAL PROPERTY ROZ_RUST_SDK_DIR)
  set(dir ${CMAKE_CURRENT_BINARY_DIR}/roz_rust)
  set(rlib ${dir}/libroz_controller.rlib)
  get_property(done DIRECTORY PROPERTY ROZ_RUST_SDK_RLIB)
  if(NOT done)
    file(GLOB srcs CONFIGURE_DEPENDS ${sdk_dir}/src/*.rs)
    add_custom_command(OUTPUT ${rlib}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${dir}
      COMMAND ${ROZ_RUSTC} --edition 2018 --crate-type rlib --crate-name roz_controller
              --target wasm32-unknown-unknown -C opt-level=2 -C panic=abort -C debuginfo=0
              -D warnings -o ${rlib} ${sdk_dir}/src/lib.rs
      DEPENDS ${srcs} VERBATIM COMMENT "rustc wasm32 roz_controller (the Rust controller SDK)")
    set_property(DIRECTORY PROPERTY ROZ_RUST_SDK_RLIB ${rlib})
  endif()
  set(${out} ${rlib} PARENT_SCOPE)
endfunction()

function(roz_add_rust_controller name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "SOURCE;SOURCE_ROOT" "MANIFEST;DEPENDS;RUSTFLAGS")
  if(NOT arg_SOURCE)
    message(FATAL_ERROR "roz_add_rust_controller(${name}): SOURCE is required")
  endif()
  if(NOT ROZ_RUSTC)
    message(FATAL_ERROR
      "roz_add_rust_controller(${name}): no rustc with the wasm32-unknown-unknown target. "
      "Debian 12: apt-get install rustc libstd-rust-dev-wasm32; rustup: rustup target add "
      "wasm32-unknown-unknown; or pass -DROZ_RUSTC=/path/to/rustc")
  endif()
  get_property(sdk_dir GLOBAL PROPERTY ROZ_RUST_SDK_DIR)
  if(NOT EXISTS ${sdk_dir}/src/lib.rs)
    message(FATAL_ERROR "roz_add_rust_controller(${name}): the Rust controller SDK is not "
                        "in ${sdk_dir} (ROZ_RUST_SDK_DIR)")
  endif()
  cmake_path(ABSOLUTE_PATH arg_SOURCE BASE_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR} NORMALIZE)
  roz__rust_sdk(rlib)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${name}.wasm)
  set(gen_dir ${CMAKE_CURRENT_BINARY_DIR}/roz_generated/rust_${name})
  set(generated "")
  if(arg_MANIFEST)
    if(NOT arg_SOURCE_ROOT)
      set(arg_SOURCE_ROOT ${PROJECT_SOURCE_DIR})
    endif()
    roz__rozgen_command(generated unused ${gen_dir} ${arg_SOURCE_ROOT} OFF ${arg_MANIFEST})
  endif()
  set(deps "")
  foreach(d IN LISTS arg_DEPENDS)
    cmake_path(ABSOLUTE_PATH d BASE_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR} NORMALIZE)
    list(APPEND deps ${d})
  endforeach()
  string(MAKE_C_IDENTIFIER "${name}" crate)
  add_custom_command(OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${gen_dir}
    COMMAND ${CMAKE_COMMAND} -E env OUT_DIR=${gen_dir}
            ${ROZ_RUSTC} --edition 2018 --crate-type cdylib --crate-name ${crate}
            --target wasm32-unknown-unknown -C opt-level=2 -C panic=abort -C debuginfo=0
            -D warnings --extern roz_controller=${rlib}
            -C link-arg=-zstack-size=16384 -C link-arg=--strip-all
            ${arg_RUSTFLAGS} -o ${out} ${arg_SOURCE}
    DEPENDS ${arg_SOURCE} ${rlib} ${generated} ${deps}
    COMMAND_EXPAND_LISTS VERBATIM COMMENT "rustc wasm32 ${name}.wasm")
  add_custom_target(roz_wasm_${name} DEPENDS ${out})
  if(NOT TARGET roz_controllers)
    add_custom_target(roz_controllers ALL)
  endif()
  add_dependencies(roz_controllers roz_wasm_${name})
endfunction()
