# SPDX-License-Identifier: Apache-2.0
"""Flight recordings end to end: rozrun --record on the loopback, every file
read back with the PyPI `mcap` and `mcap-ros2-support` readers (every record
decodes, chunk and data-section CRCs checked, counts against the summary),
rozrun --replay of every example controller identical bit for bit, faults
and interventions replayed, a deliberate divergence reported exactly (tick,
channel, both values), another controller compared and plotted, a file cut
short or corrupted named by offset. ROZRUN and CTL come from the build."""
import os
import pathlib
import re
import struct
import subprocess
import sys

import pytest
from mcap.reader import make_reader
from mcap.writer import CompressionType, Writer
from mcap_ros2.decoder import DecoderFactory

ROOT = pathlib.Path(__file__).resolve().parents[2]
ROZRUN = os.environ.get("ROZRUN", "")
CTL = pathlib.Path(os.environ.get("CTL", "."))
TOOL = ROOT / "tools" / "recording.py"

pytestmark = pytest.mark.skipif(not ROZRUN, reason="ROZRUN not set (run through ctest)")

sys.path.insert(0, str(ROOT / "tools"))
import recording  # noqa: E402

# every example controller, on the robots it is written for
CASES = [("ur5", c) for c in ("sine", "sine_wat", "constant_velocity", "constant_velocity_wat",
                              "hold", "pd_hold", "reach")]
CASES += [("quadcopter", "sine"), ("diff_drive", "constant_velocity"),
          ("unitree_g1", "g1_pd"), ("unitree_g1", "g1_stand"),
          ("engineai_pm01", "pm01_stand"), ("agibot_x2", "x2_stand")]


def rozrun(*args, ok=(0,)):
    p = subprocess.run([ROZRUN, *map(str, args)], capture_output=True, text=True, timeout=300)
    if p.returncode not in ok:
        pytest.fail(f"rozrun {' '.join(map(str, args))}: exit {p.returncode}\n{p.stdout}\n"
                    f"{p.stderr}")
    return p


def decode_all(path):
    """Every message decoded by mcap-ros2-support, CRCs checked; counts per
    topic, checked against the summary's statistics."""
    counts = {}
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()], validate_crcs=True)
        summary = reader.get_summary()
        for _, channel, _, decoded in reader.iter_decoded_messages(log_time_order=False):
            assert decoded is not None
            counts[channel.topic] = counts.get(channel.topic, 0) + 1
    assert summary.statistics.message_count == sum(counts.values())
    for cid, ch in summary.channels.items():
        assert summary.statistics.channel_message_counts.get(cid, 0) == counts.get(ch.topic, 0)
    assert len(summary.chunk_indexes) >= 1
    # the indexed reader (chunk indexes, message indexes) finds the same messages
    with open(path, "rb") as f:
        reader = make_reader(f, validate_crcs=True)
        indexed = sum(1 for _ in reader.iter_messages(log_time_order=True))
    assert indexed == sum(counts.values())
    recording._check_summary_crc(path)  # the footer's CRC of the summary
    return counts


def record(tmp_path, robot, ctl, ticks, *extra, name="run"):
    path = tmp_path / f"{name}.mcap"
    rozrun("--robot", robot, "--controller", CTL / f"{ctl}.wasm", "--ticks", ticks,
           "--record", path, *extra, ok=(0, 1))
    return path


@pytest.mark.parametrize("robot,ctl", CASES)
def test_record_replay_identical(tmp_path, robot, ctl):
    path = record(tmp_path, robot, ctl, 300)
    counts = decode_all(path)
    for topic in ("/roz/tick", "/roz/state", "/roz/target", "/roz/applied"):
        assert counts[topic] == 300
    assert counts["/roz/run"] == 1 and counts["/roz/controller"] == 1
    p = rozrun("--replay", path, "--controller", CTL / f"{ctl}.wasm")
    assert "ticks replayed         300\n" in p.stdout
    assert "result                 identical" in p.stdout
    assert "the recorded one" in p.stdout


def test_fields_named_after_channels(tmp_path):
    path = record(tmp_path, "ur5", "sine", 20)
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        msgs = {}
        for schema, channel, message, decoded in reader.iter_decoded_messages():
            msgs.setdefault(channel.topic, (schema, message, decoded))
    schema, message, state = msgs["/roz/state"]
    assert schema.name == "roz_ur5/msg/State" and schema.encoding == "ros2msg"
    assert state.shoulder_pan_joint_position == 0.0
    assert hasattr(state, "wrist_3_joint_velocity")
    assert msgs["/roz/applied"][0].name == "roz_ur5/msg/Commands"
    run = msgs["/roz/run"][2]
    assert run.robot_id == "ur5" and run.control_rate_hz == 100 and run.decimation == 1
    assert run.command_names[0] == "shoulder_pan_joint/velocity"
    tick = msgs["/roz/tick"][2]
    assert tick.fresh and tick.ran and tick.wrote and tick.fuel > 0
    # log time is simulated time: tick x 10 ms
    with open(path, "rb") as f:
        times = [m.log_time for _, c, m in make_reader(f).iter_messages(topics=["/roz/tick"])]
    assert times == [i * 10_000_000 for i in range(20)]


def test_faults_replayed(tmp_path):
    """E-stop pressed, released, cleared; frames dropped (stale), NaN state, a
    peer restart (link): recorded, read back, and replayed identically; the
    recording's CSV is rozrun's own trace, byte for byte."""
    trace = tmp_path / "trace.csv"
    args = ("--estop-at", 50, "--estop-release-at", 80, "--clear-at", 100,
            "--param", "drop=150:170", "--param", "nan=2@200:205", "--param", "restart=240:250",
            "--clear-at", 230, "--trace", trace)
    path = record(tmp_path, "ur5", "sine", 400, *args)
    counts = decode_all(path)
    assert counts["/roz/fault"] >= 4
    run, ticks, _ = recording.read(path)
    by = {t["tick"]: t for t in ticks}
    assert by[50]["faults"] & 8 and by[50]["message"] == "e-stop input"
    assert by[100]["faults"] == 0 and by[100]["message"] == ""
    assert any(t["faults"] & 4 for t in ticks)    # stale
    assert any(t["faults"] & 32 for t in ticks)   # link
    out = tmp_path / "from_recording.csv"
    recording.main(["csv", str(path), str(out)])
    assert out.read_bytes() == trace.read_bytes()
    p = rozrun("--replay", path, "--controller", CTL / "sine.wasm")
    assert "ticks replayed         400\n" in p.stdout
    assert "result                 identical" in p.stdout


def test_trap_and_rebuild_replayed(tmp_path):
    """The controller traps at its tick 150; the clear at 200 rebuilds it
    (a fresh instance from its tick 0): both replayed."""
    path = record(tmp_path, "ur5", "bad_trap_run", 300, "--clear-at", 200)
    _, ticks, _ = recording.read(path)
    by = {t["tick"]: t for t in ticks}
    assert by[150]["faults"] == 1
    assert by[150]["message"] == "trap at tick 150: [trap] unreachable executed"
    assert by[200]["faults"] == 0 and by[200]["flags"] & recording.FLAG_CLEAR
    assert by[200]["flags"] & recording.FLAG_SWAP     # the rebuilt instance
    assert by[299]["faults"] == 0
    p = rozrun("--replay", path, "--controller", CTL / "bad_trap_run.wasm")
    assert "ticks replayed         300\n" in p.stdout
    assert "result                 identical" in p.stdout


def rewrite(src, dst, patch):
    """Copies a recording with the Python writer (uncompressed), patch(topic,
    log_time, data) -> data applied to every message."""
    with open(src, "rb") as f, open(dst, "wb") as out:
        reader = make_reader(f)
        summary = reader.get_summary()
        w = Writer(out, compression=CompressionType.NONE)
        w.start(profile="ros2", library="test")
        for sid, s in sorted(summary.schemas.items()):
            assert w.register_schema(s.name, s.encoding, s.data) == sid
        for cid, c in sorted(summary.channels.items()):
            assert w.register_channel(c.topic, c.message_encoding, c.schema_id) == cid
        for _, channel, m in reader.iter_messages(log_time_order=False):
            w.add_message(m.channel_id, m.log_time, patch(channel.topic, m.log_time, m.data),
                          m.publish_time, m.sequence)
        w.finish()


def test_divergence_reported_exactly(tmp_path):
    """One applied command changed in the recording: replay names that tick,
    that channel and both values, and exits 4."""
    path = record(tmp_path, "ur5", "sine", 300)
    _, ticks, _ = recording.read(path)
    original = ticks[123]["applied"][2]
    bad = tmp_path / "bad.mcap"

    def patch(topic, log_time, data):
        if topic == "/roz/applied" and log_time == 123 * 10_000_000:
            return data[:4 + 8 * 2] + struct.pack("<d", 0.25) + data[4 + 8 * 3:]
        return data

    rewrite(path, bad, patch)
    decode_all(bad)
    p = rozrun("--replay", bad, "--controller", CTL / "sine.wasm", ok=(4,))
    m = re.search(r"DIVERGED at tick (\d+) \(file offset (\d+)\): applied (\S+) \(command 2\): "
                  r"recorded (\S+) \(([0-9a-f]{16})\), replayed (\S+) \(([0-9a-f]{16})\)",
                  p.stdout)
    assert m, p.stdout
    assert int(m.group(1)) == 123
    assert m.group(3) == "elbow_joint/velocity"
    assert float(m.group(4)) == 0.25 and m.group(5) == "3fd0000000000000"
    assert float(m.group(6)) == original
    assert m.group(7) == struct.pack(">d", original).hex()
    # the Python writer's copy of the unpatched file replays identically
    same = tmp_path / "same.mcap"
    rewrite(path, same, lambda t, lt, d: d)
    assert "identical" in rozrun("--replay", same, "--controller", CTL / "sine.wasm").stdout


def test_another_controller(tmp_path):
    """Another controller on the recorded states: runs through, counts the
    ticks that differ, keeps a new recording and trace; the tool plots both
    side by side."""
    path = record(tmp_path, "ur5", "sine", 200)
    new, trace = tmp_path / "new.mcap", tmp_path / "new.csv"
    p = rozrun("--replay", path, "--controller", CTL / "constant_velocity.wasm",
               "--record", new, "--trace", trace)
    assert "another one than the recorded" in p.stdout
    assert "ticks replayed         200\n" in p.stdout
    assert re.search(r"\d+ of 200 ticks differ from the recording, the first at tick 0", p.stdout)
    counts = decode_all(new)
    assert counts["/roz/tick"] == 200
    png = tmp_path / "compare.png"
    recording.main(["compare", str(path), str(new), str(png)])
    assert png.stat().st_size > 10000
    png1 = tmp_path / "one.png"
    recording.main(["plot", str(new), str(png1)])
    assert png1.stat().st_size > 10000
    out = tmp_path / "new_from_recording.csv"
    recording.main(["csv", str(new), str(out)])
    # the replay's trace and its recording agree (the trace has no events)
    strip = lambda text: [",".join(r.split(",")[:-1]) for r in text.splitlines()]  # noqa: E731
    assert strip(out.read_text()) == strip(trace.read_text())


def test_cut_short_and_corrupt(tmp_path):
    path = record(tmp_path, "ur5", "sine", 3000)
    data = path.read_bytes()
    # cut short (a writer that died): replayed up to there, and said where
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[: len(data) // 2])
    p = rozrun("--replay", cut, "--controller", CTL / "sine.wasm")
    assert re.search(r"cut short at offset \d+", p.stderr), p.stderr
    replayed = int(re.search(r"ticks replayed\s+(\d+)", p.stdout).group(1))
    assert 0 < replayed < 3000
    assert "identical" in p.stdout
    with pytest.raises(SystemExit):
        recording.main(["check", str(cut)])
    # one byte flipped inside the first chunk: its CRC names the chunk's offset
    header_len = struct.unpack_from("<Q", data, 9)[0]
    chunk_at = 8 + 9 + header_len
    assert data[chunk_at] == 0x06
    bad = bytearray(data)
    bad[chunk_at + 2000] ^= 0x40
    corrupt = tmp_path / "corrupt.mcap"
    corrupt.write_bytes(bytes(bad))
    p = rozrun("--replay", corrupt, "--controller", CTL / "sine.wasm", ok=(2,))
    assert f"at offset {chunk_at}: chunk CRC mismatch" in p.stderr, p.stderr
    # not MCAP at all
    junk = tmp_path / "junk.mcap"
    junk.write_bytes(b"not a recording")
    p = rozrun("--replay", junk, "--controller", CTL / "sine.wasm", ok=(2,))
    assert "at offset 0: not an MCAP file" in p.stderr


def test_replay_refuses(tmp_path):
    path = record(tmp_path, "ur5", "sine", 20)
    p = rozrun("--replay", path, "--robot", "quadcopter", "--controller", CTL / "sine.wasm",
               ok=(2,))
    assert 'records robot "ur5"' in p.stderr and '--robot is "quadcopter"' in p.stderr


def test_record_every(tmp_path):
    """--record-every 10: every 10th tick, and the ticks of an e-stop press
    and of a clear; such a recording is read back, but not replayed."""
    path = record(tmp_path, "ur5", "sine", 100, "--record-every", 10, "--estop-at", 55,
                  "--estop-release-at", 62, "--clear-at", 73)
    decode_all(path)
    run, ticks, _ = recording.read(path)
    assert run.decimation == 10
    assert [t["tick"] for t in ticks] == [0, 10, 20, 30, 40, 50, 55, 60, 62, 70, 73, 80, 90]
    assert recording.events(ticks[7], ticks[8]) == "estop-release"
    assert ticks[6]["faults"] == 8 and ticks[6]["message"] == "e-stop input"
    assert ticks[10]["faults"] == 0
    p = rozrun("--replay", path, "--controller", CTL / "sine.wasm", ok=(2,))
    assert "recorded every 10 ticks: replay needs every tick" in p.stderr
