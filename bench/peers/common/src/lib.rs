// SPDX-License-Identifier: Apache-2.0
//! What the peer harnesses share: the manifest (from `rozgen --json`), roz's
//! controller ABI as plain Rust over that manifest (the semantics of
//! lib/src/abi.c: clamp, non-finite refusal, counters), the deterministic
//! state sequence every engine is fed (bench/peers/README.md), the check
//! against roz's own outputs, statistics, and the JSON the harnesses print;
//! the run itself ([`driver`]) and roz's host functions for an engine crate
//! ([`peer!`]), so that a harness holds only what is its engine's own.

mod driver;
mod glue;
mod nn;

pub use driver::{main, run, Peer};

use std::fs;
use std::time::Instant;

/// One command channel: its limits and safe default.
#[derive(Clone, Debug)]
pub struct Command {
    pub min: f64,
    pub max: f64,
    pub default: f64,
}

/// The parts of a manifest the ABI needs.
#[derive(Clone, Debug)]
pub struct Manifest {
    pub robot_id: String,
    pub control_rate_hz: u64,
    pub commands: Vec<Command>,
    pub n_states: usize,
}

impl Manifest {
    /// Reads the canonical JSON that `rozgen --json robot.toml` prints.
    pub fn from_json_file(path: &str) -> Result<Manifest, String> {
        let text = fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
        let v: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| format!("{path}: {e}"))?;
        let num = |x: &serde_json::Value, what: &str| -> Result<f64, String> {
            x.as_f64().ok_or_else(|| format!("{path}: {what} is not a number"))
        };
        let mut commands = Vec::new();
        let cmds = v["commands"].as_array().ok_or(format!("{path}: no commands"))?;
        for (i, c) in cmds.iter().enumerate() {
            let lim = c["limits"].as_array().ok_or(format!("{path}: commands[{i}]: no limits"))?;
            commands.push(Command {
                min: num(&lim[0], "limits[0]")?,
                max: num(&lim[1], "limits[1]")?,
                default: num(&c["default"], "default")?,
            });
        }
        let n_states = v["states"].as_array().ok_or(format!("{path}: no states"))?.len();
        Ok(Manifest {
            robot_id: v["robot_id"].as_str().unwrap_or("?").to_string(),
            control_rate_hz: v["control_rate_hz"].as_u64().ok_or(format!("{path}: no rate"))?,
            commands,
            n_states,
        })
    }
}

/// Counters of the ABI, as roz_abi_counters_t.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    pub sets: u64,
    pub set_clamped: u64,
    pub set_bad_index: u64,
    pub set_nonfinite: u64,
    pub get_bad_index: u64,
    pub estop_requests: u64,
    pub metrics: u64,
    pub nn_calls: u64,
    pub nn_refused: u64,
}

/// The context every import works on (roz_abi_t).
pub struct Abi {
    pub manifest: Manifest,
    pub target: Vec<f64>,
    pub state: Vec<f64>,
    pub tick: i64,
    pub period_ns: u64,
    pub estop_requested: bool,
    pub counters: Counters,
    /// FNV-1a over every emitted metric's bits, in order (the nn policy's
    /// output is its metric)
    pub metric_fnv: u64,
    epoch: Instant,
}

pub const FNV_START: u64 = 0xcbf2_9ce4_8422_2325;

pub const SET_TAKEN: i32 = 0;
pub const SET_CLAMPED: i32 = 1;
pub const SET_REFUSED: i32 = -1;

impl Abi {
    pub fn new(manifest: Manifest) -> Abi {
        let target = manifest.commands.iter().map(|c| c.default).collect();
        let state = vec![0.0; manifest.n_states];
        let period_ns = 1_000_000_000 / manifest.control_rate_hz;
        Abi {
            manifest,
            target,
            state,
            tick: 0,
            period_ns,
            estop_requested: false,
            counters: Counters::default(),
            metric_fnv: FNV_START,
            epoch: Instant::now(),
        }
    }

    /// roz_abi_begin_tick: this tick's snapshot.
    pub fn begin_tick(&mut self, tick: i64) {
        self.tick = tick;
        fill_state(&mut self.state, tick);
    }

    pub fn command_set(&mut self, index: i32, value: f64) -> i32 {
        self.counters.sets += 1;
        if index < 0 || index as usize >= self.manifest.commands.len() {
            self.counters.set_bad_index += 1;
            return SET_REFUSED;
        }
        let i = index as usize;
        if !value.is_finite() {
            self.counters.set_nonfinite += 1;
            self.target[i] = f64::NAN;
            return SET_REFUSED;
        }
        let c = &self.manifest.commands[i];
        if value < c.min || value > c.max {
            self.counters.set_clamped += 1;
            self.target[i] = if value < c.min { c.min } else { c.max };
            return SET_CLAMPED;
        }
        self.target[i] = value;
        SET_TAKEN
    }

    pub fn command_count(&self) -> i32 {
        self.manifest.commands.len() as i32
    }

    pub fn command_limit(&mut self, index: i32, max: bool) -> f64 {
        if index < 0 || index as usize >= self.manifest.commands.len() {
            self.counters.get_bad_index += 1;
            return f64::NAN;
        }
        let c = &self.manifest.commands[index as usize];
        if max {
            c.max
        } else {
            c.min
        }
    }

    pub fn state_get(&mut self, index: i32) -> f64 {
        if index < 0 || index as usize >= self.state.len() {
            self.counters.get_bad_index += 1;
            return f64::NAN;
        }
        self.state[index as usize]
    }

    pub fn state_count(&self) -> i32 {
        self.state.len() as i32
    }

    pub fn request_estop(&mut self) {
        self.counters.estop_requests += 1;
        self.estop_requested = true;
    }

    pub fn now_ns(&self) -> i64 {
        self.epoch.elapsed().as_nanos() as i64
    }

    pub fn sim_time_ns(&self) -> i64 {
        self.tick.wrapping_mul(self.period_ns as i64)
    }

    /// state.get_all: channels 0..count-1 of the snapshot to `mem` at `ptr`,
    /// little-endian f64; -1 (nothing written) for a bad count or range.
    pub fn state_get_all(&mut self, mem: Option<&mut [u8]>, ptr: u32, count: i32) -> i32 {
        let n = self.state.len();
        let end = ptr as u64 + 8 * count.max(0) as u64;
        match mem {
            Some(mem) if count >= 0 && count as usize <= n && end <= mem.len() as u64 => {
                let dst = &mut mem[ptr as usize..end as usize];
                for (i, v) in self.state[..count as usize].iter().enumerate() {
                    dst[8 * i..8 * i + 8].copy_from_slice(&v.to_le_bytes());
                }
                count
            }
            _ => {
                self.counters.get_bad_index += 1;
                -1
            }
        }
    }

    /// command.set_all: command.set(i, value) for channels 0..count-1 from
    /// `mem` at `ptr`; the number clamped or refused, or -1 (no change).
    pub fn command_set_all(&mut self, mem: Option<&[u8]>, ptr: u32, count: i32) -> i32 {
        let n = self.manifest.commands.len();
        let end = ptr as u64 + 8 * count.max(0) as u64;
        match mem {
            Some(mem) if count >= 0 && count as usize <= n && end <= mem.len() as u64 => {
                let src = &mem[ptr as usize..end as usize];
                let mut not_taken = 0;
                for i in 0..count as usize {
                    let v = f64::from_le_bytes(src[8 * i..8 * i + 8].try_into().unwrap());
                    not_taken += (self.command_set(i as i32, v) != SET_TAKEN) as i32;
                }
                not_taken
            }
            _ => {
                self.counters.sets += 1;
                self.counters.set_bad_index += 1;
                -1
            }
        }
    }

    /// Metrics are counted and hashed, not kept (as a roz_abi_t without a
    /// ring).
    pub fn emit_metric(&mut self, value: f64) {
        self.counters.metrics += 1;
        for b in value.to_bits().to_le_bytes() {
            self.metric_fnv = (self.metric_fnv ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

/// The state of tick `tick`: channel i holds ((37 i + 11 t) mod 2003) / 1000
/// - 1, in [-1, 1.002] (some positions outside narrow joints' limits, so
/// commands get clamped), and every seventh tick one channel is NaN (so some
/// get refused). Integer arithmetic and one division and subtraction: the
/// same bits in C (bench/peers/roz_wasm3.c) and here.
pub fn fill_state(state: &mut [f64], tick: i64) {
    let n = state.len() as i64;
    for (i, s) in state.iter_mut().enumerate() {
        let k = ((i as i64) * 37 + tick * 11).rem_euclid(2003);
        *s = k as f64 / 1000.0 - 1.0;
    }
    if n > 0 && tick.rem_euclid(7) == 3 {
        state[tick.rem_euclid(n) as usize] = f64::NAN;
    }
}

/// roz's outputs after its reference run (bench/peers/roz_wasm3.c
/// --reference): the tick count, the counters and every target's bits.
pub struct Reference {
    pub ticks: i64,
    pub counters: Counters,
    pub target_bits: Vec<u64>,
    /// the nn policy's reference: its metrics' count and FNV-1a
    pub metric_fnv: Option<u64>,
}

impl Reference {
    pub fn read(path: &str) -> Result<Reference, String> {
        let text = fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
        let mut r = Reference {
            ticks: 0,
            counters: Counters::default(),
            target_bits: Vec::new(),
            metric_fnv: None,
        };
        for (n, line) in text.lines().enumerate() {
            let mut it = line.split_whitespace();
            let key = it.next().unwrap_or("");
            let val = it.next().unwrap_or("");
            let bad = || format!("{path}:{}: bad value '{val}'", n + 1);
            let u = || val.parse::<u64>().map_err(|_| bad());
            match key {
                "ticks" => r.ticks = val.parse().map_err(|_| bad())?,
                "sets" => r.counters.sets = u()?,
                "set_clamped" => r.counters.set_clamped = u()?,
                "set_bad_index" => r.counters.set_bad_index = u()?,
                "set_nonfinite" => r.counters.set_nonfinite = u()?,
                "get_bad_index" => r.counters.get_bad_index = u()?,
                "metrics" => r.counters.metrics = u()?,
                "nn_calls" => r.counters.nn_calls = u()?,
                "nn_refused" => r.counters.nn_refused = u()?,
                "metric_fnv" => r.metric_fnv = Some(
                    u64::from_str_radix(val.trim_start_matches("0x"), 16).map_err(|_| bad())?,
                ),
                "target" => r.target_bits.push(
                    u64::from_str_radix(val.trim_start_matches("0x"), 16).map_err(|_| bad())?,
                ),
                "" => {}
                _ => return Err(format!("{path}:{}: unknown key '{key}'", n + 1)),
            }
        }
        Ok(r)
    }

    /// None when `abi` holds exactly roz's outputs, else what differs.
    pub fn compare(&self, abi: &Abi) -> Option<String> {
        // metrics are compared where the reference has them (the nn policy)
        let metrics = if self.metric_fnv.is_some() { abi.counters.metrics } else { 0 };
        let mine = Counters { estop_requests: 0, metrics, ..abi.counters };
        if mine != self.counters {
            return Some(format!("counters differ: roz {:?}, here {:?}", self.counters, mine));
        }
        if self.target_bits.len() != abi.target.len() {
            return Some(format!(
                "{} targets in the reference, {} here",
                self.target_bits.len(),
                abi.target.len()
            ));
        }
        if let Some(want) = self.metric_fnv {
            if want != abi.metric_fnv {
                return Some(format!(
                    "the metrics' FNV-1a: roz 0x{want:016x}, here 0x{:016x}",
                    abi.metric_fnv
                ));
            }
        }
        for (i, (&want, got)) in self.target_bits.iter().zip(&abi.target).enumerate() {
            if want != got.to_bits() {
                return Some(format!(
                    "command {i}: roz 0x{want:016x}, here 0x{:016x}",
                    got.to_bits()
                ));
            }
        }
        None
    }
}

/// p50/p99/max of a set of durations, in microseconds.
#[derive(Clone, Copy, Debug)]
pub struct Stats {
    pub p50: f64,
    pub p99: f64,
    pub max: f64,
}

pub fn stats(ns: &mut [u64]) -> Stats {
    ns.sort_unstable();
    let n = ns.len();
    Stats {
        p50: ns[n / 2] as f64 / 1000.0,
        p99: ns[(n * 99) / 100] as f64 / 1000.0,
        max: ns[n - 1] as f64 / 1000.0,
    }
}

/// Resident memory of this process, in KiB (VmRSS of /proc/self/status).
pub fn rss_kib() -> u64 {
    let s = fs::read_to_string("/proc/self/status").unwrap_or_default();
    for line in s.lines() {
        if let Some(rest) = line.strip_prefix("VmRSS:") {
            return rest.trim().trim_end_matches("kB").trim().parse().unwrap_or(0);
        }
    }
    0
}

/// One figure of the JSON output: a row with p50/p99/max, or a scalar.
pub enum Figure {
    Timing { name: String, stats: Stats },
    Value { name: String, value: f64, unit: &'static str },
}

/// Prints the harness's figures as one JSON object on stdout.
pub fn print_json(engine: &str, version: &str, extra: &[(&str, String)], figures: &[Figure]) {
    let mut rows = Vec::new();
    for f in figures {
        rows.push(match f {
            Figure::Timing { name, stats } => serde_json::json!({
                "name": name, "unit": "us",
                "p50": stats.p50, "p99": stats.p99, "max": stats.max,
            }),
            Figure::Value { name, value, unit } => serde_json::json!({
                "name": name, "unit": unit, "value": value,
            }),
        });
    }
    let mut doc = serde_json::json!({ "engine": engine, "version": version, "figures": rows });
    for (k, v) in extra {
        doc[*k] = serde_json::Value::String(v.clone());
    }
    println!("{}", serde_json::to_string_pretty(&doc).unwrap());
}

/// Command-line options every harness takes.
pub struct Options {
    pub wasm: String,
    /// the same controller through the bulk calls (optional)
    pub wasm_bulk: String,
    pub manifest: String,
    pub expect: String,
    /// the nn policy (bench/nn/policy.c) and roz's reference for it (optional)
    pub wasm_nn: String,
    pub expect_nn: String,
    pub calls: usize,
}

pub fn options() -> Result<Options, String> {
    let args: Vec<String> = std::env::args().collect();
    let usage = format!(
        "usage: {} --wasm G1_PD.wasm [--wasm-bulk G1_PD_BULK.wasm] --manifest G1.json --expect REFERENCE [--wasm-nn POLICY.wasm --expect-nn REFERENCE] [--calls N]",
        args.first().map(String::as_str).unwrap_or("peer")
    );
    let mut o = Options {
        wasm: String::new(),
        wasm_bulk: String::new(),
        manifest: String::new(),
        expect: String::new(),
        wasm_nn: String::new(),
        expect_nn: String::new(),
        calls: 20000,
    };
    let mut i = 1;
    while i < args.len() {
        let v = args.get(i + 1).cloned().ok_or(usage.clone())?;
        match args[i].as_str() {
            "--wasm" => o.wasm = v,
            "--wasm-bulk" => o.wasm_bulk = v,
            "--manifest" => o.manifest = v,
            "--expect" => o.expect = v,
            "--wasm-nn" => o.wasm_nn = v,
            "--expect-nn" => o.expect_nn = v,
            "--calls" => o.calls = v.parse().map_err(|_| usage.clone())?,
            _ => return Err(usage),
        }
        i += 2;
    }
    if o.wasm.is_empty() || o.manifest.is_empty() || o.expect.is_empty() || o.calls < 100
        || o.wasm_nn.is_empty() != o.expect_nn.is_empty()
    {
        return Err(usage);
    }
    Ok(o)
}

/// Times `f` once, in nanoseconds.
pub fn time_ns<R>(f: impl FnOnce() -> R) -> (R, u64) {
    let t0 = Instant::now();
    let r = f();
    (r, t0.elapsed().as_nanos() as u64)
}
