# SPDX-License-Identifier: Apache-2.0
"""tools/plot_trace.py: the fault spans and event marks it draws from a
trace's faults and events columns, and traces without those columns."""
import csv
import math
import importlib.util
import pathlib
import sys

import pytest

TOOL = pathlib.Path(__file__).resolve().parents[2] / "tools" / "plot_trace.py"
spec = importlib.util.spec_from_file_location("plot_trace", TOOL)
plot_trace = importlib.util.module_from_spec(spec)
spec.loader.exec_module(plot_trace)
plt = plot_trace.plt


def write_trace(path, rows, with_marks=True):
    header = ["tick", "time_s", "target:j/velocity", "applied:j/velocity", "state:j/position"]
    if with_marks:
        header += ["faults", "events"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for r in rows:
            w.writerow(r if with_marks else r[:5])


def rows_with_events():
    """10 ticks: e-stop at 2 (latched until the clear at 6), a swap at 8."""
    events = {2: "estop fault:e-stop", 4: "estop-release", 6: "clear cleared:e-stop", 8: "swap"}
    return [[t, t / 10, 0.1, 0.0 if 2 <= t < 6 else 0.1, t / 100, 8 if 2 <= t < 6 else 0,
             events.get(t, "")] for t in range(10)]


def test_fault_spans():
    t = [0.0, 0.1, 0.2, 0.3, 0.4]
    assert plot_trace.fault_spans(t, [0, 8, 8, 0, 0]) == [(0.1, 0.3)]
    assert plot_trace.fault_spans(t, [1, 0, 0, 4, 4]) == [(0.0, 0.1), (0.3, 0.4)]
    assert plot_trace.fault_spans(t, [0] * 5) == []


def test_event_label():
    assert plot_trace.event_label("estop fault:e-stop") == ("estop, fault: e-stop", True)
    assert plot_trace.event_label("clear cleared:e-stop") == ("clear", False)
    assert plot_trace.event_label("clear rebuild cleared:trap") == ("clear, rebuild", False)
    assert plot_trace.event_label("fault:stale-state") == ("fault: stale-state", True)
    assert plot_trace.event_label("verify-refused") == ("verify-refused", False)
    assert plot_trace.event_label("") == ("", False)


def test_marks_on_the_axes(tmp_path):
    path = tmp_path / "trace.csv"
    write_trace(path, rows_with_events())
    header, cols = plot_trace.read(path)
    assert cols["events"][2] == "estop fault:e-stop" and cols["faults"][3] == 8.0
    fig, axes = plt.subplots(2, 1)
    plot_trace.mark(axes, cols["time_s"], cols)
    for ax in axes:
        # one line per tick with events, one shaded span for the fault
        assert sorted(line.get_xdata()[0] for line in ax.lines) == [0.2, 0.4, 0.6, 0.8]
        assert len(ax.patches) == 1
    labels = sorted(text.get_text() for text in axes[0].texts)
    assert labels == ["clear", "estop, fault: e-stop", "estop-release", "swap"]
    red = [text.get_text() for text in axes[0].texts if text.get_color() == "tab:red"]
    assert red == ["estop, fault: e-stop"]
    plt.close(fig)


@pytest.mark.parametrize("with_marks", [True, False])
def test_plots_a_trace(tmp_path, monkeypatch, with_marks):
    path, png = tmp_path / "trace.csv", tmp_path / "plot.png"
    write_trace(path, rows_with_events(), with_marks)
    monkeypatch.setattr(sys, "argv", ["plot_trace.py", str(path), str(png)])
    plot_trace.main()
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


ARM = [f"joint{i}" for i in range(1, 8)] + ["gripper"]


def write_arm_trace(path):
    """A 7-joint arm with a gripper: a velocity command and a position state
    per joint, a position command and a position state for the gripper."""
    commands = [f"joint{i}/velocity" for i in range(1, 8)] + ["gripper/position"]
    states = [f"{j}/position" for j in ARM]
    header = (["tick", "time_s"] + [f"target:{c}" for c in commands]
              + [f"applied:{c}" for c in commands] + [f"state:{s}" for s in states]
              + ["faults", "events"])
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for t in range(20):
            values = [0.01 * (k + 1) * t for k in range(len(commands))]
            w.writerow([t, t / 100] + values + values + [v / 2 for v in values] + [0, ""])
    return commands, states


def drawn(fig):
    """{label: [(axes index, line)]} of every labelled line in the figure."""
    out = {}
    for k, ax in enumerate(fig.axes):
        for line in ax.lines:
            if not line.get_label().startswith("_"):
                out.setdefault(line.get_label(), []).append((k, line))
    return out


def test_every_channel_of_a_7_joint_arm_with_gripper_is_drawn(tmp_path):
    path = tmp_path / "arm.csv"
    commands, states = write_arm_trace(path)
    header, cols = plot_trace.read(path)
    fig = plot_trace.figure([(header, cols, "")])
    lines = drawn(fig)
    # 8 commands and 8 positions: two pairs of axes (6 + 2 channels each)
    assert len(fig.axes) == 4
    for name in commands:
        applied = [line for k, line in lines[name] if k % 2 == 0]
        assert len(applied) == 1, name
        assert list(applied[0].get_ydata()) == cols[f"applied:{name}"]
    for name in states:
        drawn_state = [line for k, line in lines[name] if k % 2 == 1]
        assert len(drawn_state) == 1, name
        assert list(drawn_state[0].get_ydata()) == cols[f"state:{name}"]
    # the dotted targets: one per command
    dotted = [line for ax in fig.axes[0::2] for line in ax.lines if line.get_linestyle() == ":"]
    assert len(dotted) == len(commands)
    # joint7 and the gripper are on the second pair, with their legend
    assert {line.get_label() for line in fig.axes[2].lines if line.get_linestyle() == "-"} == \
        {"joint7/velocity", "gripper/position"}
    assert [t.get_text() for t in fig.axes[3].get_legend().get_texts()] == \
        ["joint7/position", "gripper/position"]
    plt.close(fig)


def test_channels_filter(tmp_path):
    path = tmp_path / "arm.csv"
    write_arm_trace(path)
    header, cols = plot_trace.read(path)
    pattern = plot_trace.channel_filter("joint[67]|gripper", [header])
    fig = plot_trace.figure([(header, cols, "")], pattern=pattern)
    assert len(fig.axes) == 2
    assert sorted(drawn(fig)) == ["gripper/position", "joint6/position", "joint6/velocity",
                                  "joint7/position", "joint7/velocity"]
    plt.close(fig)


def test_channels_filter_that_matches_nothing_names_the_channels(tmp_path, monkeypatch, capsys):
    path, png = tmp_path / "arm.csv", tmp_path / "plot.png"
    write_arm_trace(path)
    monkeypatch.setattr(sys, "argv", ["plot_trace.py", str(path), str(png), "--channels", "wrist"])
    with pytest.raises(SystemExit) as e:
        plot_trace.main()
    assert "--channels 'wrist' matches no channel" in str(e.value)
    assert "joint7/velocity" in str(e.value) and "gripper/position" in str(e.value)
    monkeypatch.setattr(sys, "argv", ["plot_trace.py", str(path), str(png), "--channels", "("])
    with pytest.raises(SystemExit) as e:
        plot_trace.main()
    assert "not a regular expression" in str(e.value)
    assert not png.exists()


def test_compare_draws_every_channel_of_both_runs(tmp_path):
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    commands, states = write_arm_trace(a)
    write_arm_trace(b)
    runs = [(*plot_trace.read(a), "a"), (*plot_trace.read(b), "b")]
    fig = plot_trace.figure(runs)
    assert len(fig.axes) == 8
    for name in commands + states:
        # each run's column has the channel once (a command and a state may share a name)
        columns = sorted(k % 2 for k, _ in drawn(fig)[name])
        assert columns.count(0) == columns.count(1) >= 1, name
    plt.close(fig)


def test_truth_and_span(tmp_path, monkeypatch):
    """A trace with a simulator's truth gets a third plot, the base's height
    with its roll and pitch; --span shades the same interval on every plot."""
    path, png = tmp_path / "trace.csv", tmp_path / "plot.png"
    header = ["tick", "time_s", "target:j/position", "applied:j/position", "state:j/position",
              "truth:base.x", "truth:base.y", "truth:base.z", "truth:base.roll",
              "truth:base.pitch", "truth:base.yaw", "faults", "events"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for t in range(10):
            w.writerow([t, t / 10, 0.1, 0.1, t / 100, 0, 0, 0.78 - t / 1000, 0, 0.01 * t, 0, 0, ""])
    made = []
    real = plt.subplots
    monkeypatch.setattr(plt, "subplots", lambda *a, **k: made.append(real(*a, **k)) or made[-1])
    monkeypatch.setattr(sys, "argv", ["plot_trace.py", str(path), str(png), "--span", "0.3:0.4:push"])
    plot_trace.main()
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    fig, axes = made[0]
    assert axes.shape == (3, 1)
    height = axes[2][0].lines[0]
    assert list(height.get_ydata())[0] == 0.78
    for row in axes:
        assert [(p.get_x(), round(p.get_x() + p.get_width(), 6)) for p in row[0].patches] == [(0.3, 0.4)]
    # the position state's own command, dotted beside it: the tracking
    assert [ln.get_linestyle() for ln in axes[1][0].lines] == ["-", ":"]


def test_render_frames_quaternion():
    """tools/render_frames.py turns the trace's Z-Y-X angles into MuJoCo's
    w, x, y, z quaternion."""
    try:
        import mujoco  # noqa: F401
    except ImportError:
        pytest.fail("mujoco (tools/requirements.txt) is not installed")
    spec_r = importlib.util.spec_from_file_location("render_frames", TOOL.parent / "render_frames.py")
    rf = importlib.util.module_from_spec(spec_r)
    spec_r.loader.exec_module(rf)
    assert rf.quat(0.0, 0.0, 0.0) == pytest.approx((1.0, 0.0, 0.0, 0.0))
    h = math.sqrt(0.5)
    assert rf.quat(0.0, 0.0, math.pi / 2) == pytest.approx((h, 0.0, 0.0, h))
    assert rf.quat(0.0, math.pi / 2, 0.0) == pytest.approx((h, 0.0, h, 0.0))
    assert rf.quat(math.pi / 2, 0.0, 0.0) == pytest.approx((h, h, 0.0, 0.0))


# ---- a walking run: tools/tracking.py and the operator's marks -------------------

OPERATOR = ("# forward, stop, turn, stop\n"
            "time_s,operator/velocity.x,operator/velocity.y,operator/yaw_rate\n"
            "0,0,0,0\n1,0.5,0,0\n5,0,0,0\n7,0,0,0.5\n11,0,0,0\n")
INPUTS = ("operator/velocity.x", "operator/velocity.y", "operator/yaw_rate")


def write_walk(path, follows=True, rate=50, end=13.0):
    """A base that does what the operator above says (or, not following,
    walks forward at 0.5 m/s throughout), swaying 2 cm sideways each 0.8 s
    step as a walker does: the truth columns and the inputs' columns."""
    spec_t = importlib.util.spec_from_file_location("tracking", TOOL.parent / "tracking.py")
    tracking = importlib.util.module_from_spec(spec_t)
    spec_t.loader.exec_module(tracking)
    rows = [(0.0, {})] + tracking.commands([(1.0, {INPUTS[0]: 0.5}), (5.0, {INPUTS[0]: 0.0}),
                                            (7.0, {INPUTS[2]: 0.5}), (11.0, {INPUTS[2]: 0.0})])
    header = (["tick", "time_s", "state:j/position"] + [f"input:{n}" for n in INPUTS]
              + ["truth:base.x", "truth:base.y", "truth:base.z", "truth:base.roll",
                 "truth:base.pitch", "truth:base.yaw", "faults", "events"])
    x = y = yaw = 0.0
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for k in range(int(end * rate) + 1):
            t = k / rate
            c = [cmd for t0, cmd in rows if t0 <= t][-1] if t >= 1.0 else (0.0, 0.0, 0.0)
            v = c if follows else (0.5, 0.0, 0.0)
            sway = 0.02 * math.sin(2 * math.pi * t / 0.8)
            w.writerow([k, t, 0.0, *c, x - math.sin(yaw) * sway, y + math.cos(yaw) * sway, 0.78,
                        0, 0, yaw, 0, ""])
            x += (math.cos(yaw) * v[0] - math.sin(yaw) * v[1]) / rate
            y += (math.sin(yaw) * v[0] + math.cos(yaw) * v[1]) / rate
            yaw += v[2] / rate
    return tracking


def test_tracking_of_a_base_that_follows(tmp_path):
    """Each segment's mean velocity is the command's, a stop drifts nothing
    and the turn makes its heading; the sway averages out over whole steps."""
    trace, op = tmp_path / "walk.csv", tmp_path / "operator.csv"
    op.write_text(OPERATOR)
    tracking = write_walk(trace)
    segs = tracking.judge(tracking.read_trace(trace), tracking.read_operator(op), settle=1.0)
    # the first second (stop) is no longer than the settling: not judged
    assert [s["kind"] for s in segs] == ["move", "stop", "turn", "stop"]
    move, turn = segs[0], segs[2]
    assert move["command"] == (0.5, 0.0, 0.0)
    assert move["vx_error"] < 0.01 and move["vy_error"] < 0.01 and move["wz_error"] < 1e-9
    # a stop's travel is its sway at most (2 x 2 cm) over a part step
    assert segs[1]["drift_m"] <= 0.04 + 1e-9 and segs[1]["drift_rad"] < 1e-9
    assert turn["wz_error"] < 1e-9 and abs(turn["heading_ratio"] - 1.0) < 0.01
    assert abs(turn["heading"] - 2.0) < 0.02  # 0.5 rad/s for 4 s


def test_tracking_bounds_catch_a_base_blind_to_the_operator(tmp_path, monkeypatch, capsys):
    trace, op = tmp_path / "walk.csv", tmp_path / "operator.csv"
    op.write_text(OPERATOR)
    tracking = write_walk(trace, follows=False)
    monkeypatch.setattr(sys, "argv", ["tracking.py", str(trace), "--operator", str(op),
                                      "--settle", "1", "--max-speed-error", "0.1",
                                      "--max-yaw-rate-error", "0.1", "--max-stop-drift", "0.1",
                                      "--max-stop-turn", "0.1", "--heading-ratio", "0.8:1.1"])
    with pytest.raises(SystemExit) as e:
        tracking.main()
    assert e.value.code == 1
    err = capsys.readouterr().err
    assert "5-7 s (stop): drift 0.500 m above 0.1" in err
    assert "7-11 s (turn): wz_error 0.500 above 0.1" in err
    assert "7-11 s (turn): heading change 0.000 of the command, outside [0.8, 1.1]" in err
    # the follower passes the same bounds
    write_walk(trace)
    with pytest.raises(SystemExit) as e:
        tracking.main()
    assert e.value.code == 0


def test_operator_marked_and_velocity_plotted(tmp_path, monkeypatch):
    """A walking run's plot: commanded (the inputs, dotted) vs achieved (the
    truth) velocity and yaw rate above the joints, and each of the
    operator's rows a line on every plot with the command it gives."""
    trace, op, png = tmp_path / "walk.csv", tmp_path / "operator.csv", tmp_path / "walk.png"
    op.write_text(OPERATOR)
    write_walk(trace)
    assert plot_trace.operator_marks(plot_trace.tracking.read_operator(op)) == [
        (0.0, "stop"), (1.0, "forward 0.5 m/s"), (5.0, "stop"), (7.0, "turn 0.5 rad/s"),
        (11.0, "stop")]
    made = []
    real = plt.subplots
    monkeypatch.setattr(plt, "subplots", lambda *a, **k: made.append(real(*a, **k)) or made[-1])
    monkeypatch.setattr(sys, "argv", ["plot_trace.py", str(trace), str(png), "--operator", str(op)])
    plot_trace.main()
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    fig, axes = made[0]
    assert axes.shape == (5, 1)  # velocity, yaw rate, commands, positions, truth
    assert axes[0][0].get_ylabel() == "base velocity [m/s]"
    assert axes[1][0].get_ylabel() == "yaw rate [rad/s]"
    forward = [ln for ln in axes[0][0].lines if ln.get_label() == "forward"][0]
    ys = [v for v in forward.get_ydata() if not math.isnan(v)]
    assert abs(max(ys) - 0.5) < 0.01
    for row in axes:
        marks = [ln.get_xdata()[0] for ln in row[0].lines if ln.get_linestyle() == "-."]
        assert marks == [0.0, 1.0, 5.0, 7.0, 11.0]
    assert [t.get_text() for t in axes[0][0].texts] == ["stop", "forward 0.5 m/s", "stop",
                                                         "turn 0.5 rad/s", "stop"]
