# SPDX-License-Identifier: Apache-2.0
# ARM's MPS2 with the AN505 image (QEMU: mps2-an505): a Cortex-M33 with
# TrustZone and FPv5-SP at 20 MHz. The image runs in the Secure state it
# resets in, from the Secure aliases: code in SSRAM1 at 0x10000000, data in
# SSRAM2 at 0x38000000 (their Non-secure aliases are 0x0 and 0x28000000).
set(FW_BOARD_CPU      cortex-m33)
set(FW_BOARD_CLOCK_HZ 20000000)
set(FW_BOARD_LD       ${CMAKE_CURRENT_LIST_DIR}/mps2-an505.ld)
set(FW_BOARD_CONSOLE  semihosting)
set(FW_BOARD_QEMU     mps2-an505)
