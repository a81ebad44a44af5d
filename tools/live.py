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

The layout (--layout, or the `layout` command from any recording of the
robot) plots the first joints' targets, applied commands and state, the
latched faults, fuel and freshness, the safety filter's counters, and the
truth's base height when the run has one (docs/live.md).
"""
import argparse
import importlib.util
import json
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


class Gate:
    """The address viewers connect to, at most MAX_VIEWERS at a time, each
    relayed to the Foxglove server on a port of 127.0.0.1 of its own: the
    server has no cap of its own and holds about 190 KB per connection, idle
    ones too. A connection past the cap is closed at once."""

    def __init__(self, host, port, backend_port):
        self.backend = backend_port
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
                conn, _ = self.sock.accept()
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
            try:
                back = socket.create_connection(("127.0.0.1", self.backend))
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

    def __init__(self, host, port):
        import foxglove
        self.foxglove = foxglove
        self.server = foxglove.start_server(name="roz-live", host="127.0.0.1", port=0)
        self.gate = Gate(host, port, self.server.port)
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
    /roz/inputs."""
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
    server = Server(args.host, args.port)
    try:
        print(f"roz-live: serving ws://{args.host}:{server.port()} (Foxglove: open "
              f"connection, Foxglove WebSocket); reading {args.input}", flush=True)
        url = server.app_url()
        if url:
            print(f"roz-live: or open {url}", flush=True)
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
    a = ap.parse_args(argv)
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
