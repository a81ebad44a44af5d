# SPDX-License-Identifier: Apache-2.0
"""Trains roz's own walking policy: examples/controllers/g1_walker.c (the
capture-point walker) distilled into an MLP by DAgger, in numpy.

The data come from collect.c (a native harness, built by CMake as
g1_walk_collect): the 12-joint G1 in MuJoCo, the walker running in shadow
every tick, the observation exactly as the deployed controller computes it
(roz_policy.h over deploy.yaml's tables), the walker's command folded into an
action of the policy (collect.c says how). Each iteration:

  1. rolls out episodes under random operator scripts (forward 0.2..0.5 m/s
     or turns on the spot of 0.2..0.5 rad/s, each followed by a stop; each
     value reaches the controller at its input's rate cap, as rozrun
     --operator feeds it), the robot driven at
     each inference by the expert with probability beta, else by the learner
     (iteration 0: beta 1, pure cloning; then BETAS), the expert's action
     perturbed by a smooth noise (DART, NOISE_SIGMA), the expert labelling
     every state visited;
  2. aggregates them with every earlier iteration's data;
  3. fits the MLP (Adam, minibatches, float32; warm-started from the last
     iteration; the observations' normalisation folded into the first layer
     at the end, so the file is a plain network);
  4. rolls the network out alone on make demo's script at 0.5 and 0.3 m/s
     (logged: how long it walked, how far off the command; not data).

Everything is seeded: the same command gives the same file on the same
machine (numpy's float32 matrix products may round differently on another
CPU). It takes tens of minutes on two cores: `make train-g1-walk`, not part
of make test. Writes OUT_DIR/policy.npz (rozgen-nn deploy reads it with
--spec SPEC below) and OUT_DIR/train_log.json (the figures of every
iteration, the dataset's sha256 and the file's, which the test g1_walk_policy_file
checks the committed file against).

    python train.py --lib build/examples/controllers/libg1_walk_collect.so
"""
import argparse
import ctypes
import hashlib
import json
import multiprocessing as mp
import os
import sys

import numpy as np

HIDDEN = 256
SPEC_FMT = "dense:{n_in}:{h}:elu,dense:{h}:{h}:elu,dense:{h}:{n_out}"
PRE_S, MOVE_S = 1.0, 1.0  # the stand before the hand-over (deploy.yaml's move_s)
# the scripts keep to what the expert holds (g1_walker.c: forward 0.3-0.6 m/s,
# stops, turns on the spot; with backward steps, turns while walking and
# 0.6 m/s it fell itself in 5 of 12 random scripts): a fallen expert labels
# nothing
VX_MIN, VX_MAX, WZ_MAX = 0.2, 0.5, 0.5
# most iterations at small but non-zero beta: at beta 0 every episode fell
# (docs/policies.md), and a fallen learner's states are mostly ones the
# walker cannot recover from either
BETAS = (1.0, 0.5, 0.3, 0.3, 0.2, 0.2, 0.1)
# DART: the action the expert drives with is perturbed by a smooth noise (an
# Ornstein-Uhlenbeck process, in action units: x0.25 rad), so the data hold
# the states just off the expert's path and the labels that lead back
NOISE_SIGMA, NOISE_TAU = 0.03, 0.05
DROP_S = 0.1  # the samples dropped before a fall (the walker cannot recover there)
INFO = 9

ACT = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.POINTER(ctypes.c_float),
                       ctypes.POINTER(ctypes.c_float), ctypes.POINTER(ctypes.c_float),
                       ctypes.POINTER(ctypes.c_double))


class Episode(ctypes.Structure):
    _fields_ = [("pre_s", ctypes.c_double), ("move_s", ctypes.c_double),
                ("duration_s", ctypes.c_double), ("n_rows", ctypes.c_int),
                ("rows", ctypes.POINTER(ctypes.c_double)), ("decimation", ctypes.c_int),
                ("min_height", ctypes.c_double)]


# ---- the network (float32, as rozgen.nn's dense layers) ----------------------------

def elu(x):
    return np.where(x > 0, x, np.expm1(np.minimum(x, 0)))


def forward(params, x):
    w1, b1, w2, b2, w3, b3 = params
    h1 = elu(x @ w1.T + b1)
    h2 = elu(h1 @ w2.T + b2)
    return h2 @ w3.T + b3


def init(rng, n_in, n_out, h=HIDDEN):
    def dense(i, o, gain=1.0):
        return (rng.normal(scale=gain / np.sqrt(i), size=(o, i)).astype(np.float32),
                np.zeros(o, dtype=np.float32))
    return [*dense(n_in, h), *dense(h, h), *dense(h, n_out, 0.1)]


def fit(params, x, y, rng, epochs, lr0=1e-3, batch=512):
    """Adam on the mean squared error; x normalised by the caller."""
    params = [p.copy() for p in params]
    m = [np.zeros_like(p) for p in params]
    v = [np.zeros_like(p) for p in params]
    n, t = len(x), 0
    steps = epochs * (n // batch)
    for _ in range(epochs):
        order = rng.permutation(n)
        for k in range(n // batch):
            t += 1
            lr = lr0 * (0.1 ** (t / steps))
            idx = order[k * batch:(k + 1) * batch]
            xb, yb = x[idx], y[idx]
            w1, b1, w2, b2, w3, b3 = params
            z1 = xb @ w1.T + b1
            h1 = elu(z1)
            z2 = h1 @ w2.T + b2
            h2 = elu(z2)
            out = h2 @ w3.T + b3
            g = (2.0 / len(xb)) * (out - yb)
            g_w3, g_b3 = g.T @ h2, g.sum(0)
            g = (g @ w3) * np.where(z2 > 0, 1.0, h2 + 1.0)
            g_w2, g_b2 = g.T @ h1, g.sum(0)
            g = (g @ w2) * np.where(z1 > 0, 1.0, h1 + 1.0)
            g_w1, g_b1 = g.T @ xb, g.sum(0)
            for i, gr in enumerate((g_w1, g_b1, g_w2, g_b2, g_w3, g_b3)):
                gr = gr.astype(np.float32)
                m[i] = 0.9 * m[i] + 0.1 * gr
                v[i] = 0.999 * v[i] + 0.001 * gr * gr
                mh = m[i] / (1 - 0.9 ** t)
                vh = v[i] / (1 - 0.999 ** t)
                params[i] -= (lr * mh / (np.sqrt(vh) + 1e-8)).astype(np.float32)
    mse = float(np.mean((forward(params, x[:20000]) - y[:20000]) ** 2))
    return params, mse


def fold(params, mean, std):
    """The normalisation x' = (x - mean) / std into the first layer."""
    w1, b1, *rest = params
    w = (w1 / std).astype(np.float32)
    return [w, (b1 - w @ mean).astype(np.float32), *rest]


# ---- operator scripts ----------------------------------------------------------------

def script(rng, duration):
    """Rows (t, vx, vy, wz) in the controller's time: forward or turn-on-the-spot
    segments of 2-4 s, each followed by a stop of 1.5-3 s (as the demo's
    script: the walker is not asked to turn while walking), the first
    starting up to 0.5 s before the hand-over (a script's time runs from the
    start of the stand)."""
    rows, t = [[0.0 - PRE_S, 0.0, 0.0, 0.0]], rng.uniform(-0.5, 1.5)
    while t < duration:
        if rng.random() < 0.55:
            rows.append([t, rng.uniform(VX_MIN, VX_MAX), 0.0, 0.0])
        else:
            rows.append([t, 0.0, 0.0, rng.choice([-1, 1]) * rng.uniform(0.2, WZ_MAX)])
        t += rng.uniform(2.0, 4.0)
        rows.append([t, 0.0, 0.0, 0.0])
        t += rng.uniform(1.5, 3.0)
    return rows


def demo_script(vx):
    """make demo's script (examples/operators/g1_walk.csv) in controller time."""
    return [[-PRE_S, 0, 0, 0], [1 - PRE_S, vx, 0, 0], [9 - PRE_S, 0, 0, 0],
            [12 - PRE_S, 0, 0, 0.5], [18 - PRE_S, 0, 0, 0]]


# ---- one episode in a fresh process ----------------------------------------------------

def episode(job):
    lib_path, rows, duration, beta, params, norm, seed, decimation, sigma = job
    lib = ctypes.CDLL(lib_path)
    lib.g1_walk_run.argtypes = [ctypes.POINTER(Episode), ACT, ctypes.c_void_p,
                                ctypes.POINTER(ctypes.c_double)]
    n_in, n_out = lib.g1_walk_n_in(), lib.g1_walk_n_out()
    rng = np.random.default_rng(seed)
    obs, labels, infos, used = [], [], [], []
    decay = np.exp(-lib_dec(lib_path) / lib.g1_walk_rate_hz() / NOISE_TAU)
    noise = np.zeros(n_out)

    def act(_user, o, lab, a, info):
        x = np.ctypeslib.as_array(o, shape=(n_in,)).copy()
        y = np.ctypeslib.as_array(lab, shape=(n_out,)).copy()
        inf = np.ctypeslib.as_array(info, shape=(INFO,)).copy()
        obs.append(x)
        labels.append(y)
        infos.append(inf)
        noise[:] = decay * noise + np.sqrt(1 - decay * decay) * sigma * rng.normal(size=n_out)
        if params is None or rng.random() < beta:
            out, e = y + noise, 1
        else:
            out, e = forward(params, ((x - norm[0]) / norm[1])[None].astype(np.float32))[0], 0
        used.append(e)
        for j in range(n_out):
            a[j] = float(out[j])
        return 0

    cb = ACT(act)
    r = np.array(rows, dtype=np.float64).ravel()
    ep = Episode(PRE_S, MOVE_S, duration, len(rows), r.ctypes.data_as(ctypes.POINTER(ctypes.c_double)),
                 decimation, 0.55)
    summary = (ctypes.c_double * 6)()
    ticks = lib.g1_walk_run(ctypes.byref(ep), cb, None, summary)
    return (np.array(obs, dtype=np.float32).reshape(-1, n_in),
            np.array(labels, dtype=np.float32).reshape(-1, n_out),
            np.array(infos).reshape(-1, INFO), np.array(used), ticks, list(summary))


def lib_dec(path):
    return ctypes.CDLL(path).g1_walk_decimation()


def rollouts(lib, jobs, workers):
    ctx = mp.get_context("fork")
    with ctx.Pool(workers, maxtasksperchild=1) as pool:
        return pool.map(episode, [(lib, *j) for j in jobs], chunksize=1)


def tracking(infos, rows, duration):
    """Mean forward speed and yaw rate achieved against the command in the
    steady part of each segment (from 1.5 s after its start to its end)."""
    t = infos[:, 0]
    err_v, err_w = [], []
    ends = [r[0] for r in rows[1:]] + [duration]
    for r, end in zip(rows, ends):
        sel = (t >= max(r[0], 1.4) + 1.5) & (t < end)
        if sel.sum() > 10:
            err_v.append(abs(infos[sel, 1].mean() - r[1]))
            err_w.append(abs(infos[sel, 3].mean() - r[3]))
    return (max(err_v) if err_v else float("nan"), max(err_w) if err_w else float("nan"))


def check(out_dir, spec):
    """The committed file is the one the script wrote (train_log.json's
    sha256) and of the shape the build deploys (SPEC)."""
    with open(os.path.join(out_dir, "train_log.json")) as f:
        log = json.load(f)
    path = os.path.join(out_dir, "policy.npz")
    digest = hashlib.sha256(open(path, "rb").read()).hexdigest()
    if digest != log["policy_sha256"]:
        print(f"{path}: sha256 {digest}, but train.py wrote {log['policy_sha256']} "
              "(train_log.json): the file is not the one the script trained", file=sys.stderr)
        return 1
    if spec is not None and spec != log["spec"]:
        print(f"{path}: trained as {log['spec']}, deployed as {spec}", file=sys.stderr)
        return 1
    last = log["iterations"][-1]
    print(f"{path}: the file train.py wrote (sha256 {digest[:16]}...), {log['spec']}, "
          f"{len(log['iterations'])} iterations, {last['samples']} samples")
    return 0


def write(out_dir, params, norm, data_x, data_y, log, n_in, n_out, seed):
    """OUT_DIR/policy.npz (the normalisation folded in) and train_log.json."""
    final = fold(params, norm[0].astype(np.float32), norm[1].astype(np.float32))
    names = ("l0.weight", "l0.bias", "l1.weight", "l1.bias", "l2.weight", "l2.bias")
    out = os.path.join(out_dir, "policy.npz")
    np.savez(out, **{k: v for k, v in zip(names, final)})
    digest = hashlib.sha256(open(out, "rb").read()).hexdigest()
    data = hashlib.sha256()
    for d in (*data_x, *data_y):
        data.update(d.tobytes())
    with open(os.path.join(out_dir, "train_log.json"), "w") as f:
        json.dump({"spec": SPEC_FMT.format(n_in=n_in, h=len(params[1]), n_out=n_out), "seed": seed,
                   "policy_sha256": digest, "dataset_sha256": data.hexdigest(),
                   "iterations": log}, f, indent=1)
        f.write("\n")
    print(f"wrote {out} (sha256 {digest})", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lib", help="the harness, libg1_walk_collect.so")
    ap.add_argument("--check", metavar="SPEC", nargs="?", const="",
                    help="only check OUT_DIR's policy.npz against train_log.json (and SPEC)")
    ap.add_argument("--out-dir", default=os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--iterations", type=int, default=len(BETAS))
    ap.add_argument("--episodes", type=int, default=14, help="a DAgger iteration's")
    ap.add_argument("--duration", type=float, default=12.0, help="s, an episode's controller time")
    ap.add_argument("--epochs", type=int, default=8)
    ap.add_argument("--hidden", type=int, default=HIDDEN, help="the hidden layers' width")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--decimation", type=int, default=0, help="0: deploy.yaml's")
    ap.add_argument("--noise", type=float,
                    help=f"the expert's action noise (DART; action units): {NOISE_SIGMA} "
                    "in training, 0 with --expert-only")
    ap.add_argument("--snapshots", metavar="DIR",
                    help="also write each iteration's network and log to DIR/itN")
    ap.add_argument("--state", metavar="PATH.npz",
                    help="save the DAgger state (data, network) after each iteration here")
    ap.add_argument("--resume", action="store_true",
                    help="continue from --state's last iteration up to --iterations")
    ap.add_argument("--expert-only", nargs="?", const="0.3", choices=("0.3", "both"),
                    help="roll out the folded expert on make demo's script (at 0.3 m/s, or "
                    "0.3 and 0.5) for --duration s and stop; exit 1 if it falls at 0.3")
    a = ap.parse_args()
    if a.check is not None:
        return check(a.out_dir, a.check or None)
    if a.lib is None:
        ap.error("--lib is required")
    lib = os.path.abspath(a.lib)
    probe = ctypes.CDLL(lib)  # never runs an episode here: the workers fork fresh
    n_in, n_out = probe.g1_walk_n_in(), probe.g1_walk_n_out()
    rng = np.random.default_rng(a.seed)
    if a.expert_only:  # the folded labels drive: does the expert walk as a policy acts?
        speeds = (0.3, 0.5) if a.expert_only == "both" else (0.3,)
        dur = min(a.duration, 20.0)
        res = rollouts(lib, [(demo_script(v), dur, 1.0, None, None, 0, a.decimation,
                              a.noise or 0.0)
                             for v in speeds], a.workers)
        fell = 0
        for v, (o, y, inf, used, ticks, summ) in zip(speeds, res):
            ev, ew = tracking(inf, demo_script(v), dur)
            print(f"expert (folded, decimation {a.decimation or 'config'}) at {v} m/s: "
                  f"{ticks} ticks, {o.shape[0]} observations of {o.shape[1]}, lowest "
                  f"{summ[0]:.3f} m, fell {summ[5]:.0f}, speed error {ev:.3f} m/s, "
                  f"yaw-rate error {ew:.3f} rad/s, filter clamps {summ[2]:.0f}, "
                  f"values outside the manifest {summ[4]:.0f}")
            # at 0.3 the folded expert walks: up, on speed (measured 0.019 m/s off over
            # 4 s, 0.075 with the 0.5 m/s walker of the walk branch; without the
            # feed-forward torques folded in, 0.54 and down to 0.67 m)
            fell += v == 0.3 and (summ[5] or summ[4] or summ[0] < 0.7 or not ev < 0.15
                                  or o.shape[0] != ticks // lib_dec(lib))
        return 1 if fell else 0
    if a.noise is None:
        a.noise = NOISE_SIGMA
    params = init(rng, n_in, n_out, a.hidden)
    norm = None
    data_x, data_y, log = [], [], []
    first = 0
    if a.resume:  # --state's last iteration: its data, network, normalisation, log, rng
        st = np.load(a.state)
        data_x, data_y = [st["x"]], [st["y"]]
        params = [st[f"p{i}"] for i in range(6)]
        norm = (st["mean"], st["std"])
        saved = json.loads(str(st["meta"]))
        log, first = saved["log"], saved["log"][-1]["iteration"] + 1
        rng.bit_generator.state = saved["rng"]
    for it in range(first, a.iterations):
        beta = BETAS[it] if it < len(BETAS) else 0.0
        jobs = []
        for e in range(a.episodes):
            s = int(rng.integers(1 << 31))
            erng = np.random.default_rng(s)
            if e < 2:  # the demo's script at 0.5 m/s (g1_walk.csv), and at 0.3
                rows = demo_script(0.5 if e == 0 else 0.3)
                dur = 20.0
            else:
                rows, dur = script(erng, a.duration), a.duration
            jobs.append((rows, dur, beta, params if it > 0 else None, norm, s, a.decimation,
                         a.noise))
        res = rollouts(lib, jobs, a.workers)
        falls, steps, demo = 0, 0, None
        for k, (o, y, inf, used, ticks, summ) in enumerate(res):
            keep = len(o) - (int(DROP_S * len(o) / max(ticks, 1) * 500) if summ[5] else 0)
            data_x.append(o[:max(keep, 0)])
            data_y.append(y[:max(keep, 0)])
            falls += int(summ[5])
            steps += len(o)
            if k == 0:
                demo = (ticks, summ, tracking(inf, jobs[0][0], jobs[0][1]))
        x, y = np.concatenate(data_x), np.concatenate(data_y)
        new = sum(len(d) for d in data_x[-len(res):])
        if norm is None:
            norm = (x.mean(0), x.std(0) + 1e-3)
        xn = ((x - norm[0]) / norm[1]).astype(np.float32)
        params, mse = fit(params, xn, y, rng, a.epochs)
        tail = slice(len(x) - min(new, 20000), len(x))
        mse_new = float(np.mean((forward(params, xn[tail]) - y[tail]) ** 2))
        del xn
        entry = {"iteration": it, "beta": beta, "noise": a.noise, "episodes": a.episodes,
                 "falls": falls, "samples": int(len(x)), "mse": mse, "mse_new": mse_new,
                 "demo_ticks": demo[0],
                 "demo_fell": demo[1][5], "demo_lowest_m": demo[1][0],
                 "demo_speed_error": demo[2][0], "demo_yaw_error": demo[2][1]}
        # the network just fitted, alone (beta 0, no noise), on the demo's script
        # at 0.5 and 0.3 m/s: the figure that matters (not part of the data)
        speeds = (0.5, 0.3)
        alone = rollouts(lib, [(demo_script(v), 20.0, 0.0, params, norm, 0, a.decimation, 0.0)
                               for v in speeds], a.workers)
        for v, (o, y_, inf, used, ticks, summ) in zip(speeds, alone):
            ev, ew = tracking(inf, demo_script(v), 20.0)
            entry[f"alone_{v}"] = {"walked_s": ticks / 500.0, "fell": summ[5],
                                   "lowest_m": summ[0], "speed_error": ev, "yaw_error": ew}
        log.append(entry)
        print(json.dumps(entry), flush=True)
        if a.state:
            meta = json.dumps({"log": log, "rng": rng.bit_generator.state})
            np.savez(a.state, x=x, y=y, mean=norm[0], std=norm[1], meta=np.array(meta),
                     **{f"p{i}": p for i, p in enumerate(params)})
        if a.snapshots:  # as if the run had stopped here (--iterations it + 1)
            d = os.path.join(a.snapshots, f"it{it}")
            os.makedirs(d, exist_ok=True)
            write(d, params, norm, data_x, data_y, log, n_in, n_out, a.seed)
        del x, y
    write(a.out_dir, params, norm, data_x, data_y, log, n_in, n_out, a.seed)
    return 0


if __name__ == "__main__":
    sys.exit(main())
