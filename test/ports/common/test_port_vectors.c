/* SPDX-License-Identifier: Apache-2.0 */
/* The DDS ports and the mujoco port refuse at open what rozgen refuses at
 * build time, in the same words: every shared vector of manifests/invalid/
 * whose [hardware] port is unitree/G1, agibot/X2, engineai/PM01 or mujoco
 * (where the build has it) and which roz's C loader
 * reads (the port's rules are not the loader's), opened through its port
 * with no run-time parameter: the open fails, and "<file>: <its error>" is
 * the one line of <vector>.expected (`rozgen --check` from the repository
 * root; the port stops at its first problem, so each of these vectors has
 * one). rozgen's side is test_invalid.py on the same files. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "dds_open_file.h"
#include "roz/error.h"
#include "support.h"
#include "roz/hal/thread.h"

#ifndef ROZ_SOURCE_DIR
#error "ROZ_SOURCE_DIR: the repository"
#endif

#define VECTORS "manifests/invalid"
#define MAX_VECTORS 512

static char names[MAX_VECTORS][128];
static size_t n_names;

static int by_name(const void *a, const void *b)
{
    return strcmp(a, b);
}

/* the vectors' file names, sorted */
static void list_vectors(void)
{
    DIR *d = opendir(ROZ_SOURCE_DIR "/" VECTORS);
    struct dirent *e;

    assert_non_null(d);
    n_names = 0;
    while ((e = readdir(d)) != NULL) {
        size_t n = strlen(e->d_name);
        if (n < 6 || strcmp(e->d_name + n - 5, ".toml") != 0)
            continue;
        assert_true(n < sizeof names[0] && n_names < MAX_VECTORS);
        memcpy(names[n_names++], e->d_name, n + 1);
    }
    closedir(d);
    qsort(names, n_names, sizeof names[0], by_name);
}

/* <vector>.expected, which must be one line: that line, without its newline */
static void expected_line(const char *name, char *out, size_t len)
{
    char path[512];
    size_t n = strlen(name);

    snprintf(path, sizeof path, "%s/%s/%.*s.expected", ROZ_SOURCE_DIR, VECTORS, (int)(n - 5),
             name);
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        fail_msg("%s: cannot read", path);
    size_t got = fread(out, 1, len - 1, f);
    fclose(f);
    out[got] = '\0';
    char *nl = strchr(out, '\n');
    if (nl == NULL || nl[1] != '\0')
        fail_msg("%s: expected one line, as the port reports one problem", path);
    *nl = '\0';
}

/* The .expected lines are rozgen's words on the machine that builds, whose
 * least thread stack is 64 KiB; a target whose C library needs more
 * (aarch64 Linux: 128, roz/hal/thread.h) refuses the same value naming its
 * own range: the target's words are wanted there. */
#define BUILD_STACK_RANGE "64..65536"
static void target_stack_range(char *want, size_t len)
{
    char buf[2048];
    const char *at = strstr(want, BUILD_STACK_RANGE);
    if (at == NULL || strcmp(BUILD_STACK_RANGE, ROZ_THREAD_STACK_RANGE) == 0)
        return;
    snprintf(buf, sizeof buf, "%.*s%s%s", (int)(at - want), want, ROZ_THREAD_STACK_RANGE,
             at + strlen(BUILD_STACK_RANGE));
    snprintf(want, len, "%s", buf);
}

/* The mujoco port's errors name the robot.toml it opened ("mujoco: FILE: ")
 * and the model by the path it resolved; rozgen's name them as the file
 * was given, from the repository root: the port's words without the
 * prefix, the paths taken from the source root. */
static void mujoco_words(const char *path, char *err)
{
    char buf[1024];
    const char *e = err;
    size_t pl = strlen(path);
    if (strncmp(e, "mujoco: ", 8) == 0 && strncmp(e + 8, path, pl) == 0 && e[8 + pl] == ':')
        e += 8 + pl + 2;
    const char *root = ROZ_SOURCE_DIR "/";
    size_t rl = strlen(root), k = 0;
    while (*e != '\0' && k + 1 < sizeof buf) {
        if (strncmp(e, root, rl) == 0) {
            e += rl;
            continue;
        }
        buf[k++] = *e++;
    }
    buf[k] = '\0';
    memcpy(err, buf, k + 1);
}

/* Vectors of a model MuJoCo's own reader refuses (not there, an include
 * not there): both refuse them, each in its reader's words. */
static int read_by_mujoco(const char *name)
{
    return strncmp(name, "mujoco-model", 12) == 0 && strcmp(name, "mujoco-model--missing.toml") != 0;
}

static void test_port_vectors_agree(void **state)
{
    unsigned g1_vectors = 0, ros2_vectors = 0, mujoco_vectors = 0, failed = 0;
    (void)state;

    list_vectors();
    for (size_t i = 0; i < n_names; i++) {
        char path[512], err[1024], want[2048], got[2048];
        const char *port_name;

        snprintf(path, sizeof path, "%s/%s/%s", ROZ_SOURCE_DIR, VECTORS, names[i]);
        int rc = roz_test_dds_open_file(path, &port_name, err, sizeof err);
        if (rc == ROZ_TEST_NOT_LOADED || rc == ROZ_TEST_NO_DDS_PORT)
            continue; /* the loader's own rules, or another port's */
        if (strcmp(port_name, "unitree/G1") == 0)
            g1_vectors++;
        else if (strcmp(port_name, "mujoco") == 0)
            mujoco_vectors++;
        else
            ros2_vectors++;
        if (rc == ROZ_OK) {
            print_error("%s: the port opens it\n", names[i]);
            failed++;
            continue;
        }
        if (read_by_mujoco(names[i]))
            continue; /* refused (above), in MuJoCo's words */
        expected_line(names[i], want, sizeof want);
        target_stack_range(want, sizeof want);
        if (strcmp(port_name, "mujoco") == 0)
            mujoco_words(path, err);
        snprintf(got, sizeof got, "%s/%s: %s", VECTORS, names[i], err);
        if (strcmp(got, want) != 0) {
            print_error("%s:\n  port:   %s\n  rozgen: %s\n", names[i], got, want);
            failed++;
        }
    }
    print_message("%u unitree/G1, %u ROS 2 and %u mujoco port vectors, %u disagreeing\n",
                  g1_vectors, ros2_vectors, mujoco_vectors, failed);
    assert_int_equal(failed, 0);
    /* the vectors are there: a glob that finds none proves nothing */
    assert_true(g1_vectors >= 10);
    assert_true(ros2_vectors >= 8);
#ifdef ROZ_TEST_HAVE_MUJOCO
    assert_true(mujoco_vectors >= 14);
#endif
}

ROZ_TEST_MAIN(cmocka_unit_test(test_port_vectors_agree))
