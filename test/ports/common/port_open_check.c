/* SPDX-License-Identifier: Apache-2.0 */
/*
 * port_open_check: opens each robot.toml given through its DDS port, as
 * rozrun would with no --param, and says what the open says:
 *
 *   port_open_check FILE...
 *
 * one line per file on stdout: "FILE: ok" when the port opens (and is
 * closed again), "FILE: <the port's error>" when it refuses,
 * "FILE: [loader] ..." when roz's C loader refuses the file, "FILE: [no DDS
 * port]" for a robot of another port. test/ports/common/port_agreement.py compares
 * these with rozgen's verdict on the same files. Exit status 0, or 2 on a
 * usage error.
 */
#include <stdio.h>
#include <string.h>

#include "dds_open_file.h"
#include "roz/error.h"

static void check(const char *file)
{
    char err[1024];
    int rc = roz_test_dds_open_file(file, NULL, err, sizeof err);
    if (rc == ROZ_TEST_NOT_LOADED)
        printf("%s: [loader] %s\n", file, err);
    else if (rc == ROZ_TEST_NO_DDS_PORT)
        printf("%s: [no DDS port]\n", file);
    else if (rc == ROZ_OK)
        printf("%s: ok\n", file);
    else
        printf("%s: %s\n", file, err);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: port_open_check FILE...\n");
        return 2;
    }
    for (int i = 1; i < argc; i++)
        check(argv[i]);
    return 0;
}
