#!/bin/sh
# SPDX-License-Identifier: Apache-2.0
# Runs a DDS test in a private network namespace whose only interface is
# lo, brought up: its traffic cannot leave the machine, and tests running at
# the same time cannot hear each other. Where the namespace is not
# permitted, the test runs on lo in the machine's namespace, and this says
# so (each DDS test also has a domain id of its own).
#   run_netns.sh COMMAND [ARG]...
if command -v unshare >/dev/null 2>&1 && command -v ip >/dev/null 2>&1; then
    for flags in -n -rn; do
        if unshare $flags true 2>/dev/null; then
            exec unshare $flags sh -c 'ip link set lo up && exec "$@"' run_netns "$@"
        fi
    done
fi
echo "run_netns: a private network namespace is not permitted here (unshare -n):" \
     "running on lo in the machine's own namespace"
exec "$@"
