# SPDX-License-Identifier: Apache-2.0
"""Commanded vs achieved velocity of a walking robot, from a rozrun trace.

    python tools/tracking.py TRACE --operator FILE [--settle S] [bounds...]

The command is the operator's (rozrun --operator FILE: a header `time_s`, then
input names, one row per change, each value held until the next row); the
trace's `input:` columns are the command as the controller read it (after the
inputs' rate caps). The achieved velocity is the simulator's truth (the
`truth:base.*` columns, not a sensor): the base's travel turned into the
heading frame (x forward, y left, by the base's yaw at each tick) and its yaw
rate. A walking base sways within each step, so the figures are means over a
window: each segment of constant command is judged over its settled part,
from SETTLE seconds after the command changed to the next change:

  moving segment   mean forward and lateral velocity and mean yaw rate
                   against the command (errors in m/s and rad/s)
  stop segment     drift: the base's travel (m) and heading change (rad)
  turning segment  heading change over the whole segment against the
                   commanded rate times its length (a ratio)

Bounds given as options are checked; the figures are printed either way, and
the exit status is 1 when one is outside its bound. plot_trace.py draws the
same series (velocity(): one gait period's centred difference).
"""
import argparse
import csv
import math
import sys

#: the inputs a walking policy reads (robot.toml's [[manifest.inputs]])
VX, VY, WZ = "operator/velocity.x", "operator/velocity.y", "operator/yaw_rate"
#: a gait period of unitree_rl_gym's G1 policy (its phase observation), s:
#: the window the plotted velocity is averaged over
GAIT_PERIOD = 0.8


def read_operator(path):
    """The scripted operator: [(time_s, {input: value})], rows in order,
    each row's values (inputs it does not name keep theirs)."""
    rows, header = [], None
    with open(path, newline="") as f:
        for line in f:
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            cells = [c.strip() for c in next(csv.reader([line]))]
            if header is None:
                if cells[0] != "time_s":
                    sys.exit(f"{path}: the header must start with time_s")
                header = cells
                continue
            rows.append((float(cells[0]), {n: float(v) for n, v in zip(header[1:], cells[1:])}))
    if not rows:
        sys.exit(f"{path}: no rows")
    return rows


def commands(rows):
    """[(t0, (vx, vy, wz))]: the command from each row on, every input held."""
    now, out = {VX: 0.0, VY: 0.0, WZ: 0.0}, []
    for t, values in rows:
        now.update({k: v for k, v in values.items() if k in now})
        out.append((t, (now[VX], now[VY], now[WZ])))
    return out


def read_trace(path):
    with open(path, newline="") as f:
        r = csv.reader(f)
        header = next(r)
        cols = {h: [] for h in header}
        for row in r:
            for h, v in zip(header, row):
                if h != "events":
                    cols[h].append(float(v))
    for need in ("time_s", "truth:base.x", "truth:base.y", "truth:base.yaw"):
        if need not in cols:
            sys.exit(f"{path}: no column {need} (a simulator's run has the truth columns)")
    return cols


def unwrap(angles):
    out, last = [], None
    for a in angles:
        if last is not None:
            while a - last > math.pi:
                a -= 2 * math.pi
            while a - last < -math.pi:
                a += 2 * math.pi
        out.append(a)
        last = a
    return out


def heading_steps(cols):
    """Per tick k >= 1: the base's step from tick k-1 in the heading frame
    (forward, left) and the heading change, unwrapped."""
    x, y, yaw = cols["truth:base.x"], cols["truth:base.y"], unwrap(cols["truth:base.yaw"])
    steps = [(0.0, 0.0, 0.0)]
    for k in range(1, len(x)):
        dx, dy = x[k] - x[k - 1], y[k] - y[k - 1]
        h = 0.5 * (yaw[k] + yaw[k - 1])
        steps.append((math.cos(h) * dx + math.sin(h) * dy,
                      -math.sin(h) * dx + math.cos(h) * dy, yaw[k] - yaw[k - 1]))
    return steps


def velocity(cols, window=GAIT_PERIOD):
    """(t, vx, vy, wz): the achieved velocity in the heading frame at each
    tick, each a centred difference over @p window seconds (NaN near the
    ends)."""
    t = cols["time_s"]
    steps = heading_steps(cols)
    dt = t[1] - t[0] if len(t) > 1 else 1.0
    half = max(1, int(round(window / dt / 2)))
    acc = [(0.0, 0.0, 0.0)]
    for s in steps[1:]:
        a = acc[-1]
        acc.append((a[0] + s[0], a[1] + s[1], a[2] + s[2]))
    out = ([], [], [])
    for k in range(len(t)):
        if k - half < 0 or k + half >= len(t):
            for o in out:
                o.append(math.nan)
            continue
        span = t[k + half] - t[k - half]
        for i in range(3):
            out[i].append((acc[k + half][i] - acc[k - half][i]) / span)
    return (t, *out)


def judge(cols, rows, settle):
    """One dict per segment of constant command (see the module's text)."""
    t = cols["time_s"]
    steps = heading_steps(cols)
    cmds = commands(rows)
    end = t[-1]
    out = []
    for i, (t0, c) in enumerate(cmds):
        t1 = cmds[i + 1][0] if i + 1 < len(cmds) else end
        t1 = min(t1, end)
        if t1 - t0 <= settle:
            continue
        ks = [k for k in range(1, len(t)) if t0 + settle < t[k] <= t1]
        whole = [k for k in range(1, len(t)) if t0 < t[k] <= t1]
        dur = t[ks[-1]] - t[ks[0] - 1]
        fx = sum(steps[k][0] for k in ks)
        fy = sum(steps[k][1] for k in ks)
        turn = sum(steps[k][2] for k in ks)
        seg = {"from": t0, "to": t1, "command": c, "settled_s": dur,
               "vx": fx / dur, "vy": fy / dur, "wz": turn / dur}
        if any(c):
            seg["kind"] = "turn" if c[2] != 0 and c[0] == 0 and c[1] == 0 else "move"
            seg["vx_error"] = abs(seg["vx"] - c[0])
            seg["vy_error"] = abs(seg["vy"] - c[1])
            seg["wz_error"] = abs(seg["wz"] - c[2])
            if c[2] != 0:
                heading = sum(steps[k][2] for k in whole)
                seg["heading"] = heading
                seg["heading_ratio"] = heading / (c[2] * (t1 - t0))
        else:
            seg["kind"] = "stop"
            seg["drift_m"] = math.hypot(fx, fy)
            seg["drift_rad"] = abs(turn)
        out.append(seg)
    return out


def report(segs):
    lines = []
    for s in segs:
        c = s["command"]
        head = (f"{s['from']:5.1f}-{s['to']:5.1f} s  {s['kind']:4}  command vx {c[0]:+.2f} "
                f"vy {c[1]:+.2f} wz {c[2]:+.2f}  achieved vx {s['vx']:+.3f} vy {s['vy']:+.3f} "
                f"wz {s['wz']:+.3f}")
        if s["kind"] == "stop":
            head += f"  drift {s['drift_m']:.3f} m {math.degrees(s['drift_rad']):.1f} deg"
        else:
            head += (f"  error vx {s['vx_error']:.3f} vy {s['vy_error']:.3f} "
                     f"wz {s['wz_error']:.3f}")
        if "heading" in s:
            head += (f"  heading {math.degrees(s['heading']):+.1f} deg "
                     f"({s['heading_ratio']:.2f} of the command)")
        lines.append(head)
    return "\n".join(lines)


def check(segs, a):
    """The bounds given in @p a that a segment breaks, as sentences."""
    bad = []
    for s in segs:
        where = f"{s['from']:g}-{s['to']:g} s ({s['kind']})"
        if s["kind"] != "stop":
            for key, bound in (("vx_error", a.max_speed_error), ("vy_error", a.max_speed_error),
                               ("wz_error", a.max_yaw_rate_error)):
                if bound is not None and s[key] > bound:
                    bad.append(f"{where}: {key} {s[key]:.3f} above {bound}")
            if "heading_ratio" in s and a.heading_ratio is not None:
                lo, hi = a.heading_ratio
                if not lo <= s["heading_ratio"] <= hi:
                    bad.append(f"{where}: heading change {s['heading_ratio']:.3f} of the "
                               f"command, outside [{lo}, {hi}]")
        else:
            if a.max_stop_drift is not None and s["drift_m"] > a.max_stop_drift:
                bad.append(f"{where}: drift {s['drift_m']:.3f} m above {a.max_stop_drift}")
            if a.max_stop_turn is not None and s["drift_rad"] > a.max_stop_turn:
                bad.append(f"{where}: heading drift {s['drift_rad']:.3f} rad above "
                           f"{a.max_stop_turn}")
    return bad


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("trace")
    ap.add_argument("--operator", required=True, metavar="FILE",
                    help="the scripted operator the run followed (rozrun --operator)")
    ap.add_argument("--settle", type=float, default=2.0, metavar="S",
                    help="seconds after each change before a segment is judged (2)")
    ap.add_argument("--max-speed-error", type=float, metavar="M/S",
                    help="moving segments: |mean vx - command| and |mean vy - command|")
    ap.add_argument("--max-yaw-rate-error", type=float, metavar="RAD/S",
                    help="moving segments: |mean yaw rate - command|")
    ap.add_argument("--max-stop-drift", type=float, metavar="M",
                    help="stop segments: the base's travel over the settled part")
    ap.add_argument("--max-stop-turn", type=float, metavar="RAD",
                    help="stop segments: the heading change over the settled part")
    ap.add_argument("--heading-ratio", type=lambda s: tuple(map(float, s.split(":"))),
                    metavar="LO:HI", help="turning segments: heading change over the "
                    "commanded rate times the segment's length")
    a = ap.parse_args()
    segs = judge(read_trace(a.trace), read_operator(a.operator), a.settle)
    print(report(segs))
    bad = check(segs, a)
    for b in bad:
        print(f"tracking: {b}", file=sys.stderr)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
