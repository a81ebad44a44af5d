# SPDX-License-Identifier: Apache-2.0
"""Foxglove's Teleop panel through roz-live (docs/live.md, "Teleop"): a
strict Foxglove WebSocket client advertises a json geometry_msgs/msg/Twist
channel and publishes twists (binary Client Message Data: opcode 1, the
channel id, the JSON) to `roz-live --teleop SOCKET`, which hands each to
`rozrun --teleop SOCKET`; the run's trace shows the operator input the
controller read. A malformed, oversized or non-finite message is refused
with a status message and the input unchanged; a viewer that is not on a
loopback address gets no clientPublish unless --teleop-remote."""
import contextlib
import json
import os
import pathlib
import queue
import re
import signal
import socket
import struct
import subprocess
import sys
import threading
import time

import pytest
from websockets.sync.client import connect

from test_live import CTL, LIVE, ROZRUN, SUBPROTOCOL, StrictClient, Viewer, summary_line

ROOT = pathlib.Path(__file__).resolve().parents[2]
INPUT = "operator/velocity.x"

pytestmark = pytest.mark.skipif(not ROZRUN, reason="ROZRUN not set (run through ctest)")


def manifest_input(name, source, tail='interface_type = "velocity"\nunit = "m/s"\n'
                   'limits = [-0.5, 0.5]\nscale = 0.5\n'):
    """A [[manifest.inputs]] table, held (never stale) for the whole run."""
    return (f'\n[[manifest.inputs]]\nname = "{name}"\nsource = "{source}"\ndefault = 0.0\n'
            f'max_rate_of_change = 1.0\nstale_after_ms = 600000\n{tail}')


TWIST_INPUT = manifest_input(INPUT, "twist.linear.x")


def robot_with_input(tmp_path, inputs=TWIST_INPUT, name="ur5_teleop.toml"):
    text = (ROOT / "manifests" / "ur5.toml").read_text()
    path = tmp_path / name
    path.write_text(text + inputs)
    return path


def twist_json(x, extra=""):
    return json.dumps({"linear": {"x": x, "y": 0, "z": 0},
                       "angular": {"x": 0, "y": 0, "z": 0}}) + extra


def publish(ws, channel, payload):
    data = payload.encode() if isinstance(payload, str) else payload
    ws.send(b"\x01" + struct.pack("<I", channel) + data)


def statuses(client, seconds):
    """The status messages that arrive within @p seconds (the rest pumped)."""
    out = []
    end = time.monotonic() + seconds
    orig = client._text

    def text(t):
        msg = json.loads(t)
        if msg.get("op") == "status":
            out.append(msg)
        orig(t)
    client._text = text
    try:
        while time.monotonic() < end:
            client.pump(0.1)
    finally:
        client._text = orig
    return out


def trace_column(path, name):
    lines = pathlib.Path(path).read_text().splitlines()
    head = lines[0].split(",")
    k = head.index(f"input:{name}")
    return [float(line.split(",")[k]) for line in lines[1:]]


@contextlib.contextmanager
def teleop_run(tmp_path, robot, *viewer_args):
    """roz-live --teleop (and @p viewer_args) with a strict client on it, and
    rozrun on the loopback port feeding it, once rozrun has made its teleop
    socket: yields (viewer, client, run, trace); all stopped after."""
    fifo, sock, trace = tmp_path / "run.live", tmp_path / "teleop.sock", tmp_path / "trace.csv"
    viewer = Viewer(fifo, "--teleop", sock, *viewer_args)
    client = StrictClient(viewer.port)
    run = None
    try:
        while client.info is None:
            client.pump(1.0)
        run = subprocess.Popen([ROZRUN, "--robot", robot, "--port", "loopback", "--realtime",
                                "--ticks", "1000", "--controller", CTL / "sine.wasm",
                                "--allow-other-robot", "--live", fifo, "--teleop", sock,
                                "--trace", trace],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        end = time.monotonic() + 60
        while not sock.exists():
            assert time.monotonic() < end and run.poll() is None, "rozrun made no socket"
            client.pump(0.05)
        yield viewer, client, run, trace
    finally:
        if run is not None and run.poll() is None:
            run.kill()
        client.close()
        viewer.stop()


def assert_joy_held(trace, says):
    """The joystick inputs of JOY_INPUTS in @p trace: forward 0.25 and A
    pressed from the first tick they arrive on, unchanged by what was refused
    after (@p says)."""
    forward, a = trace_column(trace, "operator/forward"), trace_column(trace, "remote/a")
    assert 0.25 in forward and set(forward) <= {0.0, 0.25}, sorted(set(forward))
    first = forward.index(0.25)
    assert all(v == 0.25 for v in forward[first:]), f"the input moved after the refused {says}"
    assert a[first:] == [1.0] * len(a[first:]) and set(a) <= {0.0, 1.0}


def test_teleop_reaches_a_controller(tmp_path):
    robot = robot_with_input(tmp_path)
    sock = tmp_path / "teleop.sock"
    with teleop_run(tmp_path, robot) as (viewer, client, run, trace):
        assert "clientPublish" in client.info["capabilities"]
        assert "json" in client.info.get("supportedEncodings", [])
        ws = client.ws
        ws.send(json.dumps({"op": "advertise", "channels": [
            {"id": 7, "topic": "/cmd_vel", "encoding": "json",
             "schemaName": "geometry_msgs/msg/Twist"}]}))
        for _ in range(10):  # 0.6 m/s: the input is 0.3 (scale 0.5)
            publish(ws, 7, twist_json(0.6))
            client.pump(0.05)
        # refused, each with a status, the input unchanged
        publish(ws, 7, '{"linear": {"x": NaN, "y": 0, "z": 0}, "angular": {"x": 0, "y": 0, '
                       '"z": 0}}')
        publish(ws, 7, twist_json(0.1)[:-3])            # cut short: not JSON
        publish(ws, 7, twist_json(0.1, " " * 5000))     # past MAX_TELEOP_BYTES
        publish(ws, 7, "[" * 2000 + "]" * 2000)         # deeper than Python's decoder
        publish(ws, 7, '{"linear": {"x": 0.1, "y": 0}, "angular": {"x": 0, "y": 0, "z": 0}}')
        publish(ws, 8, twist_json(0.1))                 # a channel never advertised
        ws.send(json.dumps({"op": "advertise", "channels": [
            {"id": 9, "topic": "/joy", "encoding": "json", "schemaName": "std_msgs/msg/String"}]}))
        publish(ws, 9, twist_json(0.1))                 # advertised, not a twist
        got = [s["message"] for s in statuses(client, 1.0)]
        for says in ("NaN is not a number", "not JSON", "more than 4096", "nested too deeply",
                     "linear: expected an object of x, y and z", "Unknown channel ID: 8",
                     "json geometry_msgs/msg/Twist or sensor_msgs/Joy only",
                     "channel 9, which is no advertised twist or Joy"):
            assert any(says in m for m in got), f"no status says '{says}': {got}"
        # past rozrun's own checks: a datagram of another size, a NaN it passes
        # on (the runtime's input refuses it and counts)
        # and hostile ones: empty, the wrong magic at the right size, one
        # far past the largest (cut by the socket: still refused), each counted
        raw = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        raw.sendto(b"TWST" + struct.pack("<5d", 0.1, 0, 0, 0, 0), str(sock))
        raw.sendto(b"TWST" + struct.pack("<6d", float("nan"), 0, 0, 0, 0, 0), str(sock))
        raw.sendto(b"", str(sock))
        raw.sendto(b"TWSt" + struct.pack("<6d", 0.1, 0, 0, 0, 0, 0), str(sock))
        raw.sendto(b"TWST" + struct.pack("<6d", 0.1, 0, 0, 0, 0, 0) + b"\0" * 60000, str(sock))
        raw.close()
        ws.send(json.dumps({"op": "unadvertise", "channelIds": [7]}))
        publish(ws, 7, twist_json(0.2))                 # unadvertised: refused
        assert any("Unknown channel ID: 7" in s["message"] for s in statuses(client, 0.5))
        out, err = run.communicate(timeout=120)
        assert run.returncode == 0, out + err
    line = summary_line(out, "teleop")
    m = re.match(r"(\d+) twists from .*, (\d+) malformed refused; inputs clamped (\d+), "
                 r"refused \(non-finite\) (\d+)", line)
    assert m, line
    twists, malformed, clamped, nonfinite = map(int, m.groups())
    assert twists == 11 and malformed == 4 and clamped == 0 and nonfinite == 1, line
    values = trace_column(trace, INPUT)
    assert 0.3 in values, values[:50]
    assert set(values) <= {0.0, 0.3}, sorted(set(values))
    assert values[-1] == 0.3
    first = values.index(0.3)
    assert all(v == 0.3 for v in values[first:]), "the input moved after the refused messages"


JOY_INPUTS = (manifest_input("operator/forward", "remote.ly")
              + manifest_input("remote/a", "remote.btn.a", 'interface_type = "position"\n'
                               'unit = ""\nlimits = [0.0, 1.0]\n'))


def joy_json(axes, buttons, **extra):
    """A Joy as Foxglove's Joystick panel publishes it (its header's stamp is
    sec and nsec)."""
    msg = {"header": {"stamp": {"sec": 1, "nsec": 2}, "frame_id": ""}, "axes": axes,
           "buttons": buttons}
    msg.update(extra)
    return json.dumps(msg)


def test_joystick_reaches_a_controller(tmp_path):
    """Foxglove's Joystick panel (sensor_msgs/Joy, json: a gamepad in the
    browser's standard layout, its axes negated) through roz-live and rozrun
    --teleop onto the remote: the left stick half up is remote.ly (0.5 x 0.5
    = 0.25 for the input), button 0 is A. A Joy that is not strictly one is
    refused by roz-live with a status; one too short for the panel's map (a
    keyboard's two axes) and malformed datagrams by rozrun, counted; the
    inputs unchanged by all of them."""
    robot = robot_with_input(tmp_path, JOY_INPUTS, "ur5_joy.toml")
    sock = tmp_path / "teleop.sock"
    pad = [0.0, 0.5, 0.0, 0.0]      # the left stick half up: axis 1 (negated by the panel)
    pressed = [1] + [0] * 16        # A
    with teleop_run(tmp_path, robot) as (viewer, client, run, trace):
        assert "clientPublish" in client.info["capabilities"]
        ws = client.ws
        ws.send(json.dumps({"op": "advertise", "channels": [
            {"id": 3, "topic": "/joy", "encoding": "json", "schemaName": "sensor_msgs/Joy"}]}))
        for _ in range(10):
            publish(ws, 3, joy_json(pad, pressed))
            client.pump(0.05)
        # refused by roz-live, each with a status
        publish(ws, 3, joy_json([0.0, 0.0, 0.0, 0.0], pressed).replace("0.0,", "NaN,", 1))
        publish(ws, 3, joy_json(pad, [1.5] + [0] * 16))
        publish(ws, 3, joy_json([0.0] * 33, pressed))
        publish(ws, 3, json.dumps({"axes": pad}))
        publish(ws, 3, joy_json(pad, pressed, extra=1))
        got = [s["message"] for s in statuses(client, 1.0)]
        for says in ("NaN is not a number", "buttons[0]: not a 32-bit integer",
                     "axes: 33, more than 32"):
            assert any(says in m for m in got), f"no status says '{says}': {got}"
        assert sum("expected an object of axes and buttons" in m for m in got) == 2, got
        # refused by rozrun: a keyboard's Joy (two axes; the map needs four
        # and sixteen buttons), a datagram cut short, a count past the bound
        publish(ws, 3, joy_json([0.0, -0.5], [0, 0]))
        client.pump(0.3)
        raw = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        raw.sendto(b"JOY1" + struct.pack("<BBxx", 4, 17) + struct.pack("<4f", *pad), str(sock))
        raw.sendto(b"JOY1" + struct.pack("<BBxx", 33, 0) + struct.pack("<33f", *[0] * 33),
                   str(sock))
        # a map length past the bound; a datagram of 64 KiB; a magic alone
        raw.sendto(b"JOY1" + struct.pack("<BBH", 4, 17, 0xFFFF) + struct.pack("<4f17i", *pad,
                   *pressed) + b"x" * 0xFFFF, str(sock))
        raw.sendto(b"JOY1" + b"\xff" * 65532, str(sock))
        raw.sendto(b"JOY1", str(sock))
        raw.close()
        out, err = run.communicate(timeout=120)
        assert run.returncode == 0, out + err
    line = summary_line(out, "teleop")
    m = re.match(r"(\d+) twists from .*, (\d+) joysticks, (\d+) malformed refused", line)
    assert m, line
    assert tuple(map(int, m.groups())) == (0, 10, 6), line
    assert_joy_held(trace, "Joys")


def test_joystick_map_option(tmp_path):
    """roz-live --joy-map: the panel's axes and buttons by another map than
    its gamepad layout (here the right stick's vertical axis is the remote's
    ly and button 3 its A), carried to rozrun with each Joy and read by the
    core's rule; a map the rule refuses makes rozrun refuse its Joys, count
    them and say why once; roz-live refuses a map that is no printable text,
    and --joy-map without --teleop."""
    robot = robot_with_input(tmp_path, JOY_INPUTS, "ur5_joy.toml")
    fifo, sock = tmp_path / "run.live", tmp_path / "teleop.sock"
    for bad, says in ((["--joy-map", "ly=a1"], "--joy-map needs --teleop SOCKET"),
                      (["--teleop", sock, "--joy-map", "ly=a1\tbtn.a=b0"], "printable ASCII"),
                      (["--teleop", sock, "--joy-map", "x" * 513], "at most 512 characters")):
        p = subprocess.run([sys.executable, LIVE, fifo, *map(str, bad)], capture_output=True,
                           text=True, timeout=60)
        assert p.returncode == 2 and says in p.stderr, p.stderr
    with teleop_run(tmp_path, robot, "--joy-map", "ly=a3 btn.a=b3") as (viewer, client, run,
                                                                         trace):
        client.ws.send(json.dumps({"op": "advertise", "channels": [
            {"id": 3, "topic": "/joy", "encoding": "json", "schemaName": "sensor_msgs/Joy"}]}))
        # the left stick full down and A released: the panel's layout would
        # read -0.5 and 0; this map reads the right stick half up and button 3
        for _ in range(10):
            publish(client.ws, 3, joy_json([0.0, -1.0, 0.0, 0.5], [0, 0, 0, 1]))
            client.pump(0.05)
        # a map the rule refuses, as a datagram carries it: refused, counted
        raw = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        bad_map = b"ly=a3 btn.q=b0"
        raw.sendto(b"JOY1" + struct.pack("<BBH", 4, 4, len(bad_map))
                   + struct.pack("<4f4i", 0.0, 0.0, 0.0, -1.0, 0, 0, 0, 0) + bad_map, str(sock))
        raw.close()
        out, err = run.communicate(timeout=120)
        assert run.returncode == 0, out + err
    assert "a Joy mapped by ly=a3 btn.a=b3" in "".join(viewer.out)
    m = re.match(r"(\d+) twists from .*, (\d+) joysticks, (\d+) malformed refused",
                 summary_line(out, "teleop"))
    assert m and tuple(map(int, m.groups())) == (0, 10, 1), out
    assert err.count('roz-live --joy-map = "ly=a3 btn.q=b0": "btn.q=b0": not a field') == 1, err
    assert_joy_held(trace, "Joy")


def own_address():
    """A non-loopback IPv4 address of this machine (no packet is sent), or None."""
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    try:
        s.connect(("192.0.2.1", 9))
        addr = s.getsockname()[0]
    except OSError:
        return None
    finally:
        s.close()
    return None if addr.startswith("127.") else addr


def server_info(addr, port):
    with connect(f"ws://{addr}:{port}", subprotocols=[SUBPROTOCOL], open_timeout=30,
                 proxy=None, compression=None) as ws:
        msg = json.loads(ws.recv(timeout=30))
        assert msg["op"] == "serverInfo", msg
        caps = msg["capabilities"]
        if "clientPublish" not in caps:
            # publishing anyway changes nothing: no twist nor Joy goes to the run
            ws.send(json.dumps({"op": "advertise", "channels": [
                {"id": 1, "topic": "/cmd_vel", "encoding": "json",
                 "schemaName": "geometry_msgs/msg/Twist"}]}))
            ws.send(b"\x01" + struct.pack("<I", 1) + twist_json(0.5).encode())
            ws.send(json.dumps({"op": "advertise", "channels": [
                {"id": 2, "topic": "/joy", "encoding": "json", "schemaName": "sensor_msgs/Joy"}]}))
            ws.send(b"\x01" + struct.pack("<I", 2) + joy_json([0.0, 1.0, 0, 0], [1] * 16).encode())
            try:
                while True:
                    ws.recv(timeout=0.5)
            except TimeoutError:
                pass
        return caps


@pytest.mark.parametrize("remote", [False, True])
def test_teleop_from_another_machine(tmp_path, remote):
    addr = own_address()
    if addr is None:
        pytest.skip("this machine has no address but the loopback")
    fifo, sock = tmp_path / "run.live", tmp_path / "teleop.sock"
    # a socket that counts what roz-live would hand a run
    taken = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    taken.bind(str(sock))
    taken.settimeout(0.5)
    p = subprocess.Popen([sys.executable, str(LIVE), str(fifo), "--host", addr, "--port", "0",
                          "--teleop", str(sock), *(["--teleop-remote"] if remote else [])],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        line = p.stdout.readline()
        m = re.match(r"roz-live: serving ws://[^:]+:(\d+) ", line)
        assert m, line
        caps = server_info(addr, int(m.group(1)))
        assert ("clientPublish" in caps) == remote, caps
        if not remote:
            with pytest.raises(TimeoutError):
                taken.recv(64)
    finally:
        p.send_signal(signal.SIGINT)
        out = p.communicate(timeout=30)[0]
        taken.close()
    assert p.returncode == 0, out


def test_teleop_socket_refusals(tmp_path):
    """rozrun --teleop: a path that is not a socket, or too long for one, and
    --teleop with --replay exit 2 naming it; roz-live --teleop-remote alone
    is refused."""
    robot = robot_with_input(tmp_path)
    plain = tmp_path / "not_a_socket"
    plain.write_text("x")
    base = [ROZRUN, "--robot", robot, "--port", "loopback", "--ticks", "10",
            "--controller", CTL / "sine.wasm", "--allow-other-robot"]
    r = subprocess.run([*base, "--teleop", plain], capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and f"--teleop {plain}: exists and is not a socket" in r.stderr, \
        r.stderr
    assert plain.read_text() == "x"
    long = tmp_path / ("s" * 120)
    r = subprocess.run([*base, "--teleop", long], capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "longer than a socket's path may be" in r.stderr, r.stderr
    r = subprocess.run([ROZRUN, "--replay", tmp_path / "none.mcap", "--controller",
                        CTL / "sine.wasm", "--teleop", tmp_path / "t.sock"],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "--teleop and --replay" in r.stderr, r.stderr
    r = subprocess.run([sys.executable, str(LIVE), "-", "--teleop-remote"],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "--teleop-remote needs --teleop SOCKET" in r.stderr, r.stderr


def test_loopback_rule():
    """Who is offered clientPublish, on any machine (test_teleop_from_another_machine
    needs an address besides the loopback): roz-live's rule on peer addresses,
    run in a process of its own (importing roz-live patches the mcap reader)."""
    code = f"""
import importlib.util
spec = importlib.util.spec_from_file_location("live", {str(LIVE)!r})
live = importlib.util.module_from_spec(spec)
spec.loader.exec_module(live)
for a in ("127.0.0.1", "127.1.2.3", "::1", "::ffff:127.0.0.1"):
    assert live.loopback(a), a
for a in ("192.0.2.1", "10.0.0.1", "0.0.0.0", "::", "::ffff:192.0.2.1", "fe80::1%eth0",
          "2001:db8::1", "localhost", "", "127.0.0.1.evil"):
    assert not live.loopback(a), a
"""
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
