# SPDX-License-Identifier: Apache-2.0
"""Read a roz flight recording (MCAP, rozrun --record): check it, turn it into
rozrun's CSV trace, plot it, or plot two recordings side by side.

    python tools/recording.py check run.mcap
    python tools/recording.py csv run.mcap out.csv
    python tools/recording.py plot run.mcap out.png [--title TEXT]
    python tools/recording.py compare a.mcap b.mcap out.png [--title TEXT]
    python tools/recording.py truth run.mcap [out.csv]
    roz-recording ...                 (the same, installed with roz)

plot and compare take --channels REGEX (tools/plot_trace.py's).

The CSV has the columns of rozrun's --trace (tools/rozrun/trace.h): tick,
time_s, target:<command>..., applied:<command>..., state:<state>..., faults,
events; the plots are tools/plot_trace.py's. `check` reads every record with
the `mcap` readers, chunk and data-section CRCs checked, decodes every
message with mcap-ros2-support, checks the counts against the summary and
prints them; any problem exits non-zero. `truth` prints what a simulator's
/roz/truth says of the base (height, roll, pitch at the end and the worst
over the run; the bodies touching the ground) and writes it per tick as CSV.

Before the `mcap` readers see a file, every top-level record's length, and
every chunk's uncompressed size, is checked against MAX_RECORD (16 MiB, the
C reader's ROZ_MCAP_MAX_RECORD): a file claiming more is refused, naming the
offset, before anything is allocated for it (docs/recording-format.md).
"""
import argparse
import datetime
import importlib.util
import math
import pathlib
import sys
import zlib

from mcap.exceptions import McapError
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from zstandard import ZstdError as zstd_error

_here = pathlib.Path(__file__).resolve().parent
_spec = importlib.util.spec_from_file_location("plot_trace", _here / "plot_trace.py")
plot_trace = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(plot_trace)
_spec = importlib.util.spec_from_file_location("mcap_chunks", _here / "mcap_chunks.py")
mcap_chunks = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(mcap_chunks)
mcap_chunks.install()

# roz_record_flag (lib/include/roz/recorder.h)
FLAG_ESTOP_LEVEL = 1 << 4
FLAG_ESTOP_PRESS = 1 << 5
FLAG_CLEAR = 1 << 6
FLAG_SWAP = 1 << 7
# roz_fault_name(), with '-' for spaces, as rozrun's trace writes them
FAULT_NAMES = ["trap", "overrun", "stale-state", "e-stop", "controller-e-stop-request",
               "port-link", "robot-fault", "command-timeout", "fall"]


# /roz/truth's fields (roz_msgs/msg/Truth, docs/recording.md)
TRUTH_FIELDS = ("floating", "x", "y", "height", "qw", "qx", "qy", "qz", "roll", "pitch", "yaw",
                "contacts", "bodies")


# the largest record, and chunk once decompressed, read (roz/mcap.h)
MAX_RECORD = mcap_chunks.MAX_RECORD
MAGIC = b"\x89MCAP0\r\n"


class RecordingError(Exception):
    pass


def check_limits(path):
    """Every top-level record's length and every chunk's uncompressed size
    against MAX_RECORD, reading only record headers."""
    with open(path, "rb") as f:
        size = f.seek(0, 2)
        f.seek(0)
        if f.read(8) != MAGIC:
            raise RecordingError(f"{path}: at offset 0: not an MCAP file (no MCAP magic)")
        at = 8
        while size - at >= 9:
            f.seek(at)
            head = f.read(9 + 24)
            op, n = head[0], int.from_bytes(head[1:9], "little")
            if n > MAX_RECORD:
                raise RecordingError(f"{path}: at offset {at}: a record (opcode 0x{op:02x}) of {n} "
                                     f"bytes, past this reader's limit of {MAX_RECORD} bytes")
            if op == 0x06 and len(head) >= 33:
                usize = int.from_bytes(head[25:33], "little")
                if usize > MAX_RECORD:
                    raise RecordingError(f"{path}: at offset {at}: a chunk of {usize} bytes "
                                         f"uncompressed, past this reader's limit of "
                                         f"{MAX_RECORD} bytes")
            if op == 0x02:
                break
            at += 9 + n


def read(path):
    """The run's account and its ticks: (run, ticks, counts), ticks a list of
    dicts with tick, time_s, target, applied, state, faults, flags, message,
    and inputs (the operator's, as the controller read them) when the run has
    them."""
    try:
        return _read(path)
    except mcap_chunks.ChunkError as e:
        raise RecordingError(f"{path}: {e}") from None


def _read(path):
    run, ticks, counts, by_time = None, [], {}, {}
    check_limits(path)
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()], validate_crcs=True)
        summary = reader.get_summary()
        if summary is None or summary.statistics is None:
            raise RecordingError(f"{path}: no summary (the file is cut short?)")
        current = None
        for schema, channel, message, decoded in reader.iter_decoded_messages(log_time_order=False):
            counts[channel.topic] = counts.get(channel.topic, 0) + 1
            if channel.topic == "/roz/run":
                run = decoded
            elif channel.topic == "/roz/tick":
                current = {"tick": decoded.tick, "time_s": decoded.sim_time_ns / 1e9,
                           "faults": decoded.faults, "flags": decoded.flags, "message": None,
                           "fuel": decoded.fuel}
                ticks.append(current)
            elif channel.topic in ("/roz/state", "/roz/inputs", "/roz/target", "/roz/applied"):
                if current is None:
                    raise RecordingError(f"{path}: {channel.topic} before any /roz/tick")
                # the schema's fields, in manifest order (mcap_ros2 keeps it)
                values = [getattr(decoded, n) for n in type(decoded).__slots__]
                want = len(run.state_names if channel.topic == "/roz/state"
                           else input_names(run) if channel.topic == "/roz/inputs"
                           else run.command_names)
                if len(values) != want:
                    raise RecordingError(f"{path}: {channel.topic} has {len(values)} fields, "
                                         f"the run {want} channels")
                current[channel.topic[len("/roz/"):]] = values
            elif channel.topic == "/roz/fault" and current is not None:
                current["message"] = decoded.message
            elif channel.topic == "/roz/truth":
                if current is None:
                    raise RecordingError(f"{path}: /roz/truth before any /roz/tick")
                current["truth"] = {f: getattr(decoded, f) for f in TRUTH_FIELDS}
    if run is None:
        raise RecordingError(f"{path}: no /roz/run message: not a roz recording")
    stats = summary.statistics
    ids = {c.topic: i for i, c in summary.channels.items()}
    for topic, n in counts.items():
        if stats.channel_message_counts.get(ids[topic], 0) != n:
            raise RecordingError(f"{path}: {topic}: {n} messages read, the summary says "
                                 f"{stats.channel_message_counts.get(ids[topic], 0)}")
    if sum(counts.values()) != stats.message_count:
        raise RecordingError(f"{path}: {sum(counts.values())} messages read, the summary says "
                             f"{stats.message_count}")
    parts = ("state", "target", "applied") + (("inputs",) if input_names(run) else ())
    for t in ticks:
        for part in parts:
            if part not in t:
                raise RecordingError(f"{path}: tick {t['tick']} lacks /roz/{part}")
    _check_summary_crc(path)
    return run, ticks, counts


def input_names(run):
    """The run's operator inputs (/roz/run's input_names; none in files
    before /roz/inputs)."""
    return list(getattr(run, "input_names", None) or [])


def _check_summary_crc(path):
    """The footer's summary CRC, which the readers do not check (the
    summary read in pieces: a file may be large)."""
    with open(path, "rb") as f:
        size = f.seek(0, 2)
        f.seek(size - 8 - 29)
        footer = f.read(29)
        # 20 bytes; roz's files before it said 16 for the same 20 (its CRC too)
        if footer[0] != 0x02 or int.from_bytes(footer[1:9], "little") not in (16, 20):
            raise RecordingError(f"{path}: no footer record before the trailing magic")
        summary_start = int.from_bytes(footer[9:17], "little")
        crc = int.from_bytes(footer[25:29], "little")
        if not summary_start or not crc:
            return
        if summary_start > size - 8 - 4:
            raise RecordingError(f"{path}: the footer's summary start {summary_start} is past "
                                 "the footer")
        f.seek(summary_start)
        left, got = size - 8 - 4 - summary_start, 0
        while left > 0:
            piece = f.read(min(left, 1 << 20))
            got = zlib.crc32(piece, got)
            left -= len(piece)
        if got != crc:
            raise RecordingError(f"{path}: summary CRC mismatch")


def events(prev, t):
    """A tick's events, as rozrun's trace writes them (those a recording
    holds: e-stop press and release, swap, clear, faults latching and
    clearing), after the previous recorded tick @p prev (None: none)."""
    words = []
    prev_faults = prev["faults"] if prev else 0
    if t["flags"] & FLAG_ESTOP_PRESS:
        words.append("estop")
    if prev and prev["flags"] & FLAG_ESTOP_LEVEL and not t["flags"] & FLAG_ESTOP_LEVEL:
        words.append("estop-release")
    if t["flags"] & FLAG_SWAP and t["tick"] != 0:
        words.append("swap")
    if t["flags"] & FLAG_CLEAR:
        words.append("clear")
    for b, name in enumerate(FAULT_NAMES):
        bit = 1 << b
        if t["faults"] & bit and not prev_faults & bit:
            words.append(f"fault:{name}")
        elif prev_faults & bit and not t["faults"] & bit:
            words.append(f"cleared:{name}")
    return " ".join(words)


def table(run, ticks):
    """The trace's header and columns (plot_trace.read()'s shape)."""
    inputs = input_names(run)
    header = (["tick", "time_s"] + [f"target:{n}" for n in run.command_names]
              + [f"applied:{n}" for n in run.command_names]
              + [f"state:{n}" for n in run.state_names] + [f"input:{n}" for n in inputs]
              + ["faults", "events"])
    cols = {h: [] for h in header}
    prev = None
    for t in ticks:
        cols["tick"].append(float(t["tick"]))
        cols["time_s"].append(t["time_s"])
        for i, n in enumerate(run.command_names):
            cols[f"target:{n}"].append(t["target"][i])
            cols[f"applied:{n}"].append(t["applied"][i])
        for i, n in enumerate(run.state_names):
            cols[f"state:{n}"].append(t["state"][i])
        for i, n in enumerate(inputs):
            cols[f"input:{n}"].append(t["inputs"][i])
        cols["faults"].append(float(t["faults"]))
        cols["events"].append(events(prev, t))
        prev = t
    return header, cols


def truth_summary(run, ticks):
    """One line on the simulator's truth of a run: the base's height, roll
    and pitch at the last tick and the worst of the run, the contacts."""
    samples = [t["truth"] for t in ticks if "truth" in t]
    if not samples:
        raise RecordingError(f"{run.robot_id}: no /roz/truth messages (not a simulator's run)")
    last = samples[-1]
    bodies = ", ".join(last["bodies"]) or "none"
    if not last["floating"]:
        return (f"{run.robot_id}: fixed base; {len(samples)} truth samples; at the end "
                f"{last['contacts']} ground contacts ({bodies})")
    lowest = min(t["height"] for t in samples)
    tilt = max(max(abs(t["roll"]), abs(t["pitch"])) for t in samples)
    return (f"{run.robot_id}: {len(samples)} truth samples; at the end base height "
            f"{last['height']:.3f} m, roll {math.degrees(last['roll']):.1f} deg, pitch "
            f"{math.degrees(last['pitch']):.1f} deg, {last['contacts']} ground contacts "
            f"({bodies}); lowest {lowest:.3f} m, largest tilt {math.degrees(tilt):.1f} deg")


def write_truth_csv(ticks, out):
    with open(out, "w") as f:
        f.write("tick,time_s," + ",".join(TRUTH_FIELDS) + "\n")
        for t in ticks:
            if "truth" not in t:
                continue
            tr = t["truth"]
            row = [f"{t['tick']}", f"{t['time_s']:.6f}", f"{int(tr['floating'])}"]
            row += ["nan" if math.isnan(tr[k]) else f"{tr[k]:.9g}" for k in TRUTH_FIELDS[1:-2]]
            row += [f"{tr['contacts']}", " ".join(tr["bodies"])]
            f.write(",".join(row) + "\n")


def write_csv(header, cols, out):
    with open(out, "w") as f:
        f.write(",".join(header) + "\n")
        for i in range(len(cols["tick"])):
            row = [f"{cols['tick'][i]:.0f}", f"{cols['time_s'][i]:.6f}"]
            for h in header[2:-2]:
                v = cols[h][i]
                row.append("nan" if math.isnan(v) else f"{v:.9g}")
            row.append(f"{int(cols['faults'][i])}")
            row.append(cols["events"][i])
            f.write(",".join(row) + "\n")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    c = sub.add_parser("check")
    c.add_argument("mcap")
    c = sub.add_parser("csv")
    c.add_argument("mcap")
    c.add_argument("csv")
    plotting = argparse.ArgumentParser(add_help=False)  # the options of a plot
    plotting.add_argument("--title", default="")
    plotting.add_argument("--channels", metavar="REGEX", help="as plot_trace.py --channels")
    c = sub.add_parser("plot", parents=[plotting])
    c.add_argument("mcap")
    c.add_argument("png")
    c = sub.add_parser("compare", parents=[plotting])
    c.add_argument("a")
    c.add_argument("b")
    c.add_argument("png")
    c = sub.add_parser("truth")
    c.add_argument("mcap")
    c.add_argument("csv", nargs="?")
    a = ap.parse_args(argv)
    try:
        if a.cmd == "check":
            run, ticks, counts = read(a.mcap)
            start = getattr(run, "start_time_ns", 0)  # absent in older files
            when = (datetime.datetime.fromtimestamp(start / 1e9, datetime.timezone.utc)
                    .isoformat(timespec="seconds") if start else "no wall-clock start")
            print(f"{a.mcap}: {run.robot_id}, {len(ticks)} ticks from {when}, "
                  + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))
        elif a.cmd == "truth":
            run, ticks, _ = read(a.mcap)
            print(truth_summary(run, ticks))
            if a.csv:
                write_truth_csv(ticks, a.csv)
        elif a.cmd == "csv":
            write_csv(*table(*read(a.mcap)[:2]), a.csv)
        elif a.cmd == "plot":
            header, cols = table(*read(a.mcap)[:2])
            plot_trace.plot([(header, cols, "")], a.png, a.title,
                            plot_trace.channel_filter(a.channels, [header]))
        else:
            runs = []
            for path in (a.a, a.b):
                header, cols = table(*read(path)[:2])
                runs.append((header, cols, pathlib.Path(path).name))
            plot_trace.plot(runs, a.png, a.title,
                            plot_trace.channel_filter(a.channels, [r[0] for r in runs]))
    except RecordingError as e:
        sys.exit(f"recording: {e}")
    except (McapError, EOFError, ValueError, MemoryError, zstd_error, RuntimeError) as e:
        why = str(e) or type(e).__name__
        sys.exit(f"recording: {getattr(a, 'mcap', None) or a.a}: cannot be read: {why}")


if __name__ == "__main__":
    main()
