// SPDX-License-Identifier: Apache-2.0
//! The G1 PD controller under wasmtime (Cranelift), with roz's host
//! functions: its outputs checked against roz's bit for bit, then per-call
//! cost with no metering, with fuel and with epoch interruption; compile and
//! instantiate time; resident memory added. JSON on stdout.

use roz_peer_common::{self as common, Abi, Figure, Manifest, Reference};
use wasmtime::{Caller, Memory, Config, Engine, Instance, Linker, Module, Store, TypedFunc};

const VERSION: &str = "48.0.8"; // the pin in Cargo.toml

#[derive(Clone, Copy, PartialEq)]
enum Metering {
    Off,
    Fuel,
    Epoch,
}

fn engine(m: Metering) -> Result<Engine, String> {
    let mut c = Config::new();
    c.consume_fuel(m == Metering::Fuel);
    c.epoch_interruption(m == Metering::Epoch);
    Engine::new(&c).map_err(|e| format!("engine: {e}"))
}

/// The store's data: roz's ABI context and the instance's memory (for the
/// bulk calls, looked up once after instantiation).
struct Host {
    abi: Abi,
    mem: Option<Memory>,
}

fn link_err(e: impl std::fmt::Display) -> String {
    format!("linker: {e}")
}

fn linker(engine: &Engine) -> Result<Linker<Host>, String> {
    let mut l = Linker::new(engine);
    l.func_wrap("command", "set", |mut c: Caller<'_, Host>, i: i32, v: f64| c.data_mut().abi.command_set(i, v)).map_err(link_err)?;
    l.func_wrap("command", "count", |c: Caller<'_, Host>| c.data().abi.command_count()).map_err(link_err)?;
    l.func_wrap("command", "limit_min", |mut c: Caller<'_, Host>, i: i32| c.data_mut().abi.command_limit(i, false)).map_err(link_err)?;
    l.func_wrap("command", "limit_max", |mut c: Caller<'_, Host>, i: i32| c.data_mut().abi.command_limit(i, true)).map_err(link_err)?;
    l.func_wrap("state", "get", |mut c: Caller<'_, Host>, i: i32| c.data_mut().abi.state_get(i)).map_err(link_err)?;
    l.func_wrap("state", "count", |c: Caller<'_, Host>| c.data().abi.state_count()).map_err(link_err)?;
    l.func_wrap("math", "sin", |x: f64| x.sin()).map_err(link_err)?;
    l.func_wrap("math", "cos", |x: f64| x.cos()).map_err(link_err)?;
    l.func_wrap("safety", "request_estop", |mut c: Caller<'_, Host>| c.data_mut().abi.request_estop()).map_err(link_err)?;
    l.func_wrap("timing", "now_ns", |c: Caller<'_, Host>| c.data().abi.now_ns()).map_err(link_err)?;
    l.func_wrap("timing", "sim_time_ns", |c: Caller<'_, Host>| c.data().abi.sim_time_ns()).map_err(link_err)?;
    l.func_wrap("telemetry", "emit_metric", |mut c: Caller<'_, Host>, v: f64| c.data_mut().abi.emit_metric(v)).map_err(link_err)?;
    l.func_wrap("state", "get_all", |mut c: Caller<'_, Host>, p: i32, n: i32| match c.data().mem {
        Some(m) => {
            let (data, host) = m.data_and_store_mut(&mut c);
            host.abi.state_get_all(Some(data), p as u32, n)
        }
        None => c.data_mut().abi.state_get_all(None, p as u32, n),
    })
    .map_err(link_err)?;
    l.func_wrap("command", "set_all", |mut c: Caller<'_, Host>, p: i32, n: i32| match c.data().mem {
        Some(m) => {
            let (data, host) = m.data_and_store_mut(&mut c);
            host.abi.command_set_all(Some(&*data), p as u32, n)
        }
        None => c.data_mut().abi.command_set_all(None, p as u32, n),
    })
    .map_err(link_err)?;
    Ok(l)
}

struct Loaded {
    store: Store<Host>,
    process: TypedFunc<i64, ()>,
    metering: Metering,
}

impl Loaded {
    fn new(engine: &Engine, module: &Module, m: &Manifest, metering: Metering) -> Result<Loaded, String> {
        let l = linker(engine)?;
        let mut store = Store::new(engine, Host { abi: Abi::new(m.clone()), mem: None });
        arm(&mut store, metering);
        let inst: Instance = l.instantiate(&mut store, module).map_err(|e| format!("instantiate: {e}"))?;
        let process = inst
            .get_typed_func::<i64, ()>(&mut store, "process")
            .map_err(|e| format!("process: {e}"))?;
        store.data_mut().mem = inst.get_memory(&mut store, "memory");
        Ok(Loaded { store, process, metering })
    }

    fn call(&mut self, tick: i64) -> Result<(), String> {
        arm(&mut self.store, self.metering);
        self.process.call(&mut self.store, tick).map_err(|e| format!("process({tick}): {e}"))
    }
}

/// Gives the next call its budget, as a tick loop does before each call
/// (no thread advances the epoch: this measures the checks' cost).
fn arm(store: &mut Store<Host>, metering: Metering) {
    match metering {
        Metering::Off => {}
        Metering::Fuel => store.set_fuel(10_000_000).unwrap(),
        Metering::Epoch => store.set_epoch_deadline(1_000_000),
    }
}

fn main() {
    if let Err(e) = run() {
        eprintln!("roz-peer-wasmtime: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let o = common::options()?;
    let m = Manifest::from_json_file(&o.manifest)?;
    let reference = Reference::read(&o.expect)?;
    let wasm = std::fs::read(&o.wasm).map_err(|e| format!("{}: {e}", o.wasm))?;
    let mut figures = Vec::new();

    // Resident memory: before any engine, then with one instance loaded
    // and run (the engine, its compiled code, the store, linear memory).
    let rss0 = common::rss_kib();
    let e0 = engine(Metering::Off)?;
    let module = Module::new(&e0, &wasm).map_err(|e| format!("compile: {e}"))?;
    let mut first = Loaded::new(&e0, &module, &m, Metering::Off)?;
    for t in 0..100 {
        first.store.data_mut().abi.begin_tick(t);
        first.call(t)?;
    }
    let rss1 = common::rss_kib();
    drop(first);

    // Outputs first: every metering mode against roz's, bit for bit.
    let modes = [(Metering::Off, "off"), (Metering::Fuel, "fuel"), (Metering::Epoch, "epoch")];
    let bulk = if o.wasm_bulk.is_empty() {
        None
    } else {
        Some(std::fs::read(&o.wasm_bulk).map_err(|e| format!("{}: {e}", o.wasm_bulk))?)
    };
    let mut variants = vec![(&wasm, "")];
    if let Some(b) = &bulk {
        variants.push((b, "bulk, "));
    }
    let mut loaded = Vec::new();
    for ((mode, mname), (w, vname)) in modes.iter().flat_map(|m| variants.iter().map(move |v| (*m, *v))) {
        let name = format!("{vname}metering {mname}");
        let e = engine(mode)?;
        let module = Module::new(&e, w).map_err(|e| format!("compile: {e}"))?;
        let mut l = Loaded::new(&e, &module, &m, mode)?;
        for t in 0..reference.ticks {
            l.store.data_mut().abi.begin_tick(t);
            l.call(t)?;
        }
        if let Some(why) = reference.compare(&l.store.data().abi) {
            return Err(format!("{name}: outputs differ from roz's after {} ticks: {why}", reference.ticks));
        }
        loaded.push((e, l, name));
    }

    // Compile and instantiate, 20 times each.
    let reps = 20;
    let (mut comp, mut inst) = (Vec::new(), Vec::new());
    for _ in 0..reps {
        let (module, ns) = common::time_ns(|| Module::new(&e0, &wasm));
        let module = module.map_err(|e| format!("compile: {e}"))?;
        comp.push(ns);
        let (l, ns) = common::time_ns(|| Loaded::new(&e0, &module, &m, Metering::Off));
        l?;
        inst.push(ns);
    }
    figures.push(Figure::Timing { name: "compile".into(), stats: common::stats(&mut comp) });
    figures.push(Figure::Timing { name: "instantiate".into(), stats: common::stats(&mut inst) });

    // process() per call, the modes alternating rounds of 100 calls so
    // drift on the machine hits them alike.
    let mut ns: Vec<Vec<u64>> = vec![Vec::with_capacity(o.calls); loaded.len()];
    for (_, l, _) in loaded.iter_mut() {
        for t in 0..1000 {
            l.store.data_mut().abi.begin_tick(t);
            l.call(t)?;
        }
    }
    let mut r = 0;
    while r < o.calls {
        for (k, (_, l, _)) in loaded.iter_mut().enumerate() {
            for t in r..(r + 100).min(o.calls) {
                l.store.data_mut().abi.begin_tick(t as i64);
                let (res, d) = common::time_ns(|| l.call(t as i64));
                res?;
                ns[k].push(d);
            }
        }
        r += 100;
    }
    for (k, (_, _, name)) in loaded.iter().enumerate() {
        figures.push(Figure::Timing {
            name: format!("process, {name}"),
            stats: common::stats(&mut ns[k]),
        });
    }
    figures.push(Figure::Value { name: "resident memory added".into(), value: rss1.saturating_sub(rss0) as f64, unit: "KiB" });
    common::print_json(
        "wasmtime",
        VERSION,
        &[("checked", format!("outputs (the PD, and the bulk PD when given) equal to roz's after {} ticks in every metering mode", reference.ticks))],
        &figures,
    );
    Ok(())
}
