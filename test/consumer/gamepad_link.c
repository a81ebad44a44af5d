/* SPDX-License-Identifier: Apache-2.0 */
/* Links roz::gamepad from the package and decodes one frame: A pressed on a
 * pad whose left stick is pushed fully up. A package that does not export
 * the gamepad (or its header) fails here. */
#include <stdio.h>
#include <string.h>

#include "roz/gamepad.h"

static roz_gamepad_t gp;

int main(void)
{
    struct input_absinfo abs[ROZ_GAMEPAD_AXES];
    memset(abs, 0, sizeof abs);
    for (int k = 0; k < ROZ_GAMEPAD_AXES; k++) {
        abs[k].minimum = -32768;
        abs[k].maximum = 32767;
    }
    roz_gamepad_init(&gp, abs);
    const struct input_event ev[] = {
        { .type = EV_KEY, .code = BTN_SOUTH, .value = 1 },
        { .type = EV_ABS, .code = ABS_Y, .value = -32768 },
        { .type = EV_SYN, .code = SYN_REPORT, .value = 0 },
    };
    int done = 0;
    for (size_t i = 0; i < sizeof ev / sizeof ev[0]; i++)
        done = roz_gamepad_event(&gp, &ev[i]);
    if (!done || gp.frame.buttons != ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_A) ||
        gp.frame.ly < 0.99f) {
        fprintf(stderr, "consumer: the gamepad's frame: done %d, buttons %#x, ly %g\n", done,
                (unsigned)gp.frame.buttons, (double)gp.frame.ly);
        return 1;
    }
    printf("consumer: roz::gamepad linked: A and the left stick up decoded\n");
    return 0;
}
