# SPDX-License-Identifier: Apache-2.0
# Cortex-M33: ARMv8-M Mainline, single-precision FPU (FPv5-SP-D16),
# hard-float ABI. Every double operation is a libgcc soft-float call on this
# core, as on the Cortex-M4F. QEMU board: mps2-an505.
# Use: cmake -DCMAKE_TOOLCHAIN_FILE=<this file> ...
set(ROZ_FW_CPU cortex-m33)
set(ROZ_FW_CPU_FLAGS "-mcpu=cortex-m33 -mthumb -mfloat-abi=hard -mfpu=fpv5-sp-d16")
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi.cmake)
