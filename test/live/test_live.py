# SPDX-License-Identifier: Apache-2.0
"""Watching a run live (docs/live.md): rozrun --live on the loopback UR5,
roz-live (tools/live.py) serving it on 127.0.0.1, and a client that speaks
the Foxglove WebSocket protocol v1 (subprotocol foxglove.sdk.v1) strictly
with PyPI's `websockets`: the subprotocol negotiated, serverInfo first,
every text message a JSON object with its op, the advertised channels and
schemas those of the run's own recording, every binary message a Message
Data frame (opcode 1, a subscription id the client chose, the log time) whose
payload decodes with the advertised ros2msg schema to the recording's
values. And the stream never holds up the tick: a reader that never reads,
or one that went away, costs dropped ticks of the stream, counted, while
the run and its file recording go on whole. ROZRUN and CTL come from the
build; only 127.0.0.1 is used."""
import json
import math
import os
import pathlib
import queue
import re
import signal
import struct
import subprocess
import sys
import threading
import time

import pytest
from mcap.exceptions import EndOfFile
from mcap.reader import make_reader
from mcap.records import Message, Schema
from mcap.stream_reader import StreamReader
from mcap_ros2.decoder import DecoderFactory
from websockets.sync.client import connect

ROOT = pathlib.Path(__file__).resolve().parents[2]
ROZRUN = os.environ.get("ROZRUN", "")
CTL = pathlib.Path(os.environ.get("CTL", "."))
LIVE = ROOT / "tools" / "live.py"
SUBPROTOCOL = "foxglove.sdk.v1"
SERVER_OPS = {"serverInfo", "status", "removeStatus", "advertise", "unadvertise",
              "subscriptionResponse"}

pytestmark = pytest.mark.skipif(not ROZRUN, reason="ROZRUN not set (run through ctest)")


def rozrun(*args, **kw):
    return subprocess.run([ROZRUN, *map(str, args)], capture_output=True, text=True,
                          timeout=300, **kw)


def summary_line(out, key):
    m = re.search(rf"^  {key} +(.*)$", out, re.M)
    assert m, f"no '{key}' line in the summary:\n{out}"
    return m.group(1)


def live_counts(out):
    m = re.search(r"(\d+) of (\d+) ticks sent, (\d+) dropped", summary_line(out, "live"))
    assert m, out
    return tuple(int(g) for g in m.groups())


def recorded(path):
    """The recording's channels {topic: advertised fields} and its messages
    {(topic, log_time): (bytes, decoded)}."""
    channels, messages = {}, {}
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()], validate_crcs=True)
        summary = reader.get_summary()
        for ch in summary.channels.values():
            sc = summary.schemas[ch.schema_id]
            channels[ch.topic] = {"encoding": ch.message_encoding, "schemaName": sc.name,
                                  "schema": sc.data.decode(), "schemaEncoding": sc.encoding}
        for _, ch, msg, dec in reader.iter_decoded_messages(log_time_order=False):
            key = (ch.topic, msg.log_time)
            assert key not in messages, f"two {ch.topic} messages at {msg.log_time}"
            messages[key] = (bytes(msg.data), dec)
    return channels, messages


def same_value(a, b):
    if isinstance(a, float) and isinstance(b, float):
        return struct.pack("<d", a) == struct.pack("<d", b) or (math.isnan(a) and math.isnan(b))
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(same_value(x, y) for x, y in zip(a, b))
    return a == b


def fields_of(decoded):
    return {n: getattr(decoded, n) for n in type(decoded).__slots__}


class Viewer:
    """roz-live on a FIFO, port 0, its output lines in a queue."""

    def __init__(self, fifo, *extra):
        self.p = subprocess.Popen([sys.executable, str(LIVE), str(fifo), "--host", "127.0.0.1",
                                   "--port", "0", *extra], stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True)
        self.lines = queue.Queue()
        self.out = []
        threading.Thread(target=self._read, daemon=True).start()
        line = self.wait_for("roz-live: serving ")
        m = re.match(r"roz-live: serving ws://127\.0\.0\.1:(\d+) ", line)
        assert m, line
        self.port = int(m.group(1))

    def _read(self):
        for line in self.p.stdout:
            self.out.append(line)
            self.lines.put(line)

    def wait_for(self, prefix, timeout=60):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            try:
                line = self.lines.get(timeout=0.2)
            except queue.Empty:
                assert self.p.poll() is None, f"roz-live exited {self.p.returncode}: " \
                                              f"{''.join(self.out)}"
                continue
            if line.startswith(prefix):
                return line
        pytest.fail(f"roz-live never said '{prefix}': {''.join(self.out)}")

    def stop(self):
        if self.p.poll() is None:
            self.p.send_signal(signal.SIGINT)
        try:
            assert self.p.wait(timeout=30) == 0, "".join(self.out)
        finally:
            if self.p.poll() is None:
                self.p.kill()


class StrictClient:
    """A Foxglove WebSocket protocol v1 client that fails on anything the
    specification does not allow a server to send."""

    def __init__(self, port):
        self._conn = connect(f"ws://127.0.0.1:{port}", subprotocols=[SUBPROTOCOL],
                             open_timeout=30, max_size=None, proxy=None, compression=None)
        self.ws = self._conn.__enter__()
        assert self.ws.subprotocol == SUBPROTOCOL, "the server did not select the subprotocol"
        self.info = None
        self.channels = {}     # channel id -> advertised channel
        self.subs = {}         # subscription id -> channel id
        self.next_sub = 1000   # the client's own ids, unlike the channels'
        self.received = []     # (topic, timestamp, payload)

    def _text(self, text):
        msg = json.loads(text)
        assert isinstance(msg, dict) and isinstance(msg.get("op"), str), text
        op = msg["op"]
        assert op in SERVER_OPS, f"a server op the client never asked for: {text[:200]}"
        if self.info is None:
            assert op == "serverInfo", f"the first message is {op}, not serverInfo"
        if op == "serverInfo":
            assert self.info is None, "a second serverInfo"
            assert isinstance(msg.get("name"), str)
            caps = msg.get("capabilities")
            assert isinstance(caps, list) and all(isinstance(c, str) for c in caps)
            self.info = msg
        elif op == "advertise":
            assert isinstance(msg.get("channels"), list)
            subscribe = []
            for ch in msg["channels"]:
                for key in ("topic", "encoding", "schemaName", "schema"):
                    assert isinstance(ch.get(key), str), f"advertise: {key} in {ch}"
                assert isinstance(ch.get("id"), int)
                if "schemaEncoding" in ch:
                    assert isinstance(ch["schemaEncoding"], str)
                assert ch["id"] not in self.channels, f"channel {ch['id']} advertised twice"
                self.channels[ch["id"]] = ch
                subscribe.append({"id": self.next_sub, "channelId": ch["id"]})
                self.subs[self.next_sub] = ch["id"]
                self.next_sub += 1
            if subscribe:
                self.ws.send(json.dumps({"op": "subscribe", "subscriptions": subscribe}))
        elif op == "subscriptionResponse":  # the SDK's: the subscriptions it took
            for sub in msg["subscriptions"]:
                assert self.subs.get(sub["id"]) == sub["channelId"], text
        elif op == "unadvertise":
            pytest.fail(f"channels withdrawn during the run: {text}")

    def _binary(self, data):
        assert len(data) >= 1 + 4 + 8, f"a binary message of {len(data)} bytes"
        assert data[0] == 0x01, f"binary opcode {data[0]}: only Message Data (1) is expected"
        sub, ts = struct.unpack_from("<IQ", data, 1)
        assert sub in self.subs, f"Message Data for subscription {sub}, never made"
        self.received.append((self.channels[self.subs[sub]]["topic"], ts, bytes(data[13:])))

    def pump(self, timeout):
        """Handles what arrives within @p timeout seconds; False when nothing did."""
        try:
            m = self.ws.recv(timeout=timeout)
        except TimeoutError:
            return False
        if isinstance(m, str):
            self._text(m)
        else:
            assert self.info is not None, "binary data before serverInfo"
            self._binary(m)
        return True

    def close(self):
        self._conn.__exit__(None, None, None)


def watch_run(client, viewer, args):
    """rozrun with @p args through the viewer while the client pumps, until
    the run is over and nothing came for a second; rozrun's stdout."""
    run = subprocess.Popen([ROZRUN, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           text=True)
    deadline = time.monotonic() + 120
    ended = False
    while time.monotonic() < deadline:
        got = client.pump(1.0)
        if not ended and run.poll() is not None:
            viewer.wait_for("roz-live: the run ended")
            ended = True
        if ended and not got:
            break  # the run is over and nothing came for a second
    out, err = run.communicate(timeout=60)
    assert run.returncode == 0, out + err
    return out


def watch(client, viewer, ticks, record, fifo):
    """One run at the UR5's rate through the viewer while the client pumps;
    rozrun's stdout."""
    return watch_run(client, viewer, ["--robot", "ur5", "--port", "loopback", "--realtime",
                                      "--ticks", str(ticks), "--controller", CTL / "sine.wasm",
                                      "--record", record, "--live", fifo])


def test_live_run_equals_its_recording(tmp_path):
    """Every channel roz-live advertises is the recording's (topic, cdr,
    schema name and ros2msg text); every message the client receives is a
    recorded one, byte for byte, and decodes with the advertised schema to
    the recording's values. A second run on the same FIFO follows on the
    same channels, its /roz/run included."""
    fifo = tmp_path / "run.live"
    viewer = Viewer(fifo)
    client = StrictClient(viewer.port)
    try:
        while client.info is None:
            assert client.pump(30), "no serverInfo"
        # a few seconds of ticks, so the client has subscribed while most
        # of them are still to come
        out1 = watch(client, viewer, 300, tmp_path / "run.mcap", fifo)
        viewer.wait_for("roz-live: waiting for the next run")
        first = len(client.received)
        out2 = watch(client, viewer, 150, tmp_path / "run2.mcap", fifo)
    finally:
        client.close()
        viewer.stop()

    channels, messages = recorded(tmp_path / "run.mcap")
    channels2, messages2 = recorded(tmp_path / "run2.mcap")
    assert channels2 == channels
    advertised = {ch["topic"]: {k: ch.get(k) for k in ("encoding", "schemaName", "schema",
                                                       "schemaEncoding")}
                  for ch in client.channels.values()}
    assert advertised == channels  # once each: the second run kept them
    assert set(channels) == {"/roz/run", "/roz/controller", "/roz/tick", "/roz/state",
                             "/roz/target", "/roz/applied", "/roz/fault"}
    assert live_counts(out1) == (300, 300, 0), out1
    assert live_counts(out2) == (150, 150, 0), out2
    assert not set(messages) & set(messages2)  # the second run starts later

    factory = DecoderFactory()
    decoders = {}
    ticks_seen = [set(), set()]
    for n, (topic, ts, payload) in enumerate(client.received):
        run = 0 if n < first else 1
        recorded_run = (messages, messages2)[run]
        assert (topic, ts) in recorded_run, f"{topic} at {ts}: not in run {run + 1}'s recording"
        data, dec = recorded_run[(topic, ts)]
        assert payload == data, f"{topic} at {ts}: not the recorded bytes"
        if topic not in decoders:
            ch = next(c for c in client.channels.values() if c["topic"] == topic)
            decoders[topic] = factory.decoder_for(
                ch["encoding"], Schema(id=ch["id"], name=ch["schemaName"],
                                       encoding=ch["schemaEncoding"],
                                       data=ch["schema"].encode()))
        live = fields_of(decoders[topic](payload))
        rec = fields_of(dec)
        assert live.keys() == rec.keys()
        for k in rec:
            assert same_value(live[k], rec[k]), f"{topic}.{k} at {ts}: {live[k]} != {rec[k]}"
        if topic == "/roz/tick":
            ticks_seen[run].add(live["tick"])
    # the client subscribed within a few ticks of the first run's start, and
    # before the second run: most ticks of one, and the other's /roz/run
    assert len(ticks_seen[0]) >= 150, f"only {len(ticks_seen[0])} of 300 ticks reached the client"
    assert len(ticks_seen[1]) >= 140, f"only {len(ticks_seen[1])} of 150 ticks reached the client"
    assert any(t == "/roz/run" for t, _, _ in client.received[first:])
    per_topic = {}
    for topic, ts, _ in client.received[:first]:
        per_topic.setdefault(topic, set()).add(ts)
    # the client subscribes to one topic after another, a tick or more apart
    # on a loaded machine; from the tick every subscription is in, each tick
    # reaches it whole (a tick is queued whole or dropped whole)
    topics = ("/roz/tick", "/roz/state", "/roz/target", "/roz/applied")
    start = max(min(per_topic[t]) for t in topics)
    tick_times = {ts for ts in per_topic["/roz/tick"] if ts >= start}
    for topic in topics[1:]:
        assert {ts for ts in per_topic[topic] if ts >= start} == tick_times, topic


def stream_ticks(data):
    """The /roz/tick messages in a live stream's bytes, and whether it ended
    with its footer."""
    import io
    n, complete = 0, False
    reader = StreamReader(io.BytesIO(data), validate_crcs=True)
    topics = {}
    try:
        for rec in reader.records:
            if type(rec).__name__ == "Channel":
                topics[rec.id] = rec.topic
            elif isinstance(rec, Message) and topics[rec.channel_id] == "/roz/tick":
                n += 1
            elif type(rec).__name__ == "Footer":
                complete = True
    except (EndOfFile, struct.error):  # the last chunk cut at the close
        pass
    return n, complete


@pytest.mark.parametrize("realtime", [False, True], ids=["simulated", "realtime"])
def test_reader_that_never_reads_costs_stream_ticks_only(tmp_path, realtime):
    """A pipe nobody reads: every tick runs, the file recording beside the
    stream is whole, and the stream drops whole ticks, counted; what sits in
    the pipe is the stream's start and exactly the ticks counted as sent."""
    r, w = os.pipe()
    ticks = 300 if realtime else 20000
    try:
        p = rozrun("--robot", "ur5", "--port", "loopback", "--ticks", ticks, *(
            ["--realtime"] if realtime else []), "--controller", CTL / "sine.wasm",
            "--record", tmp_path / "run.mcap", "--live", f"/dev/fd/{w}", pass_fds=(w,))
        os.close(w)
        w = -1
        assert p.returncode == 0, p.stdout + p.stderr
        assert summary_line(p.stdout, "ticks").startswith(f"{ticks} "), p.stdout
        assert f"({ticks} ticks, none dropped)" in summary_line(p.stdout, "recording")
        sent, total, dropped = live_counts(p.stdout)
        assert total == ticks and sent + dropped == ticks
        if not realtime:  # 20,000 ticks in a blink: the pipe and the queue fill
            assert dropped > 0 and "the viewer was still behind at the end" in p.stdout
        data = b""
        while chunk := os.read(r, 1 << 20):
            data += chunk
    finally:
        os.close(r)
        if w >= 0:
            os.close(w)
    n, complete = stream_ticks(data)
    assert n == sent
    assert not complete or dropped == 0


def test_viewer_that_went_away_ends_the_stream_not_the_run(tmp_path):
    r, w = os.pipe()
    os.close(r)
    try:
        p = rozrun("--robot", "ur5", "--port", "loopback", "--ticks", 2000, "--controller",
                   CTL / "sine.wasm", "--record", tmp_path / "run.mcap", "--live",
                   f"/dev/fd/{w}", pass_fds=(w,))
    finally:
        os.close(w)
    assert p.returncode == 0, p.stdout + p.stderr
    assert live_counts(p.stdout) == (0, 2000, 2000)
    assert "the viewer went away" in summary_line(p.stdout, "live")
    assert "(2000 ticks, none dropped)" in summary_line(p.stdout, "recording")


def test_viewers_are_capped(tmp_path):
    """At most MAX_VIEWERS (8) connections at a time, idle ones included (the
    server holds about 190 KB for each): the ninth is closed at once, and a
    slot freed takes a viewer again. Counted by what the viewers get, never
    by time."""
    viewers = 8  # tools/live.py's MAX_VIEWERS, as docs/live.md says
    v = Viewer(tmp_path / "cap.live")
    try:
        held = [StrictClient(v.port) for _ in range(viewers)]
        for c in held:
            assert c.ws.recv(timeout=30)  # serverInfo: each one served
        with pytest.raises(Exception):  # noqa: B017 - refused, however the client says it
            StrictClient(v.port)
        held.pop()._conn.__exit__(None, None, None)
        for _ in range(100):  # the freed slot: the relay sees the close
            try:
                again = StrictClient(v.port)
                break
            except Exception:  # noqa: BLE001
                time.sleep(0.05)
        else:
            pytest.fail("a freed slot never took a viewer again")
        assert again.ws.recv(timeout=30)
        for c in held + [again]:
            c._conn.__exit__(None, None, None)
    finally:
        v.stop()


def test_subprotocol_names(tmp_path):
    """As docs/live.md says: a client that offers the protocol only by its
    older name, foxglove.websocket.v1, or no subprotocol at all, is refused
    at the handshake; one that offers both gets foxglove.sdk.v1."""
    from websockets.exceptions import InvalidStatus
    v = Viewer(tmp_path / "names.live")
    try:
        for offered in (["foxglove.websocket.v1"], None):
            with pytest.raises(InvalidStatus):
                connect(f"ws://127.0.0.1:{v.port}", subprotocols=offered, open_timeout=30,
                        proxy=None, compression=None)
        with connect(f"ws://127.0.0.1:{v.port}", open_timeout=30, proxy=None, compression=None,
                     subprotocols=["foxglove.websocket.v1", SUBPROTOCOL]) as ws:
            assert ws.subprotocol == SUBPROTOCOL
            assert json.loads(ws.recv(timeout=30))["op"] == "serverInfo"
    finally:
        v.stop()


def test_fifo_without_a_reader_is_refused(tmp_path):
    fifo = tmp_path / "nobody.live"
    os.mkfifo(fifo)
    p = rozrun("--robot", "ur5", "--ticks", 10, "--controller", CTL / "sine.wasm",
               "--live", fifo)
    assert p.returncode == 2
    assert f"{fifo}: nobody reads this FIFO yet" in p.stderr
    p = rozrun("--robot", "ur5", "--ticks", 10, "--controller", CTL / "sine.wasm",
               "--live", "-", cwd=tmp_path)
    assert p.returncode == 2 and "not standard output" in p.stderr
    assert not (tmp_path / "-").exists()
    p = rozrun("--replay", tmp_path / "x.mcap", "--controller", CTL / "sine.wasm",
               "--live", fifo)
    assert p.returncode == 2 and "--live streams a run on a port" in p.stderr


@pytest.mark.parametrize("robot,ctl", [("ur5", "sine"), ("unitree_g1", "g1_stand")])
def test_shipped_layout_is_the_runs(tmp_path, robot, ctl):
    """tools/layouts/<robot>.json is what `roz-live layout` writes for a run
    of that robot, and every path it plots is a field of the run's schemas."""
    p = rozrun("--robot", robot, "--ticks", 5, "--controller", CTL / f"{ctl}.wasm", "--record",
               tmp_path / "run.mcap")
    assert p.returncode in (0, 1), p.stdout + p.stderr
    q = subprocess.run([sys.executable, LIVE, "layout", tmp_path / "run.mcap",
                        tmp_path / "layout.json"], capture_output=True, text=True, timeout=120)
    assert q.returncode == 0, q.stderr
    made = (tmp_path / "layout.json").read_text()
    assert made == (ROOT / "tools" / "layouts" / f"{robot}.json").read_text()
    channels, _ = recorded(tmp_path / "run.mcap")
    paths = re.findall(r'"(?:value|topicPath)": "([^"]+)"', made)
    assert len(paths) >= 10
    for path in paths:
        topic, _, field = path.partition(".")
        assert topic in channels, path
        if field:
            assert re.search(rf"^\S+ {re.escape(field)}\b", channels[topic]["schema"], re.M), path


def test_layout_plots_the_operator_inputs(tmp_path):
    """A run driven by an operator: its layout plots the inputs as the
    controller read them (/roz/inputs), every one a field of the schema."""
    op = tmp_path / "operator.csv"
    op.write_text("time_s,operator/velocity.x\n0,0.5\n")
    p = rozrun("--robot", "unitree_g1_12dof", "--ticks", 5, "--controller",
               CTL / "g1_12dof_deployed.wasm", "--operator", op, "--record", tmp_path / "run.mcap")
    assert p.returncode == 0, p.stdout + p.stderr
    q = subprocess.run([sys.executable, LIVE, "layout", tmp_path / "run.mcap",
                        tmp_path / "layout.json"], capture_output=True, text=True, timeout=120)
    assert q.returncode == 0, q.stderr
    made = (tmp_path / "layout.json").read_text()
    assert '"title": "operator inputs"' in made
    paths = [x for x in re.findall(r'"value": "([^"]+)"', made) if x.startswith("/roz/inputs.")]
    assert paths == ["/roz/inputs.operator_velocity_x", "/roz/inputs.operator_velocity_y",
                     "/roz/inputs.operator_yaw_rate"]
    channels, _ = recorded(tmp_path / "run.mcap")
    for path in paths:
        field = path.partition(".")[2]
        assert re.search(rf"^float64 {field}\b", channels["/roz/inputs"]["schema"], re.M), path


def test_live_deploy_stages(tmp_path):
    """A deploy-sequence run (rozrun --deploy, the remote's buttons from a
    scripted operator) streamed at its rate: every stage change reaches the
    strict client on /roz/stage, the recorded bytes, decoded with the
    advertised schema to move, hold, run and stop; the layout roz-live
    writes draws the stage, and the requests taken, as bands (a State
    Transitions panel) from fields the advertised schema has."""
    robot = (ROOT / "manifests" / "unitree_g1_12dof.toml").read_text()
    for b in ("start", "a", "b", "select"):
        robot += (f'\n[[manifest.inputs]]\nname = "remote/{b}"\ninterface_type = "position"\n'
                  'unit = ""\nlimits = [0.0, 1.0]\ndefault = 0.0\nmax_rate_of_change = 1.0\n'
                  "stale_after_ms = 500\n")
    (tmp_path / "g1.toml").write_text(robot)
    (tmp_path / "deploy.toml").write_text(
        '[deploy]\nmove_s = 1.0\n[deploy.inputs]\nstart = "remote/start"\nrun = "remote/a"\n'
        'stand = "remote/b"\nstop = "remote/select"\n[deploy.stand]\n'
        "pose = [-0.1, 0, 0, 0.3, -0.2, 0, -0.1, 0, 0, 0.3, -0.2, 0]\n"
        "kp = [100, 100, 100, 150, 40, 40, 100, 100, 100, 150, 40, 40]\n"
        "kd = [2, 2, 2, 4, 2, 2, 2, 2, 2, 4, 2, 2]\n")
    # Start at 1.5 s (the client subscribed long before), A at 2.8 s, Select at 3.2 s
    (tmp_path / "ops.csv").write_text("time_s,remote/start,remote/a,remote/b,remote/select\n"
                                      "0,0,0,0,0\n1.5,1,0,0,0\n1.6,0,0,0,0\n2.8,0,1,0,0\n"
                                      "2.9,0,0,0,0\n3.2,0,0,0,1\n")
    fifo, rec, lay = tmp_path / "run.live", tmp_path / "run.mcap", tmp_path / "layout.json"
    viewer = Viewer(fifo, "--layout", lay)
    client = StrictClient(viewer.port)
    try:
        while client.info is None:
            assert client.pump(30), "no serverInfo"
        out = watch_run(client, viewer, [
            "--robot", tmp_path / "g1.toml", "--allow-other-robot", "--port", "loopback",
            "--realtime", "--ticks", "1700", "--controller", CTL / "g1_12dof_deployed.wasm",
            "--deploy", tmp_path / "deploy.toml", "--operator", tmp_path / "ops.csv",
            "--record", rec, "--live", fifo])
    finally:
        client.close()
        viewer.stop()
    assert "stage stop at the end; 4 stage changes" in out, out
    channels, messages = recorded(rec)
    stage = next(c for c in client.channels.values() if c["topic"] == "/roz/stage")
    assert {k: stage.get(k) for k in channels["/roz/stage"]} == channels["/roz/stage"]
    decode = DecoderFactory().decoder_for(
        stage["encoding"], Schema(id=stage["id"], name=stage["schemaName"],
                                  encoding=stage["schemaEncoding"], data=stage["schema"].encode()))
    got = [(ts, payload) for topic, ts, payload in client.received if topic == "/roz/stage"]
    want = sorted((ts, data) for (topic, ts), (data, _) in messages.items() if topic == "/roz/stage")
    assert got == want, "the client's /roz/stage is not the recording's"
    assert [decode(p).name for _, p in got] == ["move", "hold", "run", "stop"]
    made = json.loads(lay.read_text())
    bands = [p for p in re.findall(r'"value": "(/roz/stage\.[^"]+)"', json.dumps(made))]
    assert bands == ["/roz/stage.name", "/roz/stage.request_name"]
    assert '"panelType": "StateTransitions"' in json.dumps(made)
    for path in bands:
        assert re.search(rf"^string {path.partition('.')[2]}\b", stage["schema"], re.M), path


def cut_in_header(data):
    """An offset inside the fixed fields of the stream's last chunk record
    (after its opcode and length, within its times and sizes)."""
    at, last = 8, None
    while at + 9 <= len(data):
        if data[at] == 0x06:
            last = at
        at += 9 + int.from_bytes(data[at + 1:at + 9], "little")
    assert last is not None
    return last + 9 + 26


def test_runs_back_to_back_on_one_fifo(tmp_path):
    """Runs whose streams are in the FIFO at once, one right behind the
    other: roz-live reads each to its end and no further, so every one is
    served whole (a reader that read ahead would lose the next one's
    start)."""
    streams = []
    for n in range(3):
        p = rozrun("--robot", "ur5", "--ticks", 50, "--controller", CTL / "sine.wasm",
                   "--live", tmp_path / f"{n}.live")
        assert p.returncode == 0, p.stdout + p.stderr
        streams.append((tmp_path / f"{n}.live").read_bytes())
    fifo = tmp_path / "run.live"
    viewer = Viewer(fifo)
    try:
        with open(fifo, "wb") as f:  # roz-live holds the read end: no wait
            f.write(b"".join(streams))
        for n in range(3):
            # 50 ticks of /roz/tick, state, target, applied; /roz/run,
            # /roz/controller and the first tick's /roz/fault
            line = viewer.wait_for("roz-live: the run ")
            assert line.startswith("roz-live: the run ended: 203 messages served"), \
                "".join(viewer.out)
    finally:
        viewer.stop()


def test_viewer_survives_a_stream_cut_short_or_not_mcap(tmp_path):
    """roz-live on a stream whose writer died mid-tick, and on bytes that
    are no MCAP: it says so and exits cleanly (--exit), serving what came."""
    p = rozrun("--robot", "ur5", "--ticks", 50, "--controller", CTL / "sine.wasm", "--live",
               tmp_path / "whole.live")
    assert p.returncode == 0, p.stdout + p.stderr
    whole = (tmp_path / "whole.live").read_bytes()
    # 50 ticks of /roz/tick, state, target and applied; /roz/run, /roz/controller
    # and the first tick's /roz/fault (none latched)
    cases = {"whole": (whole, "the run ended: 203 messages"),
             "cut": (whole[:len(whole) // 2 + 7], "the run ended early"),
             "cut in a chunk's header": (whole[:cut_in_header(whole)], "the run ended early"),
             "garbage": (b"not an mcap stream at all" * 10, "the run ended early")}
    for name, (data, said) in cases.items():
        q = subprocess.run([sys.executable, LIVE, "-", "--port", "0", "--exit"], input=data,
                           capture_output=True, timeout=120)
        out = q.stdout.decode() + q.stderr.decode()
        assert q.returncode == 0, f"{name}: {out}"
        assert said in out, f"{name}: {out}"
    (tmp_path / "plain").write_text("x")
    q = subprocess.run([sys.executable, LIVE, tmp_path / "plain", "--port", "0", "--exit"],
                       capture_output=True, text=True, timeout=120)
    assert q.returncode == 1 and "not a FIFO" in q.stderr
