//! Time-domain cross-check of the lobes: the plant core with its **averaged** cutting model
//! (`F_dyn = −a K_t α₀ (x − x(t − τ))`, noise, drift and static feed force off) coupled with the
//! controller core the way a master couples the two FMUs with step `h = T` (Jacobi: the plant
//! integrates over `[t_k, t_k+1]` with the command the controller computed from `y(t_{k−1})`,
//! which is the communication delay `e^{−iωT}` and hold of
//! [`chatter_control::Controller::frequency_response`]).
//!
//! Released from a 1 µm static tip displacement ([`crate::closed_loop::quiet_release`]), the response settles onto
//! the least-damped characteristic root; [`growth_ratio`] compares the peak |x| over the last
//! fifth of the run with the peak over the second fifth ([`GrowthWindows`]): above 1 the cut
//! chatters, below 1 it is stable.

use crate::closed_loop::{CoreLoop, Coupling, quiet_release};
use chatter_control::{ControllerParams, Structure};
use milling_plant::PlantParams;
use milling_plant::params::CuttingModel;
use study_kit::growth::GrowthWindows;

/// Peak |x| over the last fifth of a `duration`-second run divided by the peak over the second
/// fifth, at `rpm` and axial depth `depth` \[m\] (see the module documentation).
pub fn growth_ratio(
    plant: &PlantParams,
    ctrl: Option<&ControllerParams>,
    rpm: f64,
    depth: f64,
    duration: f64,
) -> Result<f64, String> {
    let mut p = quiet_release(plant);
    p.cutting.enabled = true;
    p.cutting.model = CuttingModel::Averaged;
    p.cutting.axial_depth = depth;
    let ctrl = ctrl.filter(|c| c.structure != Structure::Off).map(|c| ControllerParams { u_max: 1e9, ..*c });
    let mut lp = CoreLoop::new(&p, ctrl.as_ref(), Coupling::Jacobi, rpm, 0.0)?;
    let n = lp.samples_in(duration);
    let mut windows = GrowthWindows::new(n);
    Ok(match lp.run(n, |s| windows.push(s.x)) {
        Ok(()) => windows.ratio(),
        Err(_) => f64::INFINITY,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loop_frf;

    /// Depth 1 % below the computed boundary decays, 1 % above grows (the FMU check allows 3 %),
    /// open loop and closed loop with the Table 2 PID, FOPID and ADRC-FOPID.
    #[test]
    fn lobes_agree_with_time_domain_within_1_percent() {
        let plant = loop_frf::seed_plant();
        let c = |s| ControllerParams { structure: s, ..ControllerParams::paper_table2() };
        let (pid, fopid, adrc) = (c(Structure::Pid), c(Structure::Fopid), c(Structure::AdrcFopid));
        let cases =
            [(None, 2866.7), (None, 1800.0), (Some(&pid), 2500.0), (Some(&fopid), 1239.0), (Some(&adrc), 2181.3)];
        for (ctrl, rpm) in cases {
            let prob = loop_frf::problem(&plant, ctrl, 1000.0).unwrap();
            let b = prob.critical_depth(rpm).depth;
            let below = growth_ratio(&plant, ctrl, rpm, 0.99 * b, 1.5).unwrap();
            let above = growth_ratio(&plant, ctrl, rpm, 1.01 * b, 1.5).unwrap();
            let name = ctrl.map_or(Structure::Off, |c| c.structure);
            assert!(below < 1.0 && above > 1.0, "{name:?} {rpm} rpm, b = {b}: ratio below {below}, above {above}");
        }
    }
}
