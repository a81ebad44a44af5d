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
