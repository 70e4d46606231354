//! The machine's time-periodic lobes are converged by default (issue 32): the spectral
//! collocation of `delay_stability` against its reference, the first-order semi-discretisation
//! extrapolated in m (Richardson on m = 160 and 320, error `c/m²`), on the end mill
//! (3 modes in x and y, slotting) and on its low-immersion flip lobe; and what `--sd-m` selects.

use delay_stability::{Bifurcation, LobeOptions, Method, critical};
use machine::Machine;
use machine::lobes::{MachineLobes, discretisation};

fn end_mill() -> Machine {
    Machine::from_toml(include_str!("../examples/end_mill.toml"), "end_mill.toml").unwrap()
}

/// SD at m = 160 and 320 extrapolated to m → ∞ (the first-order method's error is `c/m²`).
fn richardson(m: &Machine, rpm: f64, start: f64) -> f64 {
    let model = m.sd_model().unwrap();
    let sd = |mm: usize| {
        let o = LobeOptions { method: Method::Sd { m: mm }, start, growth: 1.1, max: 0.1, rel_tol: 1e-7 };
        critical(|a| model.at(rpm, a), &o).unwrap().value.unwrap()
    };
    let (a, b) = (sd(160), sd(320));
    (4.0 * b - a) / 3.0
}

/// What `MachineLobes::compute` reports by default is converged, within 0.1 % of extrapolated SD
/// at the lowest speed of the file's range (where SD at m = 40 is worst), a middle and a high
/// speed. Mutation check: with the default switched to `Method::Sd { m: 40 }` the low speed fails
/// (SD m = 40 is above 0.1 % there) and the `discretisation` assertion fails.
#[test]
fn the_default_lobes_agree_with_extrapolated_semi_discretisation() {
    let m = end_mill();
    let speeds = [3000.0, 9000.0, 16000.0];
    let l = MachineLobes::compute(&m, &speeds, discretisation(None), &|_, _| {}).unwrap();
    assert_eq!(l.discretisation, Method::Auto { tol: 1e-3 });
    let model = m.sd_model().unwrap();
    for (i, &rpm) in speeds.iter().enumerate() {
        let conv = l.sd_depth(i);
        let reference = richardson(&m, rpm, 0.5 * conv);
        let sd40 = critical(
            |a| model.at(rpm, a),
            &LobeOptions { method: Method::Sd { m: 40 }, start: 0.5 * conv, growth: 1.1, max: 0.1, rel_tol: 1e-7 },
        )
        .unwrap()
        .value
        .unwrap();
        println!(
            "{rpm} rpm: converged {:.6} mm ({:?}, estimate {:.1e}), SD extrapolated {:.6} mm ({:+.4} %), SD m = 40 {:.6} mm ({:+.3} %)",
            conv * 1e3,
            l.sd[i].critical.method,
            l.sd[i].critical.error.unwrap(),
            reference * 1e3,
            100.0 * (conv / reference - 1.0),
            sd40 * 1e3,
            100.0 * (sd40 / reference - 1.0)
        );
        assert!(matches!(l.sd[i].critical.method, Method::Spectral(_)), "{:?}", l.sd[i].critical.method);
        assert!((conv / reference - 1.0).abs() < 1e-3, "{rpm} rpm: converged {conv} vs extrapolated SD {reference}");
    }
}

/// The low-immersion flip lobe (the example file's 26970 rpm, a_e/D = 0.05): the converged
/// default finds the same flip within 0.1 % of extrapolated SD.
#[test]
fn the_default_finds_the_low_immersion_flip_lobe() {
    let m = Machine::from_toml(include_str!("../examples/end_mill_low_immersion.toml"), "low.toml").unwrap();
    let rpm = 26_970.0;
    let l = MachineLobes::compute(&m, &[rpm], discretisation(None), &|_, _| {}).unwrap();
    assert_eq!(l.sd[0].critical.kind(), Some(Bifurcation::Flip));
    let (conv, reference) = (l.sd_depth(0), richardson(&m, rpm, 1e-3));
    println!("flip at {rpm} rpm: converged {:.6} mm, SD extrapolated {:.6} mm", conv * 1e3, reference * 1e3);
    assert!((conv / reference - 1.0).abs() < 1e-3, "converged {conv} vs extrapolated SD {reference}");
}

/// `--sd-m M` (and `sd_m=M` in Python) selects the semi-discretisation of order M, which gives
/// the reference path's numbers.
#[test]
fn an_sd_order_selects_the_semi_discretisation() {
    assert_eq!(discretisation(Some(40)), Method::Sd { m: 40 });
    let m = end_mill();
    let l = MachineLobes::compute(&m, &[10_000.0], discretisation(Some(40)), &|_, _| {}).unwrap();
    assert_eq!(l.sd[0].critical.method, Method::Sd { m: 40 });
    assert!(l.report(&m).contains("semi-discretisation, m = 40"), "{}", l.report(&m));
}
