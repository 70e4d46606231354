//! Seed 002 on the FMUs (`Spindle.ssp`: MillingProcess + SpindleStructure + LinearController in
//! the Rust master): 3 % below the semi-discretisation boundary the regenerative difference
//! decays, 3 % above it grows, open loop and with the printed §6.1 gains (and with the shipped
//! synthesised designs); and the closed-loop tool FRF. Needs the FMUs of `target/fmu` (`cargo run --release -p packaging`).

use delay_stability::presets::SEED002_GAINS;
use delay_stability::{BisectionOptions, critical_value};
use studies::sd_lobes::Preset;
use studies::seed002::{SpindleCheck, closed_peak, spindle_system, static_gain, tool_frf};

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

#[test]
fn the_printed_gains_move_the_first_tool_resonance() {
    let hz: Vec<f64> = (0..=1200).map(|k| 500.0 + 2.5 * k as f64).collect();
    // zero gain: the closed loop is the open loop
    for r in tool_frf(&static_gain(None), 37_000.0, &hz).unwrap() {
        assert!((r.closed[0] - r.open[0]).norm() <= 1e-12 * r.open[0].norm());
    }
    let rows = tool_frf(&static_gain(Some(SEED002_GAINS)), 37_000.0, &hz).unwrap();
    let first = |f: &dyn Fn(&studies::seed002::FrfRow) -> f64| {
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
