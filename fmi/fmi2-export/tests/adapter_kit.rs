//! The adapter kit on small table models (feature `checks`, which every adapter's tests enable;
//! `cargo test -p fmi2-export --features checks`): `adapter!` (the `TableModel`,
//! `parameter_assignments`, the step errors), `Table::description`, the scaled work bound,
//! `checks::work_is` refusing what it must, and `adapter_tests!` itself run on the models.
#![cfg(feature = "checks")]
#![allow(missing_docs)]

use fmi2_export::table::TableModel;
use fmi2_export::table::checks::{self, Work};
use fmi2_export::{Environment, Fmi2Model, Header, ModelLog, StepError, Table, Values};
use model_description::{ModelDescription, Value};
use serde::{Deserialize, Serialize};
use std::sync::LazyLock;

/// First-order decay `x' = -rate x + u` by explicit Euler on a grid of `dt`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DecayParams {
    pub rate: f64,
    pub dt: f64,
}

impl Default for DecayParams {
    fn default() -> Self {
        DecayParams { rate: 2.0, dt: 1e-3 }
    }
}

#[derive(Clone, Copy, Debug, Default)]
pub struct DecayInputs {
    pub u: f64,
}

#[derive(Clone, Copy, Debug, Default)]
pub struct DecayOutputs {
    pub x: f64,
}

/// The core's errors: an input it refuses, and a state it cannot continue from.
#[derive(Debug)]
pub enum DecayError {
    Input(String),
    Diverged(String),
}

impl std::fmt::Display for DecayError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DecayError::Input(m) => write!(f, "input: {m}"),
            DecayError::Diverged(m) => write!(f, "diverged: {m}"),
        }
    }
}

#[derive(Clone, Serialize, Deserialize)]
pub struct Core {
    p: DecayParams,
    x: f64,
}

impl Core {
    fn step(&mut self, h: f64, u: f64) -> Result<(), DecayError> {
        if u.abs() > 1e3 {
            return Err(DecayError::Input(format!("u = {u} beyond 1e3")));
        }
        let n = (h / self.p.dt).ceil().max(1.0) as usize;
        for _ in 0..n {
            self.x += h / n as f64 * (-self.p.rate * self.x + u);
        }
        if self.x.abs() > 1e6 {
            return Err(DecayError::Diverged(format!("x = {}", self.x)));
        }
        Ok(())
    }
}

fn table(identifier: &'static str) -> Table<DecayParams, DecayInputs, DecayOutputs> {
    Table::new(
        Header { model_name: identifier, identifier, description: "test model", default_experiment: (0.0, 1.0, 1e-3) },
        fmi2_export::variables! {
            inputs DecayInputs {
                0 "u" [u] "1" [] "forcing";
            }
            outputs DecayOutputs {
                1 "x" [x] "1" [] "state";
            }
            parameters DecayParams {
                2 "rate" [rate] "1/s" [0.0, 1e3] "decay rate";
                3 "dt" [dt] "s" [1e-6, 1.0] "grid";
            }
        },
    )
}

/// One model type per work declaration: `$cost` is its `internal_steps(h)` with `p` = `dt`.
macro_rules! decay_model {
    ($M:ident, $TABLE:ident = $table:expr, |$p:ident, $h:ident| $cost:expr) => {
        pub static $TABLE: LazyLock<Table<DecayParams, DecayInputs, DecayOutputs>> = LazyLock::new(|| $table);

        #[derive(Clone, Serialize, Deserialize)]
        pub struct $M(Core);

        fmi2_export::adapter! {
            model: $M,
            table: $TABLE as Table<DecayParams, DecayInputs, DecayOutputs>,
            parameters: |m| &m.0.p,
            input_errors: DecayError::Input,
        }

        impl Fmi2Model for $M {
            fn description() -> &'static ModelDescription {
                $TABLE.description()
            }
            fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
                Ok($M(Core { p: $TABLE.read_parameters(values)?, x: 1.0 }))
            }
            fn update_outputs(&self, v: &mut Values) {
                $TABLE.write_outputs(&DecayOutputs { x: self.0.x }, v);
            }
            fn do_step(&mut self, v: &mut Values, _t: f64, h: f64, _log: &mut dyn ModelLog) -> Result<(), StepError> {
                let u = $TABLE.read_inputs(v).map_err(StepError::Error)?.u;
                self.0.step(h, u).map_err(Self::step_error)?;
                self.update_outputs(v);
                Ok(())
            }
            fn internal_steps(&self, $h: f64) -> f64 {
                let $p = self.0.p.dt;
                $cost
            }
        }
    };
}

mod bounded {
    use super::*;
    decay_model!(Decay, TABLE = table("Decay").work_bound("dt", 1.0), |p, h| h / p + 1.0);
}
mod scaled {
    use super::*;
    decay_model!(Halves, TABLE = table("Halves").work_bound_scaled("dt", 2.0, 2.0), |p, h| 2.0 * h / p + 2.0);
}
mod unscaled {
    use super::*;
    // the FROH case before `work_bound_scaled`: twice the declared cost
    decay_model!(Mismatched, TABLE = table("Mismatched").work_bound("dt", 2.0), |p, h| 2.0 * h / p + 2.0);
}
mod undeclared {
    use super::*;
    decay_model!(Grows, TABLE = table("Grows"), |p, h| h / p + 1.0);
}
mod fixed {
    use super::*;
    decay_model!(Flat, TABLE = table("Flat"), |_p, _h| 3.0);
}
use bounded::Decay;
use fixed::Flat;
use scaled::Halves;
use undeclared::Grows;
use unscaled::Mismatched;

mod decay_checks {
    use super::*;
    fmi2_export::adapter_tests! {
        model: Decay,
        valid: [],
        params: [DecayParams { rate: 0.5, dt: 1e-4 }],
        work: Work::Bound("dt"),
        step: 1e-3,
        states: { stepped: checks::stepped::<Decay>(1.0, 10, 1e-3), fresh: checks::ready::<Decay>, seed: 7, tries: 200 },
    }
}

mod halves_checks {
    use super::*;
    fmi2_export::adapter_tests! {
        model: Halves,
        valid: [],
        params: [],
        work: Work::Bound("dt"),
        step: 1e-3,
        states: { stepped: checks::stepped::<Halves>(1.0, 10, 1e-3), fresh: checks::ready::<Halves>, seed: 7, tries: 200 },
    }
}

#[test]
fn adapter_gives_the_table_model_and_parameter_assignments() {
    assert!(std::ptr::eq(Decay::table(), &*bounded::TABLE));
    let mut inst = checks::ready_with::<Decay>(&[("rate", Value::Real(0.25))]);
    assert_eq!(inst.model().unwrap().parameters(), &DecayParams { rate: 0.25, dt: 1e-3 });
    let pairs = bounded::parameter_assignments(&DecayParams { rate: 0.5, dt: 1e-4 });
    assert_eq!(pairs, [("rate".to_string(), Value::Real(0.5)), ("dt".to_string(), Value::Real(1e-4))]);
    inst.do_step(0.0, 1e-3).unwrap();
}

/// An input error of the core is `fmi2Discard` (the instance steps on), any other `fmi2Error`,
/// each with the core's message.
#[test]
fn input_errors_discard_the_step_other_errors_are_errors() {
    use fmi2_export::instance::CallError;
    let mut inst = checks::ready::<Decay>();
    checks::set_real(&mut inst, "u", 2e3);
    match inst.do_step(0.0, 1e-3) {
        Err(CallError::Discard(m)) => assert!(m.contains("input: u = 2000 beyond 1e3"), "{m}"),
        other => panic!("expected fmi2Discard, got {other:?}"),
    }
    let mut inst = checks::ready_with::<Decay>(&[("rate", Value::Real(0.0))]);
    checks::set_real(&mut inst, "u", 1e3);
    let mut t = 0.0;
    let err = loop {
        match inst.do_step(t, 1.0) {
            Ok(()) => t += 1.0,
            Err(e) => break e,
        }
    };
    match err {
        CallError::Error(m) => assert!(m.contains("diverged: x = "), "{m}"),
        other => panic!("expected fmi2Error, got {other:?}"),
    }
}

#[test]
fn the_description_is_built_once_from_the_defaults() {
    let (a, b) = (Decay::description(), Decay::description());
    assert!(std::ptr::eq(a, b));
    assert_eq!(*a, bounded::TABLE.model_description(&DecayParams::default()).unwrap());
}

/// `work_bound_scaled("dt", 2, 2)` declares `h/dt + 1` steps of `dt`, at most 5e6 per call: a
/// master refuses exactly the steps the layer refuses at 1e7 of its own.
#[test]
fn a_scaled_work_bound_counts_in_steps_of_the_parameter() {
    let w = Decay::description().work_bound().unwrap();
    assert_eq!((w.max_internal_steps_per_call, w.extra_internal_steps_per_call), (1e7, 1.0));
    let w = Halves::description().work_bound().unwrap();
    assert_eq!(
        (w.internal_step_parameter.as_str(), w.max_internal_steps_per_call, w.extra_internal_steps_per_call),
        ("dt", 5e6, 1.0)
    );
    let edge = w.max_step(1e-3);
    for (h, refused) in [(1.0001 * edge, true), (0.9999 * edge, false)] {
        assert_eq!(w.exceeded(h, 1e-3), refused, "h = {h}: the annotation");
        assert_eq!(checks::ready::<Halves>().do_step(0.0, h).is_err(), refused, "h = {h}: the layer");
    }
}

#[test]
fn work_checks_refuse_what_the_model_does_not_do() {
    let err = |r: Result<(), String>| r.expect_err("accepted");
    // a declared bound that is not the model's cost, or on another parameter, or not declared
    assert!(err(checks::work_is::<Mismatched>(Work::Bound("dt"))).contains("the model counts"));
    assert!(err(checks::work_is::<Decay>(Work::Bound("rate"))).contains("on Some(\"dt\")"));
    assert!(err(checks::work_is::<Grows>(Work::Bound("dt"))).contains("on None"));
    // a bound declared where the adapter says there is none
    assert!(err(checks::work_is::<Decay>(Work::Fixed)).contains("declares a work bound on dt"));
    // a cost that grows with h without a declaration is not Fixed, and needs a reason
    assert!(err(checks::work_is::<Grows>(Work::Fixed)).contains("grows with h"));
    assert!(err(checks::work_is::<Grows>(Work::Undeclared(" "))).contains("needs a reason"));
    checks::work_is::<Grows>(Work::Undeclared("the grid is not a parameter")).unwrap();
    // a cost that does not grow is Fixed, not Undeclared
    checks::work_is::<Flat>(Work::Fixed).unwrap();
    assert!(err(checks::work_is::<Flat>(Work::Undeclared("why"))).contains("Work::Fixed"));
}
