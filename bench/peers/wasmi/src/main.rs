// SPDX-License-Identifier: Apache-2.0
//! The G1 PD controller under wasmi (an interpreter for embedded use), with
//! roz's host functions: its outputs checked against roz's bit for bit, then
//! per-call cost with fuel metering off and on; compile (translate) and
//! instantiate time; resident memory added. JSON on stdout. What is not
//! wasmi's own (the host functions, the run) is in roz-peer-common.

use wasmi::{Config, Engine, Store};

/// The metering mode: fuel or none.
fn engine(fuel: bool) -> Result<Engine, String> {
    let mut c = Config::default();
    c.consume_fuel(fuel);
    Ok(Engine::new(&c))
}

/// Gives the next call its budget, as a tick loop does before each call.
fn arm(store: &mut Store<Host>, fuel: bool) -> Result<(), String> {
    if fuel {
        store.set_fuel(10_000_000).map_err(|e| format!("fuel: {e}"))?;
    }
    Ok(())
}

roz_peer_common::peer! {
    crate: wasmi,
    name: "wasmi",
    version: "2.0.0", // the pin in Cargo.toml
    mode: bool,
    modes: [(false, "off"), (true, "fuel")],
    engine: engine,
    arm: arm,
    instantiate: instantiate_and_start,
}

fn main() {
    roz_peer_common::main::<Peer>();
}
