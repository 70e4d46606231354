//! Open-loop RMS of the tip displacement at the seed's nominal point (2000 rpm, a_p = 1 mm,
//! f_z = 0.05 mm, all disturbances on, time-domain cutting), 30 s per seed, 10 seeds, beside
//! the seed's Table 5 open-loop value; plus the displacement spectrum's lines.
//!
//! `cargo run -p milling-plant --release --example open_loop_study [-- seconds seeds]`

use milling_plant::{Plant, PlantInputs, PlantParams};
use num_complex::Complex64;
use rayon::prelude::*;
use rustfft::FftPlanner;
use std::f64::consts::PI;

fn main() {
    let args: Vec<f64> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let duration = args.first().copied().unwrap_or(30.0);
    let seeds = args.get(1).copied().unwrap_or(10.0) as u64;
    let runs: Vec<(u64, f64, f64, Vec<f64>)> = (1..=seeds)
        .into_par_iter()
        .map(|seed| {
            let p = PlantParams { seed, ..PlantParams::default() };
            let mut plant = Plant::new(&p).unwrap();
            let decim = 10; // record at 10 kHz
            let n = (duration / p.internal_step).round() as usize;
            let mut rec = Vec::with_capacity(n / decim);
            let (mut s2, mut s1) = (0.0, 0.0);
            for k in 0..n {
                plant.step(p.internal_step, &PlantInputs::default()).unwrap();
                let x = plant.outputs().x;
                s2 += x * x;
                s1 += x;
                if k % decim == 0 {
                    rec.push(x);
                }
            }
            let rms = (s2 / n as f64).sqrt();
            let mean = s1 / n as f64;
            (seed, rms, (rms * rms - mean * mean).sqrt(), rec)
        })
        .collect();
    println!("seed  rms_x[um]  rms_about_mean[um]");
    for (seed, rms, ac, _) in &runs {
        println!("{seed:4}  {:9.3}  {:9.3}", rms * 1e6, ac * 1e6);
    }
    let stats = |v: Vec<f64>| {
        let m = v.iter().sum::<f64>() / v.len() as f64;
        let s = (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len().max(2) - 1) as f64).sqrt();
        (m, s)
    };
    let (m, s) = stats(runs.iter().map(|r| r.1 * 1e6).collect());
    let (ma, sa) = stats(runs.iter().map(|r| r.2 * 1e6).collect());
    println!(
        "open-loop RMS x over {duration} s, {seeds} seeds: {m:.2} ± {s:.2} um (about the mean: {ma:.2} ± {sa:.2} um); seed Table 5: 3.78 ± 0.21 um"
    );
    // amplitude spectrum of seed 1 (Hann window, single-sided amplitude)
    let x = &runs[0].3;
    let fs = 1e4;
    let n = x.len().next_power_of_two() / 2;
    let mean = x[..n].iter().sum::<f64>() / n as f64;
    let mut buf: Vec<Complex64> = (0..n)
        .map(|i| Complex64::new((x[i] - mean) * (0.5 - 0.5 * (2.0 * PI * i as f64 / n as f64).cos()), 0.0))
        .collect();
    FftPlanner::new().plan_fft_forward(n).process(&mut buf);
    let amp: Vec<f64> = buf[..n / 2].iter().map(|c| 4.0 * c.norm() / n as f64).collect();
    let df = fs / n as f64;
    let peak_in = |f0: f64, f1: f64| {
        let (a, b) = ((f0 / df) as usize, (f1 / df) as usize);
        let k = (a..=b).max_by(|&i, &j| amp[i].total_cmp(&amp[j])).unwrap();
        (k as f64 * df, amp[k])
    };
    let (ft, at) = peak_in(132.0, 134.5);
    let (fm, am) = peak_in(136.0, 160.0);
    let (fl, al) = peak_in(10.0, 400.0);
    println!(
        "spectrum (seed 1, {df:.3} Hz bins): tooth-passing line {ft:.2} Hz ({:.3} um), mode band max {fm:.2} Hz ({:.3} um), largest 10-400 Hz: {fl:.2} Hz ({:.3} um)",
        at * 1e6,
        am * 1e6,
        al * 1e6
    );
}
