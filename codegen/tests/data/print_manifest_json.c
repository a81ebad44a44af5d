/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Test helper for codegen/tests/test_compile.py: prints a manifest of the
 * generated registry in rozgen's canonical JSON with the printer of
 * tools/manifest_json/json.c, to show that the generated C tables hold
 * exactly what `rozgen --json` prints.
 *
 *   print_manifest_json <robot_id>   the manifest's JSON
 *   print_manifest_json --identity <robot_id>
 *                                    "<robot_id> <hash>" as `rozgen --identity`
 *                                    prints it, the hash computed from the
 *                                    tables (roz_manifest_interface_hash())
 *   print_manifest_json --registry   check roz/builtin.h, print the ids
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "roz/builtin.h"
#include "roz/identity.h"

static int check_registry(void)
{
    size_t i, n = roz_builtin_count();

    if (n == 0 || roz_builtin_at(n) != NULL || roz_builtin_find(NULL) != NULL ||
        roz_builtin_find("no such robot") != NULL) {
        return 1;
    }
    for (i = 0; i < n; i++) {
        const roz_manifest_t *m = roz_builtin_at(i);

        if (m == NULL || roz_builtin_find(m->robot_id) != m ||
            (i > 0 && strcmp(roz_builtin_at(i - 1)->robot_id, m->robot_id) >= 0)) {
            return 1;
        }
        printf("%s\n", m->robot_id);
    }
    return 0;
}

int main(int argc, char **argv)
{
    const roz_manifest_t *m;

    if (argc == 3 && strcmp(argv[1], "--identity") == 0) {
        m = roz_builtin_find(argv[2]);
        if (m == NULL) {
            return 1;
        }
        printf("%s %016llx\n", m->robot_id,
               (unsigned long long)roz_manifest_interface_hash(m));
        return 0;
    }
    if (argc != 2) {
        return 2;
    }
    if (strcmp(argv[1], "--registry") == 0) {
        return check_registry();
    }
    m = roz_builtin_find(argv[1]);
    if (m == NULL) {
        return 1;
    }
    manifest_json_print(m, 0);
    return 0;
}
