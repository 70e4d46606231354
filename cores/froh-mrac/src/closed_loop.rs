//! # The closed loop on the cores
//!
//! Communication steps `h = T/M` from `t = 0`, Gauss–Seidel in the order controller, plant
//! (the order of the shipped `ForceControl.ssd`): at `t_j = j·h` the controller reads `F_p(t_j)`
//! and the reference, steps `[t_j, t_j + h)` and hands the plant the mean and slope of its
//! held command, with which the plant steps exactly. Because the samples fall on communication
//! points and the plant integrates the ramp, the result does not depend on M at the samples.

use crate::mrac::{FrohMrac, MracOutputs, MracParams};
use milling_force_plant::ForceError;
use milling_force_plant::plant::{ForcePlant, ForcePlantInputs, ForcePlantParams};

/// One recorded communication point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoopSample {
    /// Time [s].
    pub t: f64,
    /// Cutting force F_p(t) [N].
    pub force: f64,
    /// Reference-model force F_m(t) [N].
    pub reference_force: f64,
    /// Mean command over the step that ended at t [mm/s].
    pub feed_command: f64,
    /// Depth of cut in force at t [mm].
    pub depth: f64,
    /// Controller outputs after the step that ended at t.
    pub controller: MracOutputs,
}

/// Runs plant and controller for `steps` communication steps of `T/substeps` with a constant
/// reference force `f_ref` [N]; returns the `steps + 1` points from t = 0.
pub fn simulate(
    plant: &ForcePlantParams,
    ctrl: &MracParams,
    f_ref: f64,
    substeps: u32,
    steps: usize,
) -> Result<Vec<LoopSample>, ForceError> {
    if substeps == 0 {
        return Err(ForceError::Params("substeps must be >= 1".into()));
    }
    let mut p = ForcePlant::new(plant)?;
    let mut c = FrohMrac::new(ctrl)?;
    let h = ctrl.sample_period / substeps as f64;
    let o = p.outputs();
    let mut out = Vec::with_capacity(steps + 1);
    out.push(LoopSample {
        t: 0.0,
        force: o.force,
        reference_force: 0.0,
        feed_command: 0.0,
        depth: o.depth,
        controller: c.outputs(),
    });
    for j in 0..steps {
        let t = j as f64 * h;
        let y = p.outputs().force;
        let co = c.step(t, h, y, f_ref)?;
        p.step(h, &ForcePlantInputs { feed_command: co.feed_command, feed_command_rate: co.feed_command_rate })?;
        // the plant's clock as t₀ + j·h, not a running sum
        p.set_time((j + 1) as f64 * h);
        let o = p.outputs();
        out.push(LoopSample {
            t: (j + 1) as f64 * h,
            force: o.force,
            reference_force: co.reference_force,
            feed_command: co.feed_command,
            depth: o.depth,
            controller: co,
        });
    }
    Ok(out)
}
