# SPDX-License-Identifier: Apache-2.0
# Cortex-M4F: ARMv7E-M, single-precision FPU (FPv4-SP), hard-float ABI.
# Every double operation is a libgcc soft-float call on this core.
# QEMU boards: mps2-an386, netduinoplus2. Use: cmake -DCMAKE_TOOLCHAIN_FILE=<this file> ...
set(ROZ_FW_CPU cortex-m4f)
set(ROZ_FW_CPU_FLAGS "-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16")
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi.cmake)
