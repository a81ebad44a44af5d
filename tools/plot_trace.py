# SPDX-License-Identifier: Apache-2.0
"""Plot a rozrun trace: commanded vs applied commands, and the position states.

    python tools/plot_trace.py trace.csv out.png [--title TEXT] [--compare other.csv]
                               [--channels REGEX] [--span FROM:TO:LABEL] [--operator FILE]
    roz-plot ...                 (the same, installed with roz)

The trace's columns are tick, time_s, target:<cmd>..., applied:<cmd>...,
state:<state>..., from a simulator truth:base.x..yaw, faults, events (see
tools/rozrun/trace.h). Every command and every position state is drawn, six
to a pair of axes (commands above, positions below, each position with its
joint's applied position command dotted where it has one: the tracking), in
as many pairs as it takes; --channels REGEX draws only those whose names
match. A trace with the truth columns gets one more plot: the base's height
and its roll and pitch. --span shades FROM..TO (seconds) on every plot with
LABEL (a push, say). Ticks with a fault latched are shaded, and each event (e-stop press and release, clear, swap, refused swap,
rebuild, a fault latching) is a labelled vertical line. Traces written before
the faults and events columns existed plot without them. With --compare, a
second trace is drawn beside the first on the same axes (two runs side by
side; tools/recording.py compare does the same for two recordings).

A trace with the operator's inputs (`input:` columns: a walking policy's
velocity command) and the truth columns gets two more plots: commanded vs
achieved base velocity in the heading frame (forward, lateral) and yaw rate
(tools/tracking.py: the truth's centred difference over one gait period).
--operator FILE (the script rozrun --operator followed) marks each of its rows
on every plot with the command it gives.
"""
import argparse
import csv
import importlib.util
import math
import pathlib
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

TEXT_COLUMNS = ("events",)

_spec = importlib.util.spec_from_file_location(
    "tracking", pathlib.Path(__file__).resolve().parent / "tracking.py")
tracking = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(tracking)


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        sys.exit(f"{path}: no rows")
    header, data = rows[0], rows[1:]
    cols = {}
    for i, name in enumerate(header):
        if name in TEXT_COLUMNS:
            cols[name] = [r[i] if i < len(r) else "" for r in data]
        else:
            cols[name] = [float(r[i]) for r in data]
    return header, cols


def fault_spans(t, faults):
    """(start, end) times of the runs of rows with a fault latched."""
    spans, start = [], None
    for i, f in enumerate(faults):
        if f and start is None:
            start = t[i]
        elif not f and start is not None:
            spans.append((start, t[i]))
            start = None
    if start is not None:
        spans.append((start, t[-1]))
    return spans


def event_label(events):
    """A row's events as a label, and whether they stop the robot (an e-stop
    press or a fault latching: drawn red). cleared:<name> tokens are left to
    the clear that caused them."""
    words, stop = [], False
    for token in events.split():
        if not token or token.startswith("cleared:"):
            continue
        if token.startswith("fault:"):
            words.append("fault: " + token[len("fault:"):])
            stop = True
        else:
            words.append(token)
            stop = stop or token == "estop"
    return ", ".join(words), stop


def mark(axes, t, cols):
    """Shade the latched faults and mark each event, on every axis."""
    if "faults" in cols:
        for i, (a, b) in enumerate(fault_spans(t, cols["faults"])):
            for ax in axes:
                ax.axvspan(a, b, color="tab:red", alpha=0.12, linewidth=0,
                           label="fault latched" if i == 0 and ax is axes[0] else None)
    if "events" not in cols:
        return
    for i, events in enumerate(cols["events"]):
        label, stop = event_label(events)
        if not label:
            continue
        color = "tab:red" if stop else "0.3"
        for ax in axes:
            ax.axvline(t[i], color=color, linestyle="--", linewidth=0.8)
        # at the foot of the upper plot, clear of the legends
        axes[0].annotate(label, xy=(t[i], 0.0), xycoords=("data", "axes fraction"),
                         xytext=(2, 4), textcoords="offset points", rotation=90,
                         va="bottom", ha="left", fontsize=7, color=color,
                         bbox=dict(boxstyle="square,pad=0.1", fc="white", ec="none", alpha=0.7))


#: Channels drawn on one pair of axes; more make more pairs (rows).
PER_AXES = 6


def channels(header, pattern=None):
    """The trace's commands and position states, in file order, those whose
    name (without its target:/applied:/state: prefix) matches the regular
    expression pattern (re.search) when one is given."""
    commands = [h[len("applied:"):] for h in header if h.startswith("applied:")]
    positions = [h[len("state:"):] for h in header
                 if h.startswith("state:") and h.endswith("/position")]
    if pattern:
        commands = [n for n in commands if pattern.search(n)]
        positions = [n for n in positions if pattern.search(n)]
    return commands, positions


def rows_needed(header, pattern=None):
    """Pairs of axes (command row, position row) one run needs: every channel
    is drawn, PER_AXES to a pair."""
    commands, positions = channels(header, pattern)
    return max(1, math.ceil(len(commands) / PER_AXES), math.ceil(len(positions) / PER_AXES))


def draw(axes, header, cols, label="", pattern=None):
    """One run on a column of axes: pairs of (commanded vs applied, position
    states), PER_AXES channels to each, until every channel is drawn."""
    t = cols["time_s"]
    commands, positions = channels(header, pattern)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    pairs = len(axes) // 2
    for g in range(pairs):
        ax1, ax2 = axes[2 * g], axes[2 * g + 1]
        group = commands[g * PER_AXES:(g + 1) * PER_AXES]
        for i, name in enumerate(group):
            c = colors[i % len(colors)]
            target = cols[f"target:{name}"]
            if not all(math.isnan(v) for v in target):
                ax1.plot(t, target, color=c, linestyle=":", linewidth=1.2)
            ax1.plot(t, cols[f"applied:{name}"], color=c, linewidth=1.4, label=name)
        for i, name in enumerate(positions[g * PER_AXES:(g + 1) * PER_AXES]):
            c = colors[i % len(colors)]
            ax2.plot(t, cols[f"state:{name}"], color=c, label=name)
            if f"applied:{name}" in cols:  # its command, unlabelled: the tracking
                ax2.plot(t, cols[f"applied:{name}"], color=c, linestyle=":", linewidth=1.2)
        part = f" {g * PER_AXES + 1}-{min((g + 1) * PER_AXES, max(len(commands), len(positions)))}"
        ax1.set_ylabel("command" + (part if pairs > 1 else ""))
        ax2.set_ylabel("position state (dotted: its command)" + (part if pairs > 1 else ""))
        for ax in (ax1, ax2):
            if any(not ln.get_label().startswith("_") for ln in ax.lines):
                ax.legend(fontsize=7, ncol=3, loc="upper right")
            ax.grid(alpha=0.3)
    mark(axes, t, cols)
    what = "commanded (dotted) vs applied after the safety filter (solid)"
    axes[0].set_title(f"{label}: {what}" if label else what, fontsize=9 if label else None)
    axes[-1].set_xlabel("time [s]")


def draw_truth(ax, cols):
    """The simulator's truth: base height (left axis), roll and pitch (right)."""
    t = cols["time_s"]
    ax.plot(t, cols["truth:base.z"], color="k", linewidth=1.4, label="base height [m]")
    finite = [v for v in cols["truth:base.z"] if not math.isnan(v)]
    ax.set_ylim(0.0, max([1.0] + [v * 1.1 for v in finite]))
    ax.set_ylabel("base height [m]")
    ax.grid(alpha=0.3)
    tilt = ax.twinx()
    tilt.plot(t, [math.degrees(v) for v in cols["truth:base.roll"]], color="tab:blue",
              linewidth=1.0, label="roll [deg]")
    tilt.plot(t, [math.degrees(v) for v in cols["truth:base.pitch"]], color="tab:orange",
              linewidth=1.0, label="pitch [deg]")
    tilt.set_ylabel("tilt [deg]")
    lines = [ln for ln in ax.get_lines() + tilt.get_lines() if not ln.get_label().startswith("_")]
    ax.legend(lines, [ln.get_label() for ln in lines], fontsize=7, ncol=3, loc="lower right")
    ax.set_title("the simulator's truth (not a sensor)", fontsize=9)


def has_velocity(cols):
    """A walking run: the velocity command among the inputs, and the truth."""
    return (f"input:{tracking.VX}" in cols and f"input:{tracking.WZ}" in cols
            and "truth:base.yaw" in cols)


def draw_velocity(ax_lin, ax_yaw, cols):
    """Commanded (the inputs as the controller read them, dotted) vs achieved
    (the truth, solid): forward and lateral velocity, then yaw rate."""
    t, vx, vy, wz = tracking.velocity(cols)
    ax_lin.plot(t, cols[f"input:{tracking.VX}"], color="tab:blue", linestyle=":", linewidth=1.6)
    ax_lin.plot(t, vx, color="tab:blue", linewidth=1.4, label="forward")
    if f"input:{tracking.VY}" in cols:
        ax_lin.plot(t, cols[f"input:{tracking.VY}"], color="tab:orange", linestyle=":",
                    linewidth=1.6)
    ax_lin.plot(t, vy, color="tab:orange", linewidth=1.4, label="lateral")
    ax_lin.set_ylabel("base velocity [m/s]")
    ax_lin.set_title("operator's command (dotted) vs achieved, heading frame, mean over a "
                     f"gait period ({tracking.GAIT_PERIOD:g} s)", fontsize=9)
    ax_yaw.plot(t, cols[f"input:{tracking.WZ}"], color="tab:green", linestyle=":", linewidth=1.6)
    ax_yaw.plot(t, wz, color="tab:green", linewidth=1.4, label="yaw rate")
    ax_yaw.set_ylabel("yaw rate [rad/s]")
    for ax in (ax_lin, ax_yaw):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=3, loc="center right")


def operator_marks(rows):
    """[(time_s, label)]: each row of a scripted operator and what it
    commands (the inputs it changes; the first row says all)."""
    marks, last = [], {}
    units = {tracking.VX: ("forward", "m/s"), tracking.VY: ("lateral", "m/s"),
             tracking.WZ: ("turn", "rad/s")}
    for t, values in rows:
        changed = {k: v for k, v in values.items() if last.get(k) != v}
        last.update(values)
        moving = [k for k, v in last.items() if v != 0.0]
        if not changed and marks:
            continue
        if not moving:
            words = ["stop"]
        else:
            words = [f"{units.get(k, (k, ''))[0]} {last[k]:g} {units.get(k, ('', ''))[1]}".rstrip()
                     for k in moving]
        marks.append((t, ", ".join(words)))
    return marks


def draw_operator(axes, marks):
    """Each of the operator's commands: a line on every axis, its label atop
    the first."""
    for t, label in marks:
        for ax in axes:
            ax.axvline(t, color="tab:purple", linestyle="-.", linewidth=0.9)
        axes[0].annotate(label, xy=(t, 1.0), xycoords=("data", "axes fraction"),
                         xytext=(3, -4), textcoords="offset points", rotation=0,
                         va="top", ha="left", fontsize=8, color="tab:purple",
                         bbox=dict(boxstyle="square,pad=0.1", fc="white", ec="none", alpha=0.8))


def figure(runs, title="", pattern=None, spans=(), operator=()):
    """The figure of one run, or several side by side (same axes): runs is a
    list of (header, cols, label); pattern a compiled regular expression
    that picks channels, or None for all; spans (from_s, to_s, label) are
    shaded; operator: the rows of a scripted operator (tracking.read_operator)
    to mark."""
    n = len(runs)
    pairs = max(rows_needed(header, pattern) for header, _, _ in runs)
    truth = all("truth:base.z" in cols for _, cols, _ in runs)
    walk = all(has_velocity(cols) for _, cols, _ in runs)
    top = 2 if walk else 0
    rows = top + 2 * pairs + (1 if truth else 0)
    fig, axes = plt.subplots(rows, n, figsize=(11 * n if n == 1 else 8 * n, 3.75 * rows),
                             sharex=True, sharey="row", squeeze=False)
    for k, (header, cols, label) in enumerate(runs):
        if walk:
            draw_velocity(axes[0][k], axes[1][k], cols)
        draw([axes[r][k] for r in range(top, top + 2 * pairs)], header, cols, label, pattern)
        if operator:
            draw_operator([axes[r][k] for r in range(rows)], operator_marks(operator))
        if truth:
            draw_truth(axes[rows - 1][k], cols)
            axes[rows - 2][k].set_xlabel("")  # the time axis is the truth's, below
            axes[rows - 1][k].set_xlabel("time [s]")
        for a, b, what in spans:
            for r in range(rows):
                axes[r][k].axvspan(a, b, color="tab:purple", alpha=0.25, linewidth=0,
                                   label=what if r == rows - 1 else None)
            axes[0][k].annotate(what, xy=(a, 1.0), xycoords=("data", "axes fraction"),
                                xytext=(2, -12), textcoords="offset points", fontsize=8,
                                color="tab:purple")
    if title:
        fig.suptitle(title)
    # the figure's title above the first plot's own, never over it
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.45 / fig.get_figheight()) if title else None)
    return fig


def plot(runs, png, title="", pattern=None, spans=(), operator=()):
    """Draws runs (figure()) into png."""
    fig = figure(runs, title, pattern, spans, operator)
    fig.savefig(png, dpi=100)
    plt.close(fig)
    print(f"plot: {png}")


def channel_filter(text, headers):
    """--channels REGEX compiled; exits naming the channels when it is not a
    regular expression or matches none of them."""
    if text is None:
        return None
    try:
        pattern = re.compile(text)
    except re.error as e:
        sys.exit(f"--channels {text!r}: not a regular expression: {e}")
    if not any(any(channels(h, pattern)) for h in headers):
        names = sorted({n for h in headers for part in channels(h) for n in part})
        sys.exit(f"--channels {text!r} matches no channel; the trace has: {', '.join(names)}")
    return pattern


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("trace")
    ap.add_argument("png")
    ap.add_argument("--title", default="")
    ap.add_argument("--compare", metavar="TRACE",
                    help="a second trace, drawn beside the first on the same axes")
    ap.add_argument("--channels", metavar="REGEX",
                    help="draw only the commands and position states whose names match "
                         "(re.search), e.g. 'joint[67]|gripper'; default: all")
    ap.add_argument("--span", action="append", default=[], metavar="FROM:TO:LABEL",
                    help="shade FROM..TO seconds with LABEL (repeatable)")
    ap.add_argument("--operator", metavar="FILE",
                    help="the scripted operator the run followed (rozrun --operator): each "
                         "of its commands marked on every plot")
    a = ap.parse_args()
    spans = []
    for text in a.span:
        parts = text.split(":", 2)
        try:
            spans.append((float(parts[0]), float(parts[1]), parts[2] if len(parts) > 2 else ""))
        except (ValueError, IndexError):
            sys.exit(f"--span {text!r}: expected FROM:TO:LABEL, seconds")
    runs = [(*read(a.trace), a.trace if a.compare else "")]
    if a.compare:
        runs.append((*read(a.compare), a.compare))
    operator = tracking.read_operator(a.operator) if a.operator else ()
    plot(runs, a.png, a.title, channel_filter(a.channels, [r[0] for r in runs]), spans, operator)


if __name__ == "__main__":
    main()
