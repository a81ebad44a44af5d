#!/bin/sh
# SPDX-License-Identifier: Apache-2.0
# run_vcan.sh COMMAND [ARG...]: run a CAN test on a virtual CAN interface,
# vcan0, in a network namespace of its own (`unshare -n` as root, a user
# namespace `unshare -rn` otherwise), so that its frames meet nothing else.
# Where no namespace is permitted, or the kernel offers no vcan (the module
# is missing), it says why and exits 77, which ctest counts as skipped.
set -u
[ $# -ge 1 ] || { echo "usage: run_vcan.sh COMMAND [ARG...]" >&2; exit 2; }
for flags in -n -rn; do
    unshare $flags sh -c 'ip link set lo up' >/dev/null 2>&1 || continue
    if why=$(unshare $flags sh -c 'ip link add dev vcan0 type vcan' 2>&1); then
        exec unshare $flags sh -c 'ip link add dev vcan0 type vcan && ip link set vcan0 up &&
                                   exec "$@"' sh "$@"
    fi
    echo "run_vcan.sh: skipped: no vcan interface here (ip link add dev vcan0 type vcan: $why)"
    exit 77
done
echo "run_vcan.sh: skipped: no network namespace permitted here (unshare -n, -rn)"
exit 77
