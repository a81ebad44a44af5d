// SPDX-License-Identifier: Apache-2.0
//! The run every harness makes, whatever the engine: resident memory, the
//! outputs checked against roz's in every metering mode and variant before
//! any figure, compile and instantiate time, per-call time with the modes
//! alternating in rounds of 100 calls, and the JSON. An engine brings only
//! what is its own, through [`Peer`] (implemented by [`crate::peer!`]).

use crate::{options, print_json, rss_kib, stats, time_ns, Abi, Figure, Manifest, Reference};

/// What the driver asks of an engine.
pub trait Peer {
    /// A metering mode (how a call's budget is kept).
    type Mode: Copy + 'static;
    type Engine;
    type Module;
    /// One instance in its store, with `process` looked up.
    type Loaded;

    /// The engine's name, as the JSON and the error messages give it.
    const ENGINE: &'static str;
    /// The engine's version: the pin in its Cargo.toml.
    const VERSION: &'static str;
    /// Every metering mode measured, with its name in the figures; the first
    /// is no metering (resident memory, compile and instantiate use it).
    const MODES: &'static [(Self::Mode, &'static str)];

    /// An engine configured for `mode`.
    fn engine(mode: Self::Mode) -> Result<Self::Engine, String>;
    /// The module compiled (or translated), with validation.
    fn compile(engine: &Self::Engine, wasm: &[u8]) -> Result<Self::Module, String>;
    /// A store holding a fresh ABI context for `manifest`, the module
    /// instantiated in it with roz's host functions, its budget armed.
    fn load(
        engine: &Self::Engine,
        module: &Self::Module,
        manifest: &Manifest,
        mode: Self::Mode,
    ) -> Result<Self::Loaded, String>;
    /// The ABI context the instance's imports work on.
    fn abi(loaded: &mut Self::Loaded) -> &mut Abi;
    /// `process(tick)`, its budget armed first as a tick loop does.
    fn call(loaded: &mut Self::Loaded, tick: i64) -> Result<(), String>;
}

/// The harness's `main`: runs [`run`], or prints why not and exits 1.
pub fn main<P: Peer>() {
    if let Err(e) = run::<P>() {
        eprintln!("roz-peer-{}: {e}", P::ENGINE);
        std::process::exit(1);
    }
}

/// Ticks `from..to` on `l`: each tick's snapshot, then the call.
fn ticks<P: Peer>(l: &mut P::Loaded, from: i64, to: i64) -> Result<(), String> {
    for t in from..to {
        P::abi(l).begin_tick(t);
        P::call(l, t)?;
    }
    Ok(())
}

/// `wasm` loaded in an engine for `mode` and run for `reference`'s ticks,
/// its outputs checked against roz's, bit for bit (`name` says which run).
fn checked<P: Peer>(
    mode: P::Mode,
    wasm: &[u8],
    m: &Manifest,
    reference: &Reference,
    name: &str,
) -> Result<(P::Engine, P::Loaded), String> {
    let e = P::engine(mode)?;
    let module = P::compile(&e, wasm)?;
    let mut l = P::load(&e, &module, m, mode)?;
    ticks::<P>(&mut l, 0, reference.ticks)?;
    if let Some(why) = reference.compare(P::abi(&mut l)) {
        return Err(format!(
            "{name}: outputs differ from roz's after {} ticks: {why}",
            reference.ticks
        ));
    }
    Ok((e, l))
}

fn read(path: &str) -> Result<Vec<u8>, String> {
    std::fs::read(path).map_err(|e| format!("{path}: {e}"))
}

/// Checks, measures and prints the JSON (bench/peers/README.md says what).
pub fn run<P: Peer>() -> Result<(), String> {
    let o = options()?;
    let m = Manifest::from_json_file(&o.manifest)?;
    let reference = Reference::read(&o.expect)?;
    let wasm = read(&o.wasm)?;
    let off = P::MODES[0].0;
    let mut figures = Vec::new();

    // Resident memory: before any engine, then with one instance loaded
    // and run (the engine, its compiled code, the store, linear memory).
    let rss0 = rss_kib();
    let e0 = P::engine(off)?;
    let module = P::compile(&e0, &wasm)?;
    let mut first = P::load(&e0, &module, &m, off)?;
    ticks::<P>(&mut first, 0, 100)?;
    let rss1 = rss_kib();
    drop(first);

    // Outputs first: every metering mode and variant against roz's, bit
    // for bit.
    let bulk = if o.wasm_bulk.is_empty() { None } else { Some(read(&o.wasm_bulk)?) };
    let mut variants = vec![(&wasm, "")];
    if let Some(b) = &bulk {
        variants.push((b, "bulk, "));
    }
    let mut loaded = Vec::new();
    for &(mode, mname) in P::MODES {
        for &(w, vname) in &variants {
            let name = format!("{vname}metering {mname}");
            let (e, l) = checked::<P>(mode, w, &m, &reference, &name)?;
            loaded.push((e, l, name));
        }
    }
    // The nn policy (bench/nn/policy.c: nn.matvec and nn.act every call),
    // its metrics against roz's, bit for bit, in every metering mode.
    let nn = if o.wasm_nn.is_empty() {
        None
    } else {
        Some((read(&o.wasm_nn)?, Reference::read(&o.expect_nn)?))
    };
    if let Some((w, nn_ref)) = &nn {
        for &(mode, mname) in P::MODES {
            let name = format!("nn policy, metering {mname}");
            let (e, l) = checked::<P>(mode, w, &m, nn_ref, &name)?;
            loaded.push((e, l, name));
        }
    }

    // Compile and instantiate, 20 times each.
    let reps = 20;
    let (mut comp, mut inst) = (Vec::new(), Vec::new());
    for _ in 0..reps {
        let (module, ns) = time_ns(|| P::compile(&e0, &wasm));
        let module = module?;
        comp.push(ns);
        let (l, ns) = time_ns(|| P::load(&e0, &module, &m, off));
        l?;
        inst.push(ns);
    }
    figures.push(Figure::Timing { name: "compile".into(), stats: stats(&mut comp) });
    figures.push(Figure::Timing { name: "instantiate".into(), stats: stats(&mut inst) });

    // process() per call after 1000 warm-up calls, the modes alternating
    // rounds of 100 calls so drift on the machine hits them alike.
    let mut ns: Vec<Vec<u64>> = vec![Vec::with_capacity(o.calls); loaded.len()];
    for (_, l, _) in loaded.iter_mut() {
        ticks::<P>(l, 0, 1000)?;
    }
    let mut r = 0;
    while r < o.calls {
        for (k, (_, l, _)) in loaded.iter_mut().enumerate() {
            for t in r..(r + 100).min(o.calls) {
                P::abi(l).begin_tick(t as i64);
                let (res, d) = time_ns(|| P::call(l, t as i64));
                res?;
                ns[k].push(d);
            }
        }
        r += 100;
    }
    for (k, (_, _, name)) in loaded.iter().enumerate() {
        figures.push(Figure::Timing {
            name: format!("process, {name}"),
            stats: stats(&mut ns[k]),
        });
    }
    figures.push(Figure::Value {
        name: "resident memory added".into(),
        value: rss1.saturating_sub(rss0) as f64,
        unit: "KiB",
    });
    let checked = format!(
        "outputs (the PD, the bulk PD and the nn policy when given) equal to roz's after {} ticks in every metering mode",
        reference.ticks
    );
    print_json(P::ENGINE, P::VERSION, &[("checked", checked)], &figures);
    Ok(())
}
