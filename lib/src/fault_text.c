/* SPDX-License-Identifier: Apache-2.0 */
/* The words of the faults, for the runtime's readers and the recorder's
 * drain alike: a file of its own, so that neither calls into the other. */
#include "fault_text.h"

#include "roz/format.h"
#include "roz/runtime.h"

static const char *const fault_names[ROZ_FAULT_KIND_COUNT] = {
    "trap", "overrun", "stale state", "e-stop", "controller e-stop request", "port link",
    "robot fault", "command timeout", "fall",
};

const char *roz_fault_name(unsigned fault_bit)
{
    for (int i = 0; i < ROZ_FAULT_KIND_COUNT; i++) {
        if (fault_bit == 1u << i)
            return fault_names[i];
    }
    return "?";
}

void roz__fault_format(char *buf, size_t len, unsigned bit, const uint64_t num[4],
                       const char *text)
{
    int64_t tick = (int64_t)(num[N_TICK_LO] | (num[N_TICK_HI] << 32));

    switch (bit) {
    case 0:
        roz_format(buf, len, "%s", "");
        break;
    case ROZ_FAULT_STALE:
        if (text != NULL && text[0] != '\0')
            roz_format(buf, len, "no fresh state for %u ticks: %s", (unsigned)num[N_A], text);
        else
            roz_format(buf, len, "no fresh state for %u ticks", (unsigned)num[N_A]);
        break;
    case ROZ_FAULT_ESTOP:
        roz_format(buf, len, "e-stop input");
        break;
    case ROZ_FAULT_ESTOP_REQUEST:
        roz_format(buf, len, "the controller called safety.request_estop");
        break;
    case ROZ_FAULT_LINK:
        roz_format(buf, len,
                   "port link fault: the robot restarted or came back after it was lost");
        break;
    case ROZ_FAULT_ROBOT:
        roz_format(buf, len, "robot fault: %s %lu (0x%lx)",
                   text != NULL && text[0] != '\0' ? text : "the port reports a fault, code",
                   (unsigned long)num[N_A], (unsigned long)num[N_A]);
        break;
    case ROZ_FAULT_COMMAND_TIMEOUT:
        roz_format(buf, len,
                   "command timeout: the tick wrote no command for %lu us, longer than the "
                   "port's command_timeout_us (%lu): the port sent the robot its safe command",
                   (unsigned long)num[N_A], (unsigned long)num[N_B]);
        break;
    case ROZ_FAULT_FALL:
        roz_format(buf, len,
                   "fall: the base tilted %lu mrad from upright, beyond the fall rule's %lu "
                   "mrad (manifest.fall): the fallen stop, zero stiffness and the manifest's "
                   "damping",
                   (unsigned long)num[N_A], (unsigned long)num[N_B]);
        break;
    default:
        if (bit == ROZ_FAULT_OVERRUN && (text == NULL || text[0] == '\0') && num[N_B] != 0)
            roz_format(buf, len, "process() took %llu us at tick %lld, budget %llu us",
                       (unsigned long long)num[N_A], (long long)tick,
                       (unsigned long long)num[N_B]);
        else if (text != NULL && text[0] != '\0')
            roz_format(buf, len, "%s", text);
        else
            roz_format(buf, len, "%s at tick %lld", roz_fault_name(bit), (long long)tick);
        break;
    }
}
