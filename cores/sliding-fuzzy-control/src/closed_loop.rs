//! The tool and the controller coupled at the sample period: the loop the study runs and the
//! shipped SSP reproduces with the two FMUs.
//!
//! At `t_k = kT` the controller samples the tool's position and velocity and its force is held
//! on the tool over `[t_k, t_{k+1})` (zero-order hold; with `computation_delay` the force of the
//! previous sample). [`simulate_coupled`] runs the same loop the way a co-simulation master
//! does, with a communication step `T/M` in Gauss–Seidel or Jacobi order.

use crate::SlidingFuzzyError;
use crate::controller::{SlidingFuzzy, SlidingFuzzyParams};
use tool_xy::{ToolInputs, ToolParams, ToolPlant};

/// Samples of one run, one entry per sample instant `t_k` (before the force of `t_k` acts).
/// Displacements are measured from the static deflection of the cut
/// ([`ToolPlant::static_deflection`]): the controllers see the vibration, as the paper's
/// accelerometer-based positions (integrators and filters) do.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoopRecord {
    /// Time [s].
    pub t: Vec<f64>,
    /// Tool displacement x [m].
    pub x: Vec<f64>,
    /// Tool displacement y [m].
    pub y: Vec<f64>,
    /// Force command x [N].
    pub ux: Vec<f64>,
    /// Force command y [N].
    pub uy: Vec<f64>,
    /// Largest |damper stroke| over the run [m] (x, y).
    pub max_stroke: [f64; 2],
}

impl LoopRecord {
    /// Mean squared displacements `(x, y)` in mm² over `t ∈ [t0, t1]` (the paper's MSE).
    pub fn mse_mm(&self, t0: f64, t1: f64) -> [f64; 2] {
        let mut acc = [0.0; 2];
        let mut n = 0usize;
        for (i, &t) in self.t.iter().enumerate() {
            if t >= t0 - 1e-12 && t <= t1 + 1e-12 {
                acc[0] += (1e3 * self.x[i]).powi(2);
                acc[1] += (1e3 * self.y[i]).powi(2);
                n += 1;
            }
        }
        acc.map(|a| a / n.max(1) as f64)
    }
}

/// Run the loop from rest to `t_end`; returns the record and the final controller (its learned
/// weights).
pub fn simulate(
    tool: &ToolParams,
    ctrl: &SlidingFuzzyParams,
    t_end: f64,
) -> Result<(LoopRecord, SlidingFuzzy), SlidingFuzzyError> {
    let mut plant = ToolPlant::new(tool)?;
    let mut c = SlidingFuzzy::new(ctrl)?;
    let xs = plant.static_deflection();
    let n = (t_end / ctrl.sample_period).round() as usize;
    let mut r = LoopRecord::default();
    for k in 0..=n {
        let o = plant.outputs();
        r.t.push(k as f64 * ctrl.sample_period);
        r.x.push(o.x - xs[0]);
        r.y.push(o.y - xs[1]);
        r.max_stroke[0] = r.max_stroke[0].max(o.damper_x.abs());
        r.max_stroke[1] = r.max_stroke[1].max(o.damper_y.abs());
        if k == n {
            break;
        }
        let u = c.sample([o.x - xs[0], o.y - xs[1]], [o.vx, o.vy])?.u;
        r.ux.push(u[0]);
        r.uy.push(u[1]);
        plant.step(ctrl.sample_period, &ToolInputs { ux: u[0], uy: u[1] })?;
    }
    Ok((r, c))
}

/// The loop as a co-simulation master runs the two FMUs: communication steps `h = T/substeps`
/// from `t = 0`, the controller stepped by [`SlidingFuzzy::step`] (samples at `kT`, the force
/// of the current sample period as its output). Gauss–Seidel (`jacobi = false`, the shipped
/// order controller → plant): the plant steps `[t, t + h)` with the controller's output after
/// its step from `t`. Jacobi: with the output from before that step (one communication step
/// older: different from Gauss–Seidel in the first step after each sample instant). Recorded
/// at the sample instants, as [`simulate`]; with `substeps = 1` and Gauss–Seidel the record
/// equals [`simulate`]'s.
pub fn simulate_coupled(
    tool: &ToolParams,
    ctrl: &SlidingFuzzyParams,
    t_end: f64,
    substeps: u32,
    jacobi: bool,
) -> Result<LoopRecord, SlidingFuzzyError> {
    if substeps == 0 {
        return Err(SlidingFuzzyError::Params("substeps must be >= 1".into()));
    }
    let mut plant = ToolPlant::new(tool)?;
    let mut c = SlidingFuzzy::new(ctrl)?;
    let xs = plant.static_deflection();
    let m = substeps as usize;
    let h = ctrl.sample_period / substeps as f64;
    let n = (t_end / ctrl.sample_period).round() as usize * m;
    let mut r = LoopRecord::default();
    let mut held = c.outputs().u;
    for j in 0..=n {
        let o = plant.outputs();
        if j % m == 0 {
            r.t.push((j / m) as f64 * ctrl.sample_period);
            r.x.push(o.x - xs[0]);
            r.y.push(o.y - xs[1]);
        }
        r.max_stroke[0] = r.max_stroke[0].max(o.damper_x.abs());
        r.max_stroke[1] = r.max_stroke[1].max(o.damper_y.abs());
        if j == n {
            break;
        }
        let u = c.step(j as f64 * h, h, [o.x - xs[0], o.y - xs[1]], [o.vx, o.vy])?.u;
        let applied = if jacobi { std::mem::replace(&mut held, u) } else { u };
        if j % m == 0 {
            r.ux.push(applied[0]);
            r.uy.push(applied[1]);
        }
        plant.step(h, &ToolInputs { ux: applied[0], uy: applied[1] })?;
    }
    Ok(r)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ControlMode;

    fn tool() -> ToolParams {
        ToolParams { forcing_amplitude: [0.3, 48.0], ..Default::default() }
    }

    /// Gauss–Seidel with h = T is the study's loop; Jacobi with h = T is the same controller
    /// with one sample of computation delay: for the D-PID, whose delayed form is the plain one
    /// a sample later, bitwise.
    #[test]
    fn jacobi_coupling_is_one_sample_of_computation_delay() {
        let t_end = 0.02;
        for mode in [ControlMode::Dpid, ControlMode::DsmcT2] {
            let p = SlidingFuzzyParams { mode, ..Default::default() };
            let (r, _) = simulate(&tool(), &p, t_end).unwrap();
            let gs = simulate_coupled(&tool(), &p, t_end, 1, false).unwrap();
            assert_eq!((&gs.x, &gs.y, &gs.ux), (&r.x, &r.y, &r.ux), "{mode:?}");
        }
        let p = SlidingFuzzyParams { mode: ControlMode::Dpid, ..Default::default() };
        let jacobi = simulate_coupled(&tool(), &p, t_end, 1, true).unwrap();
        let (delayed, _) = simulate(&tool(), &SlidingFuzzyParams { computation_delay: true, ..p }, t_end).unwrap();
        assert_eq!((&jacobi.x, &jacobi.y, &jacobi.ux), (&delayed.x, &delayed.y, &delayed.ux));
        assert!(jacobi.x.iter().any(|v| v.abs() > 1e-9), "the forcing reaches the tool");
    }

    /// Sub-steps do not change the Gauss–Seidel loop: the controller samples at kT, the plant's
    /// grid is the same (bitwise, the plant's time is counted in its own steps).
    #[test]
    fn gauss_seidel_does_not_depend_on_the_communication_step() {
        let p = SlidingFuzzyParams::default();
        let one = simulate_coupled(&tool(), &p, 0.01, 1, false).unwrap();
        let ten = simulate_coupled(&tool(), &p, 0.01, 10, false).unwrap();
        assert_eq!((&one.x, &one.y), (&ten.x, &ten.y));
    }
}
