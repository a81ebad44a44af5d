# SPDX-License-Identifier: Apache-2.0
# The part every Cortex-M toolchain file here shares: Debian's
# gcc-arm-none-eabi with newlib-nano (libnewlib-arm-none-eabi), bare metal.
# The CPU flags come from the file that includes this one, in
# ROZ_FW_CPU_FLAGS, and go into CMAKE_C_FLAGS itself, so that every compile,
# CMake's own checks and the link see the same ABI.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)
set(CMAKE_AR arm-none-eabi-ar)
set(CMAKE_RANLIB arm-none-eabi-ranlib)
set(CMAKE_OBJCOPY arm-none-eabi-objcopy CACHE FILEPATH "objcopy")
set(CMAKE_SIZE arm-none-eabi-size CACHE FILEPATH "size")
set(CMAKE_NM arm-none-eabi-nm CACHE FILEPATH "nm")
# CMake's compiler checks link no executable (there is no start-up code yet).
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)

# Every function and object in a section of its own, so the link keeps only
# what is called; newlib-nano's small printf-free C library. Debug
# information (-g) costs no byte of flash and names the source of every
# function, which the footprint table needs once link-time optimisation has
# merged the objects (tools/fw_footprint.py).
set(CMAKE_C_FLAGS_INIT "${ROZ_FW_CPU_FLAGS} -ffunction-sections -fdata-sections -g")
set(CMAKE_ASM_FLAGS_INIT "${ROZ_FW_CPU_FLAGS}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${ROZ_FW_CPU_FLAGS} --specs=nano.specs -Wl,--gc-sections")
