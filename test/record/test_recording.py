# SPDX-License-Identifier: Apache-2.0
"""Flight recordings end to end: rozrun --record on the loopback, every file
read back with the PyPI `mcap` and `mcap-ros2-support` readers (every record
decodes, chunk and data-section CRCs checked, counts against the summary),
rozrun --replay of every example controller identical bit for bit, faults
and interventions replayed, a deliberate divergence reported exactly (tick,
channel, both values), another controller compared and plotted, a file cut
short or corrupted named by offset, a mujoco G1's /roz/truth against the
summary. ROZRUN and CTL come from the build."""
import math
import os
import pathlib
import re
import resource
import struct
import subprocess
import sys
import time

import pytest
from mcap.reader import make_reader
from mcap.writer import CompressionType, Writer
from mcap_ros2.decoder import DecoderFactory

ROOT = pathlib.Path(__file__).resolve().parents[2]
ROZRUN = os.environ.get("ROZRUN", "")
CTL = pathlib.Path(os.environ.get("CTL", "."))
TOOL = ROOT / "tools" / "recording.py"
# the strict checker (test/record/mcap_strict), "" when the build has no cargo
STRICT = os.environ.get("MCAP_STRICT", "")
# "1" when the build has the mujoco port (a simulator with /roz/truth)
MUJOCO = os.environ.get("ROZ_MUJOCO", "0") == "1"

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


def strict(*paths, cut=False):
    """The mcap crate's strict reader and roz-mcap-strict's checks of its
    indexes, statistics, footer and chunk times; its report (None without
    the checker)."""
    if not STRICT:
        return None
    p = subprocess.run([STRICT, *(["--cut"] if cut else []), *map(str, paths)],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stdout + p.stderr
    return p.stdout


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
    strict(path)
    return counts


def record(tmp_path, robot, ctl, ticks, *extra, name="run"):
    path = tmp_path / f"{name}.mcap"
    rozrun("--robot", robot, "--controller", CTL / f"{ctl}.wasm", "--ticks", ticks,
           "--record", path, *extra, ok=(0, 1))
    return path


def assert_csv_and_replay(tmp_path, path, trace, ctl, ticks):
    """The recording at @p path: its CSV is rozrun's @p trace byte for byte,
    and its @p ticks replay on @p ctl identically."""
    out = tmp_path / "from_recording.csv"
    recording.main(["csv", str(path), str(out)])
    assert out.read_bytes() == trace.read_bytes()
    p = rozrun("--replay", path, "--controller", CTL / ctl)
    assert f"ticks replayed         {ticks}\n" in p.stdout
    assert "result                 identical" in p.stdout


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
    # log time: the run's wall-clock start plus simulated time (tick x 10 ms)
    with open(path, "rb") as f:
        times = [m.log_time for _, c, m in make_reader(f).iter_messages(topics=["/roz/tick"])]
    assert times == [run.start_time_ns + i * 10_000_000 for i in range(20)]


def test_tick_counts_are_the_summarys(tmp_path):
    """/roz/tick carries the safety filter's counters after each tick: they
    never go down, and the last tick's are rozrun's summary (clamps, rate
    caps, limit stops, refused non-finite values)."""
    path = tmp_path / "run.mcap"
    p = rozrun("--robot", "ur5", "--port", "loopback", "--ticks", 1000, "--controller",
               CTL / "constant_velocity.wasm", "--record", path)
    want = {k: int(re.search(rf"^  {label} +(\d+)", p.stdout, re.M).group(1))
            for k, label in (("clamps", "clamps"), ("rate_caps", "rate caps"),
                             ("limit_stops", "limit stops"), ("nonfinite", "refused values"))}
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        ticks = [d for _, _, _, d in reader.iter_decoded_messages(topics=["/roz/tick"])]
    assert len(ticks) == 1000
    for k in want:
        seq = [getattr(t, k) for t in ticks]
        assert seq == sorted(seq), k
        assert seq[-1] == want[k], (k, seq[-1], p.stdout)
    assert want["rate_caps"] > 0 and want["limit_stops"] > 0  # a joint driven to its limit


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
    assert_csv_and_replay(tmp_path, path, trace, "sine.wasm", 400)


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


def rewrite(src, dst, patch, compression=CompressionType.NONE):
    """Copies a recording with the Python writer (uncompressed unless
    @p compression), patch(topic, log_time, data) -> data applied to every
    message (None: left out)."""
    with open(src, "rb") as f, open(dst, "wb") as out:
        reader = make_reader(f)
        summary = reader.get_summary()
        w = Writer(out, compression=compression)
        w.start(profile="ros2", library="test")
        for sid, s in sorted(summary.schemas.items()):
            assert w.register_schema(s.name, s.encoding, s.data) == sid
        for cid, c in sorted(summary.channels.items()):
            assert w.register_channel(c.topic, c.message_encoding, c.schema_id) == cid
        for _, channel, m in reader.iter_messages(log_time_order=False):
            data = patch(channel.topic, m.log_time, m.data)
            if data is not None:
                w.add_message(m.channel_id, m.log_time, data, m.publish_time, m.sequence)
        w.finish()


def test_replay_reads_ticks_without_the_counters(tmp_path):
    """A recording from before /roz/tick carried the filter's counters (its
    ticks end after `wrote`) still replays, identical."""
    path = record(tmp_path, "ur5", "sine", 200)
    old = tmp_path / "old.mcap"

    def cut(topic, _t, data):
        if topic != "/roz/tick":
            return data
        # 4 header bytes, 8 u64, 4 u32, 3 bools; then 5 bytes of padding and
        # the 4 counters (u64)
        assert len(data) == 4 + 64 + 16 + 3 + 5 + 32
        return data[:4 + 64 + 16 + 3]

    rewrite(path, old, cut)
    p = rozrun("--replay", old, "--controller", CTL / "sine.wasm")
    assert "ticks replayed         200\n" in p.stdout
    assert "result                 identical" in p.stdout


def test_divergence_reported_exactly(tmp_path):
    """One applied command changed in the recording: replay names that tick,
    that channel and both values, and exits 4."""
    path = record(tmp_path, "ur5", "sine", 300)
    run, ticks, _ = recording.read(path)
    original = ticks[123]["applied"][2]
    bad = tmp_path / "bad.mcap"

    def patch(topic, log_time, data):
        if topic == "/roz/applied" and log_time == run.start_time_ns + 123 * 10_000_000:
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
    # --channels picks channels in plot and compare, as in plot_trace.py
    fig = recording.plot_trace.figure(
        [(*recording.table(*recording.read(new)[:2]), "")],
        pattern=recording.plot_trace.channel_filter("elbow", [recording.table(
            *recording.read(new)[:2])[0]]))
    assert sorted(line.get_label() for ax in fig.axes for line in ax.lines
                  if not line.get_label().startswith("_")) == \
        ["elbow_joint/position", "elbow_joint/velocity"]
    recording.plot_trace.plt.close(fig)
    png2 = tmp_path / "elbow.png"
    recording.main(["compare", str(path), str(new), str(png2), "--channels", "elbow"])
    assert png2.stat().st_size > 10000
    with pytest.raises(SystemExit, match="matches no channel"):
        recording.main(["plot", str(new), str(png2), "--channels", "no_such_joint"])
    out = tmp_path / "new_from_recording.csv"
    recording.main(["csv", str(new), str(out)])
    # the replay's trace and its recording agree (the trace has no events)
    strip = lambda text: [",".join(r.split(",")[:-1]) for r in text.splitlines()]  # noqa: E731
    assert strip(out.read_text()) == strip(trace.read_text())


def test_cut_short_and_corrupt(tmp_path):
    path = record(tmp_path, "ur5", "sine", 3000, "--record-compress", "none")
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
    strict(cut, cut=True)  # every complete chunk before the cut
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


def test_operator_inputs_replayed(tmp_path):
    """A run driven by a scripted operator records the inputs the controller
    read (/roz/inputs, every tick) and replays bit for bit: the 12-joint
    G1's deployed policy reads its velocity command from them. The same
    file with /roz/inputs put back to the inputs' defaults (what a replay
    without them feeds) diverges: the inputs are what makes it identical."""
    script = tmp_path / "operator.csv"
    script.write_text("time_s,operator/velocity.x,operator/yaw_rate\n"
                      "0,0.5,0\n0.4,0,0.5\n0.8,0,0\n")
    path, trace = tmp_path / "op.mcap", tmp_path / "op.csv"
    rozrun("--robot", "unitree_g1_12dof", "--controller", CTL / "g1_12dof_deployed.wasm",
           "--ticks", 600, "--operator", script, "--record", path, "--trace", trace)
    counts = decode_all(path)
    assert counts["/roz/inputs"] == 600 and counts["/roz/tick"] == 600
    run, ticks, _ = recording.read(path)
    assert recording.input_names(run) == ["operator/velocity.x", "operator/velocity.y",
                                          "operator/yaw_rate"]
    vx = [t["inputs"][0] for t in ticks]
    yaw = [t["inputs"][2] for t in ticks]
    # at the inputs' rate caps: 0.002 m/s and 0.004 rad/s a tick
    assert vx[0] == 0.002 and abs(max(vx) - 0.4) < 1e-9 and vx[599] == 0.0
    assert max(yaw) == 0.5 and yaw[599] == 0.0
    # the recording's CSV is rozrun's trace, its input columns too
    assert_csv_and_replay(tmp_path, path, trace, "g1_12dof_deployed.wasm", 600)
    # /roz/inputs at the defaults: the policy's command is not the recorded one
    defaults = tmp_path / "defaults.mcap"
    rewrite(path, defaults,
            lambda topic, _t, data: data[:4] + bytes(len(data) - 4) if topic == "/roz/inputs"
            else data)
    p = rozrun("--replay", defaults, "--controller", CTL / "g1_12dof_deployed.wasm", ok=(4,))
    m = re.search(r"DIVERGED at tick (\d+) \(file offset \d+\): target (\S+)", p.stdout)
    assert m, p.stdout
    assert int(m.group(1)) < 20  # the first inferences after the command moved
    # a file without /roz/inputs for a robot with inputs is refused, naming it
    cut = tmp_path / "cut.mcap"
    rewrite(path, cut, lambda topic, _t, data: None if topic == "/roz/inputs" else data)
    p = rozrun("--replay", cut, "--controller", CTL / "g1_12dof_deployed.wasm", ok=(2,))
    assert "tick 0 lacks its /roz/inputs message" in p.stderr, p.stderr
    # a recording from before /roz/inputs (/roz/run ends at start_time_ns)
    # input_names: a u32 count, then each name a u32 length, its bytes and a NUL,
    # padded to 4 before the next length (CDR)
    names = [b"operator/velocity.x", b"operator/velocity.y", b"operator/yaw_rate"]
    tail = 4 + sum(4 + len(n) + 1 for n in names)
    tail += sum((4 - (len(n) + 1) % 4) % 4 for n in names[:-1])
    old = tmp_path / "old.mcap"
    rewrite(path, old, lambda topic, _t, data: data[:-tail] if topic == "/roz/run"
            else None if topic == "/roz/inputs" else data)
    p = rozrun("--replay", old, "--controller", CTL / "g1_12dof_deployed.wasm", ok=(2,))
    assert ('records 0 operator inputs; robot "unitree_g1_12dof" has 3 (a recording from '
            'before /roz/inputs cannot replay a robot with inputs)') in p.stderr, p.stderr


def g1_buttons(tmp_path):
    """The 12-joint G1 with the remote's Start, A, B and Select as inputs of 0
    or 1 (test/run_rozrun_deploy.cmake's), a deploy file naming them."""
    robot = (ROOT / "manifests" / "unitree_g1_12dof.toml").read_text()
    for b in ("start", "a", "b", "select"):
        robot += (f'\n[[manifest.inputs]]\nname = "remote/{b}"\ninterface_type = "position"\n'
                  'unit = ""\nlimits = [0.0, 1.0]\ndefault = 0.0\nmax_rate_of_change = 1.0\n'
                  "stale_after_ms = 500\n")
    toml = tmp_path / "g1_buttons.toml"
    toml.write_text(robot)
    deploy = tmp_path / "deploy.toml"
    deploy.write_text('[deploy]\nmove_s = 1.0\n[deploy.inputs]\nstart = "remote/start"\n'
                      'run = "remote/a"\nstand = "remote/b"\nstop = "remote/select"\n'
                      "[deploy.stand]\npose = [-0.1, 0, 0, 0.3, -0.2, 0, -0.1, 0, 0, 0.3, -0.2, 0]\n"
                      "kp = [100, 100, 100, 150, 40, 40, 100, 100, 100, 150, 40, 40]\n"
                      "kd = [2, 2, 2, 4, 2, 2, 2, 2, 2, 4, 2, 2]\n")
    return toml, deploy


def test_deploy_sequence_replayed(tmp_path):
    """A deploy-sequence run (rozrun --deploy) switched by the remote's
    buttons (a scripted operator) and by rozrun's stage requests records its
    sequence once (/roz/deploy) and every stage change and request taken
    (/roz/stage), and replays bit for bit: the buttons' changes from
    /roz/inputs, the requests at their ticks. Without the requests, or the
    sequence, the same file diverges; --deploy with another sequence runs
    through and counts the ticks that differ."""
    robot, deploy = g1_buttons(tmp_path)
    script = tmp_path / "buttons.csv"
    # Start at 0.2 s, A at 1.6 s (the move took 1 s), B at 2.4 s (back to the
    # stand), Select at 3.9 s; rozrun asks for run at tick 1800 (the stand
    # held since about tick 1700) and for zero at 1900 (refused: not from run)
    script.write_text("time_s,remote/start,remote/a,remote/b,remote/select\n0,0,0,0,0\n"
                      "0.2,1,0,0,0\n0.3,0,0,0,0\n1.6,0,1,0,0\n1.7,0,0,0,0\n2.4,0,0,1,0\n"
                      "2.5,0,0,0,0\n3.9,0,0,0,1\n")
    ctl = CTL / "g1_12dof_deployed.wasm"
    path = tmp_path / "deploy.mcap"
    p = rozrun("--robot", robot, "--allow-other-robot", "--controller", ctl, "--ticks", 2000,
               "--deploy", deploy, "--operator", script, "--stage-at", "1800:run",
               "--stage-at", "1900:zero", "--record", path)
    assert ("stage stop at the end; 7 stage changes, 1 requests refused; hand-overs 2"
            in p.stdout), p.stdout
    counts = decode_all(path)
    assert counts["/roz/deploy"] == 1 and counts["/roz/stage"] == 8
    stages, deploys, start = [], [], None
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        for _, ch, m, d in reader.iter_decoded_messages(
                topics=["/roz/run", "/roz/stage", "/roz/deploy"], log_time_order=False):
            if ch.topic == "/roz/run":
                start = m.log_time  # the run's tick 0 (a tick is 2 ms)
            elif ch.topic == "/roz/deploy":
                deploys.append(d)
            else:
                stages.append(((m.log_time - start) // 2000000, d.name, d.request_name))
    d = deploys[0]
    assert d.move_s == 1.0 and d.stop_damping == 8.0 and len(d.stand) == 60
    assert (d.start_input, d.run_input, d.stand_input, d.stop_input) == (3, 4, 5, 6)
    assert list(d.stand[:12]) == [-0.1, 0, 0, 0.3, -0.2, 0] * 2 and d.stand[27] == 150
    names = [(n, r) for _, n, r in stages]
    assert names == [("move", ""), ("hold", ""), ("run", ""), ("move", ""), ("hold", ""),
                     ("run", "run"), ("run", "zero"), ("stop", "")], stages
    assert [t for t, _, r in stages if r] == [1800, 1900]

    p = rozrun("--replay", path, "--robot", robot, "--controller", ctl)
    assert "ticks replayed         2000\n" in p.stdout
    assert "deploy                 the recorded sequence; stage stop at the end" in p.stdout
    assert "result                 identical" in p.stdout, p.stdout
    p = rozrun("--replay", path, "--robot", robot, "--controller", ctl, "--deploy", deploy)
    assert "the recorded sequence (--deploy: the same)" in p.stdout
    assert "result                 identical" in p.stdout, p.stdout

    # the requests left out: the stand is held where run was asked for
    def no_request(topic, _t, data):
        if topic != "/roz/stage":
            return data
        n = struct.unpack_from("<I", data, 8)[0]  # the name's length, after the stage
        return data[:12 + n] + b"\xff" + data[13 + n:]
    norequest = tmp_path / "norequest.mcap"
    rewrite(path, norequest, no_request)
    p = rozrun("--replay", norequest, "--robot", robot, "--controller", ctl, ok=(4,))
    assert ("DIVERGED at tick 1800 (file offset" in p.stdout and
            "deploy stage: recorded run, replayed hold" in p.stdout), p.stdout
    # the sequence left out: the controller drives from tick 0
    noseq = tmp_path / "noseq.mcap"
    rewrite(path, noseq, lambda topic, _t, data: None if topic == "/roz/deploy" else data)
    p = rozrun("--replay", noseq, "--robot", robot, "--controller", ctl, ok=(4,))
    assert "DIVERGED at tick 0 " in p.stdout, p.stdout
    # a stage change without its /roz/stage message
    cut = tmp_path / "nostage.mcap"
    rewrite(path, cut, lambda topic, _t, data: None if topic == "/roz/stage" else data)
    p = rozrun("--replay", cut, "--robot", robot, "--controller", ctl, ok=(2,))
    assert re.search(r"tick \d+ lacks its /roz/stage message", p.stderr), p.stderr
    # another sequence on the recorded run: every tick replayed, the differences counted
    slow = tmp_path / "slow.toml"
    slow.write_text(deploy.read_text().replace("move_s = 1.0", "move_s = 1.5"))
    p = rozrun("--replay", path, "--robot", robot, "--controller", ctl, "--deploy", slow)
    assert "--deploy's, another than the recorded" in p.stdout
    assert "ticks replayed         2000\n" in p.stdout
    assert re.search(r"result +\d+ of 2000 ticks differ from the recording, the first at tick "
                     r"\d+: (target|applied) ", p.stdout), p.stdout
    # a replay takes the recorded requests, not new ones
    p = rozrun("--replay", path, "--robot", robot, "--controller", ctl, "--stage-at", "5:stop",
               ok=(2,))
    assert "--stage-at and --replay" in p.stderr


def test_deploy_trace_targets_are_the_recordings(tmp_path):
    """In a deploy-sequence run the trace's target columns and the
    recording's /roz/target say the same thing on every tick (both written
    with 9 significant digits): what drove the tick, the stage's commands
    while a stage drives (move, hold, stop) and the controller's targets
    while it runs."""
    robot, deploy = g1_buttons(tmp_path)
    script = tmp_path / "buttons.csv"
    script.write_text("time_s,remote/start,remote/a,remote/b,remote/select\n0,0,0,0,0\n"
                      "0.2,1,0,0,0\n0.3,0,0,0,0\n1.6,0,1,0,0\n1.7,0,0,0,0\n2.4,0,0,0,1\n")
    path, trace, csv = tmp_path / "run.mcap", tmp_path / "trace.csv", tmp_path / "rec.csv"
    p = rozrun("--robot", robot, "--allow-other-robot", "--controller",
               CTL / "g1_12dof_deployed.wasm", "--ticks", 1400, "--deploy", deploy,
               "--operator", script, "--record", path, "--trace", trace)
    assert "stage stop at the end; 4 stage changes" in p.stdout, p.stdout
    subprocess.run([sys.executable, TOOL, "csv", path, csv], check=True, timeout=120)

    def targets(f):
        lines = f.read_text().splitlines()
        header = lines[0].split(",")
        cols = [i for i, h in enumerate(header) if h.startswith("target:")]
        rows = [r.split(",") for r in lines[1:]]
        return [header[i] for i in cols], [[float(r[i]) for i in cols] for r in rows]

    names, traced = targets(trace)
    rec_names, recorded = targets(csv)
    assert names == rec_names and len(names) == 60
    assert len(traced) == len(recorded) == 1400
    stand_knee = names.index("target:left_knee_joint/position")
    # the move's last ticks reach the stand's pose (0.3): the stage's commands
    assert recorded[700][stand_knee] == pytest.approx(0.3, abs=1e-3)
    for t, (a, b) in enumerate(zip(traced, recorded)):
        same = [x == y or (math.isnan(x) and math.isnan(y)) for x, y in zip(a, b)]
        assert all(same), (f"tick {t}: {names[same.index(False)]}: trace "
                           f"{a[same.index(False)]!r}, recording {b[same.index(False)]!r}")


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


def footer_length(path):
    data = pathlib.Path(path).read_bytes()
    assert data[-8 - 29] == 0x02  # the footer, before the CRC and the magic
    return struct.unpack_from("<Q", data, len(data) - 8 - 29 + 1)[0]


def test_footer_is_the_specifications(tmp_path):
    """Summary start u64, summary offset start u64, summary CRC u32: the
    footer record says 20 bytes (mcap doctor refused 16)."""
    assert footer_length(record(tmp_path, "ur5", "sine", 20)) == 20


def test_log_times_from_the_wall_clock(tmp_path):
    """/roz/run carries the wall clock at tick 0; every log time is it plus
    simulated time, so viewers show the day of the run, not 1970; a replay's
    new recording keeps the recorded timeline."""
    before = time.time_ns()
    path = record(tmp_path, "ur5", "sine", 50)
    after = time.time_ns()
    run, _, _ = recording.read(path)
    assert before - 10**9 <= run.start_time_ns <= after + 10**9
    with open(path, "rb") as f:
        msgs = list(make_reader(f).iter_messages())
    assert min(m.log_time for _, _, m in msgs) == run.start_time_ns
    assert max(m.log_time for _, _, m in msgs) == run.start_time_ns + 49 * 10_000_000
    new = tmp_path / "replayed.mcap"
    p = rozrun("--replay", path, "--controller", CTL / "hold.wasm", "--record", new)
    when = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(run.start_time_ns // 10**9))
    assert f"  recorded at            {when}\n" in p.stdout
    assert recording.read(new)[0].start_time_ns == run.start_time_ns


@pytest.mark.parametrize("robot,ctl,extra", [("agibot_x2", "x2_stand", ()),
                                             ("quadcopter", "sine", ()),
                                             ("agibot_x2", "x2_stand", ("--record-compress",
                                                                        "none"))])
def test_a_tick_in_one_chunk(tmp_path, robot, ctl, extra):
    """Chunks close between ticks: no two chunks overlap in log time (a chunk
    closed inside a tick left the rest of it to the next one)."""
    path = record(tmp_path, robot, ctl, 1000, *extra)
    with open(path, "rb") as f:
        chunks = sorted(make_reader(f).get_summary().chunk_indexes,
                        key=lambda c: c.message_start_time)
    assert len(chunks) >= 3
    for a, b in zip(chunks, chunks[1:]):
        assert b.message_start_time > a.message_end_time, (a, b)
    decode_all(path)


def test_compressed_chunks(tmp_path):
    """zstd chunks by default (the drain compresses, never the tick): the
    PyPI readers decode them, replay reads them, and they are a fraction of
    the uncompressed file."""
    z = record(tmp_path, "unitree_g1", "g1_pd", 300, name="z")
    n = record(tmp_path, "unitree_g1", "g1_pd", 300, "--record-compress", "none", name="n")
    with open(z, "rb") as f:
        assert {c.compression for c in make_reader(f).get_summary().chunk_indexes} == {"zstd"}
    with open(n, "rb") as f:
        assert {c.compression for c in make_reader(f).get_summary().chunk_indexes} == {""}
    assert decode_all(z) == decode_all(n)
    assert z.stat().st_size * 2 < n.stat().st_size
    p = rozrun("--replay", z, "--controller", CTL / "g1_pd.wasm")
    assert "result                 identical" in p.stdout
    # a flipped byte inside the first compressed chunk: refused at its offset
    data = bytearray(z.read_bytes())
    chunk_at = 8 + 9 + struct.unpack_from("<Q", data, 9)[0]
    data[chunk_at + 500] ^= 0x10
    bad = tmp_path / "z_bad.mcap"
    bad.write_bytes(bytes(data))
    p = rozrun("--replay", bad, "--controller", CTL / "g1_pd.wasm", ok=(2,))
    assert f"at offset {chunk_at}: " in p.stderr, p.stderr
    p = rozrun("--robot", "ur5", "--controller", CTL / "sine.wasm", "--record", "x.mcap",
               "--record-compress", "lz4", ok=(2,))
    assert '--record-compress "lz4": zstd or none' in p.stderr


@pytest.mark.skipif(not STRICT, reason="no strict MCAP checker in this build (cargo)")
def test_strict_reader_every_kind(tmp_path):
    """Every kind of file roz writes, through the strict reader: UR5 and G1,
    compressed or not, faults, decimated, a replay's new run, and files cut
    short (a writer that died) read up to their last complete chunk."""
    files = [record(tmp_path, "ur5", "sine", 3000, name="ur5"),
             record(tmp_path, "ur5", "sine", 3000, "--record-compress", "none", name="ur5n"),
             record(tmp_path, "unitree_g1", "g1_pd", 600, name="g1"),
             record(tmp_path, "unitree_g1", "g1_pd", 600, "--record-compress", "none",
                    name="g1n"),
             record(tmp_path, "ur5", "sine", 400, "--estop-at", 50, "--estop-release-at", 80,
                    "--clear-at", 100, "--param", "drop=150:170", "--param", "nan=2@200:205",
                    "--param", "restart=240:250", "--clear-at", 230, name="faults"),
             record(tmp_path, "ur5", "bad_trap_run", 300, "--clear-at", 200, name="trap"),
             record(tmp_path, "ur5", "sine", 1000, "--record-every", 10, "--estop-at", 55,
                    name="decimated")]
    new = tmp_path / "new.mcap"
    rozrun("--replay", files[0], "--controller", CTL / "constant_velocity.wasm", "--record", new)
    files.append(new)
    out = strict(*files)
    assert out.count(": ok: ") == len(files), out
    assert re.search(r'g1.mcap: ok: \d+ messages in \d\d+ chunks \(compression \["zstd"\]\)', out)
    cuts = []
    for f in (files[0], files[3]):
        data = f.read_bytes()
        for frac in (0.3, 0.77):
            cut = tmp_path / f"{f.stem}_cut{frac}.mcap"
            cut.write_bytes(data[: int(len(data) * frac)])
            cuts.append(cut)
    assert strict(*cuts, cut=True).count(": ok: ") == len(cuts)


def limit(gib):
    """A child's address space, for the tests of the readers' limits."""
    def set_limit():
        resource.setrlimit(resource.RLIMIT_AS, (gib << 30, gib << 30))
    return set_limit


def bomb(tmp_path, src):
    """@p src copied by the Python writer with zstd chunks whose frames do not
    state their size, then the first chunk made to claim 4 GiB of records."""
    import mcap.writer
    import zstandard

    class NoSize:
        @staticmethod
        def compress(data):
            return zstandard.ZstdCompressor(write_content_size=False).compress(data)

    out = tmp_path / "bomb.mcap"
    real = mcap.writer.zstandard
    mcap.writer.zstandard = NoSize
    try:
        rewrite(src, out, lambda topic, log_time, data: data, CompressionType.ZSTD)
    finally:
        mcap.writer.zstandard = real
    data = bytearray(out.read_bytes())
    with open(out, "rb") as f:
        at = make_reader(f).get_summary().chunk_indexes[0].chunk_start_offset
    assert data[at] == 0x06
    struct.pack_into("<Q", data, at + 9 + 16, 4 << 30)  # uncompressed_size
    out.write_bytes(bytes(data))
    return out, at


def test_readers_refuse_records_past_their_limit(tmp_path):
    """A 4 GiB chunk claim and a 5 GiB record: refused by tools/recording.py
    and by rozrun's reader before they allocate, naming the offset, under a
    2 GiB address space (the claim once grew the tool to 4.26 GB)."""
    src = record(tmp_path, "ur5", "sine", 100)
    path, at = bomb(tmp_path, src)
    p = subprocess.run([sys.executable, TOOL, "check", path], capture_output=True, text=True,
                       timeout=120, preexec_fn=limit(2))
    assert p.returncode != 0
    assert (f"at offset {at}: a chunk of {4 << 30} bytes uncompressed, past this reader's limit "
            f"of {16 << 20} bytes") in p.stderr, p.stderr
    assert "Traceback" not in p.stderr
    p = subprocess.run([ROZRUN, "--replay", path, "--controller", CTL / "sine.wasm"],
                       capture_output=True, text=True, timeout=120, preexec_fn=limit(2))
    assert p.returncode == 2
    assert f"at offset {at}: a chunk of {4 << 30} bytes uncompressed" in p.stderr, p.stderr
    # a record claiming 5 GiB in a (sparse) file that long
    data = bytearray(src.read_bytes())
    header_len = struct.unpack_from("<Q", data, 9)[0]
    chunk_at = 8 + 9 + header_len
    struct.pack_into("<Q", data, chunk_at + 1, 5 << 30)
    big = tmp_path / "big.mcap"
    with open(big, "wb") as f:
        f.write(data)
        f.truncate(chunk_at + 9 + (5 << 30) + 1024)
    p = subprocess.run([ROZRUN, "--replay", big, "--controller", CTL / "sine.wasm"],
                       capture_output=True, text=True, timeout=120, preexec_fn=limit(2))
    assert p.returncode == 2
    assert (f"at offset {chunk_at}: a record (opcode 0x06) of {5 << 30} bytes, past this "
            "reader's limit") in p.stderr, p.stderr
    p = subprocess.run([sys.executable, TOOL, "check", big], capture_output=True, text=True,
                       timeout=120, preexec_fn=limit(2))
    assert f"at offset {chunk_at}: a record (opcode 0x06) of {5 << 30} bytes" in p.stderr


@pytest.mark.skipif(not MUJOCO, reason="this build has no mujoco port")
def test_mujoco_truth_tells_standing_from_fallen(tmp_path):
    """The G1 on g1_stand_pd (the stand without its balance) stands for about
    1.5 s, then falls (docs/ports/mujoco.md): the recording alone says which, tick by tick,
    and its heights are the summary's. The manifest's fall rule latches FALL (exit 1)."""
    path = tmp_path / "g1.mcap"
    p = rozrun("--robot", "unitree_g1", "--port", "mujoco", "--ticks", 1400,
               "--controller", CTL / "g1_stand_pd.wasm", "--record", path, ok=(1,))
    assert "faults                 latched: fall (first: fall: the base tilted" in p.stdout
    m = re.search(r"base +height (-?[0-9.]+) m \(lowest (-?[0-9.]+)\), roll (-?[0-9.]+), "
                  r"pitch (-?[0-9.]+) deg", p.stdout)
    assert m, p.stdout
    counts = decode_all(path)
    assert counts["/roz/truth"] == counts["/roz/tick"] == 1400
    run, ticks, _ = recording.read(path)
    truth = [t["truth"] for t in ticks]
    assert all(t["floating"] for t in truth)
    # the summary's figures, from the last tick's sample and the lowest
    assert f"{truth[-1]['height']:.3f}" == m.group(1)
    assert f"{min(t['height'] for t in truth):.3f}" == m.group(2)
    assert f"{truth[-1]['roll'] * 57.29578:.1f}" == m.group(3)  # as the summary
    assert f"{truth[-1]['pitch'] * 57.29578:.1f}" == m.group(4)
    c = re.search(r"ground contacts +([0-9]+)", p.stdout)
    assert c and int(c.group(1)) == truth[-1]["contacts"], p.stdout
    # standing at 1.2 s: pelvis up, level, on its two feet only
    up = truth[600]
    assert up["height"] > 0.7
    assert max(abs(up["roll"]), abs(up["pitch"])) < 0.3
    assert sorted(up["bodies"]) == ["left_ankle_roll_link", "right_ankle_roll_link"]
    assert up["contacts"] >= 2
    for t in truth:  # a unit quaternion, the angles its own
        assert abs(t["qw"] ** 2 + t["qx"] ** 2 + t["qy"] ** 2 + t["qz"] ** 2 - 1.0) < 1e-9
    # fallen at 2.8 s: low, and more than the feet on the ground
    down = truth[-1]
    assert down["height"] < 0.4
    assert set(down["bodies"]) - {"left_ankle_roll_link", "right_ankle_roll_link"}
    # the tool says the same, and writes the samples
    out = subprocess.run([sys.executable, TOOL, "truth", path, tmp_path / "truth.csv"],
                         capture_output=True, text=True, check=True).stdout
    assert f"at the end base height {m.group(1)} m" in out
    assert f"lowest {m.group(2)} m" in out
    rows = (tmp_path / "truth.csv").read_text().splitlines()
    assert rows[0].startswith("tick,time_s,floating,x,y,height") and len(rows) == 1401
    strict(path)
    # the controller never sees the truth: replay is bit for bit
    p = rozrun("--replay", path, "--controller", CTL / "g1_stand_pd.wasm")
    assert "ticks replayed         1400\n" in p.stdout
    assert "result                 identical" in p.stdout


@pytest.mark.skipif(not MUJOCO, reason="this build has no mujoco port")
def test_mujoco_truth_fixed_base(tmp_path):
    """A fixed-base arm: no pose (NaN), the contacts still counted."""
    path = tmp_path / "ur5.mcap"
    rozrun("--robot", "ur5", "--port", "mujoco", "--ticks", 50,
           "--controller", CTL / "sine.wasm", "--record", path)
    run, ticks, counts = recording.read(path)
    assert counts["/roz/truth"] == 50
    for t in ticks:
        assert not t["truth"]["floating"]
        assert math.isnan(t["truth"]["height"]) and math.isnan(t["truth"]["roll"])
    strict(path)


def test_no_truth_without_a_simulator_that_gives_it(tmp_path):
    """The loopback gives no truth samples: no /roz/truth channel at all."""
    path = record(tmp_path, "ur5", "sine", 20)
    counts = decode_all(path)
    assert "/roz/truth" not in counts
    with open(path, "rb") as f:
        summary = make_reader(f).get_summary()
    assert "/roz/truth" not in {c.topic for c in summary.channels.values()}
