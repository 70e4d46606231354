//! The time-stepped process against the exact limit: at 450 rpm the pulse response decays at
//! 0.97 of the limiting depth and grows at 1.03 (small amplitude: the linearisation holds).

use turning_process::{TurningInputs, TurningParams, TurningProcess, stability_limit};

/// Peak |x| over [t0, t1) of a run at depth `w` and 450 rpm.
fn peaks(w: f64, windows: &[(f64, f64)]) -> Vec<f64> {
    let p = TurningParams { depth: w, ..Default::default() };
    let mut plant = TurningProcess::new(&p).unwrap();
    let h = 1e-4;
    let end = windows.iter().map(|w| w.1).fold(0.0, f64::max);
    let mut peaks = vec![0.0f64; windows.len()];
    let n = (end / h).round() as usize;
    for k in 0..n {
        plant.step(h, &TurningInputs::default()).unwrap();
        let t = (k + 1) as f64 * h;
        for (j, (a, b)) in windows.iter().enumerate() {
            if t >= *a && t < *b {
                peaks[j] = peaks[j].max(plant.outputs().x.abs());
            }
        }
    }
    peaks
}

#[test]
fn decays_at_097_and_grows_at_103_of_the_exact_limit() {
    let p = TurningParams::default();
    let lim = stability_limit(p.omega_n(), p.a1(0.1, 450.0), 60.0 / 450.0).unwrap();
    let w_lim = lim.a2 / p.a2(0.1, 1.0);
    let win = [(1.0, 1.5), (3.5, 4.0)];
    let below = peaks(0.97 * w_lim, &win);
    let above = peaks(1.03 * w_lim, &win);
    println!("w_lim = {w_lim:.4} mm; 0.97: {below:?}; 1.03: {above:?}");
    assert!(below[1] < 0.8 * below[0], "0.97 w_lim must decay: {below:?}");
    assert!(above[1] > 1.25 * above[0], "1.03 w_lim must grow: {above:?}");
}

#[test]
fn table_2_depths_5_mm_grows_and_2_mm_decays() {
    let win = [(0.2, 0.4), (1.6, 1.8)];
    let five = peaks(5.0, &win);
    let two = peaks(2.0, &win);
    println!("5 mm: {five:?}; 2 mm: {two:?}");
    assert!(five[1] > 2.0 * five[0], "{five:?}");
    assert!(two[1] < 0.1 * two[0], "{two:?}");
}
