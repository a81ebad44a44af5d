# SPDX-License-Identifier: Apache-2.0
"""Every parameter a port lists (rozrun --port NAME --help, from the port's
own table) is documented on its pages (`key` or `key=...`), which the port
names where it registers (roz_add_port(... DOCS ...), shown by --help as
"documented in:"), so a parameter cannot be added to a port without its
page, and a port cannot be registered without one; and its own page (the
first) is in the ports index, docs/ports/README.md.

    python port_params.py ROZRUN DOCS_DIR
"""
import os
import re
import subprocess
import sys


def ports(rozrun):
    out = subprocess.run([rozrun, "--help"], capture_output=True, text=True).stdout
    m = re.search(r"known: ([^)]*)\)", out)
    if not m:
        sys.exit("rozrun --help names no ports")
    return [p.strip() for p in m.group(1).split(",")]


def port_help(rozrun, port):
    """(its pages, its parameters) from rozrun --port PORT --help."""
    out = subprocess.run([rozrun, "--port", port, "--help"], capture_output=True,
                         text=True).stdout
    pages = re.search(r"^  documented in: (.*)$", out, re.M)
    if pages is None:
        sys.exit(f"rozrun --port {port} --help names no page")
    part = out.split("parameters (--param KEY=VALUE):", 1)
    if len(part) != 2:
        sys.exit(f"rozrun --port {port} --help lists no parameters")
    keys = {m.group(1) for m in re.finditer(r"^    ([a-z][a-z0-9_]*) ", part[1], re.M)}
    return pages.group(1).split(), keys


def main():
    rozrun, docs = sys.argv[1], sys.argv[2]
    bad = []
    with open(os.path.join(docs, "ports", "README.md"), encoding="utf-8") as f:
        index = f.read()
    for port in ports(rozrun):
        pages, keys = port_help(rozrun, port)
        if not pages or not all(p.startswith("docs/ports/") for p in pages):
            bad.append(f"{port}: its pages {pages} are not under docs/ports/")
            continue
        texts = [open(os.path.join(docs, p[len("docs/"):]), encoding="utf-8").read()
                 for p in pages]
        own = os.path.basename(pages[0])
        if f"]({own})" not in index:
            bad.append(f"{port}: its page {own} is not in the ports index, docs/ports/README.md")
        for k in sorted(keys):
            if not any(f"`{k}`" in t or f"`{k}=" in t for t in texts):
                bad.append(f"{port}: parameter {k} is not on {' or '.join(pages)}")
    if bad:
        print("\n".join(bad))
        sys.exit(1)
    print(f"port_params: every parameter of {len(ports(rozrun))} ports is on its page")


if __name__ == "__main__":
    main()
