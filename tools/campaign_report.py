# SPDX-License-Identifier: Apache-2.0
"""The report of a campaign (tools/campaign.py): static HTML with PNG plots.

    python tools/campaign_report.py DIR       (DIR: what `roz-campaign run` wrote)

Writes, in DIR: index.html (the pass rate per family and per controller
build, each family's boundary, the two first builds compared sample by
sample, the worst cases with their plots and the command that runs each
again), results.csv (every sample, one row each), and plots/*.png. It reads
only DIR/campaign.json and DIR/results.jsonl, so it can be written again at
any time, during a campaign too.
"""
import csv
import json
import math
import os
import sys

import jinja2
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import campaign  # noqa: E402

WORST = 6  # worst cases shown with plots

PAGE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>Campaign {{ c.name }}</title>
<style>
body { font-family: sans-serif; margin: 2em; max-width: 75em; color: #222; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.6em; text-align: right; }
th { background: #eee; } td.l, th.l { text-align: left; }
.pass { background: #d8f0d8; } .fail { background: #f6d5d5; } .mid { background: #f6ecc8; }
code { font-size: 0.85em; word-break: break-all; }
figure { display: inline-block; margin: 0.5em; vertical-align: top; max-width: 36em; }
figcaption { font-size: 0.85em; }
</style></head><body>
<h1>Campaign {{ c.name }}</h1>
<p id="summary">Robot <b>{{ c.robot }}</b> on port {{ c.port }}, {{ c.duration_s }} s simulated a
sample, seed {{ c.seed }}; {{ n_rows }} of {{ n_total }} samples in the results,
<b>{{ n_pass }}</b> passed, <b>{{ n_rows - n_pass }}</b> failed.
File: <code>{{ c.file }}</code>.</p>

<h2>Pass rate</h2>
<table id="pass-rate"><tr><th class="l">family</th>{% for ct in controllers %}<th>{{ ct }}</th>{% endfor %}</tr>
{% for f in families %}<tr><td class="l">{{ f }}</td>{% for ct in controllers %}{% set r = rate[f][ct] %}
<td class="{{ r.cls }}">{{ r.text }}</td>{% endfor %}</tr>
{% endfor %}<tr><th class="l">all</th>{% for ct in controllers %}{% set r = total[ct] %}<th class="{{ r.cls }}">{{ r.text }}</th>{% endfor %}</tr>
</table>

<h2>Boundaries</h2>
{% if boundaries %}<table id="boundaries"><tr><th class="l">family</th><th class="l">value</th><th class="l">controller</th>
<th>{{ "worst survived" }}</th><th>first failed</th></tr>
{% for b in boundaries %}<tr><td class="l">{{ b.family }}</td><td class="l">{{ b.value }}</td><td class="l">{{ b.controller }}</td>
<td>{{ b.survived }}</td><td>{{ b.failed }}</td></tr>{% endfor %}
</table>
<p>"Worst survived" is the most severe value (the largest where higher is worse, the lowest
where lower is) of a sample that passed; "first failed", the least severe of one that failed.</p>
{% else %}<p>No family names a boundary.</p>{% endif %}
{% for f in scatter %}<figure><img src="{{ f.png }}" alt="{{ f.alt }}" width="520"><figcaption>{{ f.caption }}</figcaption></figure>{% endfor %}

<h2>Builds compared</h2>
{% if compare %}<p>{{ compare.a }} against {{ compare.b }}, the same samples (the same values drawn):</p>
<table id="compare"><tr><th class="l">family</th><th>both pass</th><th>only {{ compare.a }}</th><th>only {{ compare.b }}</th><th>both fail</th>
<th>mean lowest base height, {{ compare.a }} &minus; {{ compare.b }} (m)</th></tr>
{% for r in compare.rows %}<tr><td class="l">{{ r.family }}</td><td>{{ r.both }}</td><td class="{{ 'fail' if r.only_a else '' }}">{{ r.only_a }}</td>
<td class="{{ 'fail' if r.only_b else '' }}">{{ r.only_b }}</td><td>{{ r.none }}</td><td>{{ r.dz }}</td></tr>{% endfor %}
</table>
{% if compare.changed %}<p>Samples whose verdict differs:</p><ul>{% for s in compare.changed %}<li><code>{{ s }}</code></li>{% endfor %}</ul>{% endif %}
{% else %}<p>One controller build: nothing to compare.</p>{% endif %}

<h2>Worst cases</h2>
{% for w in worst %}<div class="case" id="case-{{ loop.index }}">
<h3>{{ w.id }}: {{ "pass" if w.passed else "FAIL" }}</h3>
<p>{{ w.reasons }}</p><p>Values: {{ w.drawn }}</p>
<p>Peak joint speed: {{ w.speed }}</p>
<figure><img src="{{ w.png }}" alt="base height of {{ w.id }}" width="600"></figure>
<p>Run it again, bit for bit:<br><code class="command">{{ w.command }}</code></p></div>
{% else %}<p>No samples yet.</p>{% endfor %}

<h2>Every sample</h2>
<p><a href="results.csv">results.csv</a>: one row per sample (values drawn, verdict, figures, command).</p>
</body></html>
"""


def _fmt(x, nd=3):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    return f"{x:.{nd}g}" if isinstance(x, float) else str(x)


def _truth(row, key):
    t = (row.get("summary") or {}).get("truth") or {}
    return t.get(key)


def _windows(values, rate):
    """The perturbations' intervals (s) in a sample's values, to shade."""
    out = []
    labels = {k.split(".")[0] for k in values}
    for lab in sorted(labels):
        at, dur = values.get(f"{lab}.at"), values.get(f"{lab}.duration")
        if at is None:
            continue
        what = lab.rstrip("0123456789")
        text = what
        if what == "push":
            text = f"push {values.get(f'{lab}.force', 0):.0f} N"
        elif what == "operator":  # a step of the operator's command
            text = f"{values.get(f'{lab}.input', '')} {values.get(f'{lab}.value', '')}"
        out.append((float(at), float(at) + float(dur or 0.0), text))
    return out


def _plot_case(row, path, rate):
    series = _truth(row, "base_height_series") or {}
    ys = series.get("values") or []
    dt = series.get("every_s") or 0.0
    segs = row.get("tracking") if isinstance(row.get("tracking"), list) else []
    if segs:  # follows the operator: each segment's command and achieved means
        fig, (ax, tr) = plt.subplots(2, 1, figsize=(7.5, 5.2), sharex=True)
        for i, (key, color, text) in enumerate((("vx", "#1f5fa8", "forward"),
                                                ("vy", "#2a8a2a", "lateral"),
                                                ("wz", "#c0392b", "yaw rate"))):
            for k, g in enumerate(segs):
                tr.hlines(g["command"][i], g["from"], g["to"], colors=color, linestyles=":",
                          label=f"{text} commanded" if k == 0 else None)
                tr.hlines(g[key], g["to"] - g["settled_s"], g["to"], colors=color,
                          linewidth=2.5, label=f"{text} achieved" if k == 0 else None)
        tr.set_ylabel("m/s, rad/s")
        tr.legend(fontsize=7, ncol=3)
        tr.grid(alpha=0.3)
    else:
        fig, ax = plt.subplots(figsize=(7.5, 3.2))
    ax.plot([i * dt for i in range(len(ys))], ys, color="#1f5fa8")
    for t0, t1, text in _windows(row["values"], rate):
        if t1 > t0:
            ax.axvspan(t0, t1, color="#e8a33a", alpha=0.35)
        else:
            ax.axvline(t0, color="#e8a33a")
        ax.annotate(text, (t0, 1.0), xycoords=("data", "axes fraction"), va="top", fontsize=8)
    (tr if segs else ax).set_xlabel("time (s)")
    ax.set_ylabel("base height (m)")
    ax.set_title(f"{row['id']}: {'pass' if row['passed'] else 'FAIL'}", fontsize=10)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def _numeric_key(rows, fam):
    """The value a family's plots and boundary go by: its boundary's, else
    its first numeric one that varies."""
    if fam.get("boundary"):
        return fam["boundary"]["value"]
    def rank(k):  # a kind's first field first (a push's force, a payload's mass)
        kind, field = k.split(".", 1)
        fields = list(campaign.KINDS.get(kind.rstrip("0123456789"), {}))
        return (fields.index(field) if field in fields else len(fields), k)

    keys = sorted({k for r in rows for k, v in r["values"].items()
                   if isinstance(v, (int, float)) and not isinstance(v, bool)}, key=rank)
    for k in keys:
        if len({r["values"][k] for r in rows}) > 1:
            return k
    return None


def _plot_family(fam, rows, controllers, key, path):
    fig, ax = plt.subplots(figsize=(6.5, 3.2))
    marks = "osD^v<>"
    for i, ct in enumerate(controllers):
        for ok, color in ((True, "#2a8a2a"), (False, "#c0392b")):
            pts = [(r["values"][key], _truth(r, "base_height_min")) for r in rows
                   if r["controller"] == ct and r["passed"] == ok and key in r["values"]
                   and _truth(r, "base_height_min") is not None]
            if pts:
                ax.scatter(*zip(*pts), marker=marks[i % len(marks)], color=color, s=24,
                           label=f"{ct} {'pass' if ok else 'fail'}")
    inv = fam["verdict"].get("min_base_height")
    if inv is not None:
        ax.axhline(inv, color="#888", linestyle="--", linewidth=1)
    ax.set_xlabel(key)
    ax.set_ylabel("lowest base height (m)")
    ax.set_title(f"family {fam['name']}", fontsize=10)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


CSV_FIXED = ("id", "family", "index", "controller", "seed", "passed", "reasons", "status",
             "attempts", "node", "wall_s", "base_height_min", "base_height_min_time_s",
             "base_height_final", "tilt_max_deg", "joint_speed_max", "joint_speed_max_joint",
             "joint_speed_max_time_s", "faults", "wire_violations", "clamps",
             "rate_caps", "limit_stops", "fuel_run_max", "ticks", "speed_error_max",
             "yaw_rate_error_max", "stop_drift_max")


def _csv_row(r):
    s = r.get("summary") or {}
    c = s.get("counters") or {}
    out = {"id": r["id"], "family": r["family"], "index": r["index"],
           "controller": r["controller"], "seed": r["seed"], "passed": int(r["passed"]),
           "reasons": "; ".join(r["reasons"]), "status": r["status"],
           "attempts": r.get("attempts", 1), "node": r.get("node", ""),
           "wall_s": f"{r.get('wall_s', 0.0):.3f}",
           "faults": " ".join((s.get("faults") or {}).get("latched", [])),
           "wire_violations": s.get("wire_violations", ""), "clamps": c.get("clamps", ""),
           "rate_caps": c.get("rate_caps", ""), "limit_stops": c.get("limit_stops", ""),
           "fuel_run_max": (s.get("fuel") or {}).get("run_max", ""), "ticks": s.get("ticks", "")}
    for k in ("base_height_min", "base_height_min_time_s", "base_height_final", "tilt_max_deg"):
        v = _truth(r, k)
        out[k] = "" if v is None else repr(v)
    # follows the operator: the worst of its segments (tools/tracking.py's)
    segs = r.get("tracking") if isinstance(r.get("tracking"), list) else []
    moving = [g for g in segs if g["kind"] != "stop"]
    stops = [g for g in segs if g["kind"] == "stop"]
    out["speed_error_max"] = repr(max(max(g["vx_error"], g["vy_error"]) for g in moving)) \
        if moving else ""
    out["yaw_rate_error_max"] = repr(max(g["wz_error"] for g in moving)) if moving else ""
    out["stop_drift_max"] = repr(max(g["drift_m"] for g in stops)) if stops else ""
    speed = s.get("joint_speed_max") or {}
    out["joint_speed_max"] = repr(speed["value"]) if speed.get("value") is not None else ""
    out["joint_speed_max_joint"] = speed.get("joint", "")
    out["joint_speed_max_time_s"] = repr(speed["time_s"]) if "time_s" in speed else ""
    return out


def _speed(row):
    """The sample's peak joint speed, as the report says it."""
    s = ((row.get("summary") or {}).get("joint_speed_max")) or {}
    if s.get("value") is None:
        return "-"
    return f"{s['value']:.2f} rad/s ({s['joint']}, at {s['time_s']:.2f} s)"


def write(out):
    """Writes the report of the campaign in @out; returns index.html's path."""
    with open(os.path.join(out, "campaign.json")) as f:
        meta = json.load(f)
    c = meta["campaign"]
    rows = sorted(campaign.read_results(os.path.join(out, "results.jsonl")).values(),
                  key=lambda r: (r["family"], r["index"], r["controller"]))
    controllers = [ct["name"] for ct in c["controllers"]]
    families = [f["name"] for f in c["families"]]
    fams = {f["name"]: f for f in c["families"]}
    n_total = sum(f["samples"] * len(f["controllers"]) for f in c["families"])
    os.makedirs(os.path.join(out, "plots"), exist_ok=True)

    # every sample, a row
    value_keys = sorted({k for r in rows for k in r["values"]})
    tmp = os.path.join(out, "results.csv.tmp")
    with open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(list(CSV_FIXED) + [f"value:{k}" for k in value_keys] + ["command"])
        for r in rows:
            d = _csv_row(r)
            w.writerow([d[k] for k in CSV_FIXED] + [r["values"].get(k, "") for k in value_keys]
                       + [campaign.shell(r["command"])])
    os.replace(tmp, os.path.join(out, "results.csv"))

    def cell(sel):
        n = len(sel)
        p = sum(r["passed"] for r in sel)
        if n == 0:
            return {"text": "-", "cls": ""}
        cls = "pass" if p == n else "fail" if p == 0 else "mid"
        return {"text": f"{p}/{n} ({100.0 * p / n:.0f} %)", "cls": cls}

    rate = {f: {ct: cell([r for r in rows if r["family"] == f and r["controller"] == ct])
                for ct in controllers} for f in families}
    total = {ct: cell([r for r in rows if r["controller"] == ct]) for ct in controllers}

    boundaries, scatter = [], []
    for fname in families:
        fam = fams[fname]
        sel = [r for r in rows if r["family"] == fname]
        key = _numeric_key(sel, fam)
        if key is None or not sel:
            continue
        png = f"plots/family-{fname}.png"
        _plot_family(fam, sel, controllers, key, os.path.join(out, png))
        scatter.append({"png": png, "alt": f"family {fname}",
                        "caption": f"{fname}: lowest base height against {key}"})
        b = fam.get("boundary")
        if not b:
            continue
        higher = b["worse"] == "higher"
        for ct in controllers:
            vs = [(r["values"].get(key), r["passed"]) for r in sel if r["controller"] == ct
                  and isinstance(r["values"].get(key), (int, float))]
            ok = [v for v, p in vs if p]
            bad = [v for v, p in vs if not p]
            pick = max if higher else min
            least = min if higher else max
            boundaries.append({"family": fname, "value": f"{key} ({b['worse']} is worse)",
                               "controller": ct, "survived": _fmt(pick(ok)) if ok else "none",
                               "failed": _fmt(least(bad)) if bad else "none"})

    compare = None
    if len(controllers) >= 2:
        a, b = controllers[0], controllers[1]
        by = {(r["family"], r["index"], r["controller"]): r for r in rows}
        crow, changed = [], []
        for fname in families:
            cnt = {"both": 0, "only_a": 0, "only_b": 0, "none": 0}
            dz = []
            for i in range(fams[fname]["samples"]):
                ra, rb = by.get((fname, i, a)), by.get((fname, i, b))
                if ra is None or rb is None:
                    continue
                key = ("both" if ra["passed"] else "only_b") if rb["passed"] else \
                    ("only_a" if ra["passed"] else "none")
                cnt[key] += 1
                if ra["passed"] != rb["passed"]:
                    changed.append(f"{fname}/{i}: {a} {'pass' if ra['passed'] else 'fail'}, "
                                   f"{b} {'pass' if rb['passed'] else 'fail'}")
                za, zb = _truth(ra, "base_height_min"), _truth(rb, "base_height_min")
                if za is not None and zb is not None:
                    dz.append(za - zb)
            crow.append(dict(cnt, family=fname,
                             dz=f"{sum(dz) / len(dz):+.3f}" if dz else "-"))
        compare = {"a": a, "b": b, "rows": crow, "changed": changed[:50]}

    # the worst: failed first, then the lowest base height
    def badness(r):
        z = _truth(r, "base_height_min")
        return (r["passed"], z if z is not None else -1.0)

    worst = []
    for k, r in enumerate(sorted(rows, key=badness)[:WORST]):
        png = f"plots/worst-{k + 1}.png"
        _plot_case(r, os.path.join(out, png), c.get("rate_hz", 500))
        worst.append({"id": r["id"], "passed": r["passed"],
                      "reasons": "; ".join(r["reasons"]) or "all invariants held",
                      "drawn": ", ".join(f"{k2} = {_fmt(v)}" for k2, v in
                                          sorted(r["values"].items())) or "nominal",
                      "png": png, "speed": _speed(r),
                      "command": campaign.shell(r["command"])})

    env = jinja2.Environment(undefined=jinja2.StrictUndefined, autoescape=True)
    text = env.from_string(PAGE).render(
        c=c, controllers=controllers, families=families, rate=rate, total=total,
        boundaries=boundaries, scatter=scatter, compare=compare, worst=worst,
        n_rows=len(rows), n_total=n_total, n_pass=sum(r["passed"] for r in rows))
    page = os.path.join(out, "index.html")
    with open(page + ".tmp", "w") as f:
        f.write(text)
    os.replace(page + ".tmp", page)
    return page


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1:
        print(__doc__.strip().split("\n\n")[1], file=sys.stderr)
        return 2
    print(write(argv[0]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
