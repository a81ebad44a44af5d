# SPDX-License-Identifier: Apache-2.0
# ARM's MPS2 with the AN500 image (QEMU: mps2-an500): a Cortex-M7 with
# FPv5-D16 at 25 MHz, 4 MiB of code memory at 0x0, 4 MiB of SRAM at 0x20000000.
set(FW_BOARD_CPU      cortex-m7)
set(FW_BOARD_CLOCK_HZ 25000000)
set(FW_BOARD_LD       ${CMAKE_CURRENT_LIST_DIR}/mps2-an500.ld)
set(FW_BOARD_CONSOLE  semihosting)
set(FW_BOARD_QEMU     mps2-an500)
