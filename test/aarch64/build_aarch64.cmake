# SPDX-License-Identifier: Apache-2.0
# cmake -DROZ_SOURCE_DIR=<roz> -DBINARY=dir -DROZGEN_EXECUTABLE=... -DROZ_PYTHON=...
#       -DROZ_WASM3_SDIST=... [-DROZ_WASM3_SOURCE_DIR=...] [-DGENERATOR=...]
#       [-DROZ_CROSS_ROOT=/] [-DTARGETS=a;b]
#       -P build_aarch64.cmake
# Configures (once) a tree of roz for aarch64 Linux with
# cmake/toolchains/aarch64-linux-gnu.cmake (Debian's cross compiler and
# arm64 packages; its tests run under qemu-aarch64), builds it (the
# libraries, rozrun, the ports, the tests; not the benchmarks), and installs
# it into its install/ folder: the installed CMake package must be there and
# its libraries aarch64 code. rozgen and the Python tools are not installed
# with it: they run on the machine that builds controllers.
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/../checks.cmake)
generator_args(gen)
set(root "")
if(ROZ_CROSS_ROOT) # else the toolchain's choice
  set(root -DROZ_CROSS_ROOT=${ROZ_CROSS_ROOT})
endif()
# configured once; again for a tree configured before its DDS tests' ids
# were shifted (test/aarch64/CMakeLists.txt)
set(have "")
if(EXISTS ${BINARY}/CMakeCache.txt)
  file(STRINGS ${BINARY}/CMakeCache.txt have REGEX "^ROZ_TEST_DDS_DOMAIN_OFFSET:")
endif()
if(NOT have)
  run(${CMAKE_COMMAND} -S ${ROZ_SOURCE_DIR} -B ${BINARY} ${gen}
      -DCMAKE_TOOLCHAIN_FILE=${ROZ_SOURCE_DIR}/cmake/toolchains/aarch64-linux-gnu.cmake
      -DCMAKE_BUILD_TYPE=RelWithDebInfo -DROZ_WERROR=ON -DROZ_BUILD_BENCH=OFF
      -DROZ_INSTALL_ROZGEN=OFF
      # the strict MCAP checker is a host tool the host tree builds and runs;
      # cargo here would build it again for nothing
      -DROZ_CARGO=OFF
      # its DDS tests' domain ids apart from the host tree's, whose tests
      # run at the same time (test/CMakeLists.txt)
      -DROZ_TEST_DDS_DOMAIN_OFFSET=100
      -DROZGEN_EXECUTABLE=${ROZGEN_EXECUTABLE} -DROZ_PYTHON=${ROZ_PYTHON}
      -DROZ_WASM3_SDIST=${ROZ_WASM3_SDIST} -DROZ_WASM3_SOURCE_DIR=${ROZ_WASM3_SOURCE_DIR}
      ${root})
endif()
if(TARGETS) # these alone, not installed (make bench-targets: roz_fw_host)
  run(${CMAKE_COMMAND} --build ${BINARY} --target ${TARGETS})
  return()
endif()
run(${CMAKE_COMMAND} --build ${BINARY})

set(prefix ${BINARY}/install)
file(REMOVE_RECURSE ${prefix})
run(${CMAKE_COMMAND} --install ${BINARY} --prefix ${prefix})
file(GLOB_RECURSE config ${prefix}/*/rozConfig.cmake)
if(NOT config)
  message(FATAL_ERROR "${prefix}: no rozConfig.cmake installed")
endif()
# every installed static library and program is aarch64 code (ELF e_machine
# 183, at byte 18 of an ELF header; a static library's members are ELF)
file(GLOB_RECURSE libs ${prefix}/lib/*.a)
list(APPEND libs ${prefix}/bin/rozrun)
foreach(f IN LISTS libs)
  file(READ ${f} head LIMIT 1048576 HEX) # past an archive's symbol table
  string(FIND "${head}" "7f454c46" elf)
  if(elf EQUAL -1)
    message(FATAL_ERROR "${f}: no ELF object in it")
  endif()
  math(EXPR at "${elf} + 36") # 18 bytes on, in hex digits
  string(SUBSTRING "${head}" ${at} 4 machine)
  if(NOT machine STREQUAL "b700")
    message(FATAL_ERROR "${f}: not aarch64 code (ELF machine ${machine})")
  endif()
endforeach()
list(LENGTH libs n)
message(STATUS "built roz for aarch64 Linux in ${BINARY}; installed ${n} aarch64 libraries and "
               "programs and the CMake package (${config}) in ${prefix}")
