//! The ordinary end mill, end to end: the semi-discretisation boundary confirmed through
//! the FMUs (decay at 0.97, growth at 1.03).

use delay_stability::{BisectionOptions, critical_value};
use machine::Machine;
use machine::fmus::FmuCheck;

const USER: &str = include_str!("../examples/end_mill.toml");

fn sd_boundary(m: &Machine, rpm: f64) -> f64 {
    let model = m.sd_model().unwrap();
    let o = BisectionOptions { m: 40, start: 0.2e-3, growth: 1.15, max: 0.05, rel_tol: 1e-4 };
    critical_value(|a| model.at(rpm, a), &o).unwrap().value.unwrap()
}

#[test]
fn sd_boundary_is_confirmed_through_the_fmus() {
    let m = Machine::from_toml(USER, "end_mill.toml").unwrap();
    let check = FmuCheck::new(&m, &packaging::fmu_dir(), None);
    for rpm in [10_000.0, 16_000.0] {
        let b = sd_boundary(&m, rpm);
        let below = check.growth(rpm, 0.97 * b, 0.4).unwrap();
        let above = check.growth(rpm, 1.03 * b, 0.4).unwrap();
        println!("{rpm} rpm: SD {:.3} mm; growth 0.97: {:.3}, 1.03: {:.3}", b * 1e3, below.ratio, above.ratio);
        assert!(below.ratio < 1.0 && above.ratio > 1.0, "{rpm} rpm, SD {b}: {below:?} {above:?}");
    }
}

/// A controller tuned for the machine (by `chatter tune --machine`, PID): below its usable
/// closed-loop depth the FMU loop neither chatters nor saturates; 3 % above a stability limit it
/// grows, 3 % above a saturation limit (the steady cut's command reaching ±27 N, by harmonic
/// balance) the command saturates.
#[test]
fn closed_loop_depths_hold_in_the_time_domain() {
    use chatter_control::{ControllerParams, Structure};
    use machine::closed::{Limit, closed_loop_lobes};
    let m = Machine::from_toml(USER, "end_mill.toml").unwrap();
    let mut c = ControllerParams { structure: Structure::Pid, u_max: 27.0, ..ControllerParams::tuned() };
    (c.pid.kp, c.pid.ki, c.pid.kd) = (1113.68, 0.2665, 200.49);
    let check = FmuCheck::new(&m, &packaging::fmu_dir(), Some(c));
    let mut limits = Vec::new();
    for rpm in [8186.0, 12000.0] {
        let p = closed_loop_lobes(&m, &c, &[rpm], None).unwrap()[0];
        let below = check.growth(rpm, 0.97 * p.usable(), 0.4).unwrap();
        let above = check.growth(rpm, 1.03 * p.usable(), 0.4).unwrap();
        println!(
            "{rpm} rpm: stability {:.3} mm, saturation {:.3} mm; 0.97: {below:?}; 1.03: {above:?}",
            p.stability * 1e3,
            p.saturation * 1e3
        );
        assert!(below.ratio < 1.0 && !below.saturated, "{rpm} rpm below the usable depth: {below:?}");
        match p.limit() {
            Limit::Stability => assert!(above.ratio > 1.0, "{rpm} rpm above the stability limit: {above:?}"),
            Limit::Saturation => assert!(above.saturated, "{rpm} rpm above the saturation limit: {above:?}"),
        }
        limits.push(p.limit());
    }
    assert_eq!(limits, [Limit::Stability, Limit::Saturation], "one speed of each kind");
}
