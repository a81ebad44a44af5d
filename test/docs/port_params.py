# SPDX-License-Identifier: Apache-2.0
"""Every parameter a port lists (rozrun --port NAME --help, from the port's
own table) is documented on its pages (`key` or `key=...`), which the port
names where it registers (roz_add_port(... DOCS ...), shown by --help as
"documented in:"), so a parameter cannot be added to a port without its
page, and a port cannot be registered without one. The ports index,
docs/ports/README.md, lists the ports from the same registry: its table
between the "ports:" markers is written by --write (a row a port: its name,
summary, header and pages, from its info and registration), and the test
holds every port this build registers to its row there.

    python port_params.py ROZRUN DOCS_DIR            (the test)
    python port_params.py --write ROZRUN DOCS_DIR    (rewrites the table)
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


BEGIN = ("<!-- ports: written from the port registry by test/docs/port_params.py --write; "
         "do not edit -->")
END = "<!-- /ports -->"
HEAD = "| port (`--port`) | what | header | pages |\n|---|---|---|---|\n"


def index_row(rozrun, port, pages):
    """The index's row of PORT: its info's summary and header, its pages."""
    out = subprocess.run([rozrun, "--port", port, "--help"], capture_output=True,
                         text=True).stdout
    m = re.search(r"^Port (\S+): (.*) \((\S+)\)$", out, re.M)
    if m is None:
        sys.exit(f"rozrun --port {port} --help gives no summary")
    links = ", ".join(f"[{os.path.basename(p)}]({os.path.basename(p)})" for p in pages)
    summary = m.group(2).replace("|", "\\|")
    return f"| `{port}` | {summary} | `{m.group(3)}` | {links} |"


def main():
    write = sys.argv[1] == "--write"
    rozrun, docs = sys.argv[1 + write], sys.argv[2 + write]
    bad = []
    path = os.path.join(docs, "ports", "README.md")
    with open(path, encoding="utf-8") as f:
        index = f.read()
    if BEGIN not in index or END not in index:
        sys.exit(f"{path}: no table between the markers {BEGIN} and {END}")
    before, rest = index.split(BEGIN, 1)
    table, after = rest.split(END, 1)
    rows = []
    for port in ports(rozrun):
        pages, keys = port_help(rozrun, port)
        if not pages or not all(p.startswith("docs/ports/") for p in pages):
            bad.append(f"{port}: its pages {pages} are not under docs/ports/")
            continue
        texts = [open(os.path.join(docs, p[len("docs/"):]), encoding="utf-8").read()
                 for p in pages]
        rows.append(index_row(rozrun, port, pages))
        if not write and rows[-1] not in table.splitlines():
            bad.append(f"{port}: its row of the ports index, docs/ports/README.md, is not\n"
                       f"  {rows[-1]}\n  (python3 test/docs/port_params.py --write ROZRUN docs)")
        for k in sorted(keys):
            if not any(f"`{k}`" in t or f"`{k}=" in t for t in texts):
                bad.append(f"{port}: parameter {k} is not on {' or '.join(pages)}")
    if write:
        with open(path, "w", encoding="utf-8") as f:
            f.write(before + BEGIN + "\n" + HEAD + "\n".join(rows) + "\n" + END + after)
    if bad:
        print("\n".join(bad))
        sys.exit(1)
    print(f"port_params: every parameter of {len(ports(rozrun))} ports is on its page")


if __name__ == "__main__":
    main()
