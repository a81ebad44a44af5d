# SPDX-License-Identifier: Apache-2.0
# How this firmware builds roz: included by CMakeLists.txt before
# add_subdirectory(roz), and given to a build of roz that is installed for
# it (cmake -S <roz> -C roz_options.cmake -DROZ_CONFIG_HEADER=config/<x>.h,
# docs/firmware.md), so that both builds of roz are the same.
set(ROZ_BUILTIN_MANIFESTS OFF CACHE BOOL "" FORCE) # each image generates its robot's table
# wasm3's code pages in steps of 1 KiB (not 4: a small controller's code
# fits a page or two); no formatted error texts (no vsnprintf linked); a
# function's operand stack while it compiles at most 512 deep (not 2000:
# the compiler's state on the loader's C stack shrinks from about 10 KiB
# to 3; a deeper function is refused at load, "cannot compile module")
set(ROZ_WASM3_DEFINITIONS
    "d_m3CodePageAlignSize=1024;d_m3VerboseErrorMessages=0;d_m3MaxFunctionStackHeight=512"
    CACHE STRING "" FORCE)
# link-time optimisation of roz, wasm3 and the application (-flto; every
# function and object in a section of its own and the link's section GC
# come with the toolchain file): about 4 KB less on every image, the same
# fingerprints (test/firmware). The footprint table still names each
# function's component, from the debug information (tools/fw_footprint.py).
# -DCMAKE_INTERPROCEDURAL_OPTIMIZATION=OFF builds without it.
set(CMAKE_INTERPROCEDURAL_OPTIMIZATION ON CACHE BOOL "link-time optimisation")
# an install for a firmware carries the libraries and headers only: rozgen
# and the tools come from the host's install
set(ROZ_INSTALL_ROZGEN OFF CACHE BOOL "" FORCE)
set(ROZ_INSTALL_TOOLS OFF CACHE BOOL "" FORCE)
