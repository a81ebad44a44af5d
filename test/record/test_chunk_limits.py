# SPDX-License-Identifier: Apache-2.0
"""A chunk that lies about its size: tools/recording.py and roz-live's layout
decompress a chunk to at most the size it states (tools/mcap_chunks.py),
and refuse it naming the file, the chunk and the limit, under an address
space of 2 GiB. The files are written here by the PyPI mcap writer, its
compressor swapped for one that lies: a zstd frame whose header states
4 GiB (python-zstandard once allocated that), and zstd and lz4 frames that
decompress past the chunk's stated size, and frames that are not zstd or
lz4 at all."""
import pathlib
import resource
import subprocess
import sys
import types

import lz4.frame
import mcap.writer
import pytest
import zstandard
from mcap.writer import CompressionType, Writer

ROOT = pathlib.Path(__file__).resolve().parents[2]
TOOL = ROOT / "tools" / "recording.py"
LIVE = ROOT / "tools" / "live.py"
EXTRA = bytes(1 << 20)  # 1 MiB of zeros: a few KiB compressed


def zstd_frame_stating(size, data):
    """A zstd frame of @p data in one raw block whose header states @p size
    bytes (single segment, an 8-byte content size)."""
    assert len(data) < 1 << 17
    return (b"\x28\xb5\x2f\xfd" + bytes([0xE0]) + size.to_bytes(8, "little")
            + (1 | (len(data) << 3)).to_bytes(3, "little") + data)


LIARS = {
    "zstd-header": (CompressionType.ZSTD, "zstandard",
                    lambda d: zstd_frame_stating(4 << 30, d)),
    "zstd-more": (CompressionType.ZSTD, "zstandard",
                  lambda d: zstandard.ZstdCompressor(write_content_size=False).compress(d + EXTRA)),
    "lz4-more": (CompressionType.LZ4, "lz4",
                 lambda d: lz4.frame.compress(d + EXTRA, store_size=False)),
    "zstd-garbage": (CompressionType.ZSTD, "zstandard",
                     lambda d: b"\x28\xb5\x2f\xfd" + bytes(range(7, 250))),
    "lz4-garbage": (CompressionType.LZ4, "lz4",
                    lambda d: b"\x04\x22\x4d\x18" + bytes(range(7, 250))),
}


def write(path, liar):
    compression, attr, compress = LIARS[liar]
    fake = (types.SimpleNamespace(frame=types.SimpleNamespace(compress=compress))
            if attr == "lz4" else types.SimpleNamespace(compress=compress))
    real = getattr(mcap.writer, attr)
    setattr(mcap.writer, attr, fake)
    try:
        with open(path, "wb") as f:
            w = Writer(f, compression=compression)
            w.start(profile="ros2", library="test")
            sid = w.register_schema("roz_msgs/msg/Tick", "ros2msg", b"uint64 tick")
            cid = w.register_channel("/roz/tick", "cdr", sid)
            for t in range(40):
                w.add_message(cid, t * 1000, bytes(12), t * 1000)
            w.finish()
    finally:
        setattr(mcap.writer, attr, real)


def limit_2gib():
    resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))


@pytest.mark.parametrize("liar", sorted(LIARS))
def test_readers_refuse_chunks_that_lie(tmp_path, liar):
    path = tmp_path / f"{liar}.mcap"
    write(path, liar)
    assert path.stat().st_size < 64 << 10
    want = ("its zstd frame states 4294967296 bytes" if liar == "zstd-header"
            else "its data cannot be decompressed: " if liar.endswith("garbage")
            else "decompresses past its stated size, the limit of")
    for cmd in ([sys.executable, TOOL, "check", path],
                [sys.executable, LIVE, "layout", path, tmp_path / "layout.json"]):
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=120,
                           preexec_fn=limit_2gib)
        assert p.returncode != 0
        assert f"{path}: " in p.stderr and "chunk of messages 0..39000 ns" in p.stderr, p.stderr
        assert want in p.stderr, p.stderr
        assert "Traceback" not in p.stderr and "MemoryError" not in p.stderr, p.stderr
