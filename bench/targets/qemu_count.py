# SPDX-License-Identifier: Apache-2.0
"""bench/targets/qemu_count.py: instructions per tick, per part, by QEMU.

    qemu_count.py --track F[=PART] ... --tick F [--skip N] [--ticks N]
                  [--json OUT] -- QEMU ARGS... PROGRAM ARGS...

Runs a program under QEMU (user mode, qemu-aarch64 / qemu-x86_64, or
system mode, qemu-system-arm) with `-d in_asm,exec,nochain` added: QEMU
then logs each translation block's guest instructions when it translates
it, and each block's every execution (nochain: no block jumps straight to
the next unlogged). The log is read from a pipe as it comes (it is GBs for
a long run; nothing is stored): the instructions of every executed block
are summed, and attributed to the innermost *tracked* function on a shadow
call stack rebuilt from the blocks themselves: a block that ends in a call
(bl, blr, blx, call) pushes a frame for the function the next block is in,
returning to the address after the call; a block at a frame's return
address pops to it (tail calls and long jumps stay with their caller). So a
tracked function's part is its inclusive count less what tracked functions
called inside it took: the tick function's part is the runtime's own work.

Each call of the tick function (--tick) is one tick; after --skip ticks,
--ticks of them are measured and QEMU is stopped. Prints, and writes as one
JSON object, the parts' mean and largest count per tick. The count is of
guest instructions as executed, exact and the same from run to run (under
-icount for a system-mode board): no timer, no sampling, no load.
"""

import argparse
import json
import os
import re
import signal
import subprocess
import sys

CALLS = {"bl", "blr", "blx", "call", "callq"}
HEX = re.compile(r"^[0-9a-f]+$")


class Block:
    __slots__ = ("pc", "n", "end", "call", "addrs")

    def __init__(self, pc, n, end, call, addrs):
        self.pc = pc
        self.n = n
        self.end = end
        self.call = call
        self.addrs = addrs


def parse_insn(line):
    """(address, length in bytes, mnemonic) of one in_asm line, or None."""
    head, _, rest = line.partition(":")
    if not head.startswith("0x"):
        return None
    try:
        addr = int(head, 16)
    except ValueError:
        return None
    nbytes = 0
    mnem = ""
    for tok in rest.split():
        # the encoding: 2 (x86 bytes), 4 (Thumb halfwords) or 8 (A64 words)
        # hex digits a token; then the mnemonic
        if mnem == "" and len(tok) in (2, 4, 8) and HEX.match(tok):
            nbytes += len(tok) // 2
            continue
        mnem = tok
        break
    return addr, nbytes, mnem.lower()


class Counter:
    def __init__(self, track, tick, inlined=None):
        self.track = track  # function name -> part
        self.tick = tick
        # (the function the tick is inlined in, the addresses of its code
        # there): a tick is a run of those addresses in that function
        self.inlined = inlined
        self.by_ptr = {}  # host code pointer -> Block
        self.by_pc = {}  # guest pc -> Block (the latest translation)
        self.fresh = None  # the block translated last, not yet executed
        self.stack = []  # frames: [return address, owner part, is tick]
        self.rets = {}  # return address -> how many frames of the stack have it
        self.owner = None  # the innermost tracked part, None outside them
        self.prev = None  # the block executed last
        self.cur = None  # this tick's parts, or None outside a tick
        self.ticks = []  # every tick's parts
        self.seen = set()  # tracked functions entered at least once
        self.outside = 0  # instructions outside every tick
        self.prev_name = None  # the function the block executed last is in
        self.last = None  # (where the last block was counted, its block)

    def translated(self, pc, insns):
        if not insns:
            return
        addr, nbytes, mnem = insns[-1]
        blk = Block(pc, len(insns), addr + nbytes, mnem in CALLS, tuple(i[0] for i in insns))
        self.by_pc[pc] = blk
        self.fresh = blk

    def executed(self, ptr, pc, name):
        blk = None
        if self.fresh is not None and self.fresh.pc == pc:
            blk = self.fresh
            self.by_ptr[ptr] = blk
            self.fresh = None
        else:
            blk = self.by_ptr.get(ptr) or self.by_pc.get(pc)
        if blk is None:
            raise SystemExit(f"qemu_count: block at {pc:#x} executed, never translated in the log")
        # a return: pop to the frame it returns from (the search runs only
        # when some frame returns to pc)
        stack = self.stack
        rets = self.rets
        returned = False
        if pc in rets:
            for i in range(len(stack) - 1, max(-1, len(stack) - 64), -1):
                if stack[i][0] == pc:
                    # and the frames of tail calls under it, which return there too
                    while i > 0 and stack[i - 1][0] == pc:
                        i -= 1
                    for fr in stack[i:]:
                        if fr[2]:
                            self.end_tick()
                        self.forget(fr[0])
                    del stack[i:]
                    self.owner = stack[-1][1] if stack else None
                    returned = True
                    break
        # a call: the function this block is in was entered; or a tracked
        # function entered by a tail call (a jump from another function),
        # which returns where its caller's frame does
        prev = self.prev
        tail = (not returned and prev is not None and not prev.call and stack
                and name != self.prev_name and name in self.track)
        if prev is not None and (prev.call or tail):
            part = self.track.get(name)
            is_tick = name == self.tick
            if part is not None:
                self.seen.add(name)
                self.owner = part
            if is_tick:
                self.cur = {}
            ret = stack[-1][0] if tail else prev.end
            stack.append((ret, self.owner, is_tick))
            rets[ret] = rets.get(ret, 0) + 1
            if len(stack) > 4096:
                self.forget(stack[0][0])
                del stack[0]
        self.prev = blk
        self.prev_name = name
        if self.inlined is not None and name == self.inlined[0]:
            inside = sum(1 for x in blk.addrs if x in self.inlined[1])
            if inside and self.cur is None:
                self.cur = {}
                self.seen.add(self.tick)
            elif not inside and self.cur is not None:
                self.end_tick()
            # what the tick's code calls is the tick's
            self.owner = "runtime" if inside else None
            if inside:
                self.cur["runtime"] = self.cur.get("runtime", 0) + inside
                self.last = ("runtime", blk)
            else:
                self.last = (None, blk)
            self.outside += blk.n - inside
            return
        if self.cur is not None:
            key = self.owner if self.owner is not None else "(caller)"
            self.cur[key] = self.cur.get(key, 0) + blk.n
            self.last = (key, blk)
        else:
            self.outside += blk.n
            self.last = (None, blk)

    def forget(self, ret):
        """A frame returning to ret left the stack."""
        n = self.rets[ret] - 1
        if n:
            self.rets[ret] = n
        else:
            del self.rets[ret]

    def rewound(self, pc):
        """QEMU ran the last block only up to pc (an I/O access under
        -icount: the block is executed again from there, logged anew)."""
        if self.last is None:
            return
        key, blk = self.last
        undo = sum(1 for x in blk.addrs if x >= pc)
        if key is not None and self.cur is not None and key in self.cur:
            self.cur[key] -= undo
        else:
            self.outside -= undo
        self.last = None

    def end_tick(self):
        if self.cur is not None:
            self.ticks.append(self.cur)
        self.cur = None


TRACE = re.compile(r"^Trace \d+: (0x[0-9a-f]+) \[[0-9a-f]+/([0-9a-f]+)/[0-9a-f]+/[0-9a-f]+\] ?(.*)$")


def inlined_addresses(elf, func, host, prefix=""):
    """The addresses of host's code (a function in elf's symbol table) that
    is func inlined, by the debug information (binutils' addr2line -i: the
    chain of inlined calls at each address); a Thumb function's by halfword."""
    syms = subprocess.run([prefix + "nm", "-S", elf], check=True, capture_output=True,
                          text=True).stdout
    start = size = None
    for line in syms.splitlines():
        f = line.split()
        if len(f) == 4 and f[3] == host:
            start, size = int(f[0], 16) & ~1, int(f[1], 16)
    if start is None:
        raise SystemExit(f"qemu_count: {elf}: no function {host}")
    addrs = [f"{a:#x}" for a in range(start, start + size, 2)]
    out = subprocess.run([prefix + "addr2line", "-i", "-f", "-a", "-e", elf],
                         input="\n".join(addrs) + "\n", check=True, capture_output=True,
                         text=True).stdout
    found = set()
    at = None
    for line in out.splitlines():
        if line.startswith("0x"):
            at = int(line, 16)
        elif line.strip() == func and at is not None:
            found.add(at)
    return found


def parse_trace(line):
    """(host code pointer, guest pc, function) of one exec line, or None."""
    m = TRACE.match(line)
    if m is None:
        return None
    return int(m.group(1), 16), int(m.group(2), 16), m.group(3).strip()


def feed(c, lines, want):
    """Reads QEMU's log lines into the Counter c; True when want ticks were
    counted before the log ended (the reader stops there)."""
    insns = None
    pc = None
    # nearly every line is an exec line, and most are the same few thousand
    # lines again (a block run again logs the same text): each distinct one
    # is parsed once
    traces = {}
    executed = c.executed
    ticks = c.ticks
    for line in lines:
        if line[:5] == "Trace":
            t = traces.get(line)
            if t is None:
                if len(traces) > 1 << 20:
                    traces.clear()
                t = traces[line] = parse_trace(line) or ()
            if t:
                executed(*t)
                if len(ticks) >= want:
                    return True
            continue
        if line.startswith("cpu_io_recompile: rewound execution of TB to "):
            c.rewound(int(line.rsplit(" ", 1)[1], 16))
            continue
        if line.startswith("IN:"):
            insns = []
            pc = None
            continue
        if insns is not None:
            if not line.strip() or line.startswith("---"):
                if pc is not None:
                    c.translated(pc, insns)
                insns = None
                continue
            ins = parse_insn(line.strip())
            if ins is not None:
                if pc is None:
                    pc = ins[0]
                insns.append(ins)
    return False


def count(cmd, track, tick, skip, nticks, inlined=None):
    """Runs cmd (QEMU and its program) with the logging on; returns the
    Counter and the program's output. inlined: (host, addresses) when the
    tick function is inlined in host (inlined_addresses())."""
    c = Counter(track, tick, inlined)
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            errors="replace", bufsize=1 << 20, start_new_session=True)
    stopped = feed(c, proc.stderr, skip + nticks)
    if stopped:
        os.killpg(proc.pid, signal.SIGKILL)
    output = proc.stdout.read()
    rc = proc.wait()
    if not stopped and rc != 0:
        raise SystemExit(f"qemu_count: {cmd[0]} exited with {rc}\n{output}")
    return c, output


def summarise(c, skip, nticks, parts):
    ticks = c.ticks[skip:skip + nticks]
    if len(ticks) < nticks:
        raise SystemExit(f"qemu_count: {len(c.ticks)} ticks ran, {skip + nticks} wanted")
    res = {"ticks": len(ticks), "parts": {}}
    for p in ["tick"] + parts:
        if p == "tick":
            vals = [sum(t.values()) for t in ticks]
        else:
            vals = [t.get(p, 0) for t in ticks]
        res["parts"][p] = {"mean": sum(vals) / len(vals), "max": max(vals), "min": min(vals)}
    res["entered"] = sorted(c.seen)
    return res


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--track", action="append", default=[],
                    help="a function to attribute to a part: NAME or NAME=PART")
    ap.add_argument("--tick", required=True, help="the function one call of which is a tick")
    ap.add_argument("--skip", type=int, default=0, help="ticks left out first")
    ap.add_argument("--ticks", type=int, default=100, help="ticks measured")
    ap.add_argument("--json", help="write the result here")
    ap.add_argument("--label", action="append", default=[], help="KEY=VALUE put into the JSON")
    ap.add_argument("cmd", nargs=argparse.REMAINDER, help="-- QEMU [its options] PROGRAM ARGS")
    a = ap.parse_args(argv)
    cmd = a.cmd[1:] if a.cmd[:1] == ["--"] else a.cmd
    if not cmd:
        ap.error("no QEMU command after --")
    track = {}
    parts = []
    for t in a.track:
        name, _, part = t.partition("=")
        track[name] = part or name
        if (part or name) not in parts:
            parts.append(part or name)
    track[a.tick] = "runtime"
    if "runtime" not in parts:
        parts.append("runtime")
    # the log options go right after QEMU's name
    cmd = [cmd[0], "-d", "in_asm,exec,nochain"] + cmd[1:]
    c, output = count(cmd, track, a.tick, a.skip, a.ticks)
    res = summarise(c, a.skip, a.ticks, parts)
    res["command"] = " ".join(os.path.basename(x) if i == 0 else x for i, x in enumerate(a.cmd[1:]))
    for kv in a.label:
        k, _, v = kv.partition("=")
        res[k] = v
    for p, v in res["parts"].items():
        print(f"{p:12s} mean {v['mean']:12.1f}  min {v['min']:10d}  max {v['max']:10d}")
    if a.json:
        with open(a.json, "a", encoding="utf-8") as f:
            f.write(json.dumps(res, sort_keys=True) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
