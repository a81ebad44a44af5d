# SPDX-License-Identifier: Apache-2.0
"""Plot a rozrun trace: commanded vs applied commands, and the position states.

    python tools/plot_trace.py trace.csv out.png [--title TEXT]

The trace's columns are tick, time_s, target:<cmd>..., applied:<cmd>...,
state:<state>... (see examples/rozrun/trace.c). Up to six commands and six
position states are drawn.
"""
import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        sys.exit(f"{path}: no rows")
    header, data = rows[0], rows[1:]
    cols = {name: [float(r[i]) for r in data] for i, name in enumerate(header)}
    return header, cols


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("trace")
    ap.add_argument("png")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    header, cols = read(a.trace)
    t = cols["time_s"]
    commands = [h[len("applied:"):] for h in header if h.startswith("applied:")][:6]
    positions = [h for h in header if h.startswith("state:") and h.endswith("/position")][:6]

    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(11, 7.5), sharex=True)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for i, name in enumerate(commands):
        c = colors[i % len(colors)]
        target = cols[f"target:{name}"]
        if not all(math.isnan(v) for v in target):
            ax1.plot(t, target, color=c, linestyle=":", linewidth=1.2)
        ax1.plot(t, cols[f"applied:{name}"], color=c, linewidth=1.4, label=name)
    ax1.set_ylabel("command")
    ax1.set_title("commanded (dotted) vs applied after the safety filter (solid)")
    ax1.legend(fontsize=7, ncol=3, loc="upper right")
    ax1.grid(alpha=0.3)
    for i, name in enumerate(positions):
        ax2.plot(t, cols[name], color=colors[i % len(colors)], label=name[len("state:"):])
    ax2.set_ylabel("position state")
    ax2.set_xlabel("time [s]")
    ax2.legend(fontsize=7, ncol=3, loc="upper right")
    ax2.grid(alpha=0.3)
    if a.title:
        fig.suptitle(a.title)
    fig.tight_layout()
    fig.savefig(a.png, dpi=100)
    print(f"plot: {a.png}")


if __name__ == "__main__":
    main()
