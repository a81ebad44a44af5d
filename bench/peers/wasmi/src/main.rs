// SPDX-License-Identifier: Apache-2.0
//! The G1 PD controller under wasmi (an interpreter for embedded use), with
//! roz's host functions: its outputs checked against roz's bit for bit, then
//! per-call cost with fuel metering off and on; compile (translate) and
//! instantiate time; resident memory added. JSON on stdout.

use roz_peer_common::{self as common, Abi, Figure, Manifest, Reference};
use wasmi::{Caller, Memory, Config, Engine, Linker, Module, Store, TypedFunc};

const VERSION: &str = "2.0.0"; // the pin in Cargo.toml

fn engine(fuel: bool) -> Engine {
    let mut c = Config::default();
    c.consume_fuel(fuel);
    Engine::new(&c)
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
    fuel: bool,
}

impl Loaded {
    fn new(engine: &Engine, module: &Module, m: &Manifest, fuel: bool) -> Result<Loaded, String> {
        let l = linker(engine)?;
        let mut store = Store::new(engine, Host { abi: Abi::new(m.clone()), mem: None });
        if fuel {
            store.set_fuel(10_000_000).map_err(|e| format!("fuel: {e}"))?;
        }
        let inst = l.instantiate_and_start(&mut store, module).map_err(|e| format!("instantiate: {e}"))?;
        let process = inst
            .get_typed_func::<i64, ()>(&store, "process")
            .map_err(|e| format!("process: {e}"))?;
        store.data_mut().mem = inst.get_memory(&store, "memory");
        Ok(Loaded { store, process, fuel })
    }

    /// A call with its budget set first, as a tick loop does.
    fn call(&mut self, tick: i64) -> Result<(), String> {
        if self.fuel {
            self.store.set_fuel(10_000_000).map_err(|e| format!("fuel: {e}"))?;
        }
        self.process.call(&mut self.store, tick).map_err(|e| format!("process({tick}): {e}"))
    }
}

fn main() {
    if let Err(e) = run() {
        eprintln!("roz-peer-wasmi: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let o = common::options()?;
    let m = Manifest::from_json_file(&o.manifest)?;
    let reference = Reference::read(&o.expect)?;
    let wasm = std::fs::read(&o.wasm).map_err(|e| format!("{}: {e}", o.wasm))?;
    let mut figures = Vec::new();

    let rss0 = common::rss_kib();
    let e0 = engine(false);
    let module = Module::new(&e0, &wasm).map_err(|e| format!("compile: {e}"))?;
    let mut first = Loaded::new(&e0, &module, &m, false)?;
    for t in 0..100 {
        first.store.data_mut().abi.begin_tick(t);
        first.call(t)?;
    }
    let rss1 = common::rss_kib();
    drop(first);

    let modes = [(false, "off"), (true, "fuel")];
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
    for ((fuel, mname), (w, vname)) in modes.iter().flat_map(|m| variants.iter().map(move |v| (*m, *v))) {
        let name = format!("{vname}metering {mname}");
        let e = engine(fuel);
        let module = Module::new(&e, w).map_err(|e| format!("compile: {e}"))?;
        let mut l = Loaded::new(&e, &module, &m, fuel)?;
        for t in 0..reference.ticks {
            l.store.data_mut().abi.begin_tick(t);
            l.call(t)?;
        }
        if let Some(why) = reference.compare(&l.store.data().abi) {
            return Err(format!("{name}: outputs differ from roz's after {} ticks: {why}", reference.ticks));
        }
        loaded.push((e, l, name));
    }

    let reps = 20;
    let (mut comp, mut inst) = (Vec::new(), Vec::new());
    for _ in 0..reps {
        let (module, ns) = common::time_ns(|| Module::new(&e0, &wasm));
        let module = module.map_err(|e| format!("compile: {e}"))?;
        comp.push(ns);
        let (l, ns) = common::time_ns(|| Loaded::new(&e0, &module, &m, false));
        l?;
        inst.push(ns);
    }
    figures.push(Figure::Timing { name: "compile".into(), stats: common::stats(&mut comp) });
    figures.push(Figure::Timing { name: "instantiate".into(), stats: common::stats(&mut inst) });

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
        "wasmi",
        VERSION,
        &[("checked", format!("outputs (the PD, and the bulk PD when given) equal to roz's after {} ticks in every metering mode", reference.ticks))],
        &figures,
    );
    Ok(())
}
