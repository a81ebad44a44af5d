# SPDX-License-Identifier: Apache-2.0
"""Watch a roz run live in Foxglove: serve the recording that rozrun streams
(rozrun --live FIFO) on the Foxglove WebSocket protocol, with the
recording's own channels, schemas and messages.

    python tools/live.py run.live [--host 127.0.0.1] [--port 8765] [--layout out.json]
    python tools/live.py layout run.mcap out.json      (the layout of a robot's run)
    roz-live ...                                       (the same, installed with roz)

run.live is a FIFO (made when it is missing) that `rozrun ... --live
run.live` writes; `-` reads the stream from standard input. The server binds
127.0.0.1 unless --host says otherwise (--host 0.0.0.0: every interface, for
a viewer on another machine; nothing is authenticated). --port 0 takes a
free port; the line "roz-live: serving ws://HOST:PORT" says which.

Each record of the stream is served as it comes: a schema and channel become
a Foxglove channel of the same topic, schema name, schema text (ros2msg) and
message encoding (cdr); each message is logged on it with its recorded log
time. On a FIFO, one run follows another (the channels stay while the robot
does) until Ctrl-C; --exit stops after the first run.

Teleop (--teleop SOCKET, the socket of `rozrun --teleop SOCKET`): viewers may
publish (Foxglove's clientPublish) a channel of json geometry_msgs/msg/Twist,
as Foxglove's Teleop panel does, or of json sensor_msgs/Joy, as its Joystick
panel does; each message is checked (at most MAX_TELEOP_BYTES, strict JSON: a
twist's linear and angular x, y, z finite numbers; a Joy's axes finite
numbers and buttons integers, at most MAX_JOY of each) and sent to the run,
which maps a Joy onto the remote (by --joy-map, FIELD=aN|-aN|bN entries,
or the panel's gamepad layout) and whose inputs' rules judge it; anything
else is refused with a status message and a line here. Only viewers
connected from this machine (a loopback address) get the capability;
--teleop-remote gives it to every viewer.

The layout (--layout, or the `layout` command from any recording of the
robot) plots the first joints' targets, applied commands and state, the
latched faults, fuel and freshness, the safety filter's counters, the
truth's base height when the run has one, and the deploy sequence's stages
as bands above the joints' plots when the run has one (docs/live.md).
"""
import argparse
import importlib.util
import ipaddress
import json
import math
import os
import pathlib
import select
import signal
import socket
import stat
import struct
import sys
import threading
import time

from mcap.exceptions import EndOfFile, McapError
from mcap.records import Channel, Message, Schema
from mcap.stream_reader import StreamReader

# chunks decompressed within their stated size (tools/mcap_chunks.py)
_spec = importlib.util.spec_from_file_location(
    "mcap_chunks", pathlib.Path(__file__).resolve().parent / "mcap_chunks.py")
mcap_chunks = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(mcap_chunks)
mcap_chunks.install()

# the largest record the stream may hold (roz/mcap.h, ROZ_MCAP_MAX_RECORD)
MAX_RECORD = mcap_chunks.MAX_RECORD
# joints the layout plots
LAYOUT_JOINTS = 3
# viewers connected at once (docs/live.md): each costs the server about 190 KB
MAX_VIEWERS = 8
# teleop (docs/live.md): what a viewer may publish, and its largest message
TELEOP_SCHEMAS = ("geometry_msgs/msg/Twist", "geometry_msgs/Twist")
# Foxglove's Joystick panel advertises "sensor_msgs/Joy"; a ROS 2 tool the other
JOY_SCHEMAS = ("sensor_msgs/Joy", "sensor_msgs/msg/Joy")
MAX_TELEOP_BYTES = 4096
# a Joy's axes, and buttons, at most (tools/rozrun/teleop.h, ROZRUN_TELEOP_JOY_MAX)
MAX_JOY = 32
# a Joy's map's text, bytes at most (ROZRUN_TELEOP_JOY_MAP_MAX)
MAX_JOY_MAP = 512
INT32 = (-(1 << 31), (1 << 31) - 1)
FLOAT32_MAX = 3.4028234663852886e38  # an axis goes as a float32


class LiveError(Exception):
    pass


def open_fifo(path):
    """The FIFO rozrun writes (made when missing), opened for reading
    without waiting for a writer: while it is open, rozrun finds a reader
    on it, between runs too."""
    p = pathlib.Path(path)
    if not p.exists():
        os.mkfifo(p, 0o600)
    elif not stat.S_ISFIFO(p.stat().st_mode):
        raise LiveError(f"{path}: not a FIFO (rozrun --live writes one; remove the file or "
                        f"name another path)")
    return os.open(p, os.O_RDONLY | os.O_NONBLOCK)


class ExactReader:
    """A FIFO's read end that reads what is asked and no more: a buffered
    reader would read ahead into the next run's stream, already in the FIFO
    when one run follows another at once, and lose its start."""

    def __init__(self, fd):
        self.fd = fd

    def read(self, n):
        parts = []
        while n > 0:
            b = os.read(self.fd, n)
            if not b:
                break
            parts.append(b)
            n -= len(b)
        return b"".join(parts)

    def close(self):
        os.close(self.fd)


def next_run(path):
    """The next run's stream on the FIFO: a read end of its own, handed out
    once a writer has written (or come and gone), read blocking."""
    fd = open_fifo(path)
    while not select.select([fd], [], [], 0.5)[0]:
        pass
    os.set_blocking(fd, True)
    return ExactReader(fd)


class TeleopError(Exception):
    pass


def _no_constant(name):
    raise TeleopError(f"{name} is not a number")


def _one_of_each(pairs):
    keys = [k for k, _ in pairs]
    if len(set(keys)) != len(keys):
        raise TeleopError(f"a key given twice ({', '.join(sorted(keys))})")
    return dict(pairs)


def parse_twist(data):
    """The six values of a geometry_msgs/msg/Twist in JSON, as Foxglove's
    Teleop panel publishes it ({"linear": {"x", "y", "z"}, "angular": {...}}):
    strictly that, every value a finite number; TeleopError says why not."""
    msg = _json_object(data)
    if not isinstance(msg, dict) or set(msg) != {"linear", "angular"}:
        raise TeleopError("expected an object of linear and angular")
    out = []
    for part in ("linear", "angular"):
        v = msg[part]
        if not isinstance(v, dict) or set(v) != {"x", "y", "z"}:
            raise TeleopError(f"{part}: expected an object of x, y and z")
        for axis in "xyz":
            x = v[axis]
            if isinstance(x, bool) or not isinstance(x, (int, float)):
                raise TeleopError(f"{part}.{axis}: not a number")
            try:
                x = float(x)
            except OverflowError:
                x = math.inf
            if not math.isfinite(x):
                raise TeleopError(f"{part}.{axis}: not finite")
            out.append(x)
    return out


def _json_object(data):
    if len(data) > MAX_TELEOP_BYTES:
        raise TeleopError(f"{len(data)} bytes, more than {MAX_TELEOP_BYTES}")
    try:
        return json.loads(bytes(data).decode("utf-8"), parse_constant=_no_constant,
                          object_pairs_hook=_one_of_each)
    except (UnicodeDecodeError, ValueError) as e:
        raise TeleopError(f"not JSON ({e})") from None
    except RecursionError:  # 4,096 bytes of "[" nest deeper than Python's decoder goes
        raise TeleopError("not JSON (nested too deeply)") from None


def parse_joy(data):
    """The axes and buttons of a sensor_msgs/Joy in JSON, as Foxglove's
    Joystick panel publishes it ({"header": {...}, "axes": [...], "buttons":
    [...]}; the header optional and not read): axes finite numbers, buttons
    integers, at most MAX_JOY of each; TeleopError says why not."""
    msg = _json_object(data)
    if not isinstance(msg, dict) or not {"axes", "buttons"} <= set(msg) <= {
            "header", "axes", "buttons"}:
        raise TeleopError("expected an object of axes and buttons (and a header)")
    if "header" in msg and not isinstance(msg["header"], dict):
        raise TeleopError("header: expected an object")
    axes, buttons = msg["axes"], msg["buttons"]
    for name, v in (("axes", axes), ("buttons", buttons)):
        if not isinstance(v, list):
            raise TeleopError(f"{name}: expected a list")
        if len(v) > MAX_JOY:
            raise TeleopError(f"{name}: {len(v)}, more than {MAX_JOY}")
    out_axes = []
    for k, x in enumerate(axes):
        if isinstance(x, bool) or not isinstance(x, (int, float)):
            raise TeleopError(f"axes[{k}]: not a number")
        try:
            x = float(x)
        except OverflowError:
            x = math.inf
        if not math.isfinite(x) or abs(x) > FLOAT32_MAX:
            raise TeleopError(f"axes[{k}]: not finite as a float32")
        out_axes.append(x)
    for k, b in enumerate(buttons):
        if isinstance(b, bool) or not isinstance(b, int) or not INT32[0] <= b <= INT32[1]:
            raise TeleopError(f"buttons[{k}]: not a 32-bit integer")
    return out_axes, list(buttons)


def joy_datagram(axes, buttons, joy_map=b""):
    """A Joy for rozrun --teleop (tools/rozrun/teleop.h): "JOY1", the counts,
    the map's length, the axes as float32, the buttons as int32, the map
    (b"": none, rozrun maps by the panel's gamepad layout)."""
    return (b"JOY1" + struct.pack("<BBH", len(axes), len(buttons), len(joy_map))
            + struct.pack(f"<{len(axes)}f{len(buttons)}i", *axes, *buttons) + joy_map)


def check_joy_map(text):
    """--joy-map's text as bytes for the datagram: printable ASCII, at most
    MAX_JOY_MAP bytes (its grammar is rozrun's rule, roz/joy.h, which judges
    it); LiveError says why not."""
    if not text.strip() or len(text) > MAX_JOY_MAP or not all(" " <= c <= "~" for c in text):
        raise LiveError(f"--joy-map {text!r}: expected FIELD=SOURCE entries (roz/joy.h) in "
                        f"printable ASCII, at most {MAX_JOY_MAP} characters")
    return text.encode()


def loopback(address):
    """A peer's address is this machine's loopback (127/8, ::1, or an
    IPv4-mapped 127/8)."""
    try:
        a = ipaddress.ip_address(address.split("%", 1)[0])
    except ValueError:
        return False
    if getattr(a, "ipv4_mapped", None) is not None:
        a = a.ipv4_mapped
    return a.is_loopback


class Teleop:
    """The teleop server's listener: the viewers' Twist and Joy channels,
    each message checked and sent to rozrun's --teleop socket: a twist as
    "TWST" and six little-endian float64, a Joy as joy_datagram()
    (tools/rozrun/teleop.h). Called on the SDK's
    threads; each call is short and never blocks (the socket does not)."""

    def __init__(self, path, joy_map=b""):
        self.path = path
        self.joy_map = joy_map
        self.sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        self.sock.setblocking(False)
        self.lock = threading.Lock()
        self.channels = {}  # (client id, channel id) -> topic
        self.server = None
        self.sent = 0
        self.refused = 0

    def refuse(self, why):
        with self.lock:
            self.refused += 1
        print(f"roz-live: teleop: {why}", flush=True)
        if self.server is not None:
            from foxglove.websocket import StatusLevel
            self.server.publish_status(f"roz-live: {why}", StatusLevel.Error)

    def on_client_advertise(self, client, channel):
        kind = ("twist" if channel.schema_name in TELEOP_SCHEMAS else
                "joy" if channel.schema_name in JOY_SCHEMAS else None)
        if channel.encoding != "json" or kind is None:
            self.refuse(f"channel {channel.topic} ({channel.schema_name}, {channel.encoding}): "
                        f"roz-live takes json geometry_msgs/msg/Twist or sensor_msgs/Joy only")
            return
        with self.lock:
            self.channels[(client.id, channel.id)] = (channel.topic, kind)

    def on_client_unadvertise(self, client, client_channel_id):
        with self.lock:
            self.channels.pop((client.id, client_channel_id), None)

    def on_message_data(self, client, client_channel_id, data):
        with self.lock:
            topic, kind = self.channels.get((client.id, client_channel_id), (None, None))
        if topic is None:
            self.refuse(f"a message on channel {client_channel_id}, which is no advertised "
                        f"twist or Joy: refused")
            return
        try:
            if kind == "twist":
                datagram = b"TWST" + struct.pack("<6d", *parse_twist(data))
            else:
                datagram = joy_datagram(*parse_joy(data), self.joy_map)
        except TeleopError as e:
            self.refuse(f"{topic}: {e}: refused, the inputs unchanged")
            return
        try:
            self.sock.sendto(datagram, self.path)
        except OSError as e:
            self.refuse(f"{topic}: no run takes {kind}s at {self.path} ({e.strerror or e})")
            return
        with self.lock:
            self.sent += 1

    def close(self):
        self.sock.close()


class Gate:
    """The address viewers connect to, at most MAX_VIEWERS at a time, each
    relayed to the Foxglove server on a port of 127.0.0.1 of its own: the
    server has no cap of its own and holds about 190 KB per connection, idle
    ones too. A connection past the cap is closed at once."""

    def __init__(self, host, port, backend_port, teleop_port=None, teleop_remote=False):
        self.backend = backend_port
        self.teleop = teleop_port    # the teleop server's: loopback viewers' (or all)
        self.teleop_remote = teleop_remote
        self.lock = threading.Lock()
        self.open = 0
        self.refused = 0
        self.sock = socket.create_server((host, port))
        threading.Thread(target=self._accept, daemon=True).start()

    def port(self):
        return self.sock.getsockname()[1]

    def _accept(self):
        while True:
            try:
                conn, peer = self.sock.accept()
            except OSError:
                return  # closed
            with self.lock:
                full = self.open >= MAX_VIEWERS
                if full:
                    self.refused += 1
                else:
                    self.open += 1
            if full:
                conn.close()
                continue
            backend = self.backend
            if self.teleop is not None and (self.teleop_remote or loopback(peer[0])):
                backend = self.teleop
            try:
                back = socket.create_connection(("127.0.0.1", backend))
            except OSError:
                conn.close()
                self._done()
                continue
            once = threading.Event()
            for a, b in ((conn, back), (back, conn)):
                threading.Thread(target=self._pump, args=(a, b, conn, back, once),
                                 daemon=True).start()

    def _done(self):
        with self.lock:
            self.open -= 1

    def _pump(self, src, dst, conn, back, once):
        try:
            while True:
                data = src.recv(65536)
                if not data:
                    break
                dst.sendall(data)
        except OSError:
            pass
        # either side gone: both sockets closed, the slot freed once
        if not once.is_set():
            once.set()
            for s in (conn, back):
                try:
                    s.shutdown(socket.SHUT_RDWR)
                except OSError:
                    pass
            self._done()
        src.close()

    def close(self):
        self.sock.close()


class Server:
    """The Foxglove WebSocket server and the channels of one stream."""

    def __init__(self, host, port, teleop=None, teleop_remote=False, joy_map=b""):
        import foxglove
        self.foxglove = foxglove
        self.server = foxglove.start_server(name="roz-live", host="127.0.0.1", port=0)
        # teleop: a second server, on the same channels, whose viewers may
        # publish; the gate sends only those it allows to it
        self.teleop = Teleop(teleop, joy_map) if teleop is not None else None
        self.teleop_server = None
        if self.teleop is not None:
            from foxglove.websocket import Capability
            self.teleop_server = foxglove.start_server(
                name="roz-live", host="127.0.0.1", port=0,
                capabilities=[Capability.ClientPublish], supported_encodings=["json"],
                server_listener=self.teleop)
            self.teleop.server = self.teleop_server
        self.gate = Gate(host, port, self.server.port,
                         self.teleop_server.port if self.teleop_server else None, teleop_remote)
        self.schemas = {}     # this stream's schema id -> record
        self.channels = {}    # this stream's channel id -> Foxglove channel
        self.by_topic = {}    # topic -> (what it advertises, Foxglove channel), across runs
        self.messages = 0

    def new_stream(self):
        """A stream starts over: its ids are its own; the channels stay
        advertised while a topic keeps its schema (the next run of the same
        robot), and are replaced when it does not."""
        self.schemas, self.channels, self.messages = {}, {}, 0

    def port(self):
        return self.gate.port()

    def app_url(self):
        """The SDK's link that opens this server in Foxglove's app, at the
        gate's port."""
        try:
            url = self.server.app_url()
        except Exception:  # noqa: BLE001 - a convenience only
            return None
        return url.replace(f"%3A{self.server.port}", f"%3A{self.port()}").replace(
            f":{self.server.port}", f":{self.port()}") if url else url

    def take(self, record):
        fg = self.foxglove
        if isinstance(record, Schema):
            self.schemas[record.id] = record
        elif isinstance(record, Channel):
            sc = self.schemas.get(record.schema_id)
            if sc is None:
                raise LiveError(f"channel {record.topic}: schema {record.schema_id} was never "
                                f"defined")
            key = (record.message_encoding, sc.name, sc.encoding, bytes(sc.data))
            known = self.by_topic.get(record.topic)
            if known is not None and known[0] == key:
                self.channels[record.id] = known[1]
                return
            if known is not None:
                known[1].close()  # another robot on the topic: unadvertised
            schema = fg.Schema(name=sc.name, encoding=sc.encoding, data=bytes(sc.data))
            ch = fg.Channel(record.topic, schema=schema, message_encoding=record.message_encoding)
            self.channels[record.id] = ch
            self.by_topic[record.topic] = (key, ch)
        elif isinstance(record, Message):
            ch = self.channels.get(record.channel_id)
            if ch is None:
                raise LiveError(f"a message on channel {record.channel_id}, never defined")
            ch.log(bytes(record.data), log_time=record.log_time)
            self.messages += 1

    def stop(self):
        self.gate.close()
        self.server.stop()
        if self.teleop_server is not None:
            self.teleop_server.stop()
            self.teleop.close()


def fields(schema_text):
    """The float64 field names of a State or Commands schema, in order."""
    out = []
    for line in schema_text.splitlines():
        line = line.split("#", 1)[0].split()
        if len(line) == 2 and line[0] == "float64":
            out.append(line[1])
    return out


def fields_any(schema_text):
    """Every field name of a ros2msg schema, in order."""
    out = []
    for line in schema_text.splitlines():
        line = line.split("#", 1)[0].split()
        if len(line) == 2:
            out.append(line[1])
    return out


def layout(schemas, joints=LAYOUT_JOINTS):
    """A Foxglove layout (the SDK's foxglove.layouts, version 1) for a run
    whose schemas are {topic: (schema name, text)}: per joint the targets,
    applied commands and the state field of the same name; the faults, fuel
    and freshness; the safety filter's counters; the truth's base height
    when the run has /roz/truth, the operator's inputs when it has
    /roz/inputs; above the joints, the deploy sequence's stage as bands in
    time with their plots when it has /roz/stage (rozrun --deploy)."""
    import foxglove.layouts as fl
    commands = fields(schemas["/roz/target"][1])
    states = set(fields(schemas["/roz/state"][1]))
    plots = []
    for name in commands[:joints]:
        series = [fl.PlotSeries(value=f"/roz/target.{name}", label="target"),
                  fl.PlotSeries(value=f"/roz/applied.{name}", label="applied")]
        if name in states:
            series.append(fl.PlotSeries(value=f"/roz/state.{name}", label="state"))
        plots.append(fl.SplitItem(content=fl.PlotPanel(
            title=name, config=fl.PlotConfig(paths=series))))
    if "/roz/stage" in schemas:  # a band per stage, from one change to the next
        plots.insert(0, fl.SplitItem(proportion=0.4, content=fl.StateTransitionsPanel(
            title="deploy stage", config=fl.StateTransitionsConfig(is_synced=True, paths=[
                fl.StateTransitionsSeries(value="/roz/stage.name", label="stage"),
                fl.StateTransitionsSeries(value="/roz/stage.request_name",
                                          label="request taken")]))))
    safety = fl.PlotPanel(title="faults, freshness", config=fl.PlotConfig(paths=[
        fl.PlotSeries(value="/roz/tick.faults", label="latched faults (bits)"),
        fl.PlotSeries(value="/roz/tick.fresh", label="fresh state"),
        fl.PlotSeries(value="/roz/tick.wrote", label="commands written")]))
    # the filter's counters (totals since the start): a rising line is the
    # filter at work; absent from recordings made before them
    tick_fields = set(fields_any(schemas["/roz/tick"][1]))
    counters = [(f, label) for f, label in (("clamps", "clamps"), ("rate_caps", "rate caps"),
                                            ("limit_stops", "limit stops"),
                                            ("nonfinite", "refused non-finite"))
                if f in tick_fields]
    side = [fl.SplitItem(content=safety),
            fl.SplitItem(content=fl.PlotPanel(title="fuel per tick", config=fl.PlotConfig(
                paths=[fl.PlotSeries(value="/roz/tick.fuel", label="fuel")]))),
            fl.SplitItem(content=fl.RawMessagesPanel(
                title="last fault", config=fl.RawMessagesConfig(topic_path="/roz/fault")))]
    if counters:
        side.insert(1, fl.SplitItem(content=fl.PlotPanel(
            title="safety filter (totals)", config=fl.PlotConfig(paths=[
                fl.PlotSeries(value=f"/roz/tick.{f}", label=label) for f, label in counters]))))
    if "/roz/inputs" in schemas:  # the operator's inputs, as the controller read them
        side.insert(0, fl.SplitItem(content=fl.PlotPanel(
            title="operator inputs", config=fl.PlotConfig(paths=[
                fl.PlotSeries(value=f"/roz/inputs.{f}", label=f)
                for f in fields(schemas["/roz/inputs"][1])]))))
    if "/roz/truth" in schemas:
        side.insert(0, fl.SplitItem(content=fl.PlotPanel(
            title="base height (truth)", config=fl.PlotConfig(paths=[
                fl.PlotSeries(value="/roz/truth.height", label="height, m")]))))
    content = fl.SplitContainer(direction="row", items=[
        fl.SplitItem(proportion=2, content=fl.SplitContainer(direction="column", items=plots)),
        fl.SplitItem(proportion=1, content=fl.SplitContainer(direction="column", items=side))])
    return json.dumps(json.loads(fl.Layout(content=content).to_json()), indent=2,
                      sort_keys=True) + "\n"


def schemas_of(server):
    return {ch.topic(): (ch.schema_name(), bytes(ch.schema().data).decode())
            for ch in server.channels.values()}


def layout_of_recording(path):
    """{topic: (schema name, text)} of a recording (a file, or a stream)."""
    out, sch = {}, {}
    with open(path, "rb") as f:
        try:
            for rec in StreamReader(f, record_size_limit=MAX_RECORD).records:
                if isinstance(rec, Schema):
                    sch[rec.id] = rec
                elif isinstance(rec, Channel):
                    s = sch[rec.schema_id]
                    out[rec.topic] = (s.name, bytes(s.data).decode())
                elif isinstance(rec, Message):
                    break  # the schemas and channels come first
        except mcap_chunks.ChunkError as e:
            raise LiveError(f"{path}: {e}") from None
    for topic in ("/roz/target", "/roz/state"):
        if topic not in out:
            raise LiveError(f"{path}: no {topic} channel: not a roz recording")
    return out


def read_run(server, src, args):
    """Serves one run's stream; what ended it."""
    server.new_stream()
    written_layout = not args.layout
    reader = StreamReader(src, validate_crcs=True, record_size_limit=MAX_RECORD)
    try:
        for rec in reader.records:
            server.take(rec)
            if not written_layout and isinstance(rec, Message):
                pathlib.Path(args.layout).write_text(layout(schemas_of(server)))
                print(f"roz-live: layout {args.layout}", flush=True)
                written_layout = True
    except (EndOfFile, struct.error):  # rozrun killed, or closed while the viewer
        # was behind: the last record cut (the reader sees a short read)
        return "ended early: the stream stops inside a record"
    except McapError as e:  # not MCAP, or corrupt
        return f"ended early: a bad stream ({type(e).__name__}: {e})"
    except (EOFError, OSError) as e:
        return f"ended early ({e})"
    return "ended"


def serve(args):
    def interrupt(signum, frame):
        raise KeyboardInterrupt

    # Ctrl-C and SIGTERM end a blocking read too
    signal.signal(signal.SIGINT, interrupt)
    signal.signal(signal.SIGTERM, interrupt)
    fifo = args.input != "-"
    anchor = open_fifo(args.input) if fifo else None  # a reader between runs
    joy_map = check_joy_map(args.joy_map) if args.joy_map is not None else b""
    server = Server(args.host, args.port, args.teleop, args.teleop_remote, joy_map)
    try:
        print(f"roz-live: serving ws://{args.host}:{server.port()} (Foxglove: open "
              f"connection, Foxglove WebSocket); reading {args.input}", flush=True)
        url = server.app_url()
        if url:
            print(f"roz-live: or open {url}", flush=True)
        if args.teleop:
            print(f"roz-live: teleop to {args.teleop}, from "
                  f"{'every viewer' if args.teleop_remote else 'viewers on this machine'}; "
                  f"a Joy mapped by {joy_map.decode() or 'the gamepad layout'}", flush=True)
        while True:
            src = next_run(args.input) if fifo else sys.stdin.buffer
            try:
                ended = read_run(server, src, args)
            finally:
                if fifo:
                    src.close()
            print(f"roz-live: the run {ended}: {server.messages} messages served", flush=True)
            if args.exit or not fifo:
                break
            print(f"roz-live: waiting for the next run on {args.input} (Ctrl-C stops)",
                  flush=True)
        while not args.exit:  # standard input: the viewer stays up
            time.sleep(0.5)
    except KeyboardInterrupt:
        pass
    finally:
        server.stop()
        if anchor is not None:
            os.close(anchor)
    return 0


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if argv and argv[0] == "layout":
        ap = argparse.ArgumentParser(prog="roz-live layout",
                                     description="write the Foxglove layout of a robot's run")
        ap.add_argument("recording", help="a recording of the robot (rozrun --record)")
        ap.add_argument("out", help="the layout JSON to write")
        ap.add_argument("--joints", type=int, default=LAYOUT_JOINTS,
                        help=f"joints to plot (default {LAYOUT_JOINTS})")
        a = ap.parse_args(argv[1:])
        try:
            pathlib.Path(a.out).write_text(layout(layout_of_recording(a.recording), a.joints))
        except (LiveError, McapError, OSError, KeyError) as e:
            print(f"roz-live: {e}", file=sys.stderr)
            return 1
        return 0
    ap = argparse.ArgumentParser(prog="roz-live", description=__doc__.split("\n\n")[0])
    ap.add_argument("input", help="the FIFO rozrun --live writes (made when missing), or -")
    ap.add_argument("--host", default="127.0.0.1",
                    help="address to bind (default 127.0.0.1; 0.0.0.0 for every interface)")
    ap.add_argument("--port", type=int, default=8765, help="port (default 8765; 0: any free)")
    ap.add_argument("--layout", help="write the run's Foxglove layout here")
    ap.add_argument("--exit", action="store_true", help="stop when the run ends")
    ap.add_argument("--teleop", metavar="SOCKET",
                    help="take Foxglove's Teleop panel (json geometry_msgs/msg/Twist) from "
                         "viewers on this machine to the run's rozrun --teleop SOCKET")
    ap.add_argument("--teleop-remote", action="store_true",
                    help="with --teleop: from viewers on other machines too (nothing is "
                         "authenticated)")
    ap.add_argument("--joy-map", metavar="MAP",
                    help="with --teleop: how the Joystick panel's axes and buttons make the "
                         "remote's fields, FIELD=aN|-aN|bN entries (roz/joy.h; default: the "
                         "panel's gamepad mode, the browser's standard layout, docs/live.md)")
    a = ap.parse_args(argv)
    if a.teleop_remote and not a.teleop:
        print("roz-live: --teleop-remote needs --teleop SOCKET", file=sys.stderr)
        return 2
    if a.joy_map is not None and not a.teleop:
        print("roz-live: --joy-map needs --teleop SOCKET", file=sys.stderr)
        return 2
    try:
        check_joy_map(a.joy_map) if a.joy_map is not None else None
    except LiveError as e:
        print(f"roz-live: {e}", file=sys.stderr)
        return 2
    if not 0 <= a.port <= 65535:
        print(f"roz-live: --port {a.port}: not a port (0..65535)", file=sys.stderr)
        return 2
    try:
        return serve(a)
    except (LiveError, OSError, RuntimeError) as e:
        print(f"roz-live: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
