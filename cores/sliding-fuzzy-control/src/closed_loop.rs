//! The tool and the controller coupled at the sample period: the loop the study runs and the
//! shipped SSP reproduces with the two FMUs.
//!
//! At `t_k = kT` the controller samples the tool's position and velocity and its force is held
//! on the tool over `[t_k, t_{k+1})` (zero-order hold, no computation delay).

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
