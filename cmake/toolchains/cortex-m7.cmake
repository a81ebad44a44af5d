# SPDX-License-Identifier: Apache-2.0
# Cortex-M7: ARMv7E-M, double-precision FPU (FPv5-D16), hard-float ABI.
# QEMU board: mps2-an500. Use: cmake -DCMAKE_TOOLCHAIN_FILE=<this file> ...
set(ROZ_FW_CPU cortex-m7)
set(ROZ_FW_CPU_FLAGS "-mcpu=cortex-m7 -mthumb -mfloat-abi=hard -mfpu=fpv5-d16")
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi.cmake)
