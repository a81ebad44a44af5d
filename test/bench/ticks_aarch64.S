// SPDX-License-Identifier: Apache-2.0
// A program whose every instruction is known, for bench/targets/qemu_count.py
// (test_targets.py): main calls tick() 50 times; a tick runs 7 instructions
// of its own and calls part_a (2 + 2 * 100 + 3 of its own, then inner's 3)
// and part_b (4). Per tick: 219 instructions, inner's nested in part_a's.
    .text
    .global part_a, part_b, inner, tick, main

    .type part_a, %function
part_a:                     // 5 + 2 * x0 of its own
    stp x29, x30, [sp, #-16]!
    mov x1, x0
1:  subs x1, x1, #1
    b.ne 1b
    bl inner
    ldp x29, x30, [sp], #16
    ret
    .size part_a, . - part_a

    .type inner, %function
inner:                      // 3
    mov x2, #1
    add x2, x2, #1
    ret
    .size inner, . - inner

    .type part_b, %function
part_b:                     // 4
    add x0, x0, #1
    add x0, x0, #1
    add x0, x0, #1
    ret
    .size part_b, . - part_b

    .type tick, %function
tick:                       // 7 of its own
    stp x29, x30, [sp, #-16]!
    mov x0, #100
    bl part_a
    bl part_b
    ldp x29, x30, [sp], #16
    mov x0, #0
    ret
    .size tick, . - tick

    .type main, %function
main:
    stp x29, x30, [sp, #-16]!
    str x19, [sp, #-16]!
    mov x19, #50
2:  bl tick
    subs x19, x19, #1
    b.ne 2b
    ldr x19, [sp], #16
    ldp x29, x30, [sp], #16
    mov x0, #0
    ret
    .size main, . - main
    .section .note.GNU-stack, "", %progbits
