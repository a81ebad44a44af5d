/* SPDX-License-Identifier: Apache-2.0 */
/* Uses what a consumer gets: its own generated table, the core and the
 * built-in registry. Exits non-zero on the first surprise. */
#include <stdio.h>

#include "my_arm_manifest.h"
#include "roz/builtin.h"
#include "roz/manifest.h"

#define CHECK(cond)                                                   \
    do {                                                              \
        if (!(cond)) {                                                \
            fprintf(stderr, "consumer: check failed: %s\n", #cond);   \
            return 1;                                                 \
        }                                                             \
    } while (0)

int main(void)
{
    const roz_manifest_t *m = &roz_manifest_my_arm;
    const roz_manifest_t *ur5 = roz_builtin_find("ur5");

    CHECK(roz_manifest_validate(m, NULL) == ROZ_OK);
    CHECK(ROZ_MY_ARM_N_COMMANDS == 2 && m->n_commands == 2);
    CHECK(roz_manifest_find_command(m, "joint2/velocity") == ROZ_MY_ARM_CMD_JOINT2_VELOCITY);
    CHECK(m->commands[ROZ_MY_ARM_CMD_JOINT2_VELOCITY].position_state ==
          ROZ_MY_ARM_STATE_JOINT2_POSITION);
    CHECK(ur5 != NULL && ur5->n_commands == 6);
    printf("consumer: my_arm %u commands, %u states; ur5 found; roz %s\n",
           (unsigned)m->n_commands, (unsigned)m->n_states, ROZ_VERSION_STRING);
    return 0;
}
