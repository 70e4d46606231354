//! The plant FMU's step as the C ABI runs it (after the handle checks): set every real input,
//! `fmi2DoStep` of 10 µs, get every real output, on the safe [`Instance`], with 1 and 3 modes;
//! against the plant core's own step with the same parameters, measured in the same run (interleaved, best of 5,
//! thread CPU time). The difference is the export layer's cost per communication step (since
//! the generated per-step paths it is within the bench's resolution: the two loops compile
//! differently, so it can come out negative); the generic `Value` path's extra cost over the
//! direct one is measured in the same run.
//!
//! `cargo bench -p fmu-plant --bench fmu_step` (`cargo test --benches`: a short run).
#![allow(missing_docs)]

use fmi2_export::instance::{Instance, LogLevel, LogSink};
use fmi2_export::{Environment, Fmi2Model};
use fmu_plant::MillingPlant;
use milling_plant::{Plant, PlantInputs, PlantParams};
use model_description::{Causality, ScalarType, Value};
use std::hint::black_box;

struct Quiet;
impl LogSink for Quiet {
    fn emit(&mut self, _level: LogLevel, _category: &str, _message: &str) {}
}

/// CPU time of this thread [s]: on a shared machine the wall time counts other processes' turns.
fn cpu_seconds() -> f64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: a valid, writable timespec; CLOCK_THREAD_CPUTIME_ID exists on Linux.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// The value references of the real variables with causality `c`.
fn reals(c: Causality) -> Vec<u32> {
    MillingPlant::description()
        .variables()
        .iter()
        .filter(|v| v.causality == c && v.scalar_type().api_type() == ScalarType::Real)
        .map(|v| v.value_reference)
        .collect()
}

/// The value reference of `name`.
fn vr(name: &str) -> u32 {
    MillingPlant::description().variable(name).expect("a plant variable").value_reference
}

/// The FMU step on the safe `Instance`: Real inputs and outputs through `set_reals`/`get_reals`
/// (what `fmi2SetReal`/`fmi2GetReal` call) or, `generic`, through `set`/`get` with `Value`s
/// (the path of the other types, and of the Reals in earlier releases).
fn fmu_ns(steps: usize, modes: i32, generic: bool) -> f64 {
    let (ins, outs) = (reals(Causality::Input), reals(Causality::Output));
    let mut inst = Instance::<MillingPlant>::new(Environment::default(), false, Box::new(Quiet));
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization().unwrap();
    inst.set("fmi2SetInteger", ScalarType::Integer, &[vr("workpiece.modes")], &[Value::Integer(modes)]).unwrap();
    inst.exit_initialization().unwrap();
    let mut out = Vec::new();
    let mut vals: Vec<Value> = Vec::new();
    let (zeros, mut direct) = (vec![0.0; ins.len()], vec![0.0; outs.len()]);
    let start = cpu_seconds();
    for k in 0..steps {
        if generic {
            vals.clear();
            vals.extend(ins.iter().map(|_| Value::Real(0.0)));
            inst.set("fmi2SetReal", ScalarType::Real, &ins, black_box(&vals)).unwrap();
        } else {
            inst.set_reals("fmi2SetReal", &ins, black_box(&zeros)).unwrap();
        }
        inst.do_step(k as f64 * 1e-5, 1e-5).unwrap();
        if generic {
            inst.get("fmi2GetReal", ScalarType::Real, &outs, &mut out).unwrap();
            black_box(&out);
        } else {
            inst.get_reals("fmi2GetReal", &outs, &mut direct).unwrap();
            black_box(&direct);
        }
    }
    (cpu_seconds() - start) * 1e9 / steps as f64
}

fn core_ns(steps: usize, modes: u32) -> f64 {
    let mut params = PlantParams::default();
    params.workpiece.modes = modes;
    let mut plant = Plant::new(&params).unwrap();
    let inputs = PlantInputs::default();
    let start = cpu_seconds();
    for _ in 0..steps {
        plant.step(1e-5, black_box(&inputs)).unwrap();
        black_box(plant.outputs());
    }
    (cpu_seconds() - start) * 1e9 / steps as f64
}

fn main() {
    let quick = !std::env::args().any(|a| a == "--bench");
    let (steps, rounds) = if quick { (2_000, 1) } else { (100_000, 5) };
    println!(
        "plant step, 10 µs, defaults (time-domain cutting, noise, drift), best of {rounds} × {steps}, thread CPU time"
    );
    println!(
        "| modes | plant core `Plant::step` [ns] | FMU step: set {} real inputs, fmi2DoStep, get {} real outputs [ns] | export layer (difference) [ns] | FMU / core | same with `Value`s (generic path) [ns] | generic − direct [ns] |",
        reals(Causality::Input).len(),
        reals(Causality::Output).len()
    );
    println!("|---|---|---|---|---|---|---|");
    for modes in [1, 3] {
        let (mut fmu, mut core, mut generic) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
        for _ in 0..rounds {
            fmu = fmu.min(fmu_ns(steps, modes, false));
            core = core.min(core_ns(steps, modes as u32));
            generic = generic.min(fmu_ns(steps, modes, true));
        }
        let layer = fmu - core;
        let layer = if layer > 0.0 { format!("{layer:.1}") } else { format!("{layer:.1} (within resolution)") };
        println!(
            "| {modes} | {core:.1} | {fmu:.1} | {layer} | {:.2} | {generic:.1} | {:.1} |",
            fmu / core,
            generic - fmu
        );
    }
}
