/* SPDX-License-Identifier: Apache-2.0 */
/* Loading a controller fits a small C stack (docs/budget.md, "The C stack"). wasm3 compiles
 * nested blocks recursively, so the C stack the loader needs grows with the
 * nesting depth; roz bounds the depth (ROZ_CFG_WASM_MAX_BLOCK_DEPTH) so that
 * loading any accepted module fits a documented thread stack (64 KiB, 256 KiB
 * under ASan: LOAD_STACK_BYTES below).
 * This test proves that:
 *  - the deepest accepted nesting, in every block shape (block, loop, if/else,
 *    with and without a result), loads on a thread whose whole stack is the
 *    documented size (the thread's static TLS and descriptor included);
 *  - one level more is refused, with a message naming the limit;
 * and prints the stack the loader used per depth (stack painting), the
 * figures the documentation quotes. */
#define _DEFAULT_SOURCE /* MAP_ANONYMOUS, pthread_attr_setstack */
#include <limits.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include <cmocka.h>

#include "roz/controller.h"
#include "support.h"
#include "ur5_manifest.h"

/* The documented thread stack for loading (docs/budget.md, "The C stack"):
 * 64 KiB in the normal build, 256 KiB under ASan, the thread's static TLS
 * (about 22 KiB of it roz's validator) included. */
#if defined(__SANITIZE_ADDRESS__)
#define LOAD_STACK_BYTES (256u * 1024u)
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LOAD_STACK_BYTES (256u * 1024u)
#endif
#endif
#ifndef LOAD_STACK_BYTES
#define LOAD_STACK_BYTES (64u * 1024u)
#endif

/* ---- modules: process's body nests DEPTH blocks of one shape -------------- */

enum { BLOCK_VOID, BLOCK_F64, LOOP_F64, IF_ELSE_F64, N_SHAPES };
static const char *const shape_name[N_SHAPES] = { "block", "block (result f64)",
                                                  "loop (result f64)", "if/else (result f64)" };

static uint8_t wasm[64 * 1024];
static size_t wasm_len;

static void put(uint8_t b)
{
    assert_true(wasm_len < sizeof wasm);
    wasm[wasm_len++] = b;
}

static void put_f64_one(void)
{
    static const uint8_t one[8] = { 0, 0, 0, 0, 0, 0, 0xf0, 0x3f };
    put(0x44);
    for (int i = 0; i < 8; i++)
        put(one[i]);
}

static void put_size_at(size_t at)
{
    uint32_t size = (uint32_t)(wasm_len - at - 5);
    for (int i = 0; i < 5; i++)
        wasm[at + (size_t)i] = (uint8_t)(((size >> (7 * i)) & 0x7f) | (i < 4 ? 0x80 : 0));
}

static size_t put_size_later(void)
{
    size_t at = wasm_len;
    for (int i = 0; i < 5; i++)
        put(0);
    return at;
}

static void build(int shape, unsigned depth)
{
    static const uint8_t head[] = { 0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00,
                                    0x01, 0x05, 0x01, 0x60, 0x01, 0x7e, 0x00, /* (i64) */
                                    0x03, 0x02, 0x01, 0x00,
                                    0x07, 0x0b, 0x01, 0x07, 'p', 'r', 'o', 'c', 'e', 's', 's',
                                    0x00, 0x00 };
    wasm_len = 0;
    for (size_t i = 0; i < sizeof head; i++)
        put(head[i]);
    put(10);
    size_t sec = put_size_later();
    put(1);
    size_t body = put_size_later();
    put(0); /* no locals */
    for (unsigned d = 0; d < depth; d++) {
        switch (shape) {
        case BLOCK_VOID: put(0x02); put(0x40); break;
        case BLOCK_F64: put(0x02); put(0x7c); break;
        case LOOP_F64: put(0x03); put(0x7c); break;
        default: put(0x41); put(0x01); put(0x04); put(0x7c); break;
        }
    }
    if (shape != BLOCK_VOID)
        put_f64_one();
    for (unsigned d = 0; d < depth; d++) {
        if (shape == IF_ELSE_F64) {
            put(0x05);
            put_f64_one();
        }
        put(0x0b);
    }
    if (shape != BLOCK_VOID)
        put(0x1a); /* drop */
    put(0x0b);
    put_size_at(body);
    put_size_at(sec);
}

/* ---- loading on a thread of a given stack ---------------------------------- */

static roz_controller_t ctl;
static roz_abi_t abi;
static double target[ROZ_CFG_MAX_COMMANDS];
static int load_rc;
static uintptr_t entry_sp;

static void *load_thread(void *arg)
{
    (void)arg;
    entry_sp = (uintptr_t)__builtin_frame_address(0);
    roz_controller_init(&ctl);
    load_rc = roz_controller_load(&ctl, wasm, wasm_len, &abi);
    if (load_rc == ROZ_OK && roz_controller_process(&ctl, 0) != ROZ_OK)
        load_rc = -1000;
    return NULL;
}

/* Loads the module on a thread whose stack is exactly `bytes` (mmap'd, so
 * a guard page below catches an overflow as a crash); returns the load's
 * result and, through *used, the bytes of the stack that were written
 * (painting) from the top, and through *below_entry those under the thread's
 * first frame (the loader's own need). Where the C library refuses a stack
 * that small (PTHREAD_STACK_MIN: 128 KiB on aarch64 Linux, 16 KiB on
 * x86-64), the thread gets PTHREAD_STACK_MIN: the caller's check that fewer
 * than `bytes` were written still holds it to the documented size. */
static int load_on_stack(size_t bytes, size_t *used, size_t *below_entry)
{
    const size_t page = 4096;
    if (bytes < (size_t)PTHREAD_STACK_MIN)
        bytes = (size_t)PTHREAD_STACK_MIN;
    uint8_t *map = mmap(NULL, bytes + page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS,
                        -1, 0);
    assert_true(map != MAP_FAILED);
    assert_int_equal(mprotect(map, page, PROT_NONE), 0); /* guard */
    uint8_t *stack = map + page;
    memset(stack, 0xa5, bytes);

    pthread_attr_t attr;
    pthread_t th;
    assert_int_equal(pthread_attr_init(&attr), 0);
    assert_int_equal(pthread_attr_setstack(&attr, stack, bytes), 0);
    roz_abi_init(&abi, &roz_manifest_ur5, target, NULL);
    assert_int_equal(pthread_create(&th, &attr, load_thread, NULL), 0);
    assert_int_equal(pthread_join(th, NULL), 0);
    pthread_attr_destroy(&attr);
    roz_controller_unload(&ctl);

    size_t low = 0;
    while (low < bytes && stack[low] == 0xa5)
        low++;
    if (used != NULL)
        *used = bytes - low;
    if (below_entry != NULL)
        *below_entry = entry_sp - (uintptr_t)(stack + low);
    munmap(map, bytes + page);
    return load_rc;
}

/* ---- tests ---------------------------------------------------------------- */

/* The figures: C stack per nesting depth and shape, on a 1 MiB thread. */
static void test_load_stack_figures(void **st)
{
    static const unsigned depths[] = { 1, 16, 32, 64, 100, 128, 192, 255 };
    (void)st;
    print_message("loader C stack (bytes below the thread's first frame; whole thread "
                  "stack written incl. TLS):\n");
    for (int s = 0; s < N_SHAPES; s++) {
        for (size_t i = 0; i < sizeof depths / sizeof depths[0]; i++) {
            size_t used, below;
            if (depths[i] > ROZ_CFG_WASM_MAX_BLOCK_DEPTH)
                continue;
            build(s, depths[i]);
            assert_int_equal(load_on_stack(1024 * 1024, &used, &below), ROZ_OK);
            print_message("  %-22s depth %3u: %6zu (%6zu)\n", shape_name[s], depths[i], below,
                          used);
        }
    }
}

/* The deepest accepted nesting of every shape loads (and runs) on a thread
 * of LOAD_STACK_BYTES; one level more is refused by name. */
static void test_load_stack_deepest_fits(void **st)
{
    (void)st;
    for (int s = 0; s < N_SHAPES; s++) {
        size_t used, below;
        build(s, ROZ_CFG_WASM_MAX_BLOCK_DEPTH);
        int rc = load_on_stack(LOAD_STACK_BYTES, &used, &below);
        if (rc != ROZ_OK)
            fail_msg("%s x %u: %d (%s)", shape_name[s], (unsigned)ROZ_CFG_WASM_MAX_BLOCK_DEPTH, rc,
                     roz_controller_error(&ctl));
        print_message("%s x %u on a %u-byte thread: %zu bytes below the first frame, %zu "
                      "written\n", shape_name[s], (unsigned)ROZ_CFG_WASM_MAX_BLOCK_DEPTH,
                      (unsigned)LOAD_STACK_BYTES, below, used);
        assert_true(used < LOAD_STACK_BYTES);

        build(s, ROZ_CFG_WASM_MAX_BLOCK_DEPTH + 1);
        roz_controller_init(&ctl);
        assert_int_equal(roz_controller_load(&ctl, wasm, wasm_len, &abi), ROZ_EINVAL);
        char want[128];
        snprintf(want, sizeof want,
                 "blocks nested deeper than ROZ_CFG_WASM_MAX_BLOCK_DEPTH (%u;",
                 (unsigned)ROZ_CFG_WASM_MAX_BLOCK_DEPTH);
        if (strstr(roz_controller_error(&ctl), want) == NULL)
            fail_msg("\"%s\" lacks \"%s\"", roz_controller_error(&ctl), want);
        roz_controller_unload(&ctl);
    }
}

ROZ_TEST_MAIN(cmocka_unit_test(test_load_stack_figures),
              cmocka_unit_test(test_load_stack_deepest_fits))
