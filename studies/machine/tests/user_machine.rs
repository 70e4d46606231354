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

/// A low-immersion cut (a_e/D = 0.05): the semi-discretisation finds a flip (period-doubling)
/// lobe where the zero-order method claims a depth several times deeper, and the FMUs confirm
/// the semi-discretisation (decay at 0.97, growth at 1.03).
#[test]
fn a_low_immersion_flip_lobe_is_confirmed_through_the_fmus() {
    use delay_stability::Bifurcation;
    use delay_stability::frequency::{Lobes, ZeroOrder2d};
    let m = Machine::from_toml(include_str!("../examples/end_mill_low_immersion.toml"), "low.toml").unwrap();
    let rpm = 26_970.0;
    let model = m.sd_model().unwrap();
    let o = BisectionOptions { m: 80, start: 1e-3, growth: 1.1, max: 0.1, rel_tol: 1e-4 };
    let c = critical_value(|a| model.at(rpm, a), &o).unwrap();
    assert_eq!(c.kind(), Some(Bifurcation::Flip));
    let b = c.value.unwrap();
    let zo = ZeroOrder2d::new(|w: f64| m.receptance(w), &m.cutter().unwrap(), (1.0, 3300.0), rpm)
        .unwrap()
        .critical_depth(rpm)
        .depth;
    assert!(zo > 2.0 * b, "zero-order {zo} vs SD {b}: the flip lobe is what zero-order misses");
    let check = FmuCheck::new(&m, &packaging::fmu_dir(), None);
    let (below, above) = (check.growth(rpm, 0.97 * b, 0.3).unwrap(), check.growth(rpm, 1.03 * b, 0.3).unwrap());
    println!(
        "flip at {rpm} rpm: SD {:.3} mm, zero-order {:.3} mm; growth {:.3} / {:.3}",
        b * 1e3,
        zo * 1e3,
        below.ratio,
        above.ratio
    );
    assert!(below.ratio < 1.0 && above.ratio > 1.0, "{below:?} {above:?}");
}

/// First-order semi-discretisation converges as 1/m² on the 3-mode machine (successive
/// differences at m = 10, 20, 40, 80 shrink about four-fold), and with four teeth in a slot,
/// where the directional matrix is constant, it converges to the zero-order boundary.
#[test]
fn semi_discretisation_converges_in_m_and_meets_zero_order_where_theory_says() {
    use delay_stability::frequency::{Lobes, ZeroOrder2d};
    let m = Machine::from_toml(USER, "end_mill.toml").unwrap();
    let model = m.sd_model().unwrap();
    let at = |mm: usize, rpm: f64| {
        let o = BisectionOptions { m: mm, start: 3.0e-3, growth: 1.05, max: 0.05, rel_tol: 1e-8 };
        critical_value(|a| model.at(rpm, a), &o).unwrap().value.unwrap()
    };
    let d: Vec<f64> = [10, 20, 40, 80].iter().map(|&mm| at(mm, 10_000.0)).collect();
    let (r1, r2) = ((d[0] - d[1]) / (d[1] - d[2]), (d[1] - d[2]) / (d[2] - d[3]));
    println!("SD at 10000 rpm, m = 10..80: {d:?}; ratios {r1:.2}, {r2:.2}");
    assert!((3.0..5.5).contains(&r1) && (3.0..5.5).contains(&r2), "{d:?}: {r1} {r2}");
    let four = Machine::from_toml(&USER.replace("teeth = 3", "teeth = 4"), "four.toml").unwrap();
    let model4 = four.sd_model().unwrap();
    let zo = ZeroOrder2d::new(|w: f64| four.receptance(w), &four.cutter().unwrap(), (1.0, 3300.0), 5000.0).unwrap();
    for rpm in [7_000.0, 9_500.0] {
        let o = BisectionOptions { m: 40, start: 1e-3, growth: 1.1, max: 0.05, rel_tol: 1e-6 };
        let sd = critical_value(|a| model4.at(rpm, a), &o).unwrap().value.unwrap();
        let z = zo.critical_depth(rpm).depth;
        println!("4 teeth slotting at {rpm} rpm: SD {sd:.6e}, zero-order {z:.6e}");
        assert!((sd / z - 1.0).abs() < 3e-3, "{rpm}: SD {sd} vs zero-order {z}");
    }
}
