# SPDX-License-Identifier: Apache-2.0
# Netduino Plus 2 (QEMU: netduinoplus2): ST's STM32F405RG, a Cortex-M4 with
# FPv4-SP at 168 MHz, 1 MiB of flash at 0x08000000 (aliased at 0x0, where
# the core fetches its vector table), 128 KiB of SRAM at 0x20000000 (and
# 64 KiB of core-coupled RAM at 0x10000000, unused here).
set(FW_BOARD_CPU      cortex-m4f)
set(FW_BOARD_CLOCK_HZ 168000000)
set(FW_BOARD_LD       ${CMAKE_CURRENT_LIST_DIR}/netduinoplus2.ld)
set(FW_BOARD_CONSOLE  semihosting)
set(FW_BOARD_QEMU     netduinoplus2)
