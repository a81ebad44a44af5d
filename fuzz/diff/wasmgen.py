# SPDX-License-Identifier: Apache-2.0
"""wasmgen: a seeded, deterministic generator of valid WebAssembly 1.0
modules (plus memory.fill/memory.copy, sign extension and saturating
truncation, which roz accepts) in the text format, for the differential test
(fuzz/diff/diff_run.py: roz's wasm3 against wabt's wasm-interp) and as seeds
for fuzz_controller.

Every module is a valid roz controller: it imports only roz ABI functions
(roz/abi.h), defines its own memory (maximum = minimum, as roz caps it),
exports process(i64), and has no start function. The exports the
differential run calls take no parameters:

  tN_T     test function N; T is its result type; float results are
           exported as their bits (i32/i64.reinterpret), because wasm-interp
           prints floats with six decimals
  gN_T     the value of mutable global N, after the tests ran
  memhash  a checksum of the whole linear memory

What the generator aims at: integer and float ops at edge values; blocks,
loops and ifs with results; br, br_if and br_table carrying i32/i64/f32/f64
values with extra operands below them; calls with up to 255 parameters;
bounded recursion (some deep enough to exhaust an engine's stack);
memory.fill and memory.copy; long straight-line code; select; locals and
globals; loads and stores, some out of bounds; call_indirect (some traps).

Every run terminates: loops count a reserved local up to at most 8, calls go
only to functions defined earlier (call_indirect too), recursion counts
down, and each function's estimated dynamic cost is bounded.

NaN payloads and signs may differ between engines (WebAssembly allows it),
so a float is canonicalised (any NaN becomes the positive canonical NaN)
before its bits become visible to integer code: before reinterpret, before
a store, and as copysign's sign operand. Exported float results are
compared as bits by the driver, with every NaN one class.

Usage: wasmgen.py --seed N [-o out.wat]
"""
import argparse
import random
import struct
import sys

TYPES = ("i32", "i64", "f32", "f64")

I32_EDGES = [0, 1, -1, 2, 3, 7, 8, 15, 16, 31, 32, 33, 63, 64, 127, 128, 255, 256,
             0x7FFF, 0x8000, 0xFFFF, 0x10000, 0x7FFFFFFF, -0x80000000, -0x7FFFFFFF,
             -2, 0x55555555, -0x55555556, 65535, 65536, 65537]
I64_EDGES = [0, 1, -1, 2, 31, 32, 33, 63, 64, 65, 127, 255, 0x7FFFFFFF, 0x80000000,
             0xFFFFFFFF, 0x100000000, -0x80000000, 0x7FFFFFFFFFFFFFFF, -0x8000000000000000,
             -0x7FFFFFFFFFFFFFFF, -2, 0x5555555555555555, 1 << 53, (1 << 53) + 1]
F32_EDGES = [0x00000000, 0x80000000, 0x3F800000, 0xBF800000, 0x3F000000, 0x7F800000,
             0xFF800000, 0x7FC00000, 0xFFC00000, 0x7FA00000, 0x7FC00001, 0x7F7FFFFF,
             0xFF7FFFFF, 0x00800000, 0x00000001, 0x80000001, 0x4F000000, 0xCF000000,
             0x4F800000, 0x5F000000, 0xDF000000, 0x5F800000, 0x3EFFFFFF, 0x3FC00000,
             0x40200000, 0xC0200000, 0x4B800000, 0x4B800001, 0xCF000001, 0x4EFFFFFF,
             0x3F7FFFFF, 0xBF7FFFFF]
F64_EDGES = [0x0000000000000000, 0x8000000000000000, 0x3FF0000000000000, 0xBFF0000000000000,
             0x3FE0000000000000, 0x7FF0000000000000, 0xFFF0000000000000, 0x7FF8000000000000,
             0xFFF8000000000000, 0x7FF4000000000000, 0x7FF8000000000001, 0x7FEFFFFFFFFFFFFF,
             0x0010000000000000, 0x0000000000000001, 0x8000000000000001, 0x41E0000000000000,
             0xC1E0000000000000, 0x41DFFFFFFFC00000, 0xC1E0000000200000, 0x41F0000000000000,
             0x43E0000000000000, 0xC3E0000000000000, 0x43F0000000000000, 0x3FDFFFFFFFFFFFFF,
             0x3FF8000000000000, 0x4004000000000000, 0xC004000000000000, 0x4340000000000000,
             0x4340000000000001, 0x3FEFFFFFFFFFFFFF, 0x41EFFFFFFFE00000, 0xC3E0000000000001]

BINOPS = {
    "i32": ["add", "sub", "mul", "div_s", "div_u", "rem_s", "rem_u", "and", "or", "xor",
            "shl", "shr_s", "shr_u", "rotl", "rotr"],
    "f32": ["add", "sub", "mul", "div", "min", "max", "copysign"],
}
BINOPS["i64"] = BINOPS["i32"]
BINOPS["f64"] = BINOPS["f32"]
UNOPS = {
    "i32": ["clz", "ctz", "popcnt", "extend8_s", "extend16_s"],
    "i64": ["clz", "ctz", "popcnt", "extend8_s", "extend16_s", "extend32_s"],
    "f32": ["abs", "neg", "ceil", "floor", "trunc", "nearest", "sqrt"],
}
UNOPS["f64"] = UNOPS["f32"]
ICMP = ["eq", "ne", "lt_s", "lt_u", "gt_s", "gt_u", "le_s", "le_u", "ge_s", "ge_u"]
FCMP = ["eq", "ne", "lt", "gt", "le", "ge"]
# conversions to each type: (instruction, operand type); reinterpret is separate
CONVERT = {
    "i32": [("i32.wrap_i64", "i64"), ("i32.trunc_f32_s", "f32"), ("i32.trunc_f32_u", "f32"),
            ("i32.trunc_f64_s", "f64"), ("i32.trunc_f64_u", "f64"),
            ("i32.trunc_sat_f32_s", "f32"), ("i32.trunc_sat_f32_u", "f32"),
            ("i32.trunc_sat_f64_s", "f64"), ("i32.trunc_sat_f64_u", "f64")],
    "i64": [("i64.extend_i32_s", "i32"), ("i64.extend_i32_u", "i32"),
            ("i64.trunc_f32_s", "f32"), ("i64.trunc_f32_u", "f32"),
            ("i64.trunc_f64_s", "f64"), ("i64.trunc_f64_u", "f64"),
            ("i64.trunc_sat_f32_s", "f32"), ("i64.trunc_sat_f32_u", "f32"),
            ("i64.trunc_sat_f64_s", "f64"), ("i64.trunc_sat_f64_u", "f64")],
    "f32": [("f32.convert_i32_s", "i32"), ("f32.convert_i32_u", "i32"),
            ("f32.convert_i64_s", "i64"), ("f32.convert_i64_u", "i64"), ("f32.demote_f64", "f64")],
    "f64": [("f64.convert_i32_s", "i32"), ("f64.convert_i32_u", "i32"),
            ("f64.convert_i64_s", "i64"), ("f64.convert_i64_u", "i64"), ("f64.promote_f32", "f32")],
}
LOADS = {
    "i32": [("i32.load", 4), ("i32.load8_s", 1), ("i32.load8_u", 1), ("i32.load16_s", 2),
            ("i32.load16_u", 2)],
    "i64": [("i64.load", 8), ("i64.load8_s", 1), ("i64.load8_u", 1), ("i64.load16_s", 2),
            ("i64.load16_u", 2), ("i64.load32_s", 4), ("i64.load32_u", 4)],
    "f32": [("f32.load", 4)],
    "f64": [("f64.load", 8)],
}
STORES = {
    "i32": [("i32.store", 4), ("i32.store8", 1), ("i32.store16", 2)],
    "i64": [("i64.store", 8), ("i64.store8", 1), ("i64.store16", 2), ("i64.store32", 4)],
    "f32": [("f32.store", 4)],
    "f64": [("f64.store", 8)],
}
# roz's ABI (roz/abi.h), as (module, name, params, result)
ABI = [("command", "set", ("i32", "f64"), "i32"), ("command", "count", (), "i32"),
       ("command", "limit_min", ("i32",), "f64"), ("command", "limit_max", ("i32",), "f64"),
       ("state", "get", ("i32",), "f64"), ("state", "count", (), "i32"),
       ("math", "sin", ("f64",), "f64"), ("math", "cos", ("f64",), "f64"),
       ("safety", "request_estop", (), None), ("timing", "now_ns", (), "i64"),
       ("timing", "sim_time_ns", (), "i64"), ("telemetry", "emit_metric", ("f64",), None)]

FUNC_COST = 30000      # estimated dynamic instructions per function, at most
MAX_LOOP_NEST = 2


# a float's width: its exponent's bits and the struct formats of it and its bits
FLOAT_LAYOUT = {32: (8, "<f", "<I"), 64: (11, "<d", "<Q")}


def float_lit(bits, width):
    """The WAT literal of the @p width-bit float whose bits are @p bits."""
    ebits, ffmt, ifmt = FLOAT_LAYOUT[width]
    mbits = width - 1 - ebits
    bits &= (1 << width) - 1
    sign = "-" if bits >> (width - 1) else ""
    exp, frac = (bits >> mbits) & ((1 << ebits) - 1), bits & ((1 << mbits) - 1)
    if exp == (1 << ebits) - 1:
        return sign + ("inf" if frac == 0 else "nan:0x%x" % frac)
    return float.hex(struct.unpack(ffmt, struct.pack(ifmt, bits))[0])


class Func:
    def __init__(self, name, params, result, kind):
        self.name, self.params, self.result, self.kind = name, list(params), result, kind
        self.cost = 1
        self.text = None


class Gen:
    def __init__(self, seed, neutral=()):
        self.r = random.Random(seed)
        self.neutral = set(neutral)
        self.seed = seed
        self.types = {}          # signature -> type name
        self.funcs = []          # helpers, recursive and test functions, in order
        self.imports = []
        self.globals = []        # (name, type, mutable)
        self.pages = 1

    # ---- module-level pieces ------------------------------------------------
    def sig_type(self, params, result):
        key = (tuple(params), result)
        if key not in self.types:
            self.types[key] = "$ft%d" % len(self.types)
        return self.types[key]

    def const(self, t):
        r = self.r
        if t == "i32":
            v = r.choice(I32_EDGES) if r.random() < 0.7 else r.randint(-2**31, 2**31 - 1)
            return "(i32.const %d)" % v
        if t == "i64":
            v = r.choice(I64_EDGES) if r.random() < 0.7 else r.randint(-2**63, 2**63 - 1)
            if v >= 2**63:
                v -= 2**64
            return "(i64.const %d)" % v
        if t == "f32":
            b = r.choice(F32_EDGES) if r.random() < 0.7 else r.getrandbits(32)
            if r.random() < 0.3 and (b >> 23) & 0xFF != 0xFF:
                b ^= 0x80000000
            return "(f32.const %s)" % float_lit(b, 32)
        b = r.choice(F64_EDGES) if r.random() < 0.7 else r.getrandbits(64)
        if r.random() < 0.3 and (b >> 52) & 0x7FF != 0x7FF:
            b ^= 1 << 63
        return "(f64.const %s)" % float_lit(b, 64)

    # ---- function bodies ------------------------------------------------------
    def begin(self, fn):
        self.fn = fn
        self.locals = {t: [] for t in TYPES}     # names usable by local.get/set
        self.decl = []                           # (name, type) declared locals
        for i, t in enumerate(fn.params):
            self.locals[t].append("$p%d" % i)
        for t in TYPES:
            for _ in range(self.r.randint(0, 3)):
                n = "$l%d" % len(self.decl)
                self.decl.append((n, t))
                self.locals[t].append(n)
        self.decl += [("$sf", "f32"), ("$sd", "f64")]
        self.labels = []       # (name, kind, result)
        self.nlabel = 0
        self.loop_nest = 0
        self.mult = 1
        self.cost = 0

    def label(self):
        self.nlabel += 1
        return "$L%d" % self.nlabel

    def counter(self):
        n = "$c%d" % len(self.decl)
        self.decl.append((n, "i32"))
        return n

    def spend(self, n=1):
        self.cost += n * self.mult

    def rich(self):
        return self.cost < FUNC_COST // 2

    def canon(self, e, t):
        """e, with any NaN replaced by the canonical positive NaN."""
        if t == "f32":
            return ("(select (local.tee $sf %s) (f32.const nan) (f32.eq (local.get $sf) "
                    "(local.get $sf)))" % e)
        if t == "f64":
            return ("(select (local.tee $sd %s) (f64.const nan) (f64.eq (local.get $sd) "
                    "(local.get $sd)))" % e)
        return e

    def leaf(self, t):
        r = self.r
        self.spend()
        k = r.random()
        if k < 0.45 or (not self.locals[t] and not self.globals_of(t)):
            return self.const(t)
        if k < 0.8 and self.locals[t]:
            return "(local.get %s)" % r.choice(self.locals[t])
        g = self.globals_of(t)
        if g:
            return "(global.get %s)" % r.choice(g)
        return self.const(t)

    def globals_of(self, t, mutable=False):
        return [n for n, gt, m in self.globals if gt == t and (m or not mutable)]

    def addr(self, size):
        """An address expression: mostly in bounds, sometimes at the edge or anywhere."""
        r = self.r
        top = self.pages * 65536
        k = r.random()
        if k < 0.85:   # in the lower half: in bounds with any offset but 65535
            mask = (top // 2 - 1) & ~(size - 1 if r.random() < 0.5 else 0)
            return "(i32.and %s (i32.const %d))" % (self.expr("i32", 1), mask)
        if k < 0.95:
            return "(i32.const %d)" % (top - r.randint(0, size + 2))
        return self.expr("i32", 1)

    def offset(self):
        r = self.r
        return r.choice((0, 0, 0, 0, 1, 2, 4, 8, 100)) if r.random() < 0.97 else 65535

    def expr(self, t, d):
        r = self.r
        if d <= 0 or not self.rich():
            return self.leaf(t)
        self.spend()
        choices = [("leaf", 14), ("unop", 8), ("binop", 18), ("convert", 8), ("select", 4),
                   ("block", 5), ("if", 4), ("brtable", 2), ("call", 5), ("calli", 2),
                   ("load", 6), ("tee", 3), ("import", 1)]
        if t == "i32":
            choices += [("cmp", 8), ("eqz", 2), ("memsize", 1)]
        if t in ("i32", "i64", "f32", "f64"):
            choices += [("reinterp", 2)]
        if self.loop_nest < MAX_LOOP_NEST:
            choices += [("loop", 3)]
        kind = self.pick(choices)
        if kind == "leaf":
            return self.leaf(t)
        if kind == "unop":
            op = r.choice(UNOPS[t])
            return "(%s.%s %s)" % (t, op, self.expr(t, d - 1))
        if kind == "binop":
            op = r.choice(BINOPS[t])
            a, b = self.expr(t, d - 1), self.expr(t, d - 1)
            if op in ("div_s", "div_u", "rem_s", "rem_u") and r.random() < 0.7:
                b = "(%s.or %s (%s.const 1))" % (t, b, t)     # mostly no division by zero
            if op == "copysign":
                b = self.canon(b, t)
            return "(%s.%s %s %s)" % (t, op, a, b)
        if kind == "cmp":
            ot = r.choice(TYPES)
            op = r.choice(ICMP if ot[0] == "i" else FCMP)
            return "(%s.%s %s %s)" % (ot, op, self.expr(ot, d - 1), self.expr(ot, d - 1))
        if kind == "eqz":
            ot = r.choice(("i32", "i64"))
            return "(%s.eqz %s)" % (ot, self.expr(ot, d - 1))
        if kind == "convert":
            op, ot = r.choice(CONVERT[t])
            if ".trunc_f" in op and r.random() < 0.6:   # fewer traps: mostly saturating
                op = op.replace(".trunc_f", ".trunc_sat_f")
            return "(%s %s)" % (op, self.expr(ot, d - 1))
        if kind == "reinterp":
            src = {"i32": "f32", "i64": "f64", "f32": "i32", "f64": "i64"}[t]
            op = {"i32": "i32.reinterpret_f32", "i64": "i64.reinterpret_f64",
                  "f32": "f32.reinterpret_i32", "f64": "f64.reinterpret_i64"}[t]
            return "(%s %s)" % (op, self.canon(self.expr(src, d - 1), src))
        if kind == "select":
            return "(select %s %s %s)" % (self.expr(t, d - 1), self.expr(t, d - 1),
                                          self.expr("i32", d - 1))
        if kind == "tee" and self.locals[t]:
            return "(local.tee %s %s)" % (r.choice(self.locals[t]), self.expr(t, d - 1))
        if kind == "block":
            return self.block_expr(t, d)
        if kind == "if":
            cond = self.expr("i32", d - 1)
            lab = self.label()
            self.labels.append((lab, "if", t))
            a = self.stmts(r.randint(0, 2), d - 1) + [self.to_label(t, self.expr(t, d - 1))]
            b = self.stmts(r.randint(0, 2), d - 1) + [self.to_label(t, self.expr(t, d - 1))]
            self.labels.pop()
            return self.from_label(t, "(if %s (result %s) %s (then %s) (else %s))" % (
                lab, self.ltype(t), cond, " ".join(a), " ".join(b)))
        if kind == "brtable":
            return self.brtable_expr(t, d)
        if kind == "loop":
            return self.loop_expr(t, d)
        if kind == "call":
            return self.call_expr(t, d) or self.leaf(t)
        if kind == "calli":
            return self.calli_expr(t, d) or self.leaf(t)
        if kind == "import":
            cands = [i for i in ABI if i[3] == t]
            if not cands:
                return self.leaf(t)
            imp = r.choice(cands)
            return "(call $%s.%s %s)" % (imp[0], imp[1], " ".join(self.expr(p, d - 1)
                                                                   for p in imp[2]))
        if kind == "load":
            op, size = r.choice(LOADS[t])
            return "(%s offset=%d %s)" % (op, self.offset(), self.addr(size))
        if kind == "memsize":
            if r.random() < 0.5:
                return "(memory.size)"
            return "(memory.grow %s)" % r.choice(("(i32.const 0)", "(i32.const 1)",
                                                  self.expr("i32", d - 1)))
        return self.leaf(t)

    def pick(self, choices):
        total = sum(w for _, w in choices)
        x = self.r.uniform(0, total)
        for k, w in choices:
            x -= w
            if x <= 0:
                return k
        return choices[-1][0]

    # With "float-branch" neutralised (diff_run.py's classification of wasm3's
    # float-valued branch bug), labels of f32/f64 blocks carry the values'
    # bits as i32/i64 instead: the same program, but no float-valued branch.
    def ltype(self, t):
        if "float-branch" in self.neutral and t in ("f32", "f64"):
            return "i32" if t == "f32" else "i64"
        return t

    def to_label(self, t, v):
        lt = self.ltype(t)
        return v if lt == t else "(%s.reinterpret_%s %s)" % (lt, t, v)

    def from_label(self, t, v):
        lt = self.ltype(t)
        return v if lt == t else "(%s.reinterpret_%s %s)" % (t, lt, v)

    def extra(self, d):
        """A value left under a branch's operand: 1 to 3 of any type."""
        return " ".join(self.expr(self.r.choice(TYPES), min(d, 1))
                        for _ in range(self.r.randint(1, 3)))

    def block_expr(self, t, d):
        """A block of result t left by br / br_if (values with extras under them)."""
        r = self.r
        lab = self.label()
        self.labels.append((lab, "block", t))
        body = self.stmts(r.randint(0, 3), d - 1)
        k = r.random()
        if k < 0.35:   # br_if with extra operands below the value; all dropped if not taken
            ex = self.extra(d)
            body.append("%s %s %s br_if %s drop %s" % (
                ex, self.to_label(t, self.expr(t, d - 1)), self.expr("i32", d - 1), lab,
                " ".join("drop" for _ in ex_count(ex))))
            body += self.stmts(r.randint(0, 2), d - 1) + [self.to_label(t, self.expr(t, d - 1))]
        elif k < 0.6:  # br with extra operands, the block's last instruction
            body.append("%s %s br %s" % (self.extra(d), self.to_label(t, self.expr(t, d - 1)),
                                         lab))
        elif k < 0.8:  # a br_if whose value stays on the stack when not taken
            body.append("(br_if %s %s %s)" % (lab, self.to_label(t, self.expr(t, d - 1)),
                                              self.expr("i32", d - 1)))
        else:          # plain value
            body.append(self.to_label(t, self.expr(t, d - 1)))
        self.labels.pop()
        return self.from_label(t, "(block %s (result %s) %s)" % (lab, self.ltype(t),
                                                                 " ".join(body)))

    def brtable_expr(self, t, d):
        """Nested blocks of result t and a br_table into them, extras below the value."""
        r = self.r
        n = r.randint(2, 4)
        labs = [self.label() for _ in range(n)]
        for lab in labs:
            self.labels.append((lab, "block", t))
        targets = [r.choice(labs) for _ in range(r.randint(1, 5))]
        inner = "%s %s %s br_table %s" % (self.extra(d), self.to_label(t, self.expr(t, d - 1)),
                                           self.idx_expr(len(targets) + 1, d), " ".join(targets))
        lt = self.ltype(t)
        s = "(block %s (result %s) %s)" % (labs[-1], lt, inner)
        for i in range(n - 2, -1, -1):
            self.labels.pop()
            tail = self.unary_tail(t)
            if lt != t:
                tail = "%s.reinterpret_%s %s %s.reinterpret_%s" % (t, lt, tail, lt, t)
            s = "(block %s (result %s) %s %s)" % (labs[i], lt, s, tail)
        self.labels.pop()
        return self.from_label(t, s)

    def idx_expr(self, n, d):
        r = self.r
        if r.random() < 0.6:
            return "(i32.const %d)" % r.choice((0, 1, 2, n - 1, n, n + 1, -1, 0x7FFFFFFF))
        return self.expr("i32", 1)

    def unary_tail(self, t):
        """Instructions t -> t applied when falling out of a block."""
        r = self.r
        if t == "i32" or t == "i64":
            return "%s %s.%s" % (self.const(t), t, r.choice(("add", "xor", "mul", "sub")))
        return "%s.%s" % (t, r.choice(("neg", "abs", "sqrt", "ceil")))

    def counted_loop(self, max_stmts, d, tail=None):
        """A loop that runs 1..8 times on a fresh counter: (counter, label,
        count, body); `tail(counter, label, count)` adds instructions at the
        end of the body while the loop's label is in scope."""
        r = self.r
        c = self.counter()
        n = r.randint(1, 8)
        lab = self.label()
        self.loop_nest += 1
        old = self.mult
        self.mult *= n
        self.labels.append((lab, "loop", None))
        body = self.stmts(r.randint(1, max_stmts), d - 1)
        if tail is not None:
            body.extend(tail(c, lab, n))
        self.labels.pop()
        self.mult = old
        self.loop_nest -= 1
        return c, lab, n, body

    def loop_expr(self, t, d):
        def tail(c, lab, n):
            return ["(br_if %s (i32.lt_u (local.tee %s (i32.add (local.get %s) (i32.const 1))) "
                    "(i32.const %d)))" % (lab, c, c, n), self.expr(t, d - 1)]
        c, lab, _, body = self.counted_loop(3, d, tail)
        return "(block (result %s) (local.set %s (i32.const 0)) (loop %s (result %s) %s))" % (
            t, c, lab, t, " ".join(body))

    def callable(self, t, maxcost):
        return [f for f in self.funcs if f.result == t and f.kind in ("helper", "rec") and
                f.cost * self.mult <= maxcost]

    def call_args(self, f, d):
        if len(f.params) > 16:
            return " ".join(self.leaf(p) for p in f.params)
        return " ".join(self.expr(p, d - 1) for p in f.params)

    def call_expr(self, t, d):
        r = self.r
        room = FUNC_COST - self.cost
        cands = self.callable(t, room)
        if not cands:
            return None
        f = r.choice(cands)
        if f.kind == "rec":
            depth = r.choice(f.depths)
            if depth * f.cost * self.mult > room and not (self.fn.kind == "test" and self.mult == 1):
                depth = 0
            self.spend(f.cost * depth)
            rest = " ".join(self.expr(p, d - 1) for p in f.params[1:])
            return "(call %s (i32.const %d) %s)" % (f.name, depth, rest)
        self.spend(f.cost)
        return "(call %s %s)" % (f.name, self.call_args(f, d))

    def calli_expr(self, t, d):
        r = self.r
        room = FUNC_COST - self.cost
        table = [f for f in self.funcs if f.kind == "helper"]
        cands = [f for f in table if f.result == t and f.cost * self.mult <= room]
        if not cands:
            return None
        f = r.choice(cands)
        self.spend(f.cost)
        k = r.random()
        if k < 0.8:
            idx = self.table_index[f.name]
        elif k < 0.9:
            idx = r.choice([self.table_index[g.name] for g in table])   # maybe a type mismatch
        else:
            idx = r.choice((self.n_helpers, self.n_helpers + 1, 0x7FFFFFFF, -1))  # null, outside
        return "(call_indirect (type %s) %s (i32.const %d))" % (
            self.sig_type(f.params, f.result), self.call_args(f, d), idx)

    # ---- statements -------------------------------------------------------------
    def stmts(self, n, d):
        return [self.stmt(d) for _ in range(n)]

    def stmt(self, d):
        r = self.r
        if not self.rich():
            d = min(d, 1)
        self.spend()
        choices = [("set", 10), ("gset", 4), ("store", 5), ("drop", 3), ("if", 3), ("block", 3),
                   ("call", 3), ("fill", 2), ("copy", 2), ("brif", 3), ("import", 1),
                   ("br", 1), ("return", 1)]
        if self.loop_nest < MAX_LOOP_NEST and d > 0:
            choices.append(("loop", 2))
        kind = self.pick(choices)
        t = r.choice(TYPES)
        if kind == "set" and self.locals[t]:
            return "(local.set %s %s)" % (r.choice(self.locals[t]), self.expr(t, d))
        if kind == "gset" and self.globals_of(t, True):
            return "(global.set %s %s)" % (r.choice(self.globals_of(t, True)), self.expr(t, d))
        if kind == "store":
            op, size = r.choice(STORES[t])
            return "(%s offset=%d %s %s)" % (op, self.offset(), self.addr(size), self.canon(self.expr(t, d), t))
        if kind == "drop":
            return "(drop %s)" % self.expr(t, d)
        if kind == "if" and d > 0:
            lab = self.label()
            self.labels.append((lab, "if", None))
            a = self.stmts(r.randint(1, 3), d - 1)
            b = self.stmts(r.randint(0, 2), d - 1)
            self.labels.pop()
            return "(if %s %s (then %s) (else %s))" % (lab, self.expr("i32", d - 1), " ".join(a),
                                                      " ".join(b))
        if kind == "block" and d > 0:
            lab = self.label()
            self.labels.append((lab, "block", None))
            body = self.stmts(r.randint(1, 4), d - 1)
            self.labels.pop()
            return "(block %s %s)" % (lab, " ".join(body))
        if kind == "loop":
            c, lab, n, body = self.counted_loop(4, d)
            return ("(local.set %s (i32.const 0)) (loop %s %s (br_if %s (i32.lt_u (local.tee %s "
                    "(i32.add (local.get %s) (i32.const 1))) (i32.const %d))))" % (
                        c, lab, " ".join(body), lab, c, c, n))
        if kind == "call":
            room = FUNC_COST - self.cost
            cands = [f for f in self.funcs if f.result is None and f.kind == "helper" and
                     f.cost * self.mult <= room]
            if cands:
                f = r.choice(cands)
                self.spend(f.cost)
                return "(call %s %s)" % (f.name, self.call_args(f, d))
        if kind == "fill":
            return "(memory.fill %s %s %s)" % (self.addr(1), self.expr("i32", min(d, 1)),
                                               self.length())
        if kind == "copy":
            return "(memory.copy %s %s %s)" % (self.addr(1), self.addr(1), self.length())
        if kind in ("brif", "br"):
            fwd = [l for l in self.labels if l[1] != "loop"]
            if fwd:
                lab, _, lt = r.choice(fwd)
                if kind == "br" and r.random() < 0.5:
                    # unconditional: the rest of this block is dead (but validated) code
                    val = self.to_label(lt, self.expr(lt, d - 1)) if lt else ""
                    return "%s %s br %s" % (self.extra(d), val, lab)
                cond = self.expr("i32", d - 1)
                if lt is None:
                    if r.random() < 0.5:
                        return "(br_if %s %s)" % (lab, cond)
                    ex = self.extra(d)
                    return "%s %s br_if %s %s" % (ex, cond, lab, " ".join("drop" for _ in
                                                                           ex_count(ex)))
                ex = self.extra(d)
                return "%s %s %s br_if %s drop %s" % (ex, self.to_label(lt, self.expr(lt, d - 1)),
                                                      cond, lab,
                                                      " ".join("drop" for _ in ex_count(ex)))
        if kind == "return":
            if r.random() < 0.3:
                rt = self.fn.result
                return "(return %s)" % (self.expr(rt, d - 1) if rt else "")
        if kind == "import":
            imp = r.choice(ABI)
            call = "(call $%s.%s %s)" % (imp[0], imp[1], " ".join(self.expr(p, min(d, 1))
                                                                  for p in imp[2]))
            return call if imp[3] is None else "(drop %s)" % call
        if self.locals[t]:
            return "(local.set %s %s)" % (r.choice(self.locals[t]), self.expr(t, d))
        return "(drop %s)" % self.expr(t, d)

    def length(self):
        r = self.r
        if r.random() < 0.95:
            return "(i32.const %d)" % r.choice((0, 1, 2, 7, 8, 16, 33, 64, 100))
        return self.expr("i32", 1)

    def finish(self, body, result):
        fn = self.fn
        params = " ".join("(param $p%d %s)" % (i, t) for i, t in enumerate(fn.params))
        res = "(result %s)" % result if result else ""
        locs = " ".join("(local %s %s)" % (n, t) for n, t in self.decl)
        fn.cost = max(1, self.cost)
        fn.text = "(func %s (type %s) %s %s %s\n    %s)" % (
            fn.name, self.sig_type(fn.params, fn.result), params, res, locs, body)

    # ---- whole functions -----------------------------------------------------------
    def helper(self, i):
        r = self.r
        k = r.random()
        if k < 0.06:
            np = r.randint(100, 255)
        elif k < 0.15:
            np = r.randint(9, 40)
        else:
            np = r.randint(0, 5)
        params = [r.choice(TYPES) for _ in range(np)]
        result = r.choice(TYPES + (None,))
        fn = Func("$h%d" % i, params, result, "helper")
        self.begin(fn)
        if r.random() < 0.1:   # long straight-line code
            body = self.straight_line(r.randint(200, 600))
        else:
            body = self.stmts(r.randint(1, 6), r.randint(2, 4))
        if result:
            body.append(self.expr(result, 3))
        self.finish(" ".join(body), result)
        return fn

    def straight_line(self, n):
        r = self.r
        out = []
        for _ in range(n):
            t = r.choice(TYPES)
            if self.locals[t]:
                out.append("(local.set %s (%s.%s (local.get %s) %s))" % (
                    r.choice(self.locals[t]), t, r.choice(BINOPS[t][:3] + ["sub"]),
                    r.choice(self.locals[t]), self.const(t)))
            else:
                out.append("(drop %s)" % self.expr(t, 1))
            self.spend(4)
        return out

    def rec(self, i):
        """f(n, ...) = n == 0 ? base : op(f(n-1, ...), ...): recursion n deep."""
        r = self.r
        extra = [r.choice(TYPES) for _ in range(r.randint(0, 6))]
        result = r.choice(TYPES)
        fn = Func("$r%d" % i, ["i32"] + extra, result, "rec")
        self.begin(fn)
        base = self.expr(result, 2)
        args = " ".join("(local.get $p%d)" % (j + 1) if r.random() < 0.7 else self.expr(p, 1)
                        for j, p in enumerate(extra))
        rec = "(call %s (i32.sub (local.get $p0) (i32.const 1)) %s)" % (fn.name, args)
        if result in ("i32", "i64"):
            step = "(%s.add %s %s)" % (result, rec, self.expr(result, 1))
        else:
            step = "(%s.%s %s %s)" % (result, r.choice(("add", "mul", "min", "sub")), rec,
                                      self.expr(result, 1))
        body = "(if (result %s) (i32.eqz (local.get $p0)) (then %s) (else %s))" % (result, base,
                                                                                   step)
        self.finish(body, result)
        fn.cost = max(fn.cost, 8)
        # the deepest exhaust an engine's stack (the driver classifies, never fails on that)
        fn.depths = [d for d in (0, 1, 5, 50, 300, 1000, 4000, 30000)
                     if d * fn.cost <= 20 * FUNC_COST] or [0]
        return fn

    def test(self, i):
        r = self.r
        result = r.choice(TYPES + (None,))
        fn = Func("$t%d" % i, [], result, "test")
        self.begin(fn)
        body = self.stmts(r.randint(1, 6), r.randint(2, 5))
        if result:
            body.append(self.expr(result, 4))
        self.finish(" ".join(body), result)
        return fn

    def module(self):
        r = self.r
        self.pages = r.choice((1, 1, 1, 2))
        for j in range(r.randint(0, 8)):
            t = r.choice(TYPES)
            self.globals.append(("$g%d" % j, t, r.random() < 0.75))
        self.imports = ABI
        self.table_slots = []
        self.table_index = {}
        self.n_helpers = r.randint(2, 10)
        for i in range(self.n_helpers):
            f = self.helper(i)
            self.funcs.append(f)
            self.table_index[f.name] = len(self.table_slots)
            self.table_slots.append(f.name)
            if r.random() < 0.3:
                self.funcs.append(self.rec(i))
        for i in range(r.randint(3, 10)):
            self.funcs.append(self.test(i))
        return self.render()

    def render(self):
        r = self.r
        out = ["(module"]
        for (params, result), name in self.types.items():
            out.append("  (type %s (func %s %s))" % (name, " ".join("(param %s)" % p for p in params),
                                                      "(result %s)" % result if result else ""))
        for m, n, params, result in self.imports:
            out.append('  (import "%s" "%s" (func $%s.%s %s %s))' % (
                m, n, m, n, " ".join("(param %s)" % p for p in params),
                "(result %s)" % result if result else ""))
        out.append("  (memory %d %d)" % (self.pages, self.pages))
        for n, t, mut in self.globals:
            init = self.const(t)
            out.append("  (global %s %s %s)" % (n, "(mut %s)" % t if mut else t, init))
        out.append("  (table %d funcref)" % (len(self.table_slots) + 2))
        out.append("  (elem (i32.const 0) %s)" % " ".join(self.table_slots))
        for _ in range(r.randint(0, 3)):
            data = bytes(r.getrandbits(8) for _ in range(r.randint(1, 48)))
            off = r.randint(0, self.pages * 65536 - len(data))
            out.append('  (data (i32.const %d) "%s")' % (off, "".join("\\%02x" % b for b in data)))
        for f in self.funcs:
            out.append("  " + f.text)
        tests = [f for f in self.funcs if f.kind == "test"]
        for f in tests:
            name = "%s_%s" % (f.name[1:], f.result or "void")
            if f.result in ("f32", "f64"):
                it = "i32" if f.result == "f32" else "i64"
                out.append('  (func (export "%s") (result %s) (%s.reinterpret_%s (call %s)))' % (
                    name, it, it, f.result, f.name))
            else:
                out.append('  (func (export "%s") %s (call %s))' % (
                    name, "(result %s)" % f.result if f.result else "", f.name))
        for n, t, mut in self.globals:
            if not mut:
                continue
            if t in ("f32", "f64"):
                it = "i32" if t == "f32" else "i64"
                out.append('  (func (export "%s_%s") (result %s) (%s.reinterpret_%s (global.get %s)))'
                           % (n[1:], t, it, it, t, n))
            else:
                out.append('  (func (export "%s_%s") (result %s) (global.get %s))' % (n[1:], t, t, n))
        # memhash: h = (h * 31) ^ word over every 8 bytes of memory
        out.append('  (func (export "memhash") (result i64) (local $a i32) (local $h i64)\n'
                   '    (loop $l (local.set $h (i64.xor (i64.mul (local.get $h) (i64.const 31))\n'
                   '      (i64.load (local.get $a))))\n'
                   '      (br_if $l (i32.lt_u (local.tee $a (i32.add (local.get $a) (i32.const 8)))\n'
                   '        (i32.const %d))))\n'
                   '    (local.get $h))' % (self.pages * 65536))
        calls = " ".join("(call %s)" % f.name if f.result is None else "(drop (call %s))" % f.name
                         for f in tests)
        out.append('  (func (export "process") (param i64) %s)' % calls)
        out.append(")")
        return "\n".join(out) + "\n"


def ex_count(ex):
    """How many values an extra() string pushed: one per top-level expression."""
    depth, n = 0, 0
    for ch in ex:
        if ch == "(":
            if depth == 0:
                n += 1
            depth += 1
        elif ch == ")":
            depth -= 1
    return range(n)


def generate(seed, neutral=()):
    """The module of seed, as WAT text. neutral: classes of constructs to
    write in an equivalent form that avoids them (same random choices, same
    meaning): "float-branch"."""
    return Gen(seed, neutral).module()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("-o", "--out")
    ap.add_argument("--neutral", action="append", default=[],
                    help="write this class of constructs in an equivalent form: float-branch")
    a = ap.parse_args()
    text = generate(a.seed, a.neutral)
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
