#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
#
#   tools/fw_run.sh MACHINE IMAGE.elf AIM_FLASH_KB AIM_RAM_KB TITLE
#
# Boots a firmware image in QEMU (-icount shift=0: deterministic, one
# instruction per virtual nanosecond; semihosting carries the output and the
# exit status), keeps its output beside the image (IMAGE.txt), prints it and
# the footprint table of its link map (IMAGE.map, tools/fw_footprint.py)
# against the aims. Exits non-zero when the image did not run as expected.
set -euo pipefail
[ $# -eq 5 ] || { echo "usage: $0 MACHINE IMAGE.elf AIM_FLASH_KB AIM_RAM_KB TITLE" >&2; exit 2; }
machine=$1 image=$2 aim_flash=$3 aim_ram=$4 title=$5
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out=${image%.elf}.txt
map=${image%.elf}.map
python=${PYTHON:-python3}

status=0
timeout 120 qemu-system-arm -M "$machine" -nographic -monitor none -serial none \
    -semihosting-config enable=on,target=native -icount shift=0 -kernel "$image" \
    >"$out" 2>&1 || status=$?
printf '\n==== %s\n' "$title"
cat "$out"
echo
"$python" "$root/tools/fw_footprint.py" "$map" --elf "$image" --run "$out" --aim-flash "$aim_flash" \
    --aim-ram "$aim_ram" --title "footprint: $title"
if [ "$status" -ne 0 ]; then
    echo "fw_run: $image exited with $status under $machine" >&2
    exit 1
fi
