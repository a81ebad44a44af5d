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
