# SPDX-License-Identifier: Apache-2.0
"""Every parameter a port lists (rozrun --port NAME --help, from the port's
own table) is documented on its page under docs/ports/ (`key` or `key=...`),
so a parameter cannot be added to a port without its page. A DDS port's
common parameters are on dds.md.

    python port_params.py ROZRUN DOCS_DIR
"""
import re
import subprocess
import sys

# the page of each port (by the name rozrun knows it by); DDS ports also dds.md
PAGES = {
    "loopback": ["loopback.md"],
    "unitree/G1": ["unitree_g1.md", "dds.md"],
    "engineai/PM01": ["ros2.md", "dds.md"],
    "agibot/X2": ["ros2.md", "dds.md"],
    "socketcan": ["socketcan.md"],
    "mujoco": ["mujoco.md"],
}


def ports(rozrun):
    out = subprocess.run([rozrun, "--help"], capture_output=True, text=True).stdout
    m = re.search(r"known: ([^)]*)\)", out)
    if not m:
        sys.exit("rozrun --help names no ports")
    return [p.strip() for p in m.group(1).split(",")]


def port_keys(rozrun, port):
    out = subprocess.run([rozrun, "--port", port, "--help"], capture_output=True,
                         text=True).stdout
    part = out.split("parameters (--param KEY=VALUE):", 1)
    if len(part) != 2:
        sys.exit(f"rozrun --port {port} --help lists no parameters")
    return {m.group(1) for m in re.finditer(r"^    ([a-z][a-z0-9_]*) ", part[1], re.M)}


def main():
    rozrun, docs = sys.argv[1], sys.argv[2]
    bad = []
    for port in ports(rozrun):
        pages = PAGES.get(port)
        if pages is None:
            bad.append(f"{port}: no page in this test's PAGES (docs/ports/)")
            continue
        texts = [open(f"{docs}/ports/{p}", encoding="utf-8").read() for p in pages]
        keys = port_keys(rozrun, port)
        for k in sorted(keys):
            if not any(f"`{k}`" in t or f"`{k}=" in t for t in texts):
                bad.append(f"{port}: parameter {k} is not on {' or '.join(pages)}")
    if bad:
        print("\n".join(bad))
        sys.exit(1)
    print(f"port_params: every parameter of {len(ports(rozrun))} ports is on its page")


if __name__ == "__main__":
    main()
