// SPDX-License-Identifier: Apache-2.0
//! [`peer!`]: roz's host functions and the [`Peer`](crate::Peer) glue for an
//! engine crate. wasmtime and wasmi spell Linker, Caller, Memory, Store,
//! TypedFunc, `func_wrap` and `data_and_store_mut` alike, so the text is
//! written once here and expanded in each harness against its own crate.

/// Defines, in the harness that invokes it:
/// - `Host`, the store's data: roz's ABI context and the instance's memory
///   (for the bulk calls, looked up once after instantiation);
/// - `linker(&Engine)`, roz's controller imports on an engine's Linker;
/// - `Loaded`, one instance in its store, and `Peer`, the [`Peer`](crate::Peer)
///   implementation the driver runs.
///
/// What the engine brings: its crate, its name and version, the type of its
/// metering modes and the modes measured (no metering first), `engine`
/// (`fn(Mode) -> Result<Engine, String>`), `arm` (`fn(&mut Store<Host>,
/// Mode) -> Result<(), String>`, the budget of the next call) and the
/// Linker's method that instantiates a module and runs its start function.
#[macro_export]
macro_rules! peer {
    (
        crate: $k:ident,
        name: $name:literal,
        version: $version:literal,
        mode: $mode:ty,
        modes: $modes:expr,
        engine: $engine:ident,
        arm: $arm:ident,
        instantiate: $instantiate:ident $(,)?
    ) => {
        struct Host {
            abi: $crate::Abi,
            mem: Option<$k::Memory>,
        }

        fn linker(engine: &$k::Engine) -> Result<$k::Linker<Host>, String> {
            use $k::Caller;
            fn err(e: impl std::fmt::Display) -> String {
                format!("linker: {e}")
            }
            let mut l = $k::Linker::new(engine);
            l.func_wrap("command", "set", |mut c: Caller<'_, Host>, i: i32, v: f64| c.data_mut().abi.command_set(i, v)).map_err(err)?;
            l.func_wrap("command", "count", |c: Caller<'_, Host>| c.data().abi.command_count()).map_err(err)?;
            l.func_wrap("command", "limit_min", |mut c: Caller<'_, Host>, i: i32| c.data_mut().abi.command_limit(i, false)).map_err(err)?;
            l.func_wrap("command", "limit_max", |mut c: Caller<'_, Host>, i: i32| c.data_mut().abi.command_limit(i, true)).map_err(err)?;
            l.func_wrap("state", "get", |mut c: Caller<'_, Host>, i: i32| c.data_mut().abi.state_get(i)).map_err(err)?;
            l.func_wrap("state", "count", |c: Caller<'_, Host>| c.data().abi.state_count()).map_err(err)?;
            l.func_wrap("math", "sin", |x: f64| x.sin()).map_err(err)?;
            l.func_wrap("math", "cos", |x: f64| x.cos()).map_err(err)?;
            l.func_wrap("safety", "request_estop", |mut c: Caller<'_, Host>| c.data_mut().abi.request_estop()).map_err(err)?;
            l.func_wrap("timing", "now_ns", |c: Caller<'_, Host>| c.data().abi.now_ns()).map_err(err)?;
            l.func_wrap("timing", "sim_time_ns", |c: Caller<'_, Host>| c.data().abi.sim_time_ns()).map_err(err)?;
            l.func_wrap("telemetry", "emit_metric", |mut c: Caller<'_, Host>, v: f64| c.data_mut().abi.emit_metric(v)).map_err(err)?;
            l.func_wrap("state", "get_all", |mut c: Caller<'_, Host>, p: i32, n: i32| match c.data().mem {
                Some(m) => {
                    let (data, host) = m.data_and_store_mut(&mut c);
                    host.abi.state_get_all(Some(data), p as u32, n)
                }
                None => c.data_mut().abi.state_get_all(None, p as u32, n),
            })
            .map_err(err)?;
            l.func_wrap("command", "set_all", |mut c: Caller<'_, Host>, p: i32, n: i32| match c.data().mem {
                Some(m) => {
                    let (data, host) = m.data_and_store_mut(&mut c);
                    host.abi.command_set_all(Some(&*data), p as u32, n)
                }
                None => c.data_mut().abi.command_set_all(None, p as u32, n),
            })
            .map_err(err)?;
            l.func_wrap("nn", "matvec", |mut c: Caller<'_, Host>, w: i32, x: i32, b: i32, y: i32, rows: i32, cols: i32, flags: i32| match c.data().mem {
                Some(m) => {
                    let (data, host) = m.data_and_store_mut(&mut c);
                    host.abi.nn_matvec(Some(data), w as u32, x as u32, b as u32, y as u32, rows, cols, flags)
                }
                None => c.data_mut().abi.nn_matvec(None, 0, 0, 0, 0, rows, cols, flags),
            })
            .map_err(err)?;
            l.func_wrap("nn", "act", |mut c: Caller<'_, Host>, kind: i32, p: i32, n: i32| match c.data().mem {
                Some(m) => {
                    let (data, host) = m.data_and_store_mut(&mut c);
                    host.abi.nn_act(Some(data), kind, p as u32, n)
                }
                None => c.data_mut().abi.nn_act(None, kind, p as u32, n),
            })
            .map_err(err)?;
            Ok(l)
        }

        struct Loaded {
            store: $k::Store<Host>,
            process: $k::TypedFunc<i64, ()>,
            mode: $mode,
        }

        struct Peer;

        impl $crate::Peer for Peer {
            type Mode = $mode;
            type Engine = $k::Engine;
            type Module = $k::Module;
            type Loaded = Loaded;

            const ENGINE: &'static str = $name;
            const VERSION: &'static str = $version;
            const MODES: &'static [($mode, &'static str)] = &$modes;

            fn engine(mode: $mode) -> Result<$k::Engine, String> {
                $engine(mode)
            }

            fn compile(engine: &$k::Engine, wasm: &[u8]) -> Result<$k::Module, String> {
                $k::Module::new(engine, wasm).map_err(|e| format!("compile: {e}"))
            }

            fn load(engine: &$k::Engine, module: &$k::Module, m: &$crate::Manifest, mode: $mode) -> Result<Loaded, String> {
                let l = linker(engine)?;
                let mut store = $k::Store::new(engine, Host { abi: $crate::Abi::new(m.clone()), mem: None });
                $arm(&mut store, mode)?;
                let inst = l.$instantiate(&mut store, module).map_err(|e| format!("instantiate: {e}"))?;
                let process = inst
                    .get_typed_func::<i64, ()>(&mut store, "process")
                    .map_err(|e| format!("process: {e}"))?;
                store.data_mut().mem = inst.get_memory(&mut store, "memory");
                Ok(Loaded { store, process, mode })
            }

            fn abi(l: &mut Loaded) -> &mut $crate::Abi {
                &mut l.store.data_mut().abi
            }

            fn call(l: &mut Loaded, tick: i64) -> Result<(), String> {
                $arm(&mut l.store, l.mode)?;
                l.process.call(&mut l.store, tick).map_err(|e| format!("process({tick}): {e}"))
            }
        }
    };
}
