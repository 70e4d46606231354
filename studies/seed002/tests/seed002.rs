//! Seed 002 on the FMUs (`Spindle.ssp`: MillingProcess + SpindleStructure + LinearController in
//! the Rust master): 3 % below the semi-discretisation boundary the regenerative difference
//! decays, 3 % above it grows, open loop and with the printed §6.1 gains (and with the shipped
//! synthesised designs); and the closed-loop tool FRF. Needs the FMUs of `target/fmu` (`cargo run --release -p packaging`).

use delay_stability::presets::SEED002_GAINS;
use delay_stability::{BisectionOptions, critical_value};
use seed002::presets::Preset;
use seed002::spindle::{SpindleCheck, closed_peak, design_params, sd_boundary, spindle_system, static_gain, tool_frf};

#[test]
fn fmus_decay_below_and_grow_above_the_sd_boundary_open_and_closed_loop() {
    let dir = packaging::fmu_dir();
    assert!(
        dir.join("SpindleStructure.fmu").is_file(),
        "no FMUs in {}: run `cargo run --release -p packaging`",
        dir.display()
    );
    let sys = spindle_system(&dir).unwrap();
    let mut check = SpindleCheck::new(&sys);
    // the process enters the cut over 10 ms: a full engagement at once rings the spindle with
    // about its static deflection and teeth leave the cut (README)
    check.ramp = 0.01;
    let o = BisectionOptions { m: 40, start: 0.3e-3, growth: 1.1, max: 0.02, rel_tol: 1e-5 };
    let mut failures = Vec::new();
    // the closed loop's instability is fast and reaches loss of contact after about 0.1 s, so
    // its run is 0.1 s; the open loop's grows slowly
    for (preset, gains, rpm, duration) in
        [(Preset::Seed002Open61, None, 38_000.0, 0.25), (Preset::Seed002Closed61, Some(SEED002_GAINS), 37_800.0, 0.1)]
    {
        let model = preset.model().unwrap();
        let a = critical_value(|d| model.at(rpm, d), &o).unwrap().value.unwrap();
        let c = static_gain(gains);
        let below = check.growth_ratio(rpm, 0.97 * a, &c, duration).unwrap();
        let above = check.growth_ratio(rpm, 1.03 * a, &c, duration).unwrap();
        eprintln!("{preset:?} {rpm} rpm, SD a = {:.4} mm: ratio 0.97a {below:.4}, 1.03a {above:.4}", a * 1e3);
        if !(below < 1.0 && above > 1.0) {
            failures.push(format!("{preset:?} {rpm} rpm, a = {a}: below {below}, above {above}"));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}

/// The shipped synthesised designs (`target/fmu/designs/*.ssv`, bound through LinearController's
/// own table) on the FMUs: the static §6.1 design (x_F = 1) and the dynamic Table II n_c = 2
/// design (x_F = 0.744, power-law process) decay at 0.97 and grow at 1.03 of their own
/// semi-discretisation boundary.
#[test]
fn shipped_designs_decay_below_and_grow_above_their_sd_boundary_on_the_fmus() {
    let dir = packaging::fmu_dir();
    let sys = spindle_system(&dir).unwrap();
    let mut check = SpindleCheck::new(&sys);
    check.ramp = 0.01;
    let mut failures = Vec::new();
    for (file, x_f, rpm) in [("sec6_1.ssv", 1.0, 37_800.0), ("table2_nc2.ssv", 0.744, 36_000.0)] {
        let c = design_params(&dir.join("designs").join(file)).unwrap();
        check.x_f = x_f;
        let a = sd_boundary(Some(&c), x_f, rpm, 40).unwrap();
        let below = check.growth_ratio(rpm, 0.97 * a, &c, 0.1).unwrap();
        let above = check.growth_ratio(rpm, 1.03 * a, &c, 0.1).unwrap();
        eprintln!(
            "{file} (n_c = {}) {rpm} rpm, SD a = {:.4} mm: ratio 0.97a {below:.4}, 1.03a {above:.4}",
            c.n_c,
            a * 1e3
        );
        if !(below < 1.0 && above > 1.0) {
            failures.push(format!("{file}: a = {a}: below {below}, above {above}"));
        }
    }
    // the designs are what the README reports (§6.1: k1 = 1000.61, k2 = −973.80 N/mm; n_c = 2)
    let sec61 = design_params(&dir.join("designs/sec6_1.ssv")).unwrap();
    assert_eq!(sec61.n_c, 0);
    assert!(
        (sec61.dc[0][0] / 1e3 - 1000.61).abs() < 0.01 && (sec61.dc[1][0] / 1e3 + 973.80).abs() < 0.01,
        "{:?}",
        sec61.dc
    );
    assert_eq!(design_params(&dir.join("designs/table2_nc2.ssv")).unwrap().n_c, 2);
    assert!(failures.is_empty(), "{failures:?}");
}

#[test]
fn the_printed_gains_move_the_first_tool_resonance() {
    let hz: Vec<f64> = (0..=1200).map(|k| 500.0 + 2.5 * k as f64).collect();
    // zero gain: the closed loop is the open loop
    for r in tool_frf(&static_gain(None), 37_000.0, &hz).unwrap() {
        assert!((r.closed[0] - r.open[0]).norm() <= 1e-12 * r.open[0].norm());
    }
    let rows = tool_frf(&static_gain(Some(SEED002_GAINS)), 37_000.0, &hz).unwrap();
    let first = |f: &dyn Fn(&seed002::spindle::FrfRow) -> f64| {
        rows.iter()
            .filter(|r| r.hz < 1800.0)
            .map(|r| (r.hz, f(r)))
            .fold((0.0, 0.0), |m, p| if p.1 > m.1 { p } else { m })
    };
    let (ho, go) = first(&|r| r.open[0].norm());
    let (hc, gc) = first(&|r| r.closed[0].norm());
    eprintln!(
        "first tool resonance |G_xx|: open {go:.4e} m/N at {ho} Hz, closed {gc:.4e} m/N at {hc} Hz; overall closed peak at {:?} Hz",
        closed_peak(&rows)
    );
    // the paper (Figure 10): the controller shifts the first resonance
    assert!((ho / 1296.7f64 - 1.0).abs() < 0.05, "open-loop first resonance at {ho} Hz");
    assert!((hc - ho).abs() > 20.0, "the first resonance is not moved: {hc} vs {ho} Hz");
}
