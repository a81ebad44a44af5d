# SPDX-License-Identifier: Apache-2.0
# aarch64 Linux (a robot's own computer: a Jetson Orin class board, or any
# ARMv8-A Linux), cross-built on a Debian or Ubuntu workstation with its
# cross compiler (gcc-aarch64-linux-gnu) and the arm64 packages of its
# multiarch archive (dpkg --add-architecture arm64; cyclonedds-dev:arm64,
# libcmocka-dev:arm64, libzstd-dev:arm64), which install into
# /usr/lib/aarch64-linux-gnu beside the host's. rozgen, idlc, clang's wasm32
# target and wabt stay the host's: they make files, not aarch64 code.
# Where qemu-aarch64 (Debian: qemu-user) is found, it runs the built tests
# (CMAKE_CROSSCOMPILING_EMULATOR), so ctest works in the cross tree.
# Use: cmake -DCMAKE_TOOLCHAIN_FILE=<this file> ...
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(ROZ_CROSS_TRIPLE aarch64-linux-gnu)
set(CMAKE_C_COMPILER ${ROZ_CROSS_TRIPLE}-gcc)
set(CMAKE_CXX_COMPILER ${ROZ_CROSS_TRIPLE}-g++)
set(CMAKE_AR ${ROZ_CROSS_TRIPLE}-ar CACHE FILEPATH "ar")
set(CMAKE_RANLIB ${ROZ_CROSS_TRIPLE}-ranlib CACHE FILEPATH "ranlib")
set(CMAKE_NM ${ROZ_CROSS_TRIPLE}-nm CACHE FILEPATH "nm")
set(CMAKE_OBJCOPY ${ROZ_CROSS_TRIPLE}-objcopy CACHE FILEPATH "objcopy")
set(CMAKE_STRIP ${ROZ_CROSS_TRIPLE}-strip CACHE FILEPATH "strip")
# The multiarch folders (lib/aarch64-linux-gnu) hold the target's libraries
# and CMake packages: CMake searches those of this architecture and never
# the host's (lib/x86_64-linux-gnu). Programs found (rozgen, idlc, wasm-ld,
# wat2wasm) are the host's.
set(CMAKE_LIBRARY_ARCHITECTURE ${ROZ_CROSS_TRIPLE})

# The root QEMU finds the target's dynamic loader and libraries under
# (qemu-aarch64 -L). The loader and the C library must come from one build
# of glibc: they share private structures (pthread_create walks the
# loader's list of cached thread stacks), and a loader of another build
# makes the first thread a program creates spin forever. The multiarch
# packages (Cyclone DDS's) pull in the multiarch C library (libc6:arm64),
# whose libc.so.6 the loader finds through the host's ld.so.cache, so its
# own loader (/lib/ld-linux-aarch64.so.1) is the one: the root is /. Where
# that package is missing, the cross toolchain's pair under /usr/<triple>.
if(EXISTS /lib/ld-linux-${CMAKE_SYSTEM_PROCESSOR}.so.1)
  set(ROZ_CROSS_ROOT / CACHE PATH "the target's root for QEMU user mode (qemu -L)")
else()
  set(ROZ_CROSS_ROOT /usr/${ROZ_CROSS_TRIPLE} CACHE PATH
      "the target's root for QEMU user mode (qemu -L)")
endif()
find_program(ROZ_QEMU_AARCH64 qemu-aarch64 DOC "QEMU user mode, to run aarch64 programs here")
if(ROZ_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${ROZ_QEMU_AARCH64};-L;${ROZ_CROSS_ROOT})
endif()
