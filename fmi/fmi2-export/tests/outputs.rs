//! Non-finite outputs never leave `fmi2DoStep` (or initialization) with `fmi2OK`: the audit
//! found ChatterController returning NaN for u, z1, z2, z3 with status OK when an input was
//! ±1e308. The layer checks every Real output after the model's step and answers `fmi2Error`
//! with a message naming the outputs and the inputs.

mod common;

use common::{Oscillator, vr};
use fmi2_export::Environment;
use fmi2_export::instance::{CallError, Instance, LogLevel, LogSink, State};

struct Quiet;
impl LogSink for Quiet {
    fn emit(&mut self, _: LogLevel, _: &str, _: &str) {}
}

fn ready() -> Instance<Oscillator> {
    let mut i = Instance::new(Environment::default(), false, Box::new(Quiet));
    i.setup_experiment(0.0, None).unwrap();
    i.enter_initialization().unwrap();
    i.exit_initialization().unwrap();
    assert_eq!(i.state, State::StepComplete);
    i
}

#[test]
fn an_overflowing_step_is_an_error_naming_the_outputs_not_ok_with_nan() {
    // a finite input the model's arithmetic cannot carry: gain · u = 1e308 · 1e308 = inf
    let mut i = ready();
    i.set_reals("fmi2SetReal", &[vr::GAIN, vr::U], &[1e308, 1e308]).unwrap();
    let e = i.do_step(0.0, 1e-3).unwrap_err();
    let CallError::Error(m) = e else { panic!("expected fmi2Error, got {e:?}") };
    assert!(m.contains("non-finite outputs x = ") && m.contains("v = "), "{m}");
    assert!(m.contains("u = 1e308"), "the message names the input: {m}");
    // the same input at a size the arithmetic carries steps normally
    let mut i = ready();
    i.set_reals("fmi2SetReal", &[vr::U], &[1e200]).unwrap();
    i.do_step(0.0, 1e-3).unwrap();
}

#[test]
fn a_state_that_overflows_from_its_parameters_is_an_error_at_its_first_step() {
    // x0 = 1e308 and k = 1e6 make the first step's v = −1e311: the initial x is finite, the
    // step is not
    let mut i = Instance::<Oscillator>::new(Environment::default(), false, Box::new(Quiet));
    i.set_reals("fmi2SetReal", &[vr::X0, vr::K], &[1e308, 1e6]).unwrap();
    i.setup_experiment(0.0, None).unwrap();
    i.enter_initialization().unwrap();
    i.exit_initialization().unwrap();
    let e = i.do_step(0.0, 1e-3).unwrap_err();
    assert!(matches!(&e, CallError::Error(m) if m.contains("non-finite output")), "{e:?}");
}
