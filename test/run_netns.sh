#!/bin/sh
# SPDX-License-Identifier: Apache-2.0
# run_netns.sh COMMAND [ARG...]: run a DDS test in a network namespace of
# its own in which only the loopback interface exists and is up, so that
# its traffic can neither leave the machine nor meet another test's. As
# root that is `unshare -n`; otherwise a user namespace (`unshare -rn`)
# where the kernel allows one. Where neither is permitted (or `ip` is
# missing) the test runs on the host's loopback, and this says so.
set -u
[ $# -ge 1 ] || { echo "usage: run_netns.sh COMMAND [ARG...]" >&2; exit 2; }
# A test configures DDS itself, for the loopback; a user's Cyclone DDS
# configuration (which may name another interface) is not for tests.
unset CYCLONEDDS_URI

inner='ip link set lo up && exec "$@"'
for flags in -n -rn; do
    if unshare $flags sh -c 'ip link set lo up' >/dev/null 2>&1; then
        exec unshare $flags sh -c "$inner" sh "$@"
    fi
done
echo "run_netns.sh: no network namespace permitted here (unshare -n, -rn);" \
     "running on the host's loopback" >&2
exec "$@"
