//! The hostile audit's per-parameter attacks and the tunable parameters, as checks every adapter
//! runs ([`adapter_tests!`](crate::adapter_tests!)):
//!
//! * [`parameter_extremes_are_safe`]: every numeric parameter and input, one at a time, at NaN,
//!   ±Inf, ±1e308, 0, −1 and its declared min and max (Integers at 0, −1, min, max, `i32::MIN`,
//!   `i32::MAX`): each value is refused with a message, or initialization fails with one, or the
//!   instance steps; no call panics (a panic through the C boundary is `fmi2Error`, here a failed
//!   test: the layer's `catch_unwind` would hide it), none takes more than [`MAX_CALL`], and no
//!   Real output is non-finite after a step that returned OK. (Allocation failures abort the test
//!   process, as they would abort a host: the memory budget, `model_kit::budget`, keeps them out.)
//! * [`tunable_parameters_take_effect`]: every tunable parameter, changed between steps, is in
//!   the running model's parameters after the next step.

use super::{Quiet, distinct_value, ready};
use crate::Fmi2Model;
use crate::instance::Instance;
use crate::model::Environment;
use crate::table::TableModel;
use model_description::{Causality, ScalarType, Value, Variability};
use std::time::{Duration, Instant};

/// The longest a single call may take in [`parameter_extremes_are_safe`].
pub const MAX_CALL: Duration = Duration::from_secs(5);

/// The values one numeric variable is tried at (see the module documentation).
fn extremes(ty: ScalarType, range: (Option<f64>, Option<f64>)) -> Vec<Value> {
    let (lo, hi) = range;
    match ty {
        ScalarType::Real => {
            let mut v = vec![f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e308, -1e308, 0.0, -1.0];
            v.extend(lo.into_iter().chain(hi));
            v.into_iter().map(Value::Real).collect()
        }
        ScalarType::Integer | ScalarType::Enumeration => {
            let mut v = vec![0, -1, i32::MIN, i32::MAX];
            v.extend(lo.into_iter().chain(hi).map(|x| x.clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32));
            v.into_iter().map(Value::Integer).collect()
        }
        _ => Vec::new(),
    }
}

/// Time one call; `Err` if it took longer than [`MAX_CALL`].
fn timed<T>(what: &str, f: impl FnOnce() -> T) -> Result<T, String> {
    let t = Instant::now();
    let r = f();
    if t.elapsed() > MAX_CALL {
        return Err(format!("{what} took {:.1} s (limit {} s)", t.elapsed().as_secs_f64(), MAX_CALL.as_secs()));
    }
    Ok(r)
}

/// Every Real output of `inst` is finite.
fn outputs_finite<M: Fmi2Model>(inst: &mut Instance<M>, what: &str) -> Result<(), String> {
    for v in M::description().variables() {
        if v.causality == Causality::Output && v.scalar_type() == ScalarType::Real {
            let mut out = Vec::new();
            inst.get("fmi2GetReal", ScalarType::Real, &[v.value_reference], &mut out)
                .map_err(|e| format!("{what}: {}: {e:?}", v.name))?;
            if let [Value::Real(x)] = out[..]
                && !x.is_finite()
            {
                return Err(format!("{what}: output {} = {x} after a step that returned OK", v.name));
            }
        }
    }
    Ok(())
}

/// See the module documentation; `h` is the step, `steps` how many are taken after each value.
/// Returns `(values tried, refused or failed with a message, stepped)`.
pub fn parameter_extremes_are_safe<M: Fmi2Model>(h: f64, steps: usize) -> Result<(usize, usize, usize), String> {
    let md = M::description();
    let (mut tried, mut refused, mut ran) = (0, 0, 0);
    for v in md.variables() {
        if !matches!(v.causality, Causality::Parameter | Causality::Input) || v.variability == Variability::Constant {
            continue;
        }
        for x in extremes(v.scalar_type(), v.range()) {
            tried += 1;
            let what = format!("{} = {x:?}", v.name);
            let mut inst = Instance::<M>::new(Environment::default(), false, Box::new(Quiet));
            inst.setup_experiment(0.0, None).map_err(|e| format!("{what}: setup: {e:?}"))?;
            inst.enter_initialization().map_err(|e| format!("{what}: {e:?}"))?;
            let ty = v.scalar_type().api_type();
            if inst.set("fmi2Set", ty, &[v.value_reference], std::slice::from_ref(&x)).is_err() {
                refused += 1;
                continue;
            }
            if timed(&format!("{what}: initialization"), || inst.exit_initialization())?.is_err() {
                refused += 1;
                continue;
            }
            let mut failed = false;
            for k in 0..steps {
                let t = k as f64 * h;
                if timed(&format!("{what}: step {k}"), || inst.do_step(t, h))?.is_err() {
                    failed = true;
                    break;
                }
                outputs_finite(&mut inst, &what)?;
            }
            if failed { refused += 1 } else { ran += 1 }
        }
    }
    Ok((tried, refused, ran))
}

/// See the module documentation. Returns the number of tunable parameters checked.
pub fn tunable_parameters_take_effect<M: TableModel>(h: f64) -> Result<usize, String> {
    let table = M::table();
    let mut n = 0;
    for row in &table.vars().parameters {
        if !row.attrs.tunable {
            continue;
        }
        n += 1;
        let name = row.attrs.name;
        let mut inst = ready::<M>();
        inst.do_step(0.0, h).map_err(|e| format!("{name}: first step: {e:?}"))?;
        let model = inst.model().ok_or("no model")?;
        let new = distinct_value(&row.attrs, row.choice.as_ref(), &row.get(model.parameters()));
        inst.set("fmi2Set", row.ty.api_type(), &[row.attrs.vr], std::slice::from_ref(&new))
            .map_err(|e| format!("{name}: a tunable parameter refused between steps: {e:?}"))?;
        inst.do_step(h, h).map_err(|e| format!("{name}: the step after the change: {e:?}"))?;
        let now = row.get(inst.model().ok_or("no model")?.parameters());
        if now != new {
            return Err(format!("{name}: set to {new:?} between steps, the running model has {now:?}"));
        }
    }
    Ok(n)
}
