// SPDX-License-Identifier: Apache-2.0
//! The G1 PD controller under wasmtime (Cranelift), with roz's host
//! functions: its outputs checked against roz's bit for bit, then per-call
//! cost with no metering, with fuel and with epoch interruption; compile and
//! instantiate time; resident memory added. JSON on stdout. What is not
//! wasmtime's own (the host functions, the run) is in roz-peer-common.

use wasmtime::{Config, Engine, Store};

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

/// Gives the next call its budget, as a tick loop does before each call
/// (no thread advances the epoch: this measures the checks' cost).
fn arm(store: &mut Store<Host>, metering: Metering) -> Result<(), String> {
    match metering {
        Metering::Off => {}
        Metering::Fuel => store.set_fuel(10_000_000).map_err(|e| format!("fuel: {e}"))?,
        Metering::Epoch => store.set_epoch_deadline(1_000_000),
    }
    Ok(())
}

roz_peer_common::peer! {
    crate: wasmtime,
    name: "wasmtime",
    version: "48.0.8", // the pin in Cargo.toml
    mode: Metering,
    modes: [(Metering::Off, "off"), (Metering::Fuel, "fuel"), (Metering::Epoch, "epoch")],
    engine: engine,
    arm: arm,
    instantiate: instantiate,
}

fn main() {
    roz_peer_common::main::<Peer>();
}
