/* SPDX-License-Identifier: Apache-2.0 */
/* ARM semihosting (bkpt 0xab on ARMv7-M): text out and the exit status, as
 * QEMU carries them with -semihosting-config enable=on,target=native, and
 * as a debug probe does on a real board. Without a debugger attached a
 * bkpt on real hardware is a fault: a shipped firmware prints through its
 * own UART instead. */
#ifndef ROZ_FW_SEMIHOSTING_H
#define ROZ_FW_SEMIHOSTING_H

/** Writes a NUL-terminated string to the host's console. */
void fw_semihost_write(const char *s);

/** Ends the run with an exit status (SYS_EXIT_EXTENDED). Never returns. */
void fw_semihost_exit(int status) __attribute__((noreturn));

#endif /* ROZ_FW_SEMIHOSTING_H */
