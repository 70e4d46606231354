//! Time-domain cross-check of the lobes: the plant core with its **averaged** cutting model
//! (`F_dyn = −a K_t α₀ (x − x(t − τ))`, noise, drift and static feed force off) coupled with the
//! controller core the way a master couples the two FMUs with step `h = T` (Jacobi: the plant
//! integrates over `[t_k, t_k+1]` with the command the controller computed from `y(t_{k−1})`,
//! which is the communication delay `e^{−iωT}` and hold of
//! [`chatter_control::Controller::frequency_response`]).
//!
//! Released from a 1 µm static tip displacement, the response settles onto the least-damped
//! characteristic root; [`growth_ratio`] compares the peak |x| over the last fifth of the run
//! with the peak over the second fifth: above 1 the cut chatters, below 1 it is stable.

use chatter_control::{Controller, ControllerParams, Structure};
use milling_plant::params::CuttingModel;
use milling_plant::{Plant, PlantInputs, PlantParams};

/// Peak |x| over the last fifth of a `duration`-second run divided by the peak over the second
/// fifth, at `rpm` and axial depth `depth` \[m\] (see the module documentation).
pub fn growth_ratio(
    plant: &PlantParams,
    ctrl: Option<&ControllerParams>,
    rpm: f64,
    depth: f64,
    duration: f64,
) -> Result<f64, String> {
    let mut p = plant.clone();
    p.cutting.enabled = true;
    p.cutting.model = CuttingModel::Averaged;
    p.cutting.axial_depth = depth;
    p.disturbance.noise = false;
    p.disturbance.drift = false;
    p.disturbance.sine_amplitude = 0.0;
    p.workpiece.initial_displacement = 1e-6;
    p.actuator.f_max = 1e9;
    let mut plant = Plant::new(&p).map_err(|e| e.to_string())?;
    let (mut ctrl, ts) = match ctrl {
        Some(c) if c.structure != Structure::Off => {
            (Some(Controller::new(&ControllerParams { u_max: 1e9, ..*c })?), c.ts)
        }
        _ => (None, 1e-5),
    };
    let n = (duration / ts).round() as usize;
    let fifth = n / 5;
    let (mut mid, mut late) = (0.0f64, 0.0f64);
    let mut u = 0.0;
    for k in 0..n {
        let x = plant.outputs().x;
        if (fifth..2 * fifth).contains(&k) {
            mid = mid.max(x.abs());
        }
        if k >= n - fifth {
            late = late.max(x.abs());
        }
        let inputs = PlantInputs { u, spindle_speed_rpm: rpm, feed_per_tooth: 0.0 };
        if plant.step(ts, &inputs).is_err() {
            return Ok(f64::INFINITY);
        }
        if let Some(c) = ctrl.as_mut() {
            u = c.sample(x, 0.0).u;
        }
    }
    Ok(late / mid)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system;

    /// Depth 1 % below the computed boundary decays, 1 % above grows (issue 6 asks for 3 %),
    /// open loop and closed loop with the Table 2 PID, FOPID and ADRC-FOPID.
    #[test]
    fn lobes_agree_with_time_domain_within_1_percent() {
        let plant = system::seed_plant();
        let c = |s| ControllerParams { structure: s, ..ControllerParams::paper_table2() };
        let (pid, fopid, adrc) = (c(Structure::Pid), c(Structure::Fopid), c(Structure::AdrcFopid));
        let cases =
            [(None, 2866.7), (None, 1800.0), (Some(&pid), 2500.0), (Some(&fopid), 1239.0), (Some(&adrc), 2181.3)];
        for (ctrl, rpm) in cases {
            let prob = system::problem(&plant, ctrl, 1000.0).unwrap();
            let b = prob.critical_depth(rpm).depth;
            let below = growth_ratio(&plant, ctrl, rpm, 0.99 * b, 1.5).unwrap();
            let above = growth_ratio(&plant, ctrl, rpm, 1.01 * b, 1.5).unwrap();
            let name = ctrl.map_or(Structure::Off, |c| c.structure);
            assert!(below < 1.0 && above > 1.0, "{name:?} {rpm} rpm, b = {b}: ratio below {below}, above {above}");
        }
    }
}
