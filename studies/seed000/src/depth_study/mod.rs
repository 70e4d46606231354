//! Seed 000, Section 5.6.1 (Figures 9–10): the depth study through the FMUs.
//!
//! The nominal scenario of Table 5 (2000 rpm, f_z = 0.05 mm, drift and 50 N RMS noise on, the
//! shipped `ClosedLoop.ssp`) at axial depths a_p ∈ {1.0, 1.5, 2.0} mm for each controller.
//! b_lim(2000 rpm) = 34.4 mm, so this is forced response, not chatter. Per run:
//!
//! * (a) the largest single-sided amplitude of the tip displacement in 100–200 Hz, and
//! * (b) the band-integrated amplitude `√Σ|P1|²` over the same band (the caption "peak …
//!   integrated over the band" is ambiguous: both are reported), both from the spectrum of
//!   `[t_spec, T]` sampled at 10 kHz (the window is not stated in the seed; we use the last
//!   second of a 2 s run, 1 Hz resolution);
//! * (c) the RMS over 1.70–1.90 s (the seed's window), and
//! * (d) the saturation duty cycle of the command over the same window.
//!
//! Every value set on the FMUs is typed, from the adapters' tables; each run's row is appended
//! to `depth_study.csv` as soon as it finishes, so an interrupted study keeps what it had.

mod cases;

use crate::scenario::{Roles, roles};
pub use cases::*;
use chatter_control::Structure;
use fmi_master::spectrum::single_sided;
use fmi_master::{Observer, Override, Progress, RunConfig, SimError, Simulation, SystemFile};
use model_description::Value;
use model_kit::Choice;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;
use std::sync::Mutex;
use study_kit::StudyError;

/// The seed's published values (µm): open loop 7.29 → 14.56 (1 → 2 mm), FOPID 2.86 / 5.18 /
/// 8.18, ADRC-FOPID 1.17 / 2.41 / 3.60; PID 3–4 % below open loop.
pub const SEED_FIGURE9: [(Structure, [f64; 3]); 3] = [
    (Structure::Off, [7.29, f64::NAN, 14.56]),
    (Structure::Fopid, [2.86, 5.18, 8.18]),
    (Structure::AdrcFopid, [1.17, 2.41, 3.60]),
];

/// The study's settings.
#[derive(Clone, Debug)]
pub struct DepthStudy {
    /// Axial depths \[m\].
    pub depths: Vec<f64>,
    /// Controllers.
    pub controllers: Vec<Structure>,
    /// Noise seed.
    pub seed: i32,
    /// Run length \[s\].
    pub stop: f64,
    /// Start of the spectrum window \[s\] (to `stop`).
    pub spectrum_from: f64,
    /// RMS and duty-cycle window \[s\].
    pub window: (f64, f64),
    /// Extra overrides for every run (e.g. the gains of a preset).
    pub overrides: Vec<Override>,
    /// Output directory (`depth_study.csv`).
    pub out: PathBuf,
}

impl Default for DepthStudy {
    fn default() -> Self {
        DepthStudy {
            depths: vec![1e-3, 1.5e-3, 2e-3],
            controllers: vec![Structure::Off, Structure::Pid, Structure::Fopid, Structure::AdrcFopid],
            seed: 1,
            stop: 2.0,
            spectrum_from: 1.0,
            window: (1.7, 1.9),
            overrides: Vec::new(),
            out: PathBuf::from("results/depth_study"),
        }
    }
}

/// One run's metrics.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DepthRow {
    /// Controller.
    pub controller: Structure,
    /// Axial depth \[m\].
    pub depth: f64,
    /// (a) largest amplitude in 100–200 Hz \[m\].
    pub band_peak: f64,
    /// (b) band-integrated amplitude \[m\].
    pub band_integrated: f64,
    /// (c) RMS over the window \[m\].
    pub window_rms: f64,
    /// (d) fraction of the window's samples with the command saturated.
    pub saturation_duty: f64,
}

struct Collect {
    spec_from: f64,
    window: (f64, f64),
    every: u64,
    count: u64,
    spec: Vec<f64>,
    sumsq: f64,
    n: u64,
    saturated: u64,
}

impl Observer for Collect {
    fn start(&mut self, _names: &[String]) -> Result<(), SimError> {
        Ok(())
    }
    fn sample(&mut self, t: f64, v: &[f64]) -> Result<(), SimError> {
        let i = self.count;
        self.count += 1;
        if t > self.spec_from && i.is_multiple_of(self.every) {
            self.spec.push(v[0]);
        }
        if t > self.window.0 && t <= self.window.1 {
            self.sumsq += v[0] * v[0];
            self.n += 1;
            self.saturated += u64::from(v[1] != 0.0);
        }
        Ok(())
    }
    fn finish(&mut self) -> Result<(), SimError> {
        Ok(())
    }
}

/// One run: controller `c` at axial depth `depth` \[m\].
pub fn one(sys: &SystemFile, roles: &Roles, s: &DepthStudy, c: Structure, depth: f64) -> Result<DepthRow, StudyError> {
    let mut overrides = s.overrides.clone();
    overrides.push(Override::typed(format!("{}.structure", roles.controller), Value::Integer(c.index())));
    overrides.push(Override::typed(format!("{}.seed", roles.plant), Value::Integer(s.seed)));
    overrides.push(Override::typed(format!("{}.cutting.axial_depth", roles.plant), Value::Real(depth)));
    let cfg = RunConfig {
        stop: Some(s.stop),
        overrides,
        record: Some(vec![roles.measured(), format!("{}.saturated", roles.controller)]),
        ..RunConfig::default()
    };
    let mut sim = Simulation::new(sys, &cfg)?;
    let h = sim.step();
    let every = ((1e-4 / h).floor() as u64).max(1);
    let mut obs = Collect {
        spec_from: s.spectrum_from,
        window: s.window,
        every,
        count: 0,
        spec: Vec::new(),
        sumsq: 0.0,
        n: 0,
        saturated: 0,
    };
    sim.run(&mut obs, Progress::Off)?;
    if obs.n == 0 || obs.spec.len() < 16 {
        return Err(StudyError::Invalid(format!(
            "run of {:.3} s leaves no samples in the window {:?} or after {} s",
            s.stop, s.window, s.spectrum_from
        )));
    }
    let spectrum = single_sided(&obs.spec, 1.0 / (h * every as f64));
    let band: Vec<f64> = spectrum
        .freq
        .iter()
        .zip(&spectrum.amp)
        .filter(|(f, _)| (100.0..=200.0).contains(*f))
        .map(|(_, a)| *a)
        .collect();
    Ok(DepthRow {
        controller: c,
        depth,
        band_peak: band.iter().copied().fold(0.0, f64::max),
        band_integrated: band.iter().map(|a| a * a).sum::<f64>().sqrt(),
        window_rms: (obs.sumsq / obs.n as f64).sqrt(),
        saturation_duty: obs.saturated as f64 / obs.n as f64,
    })
}

/// Every run of the study (controller × depth, controller-major).
pub fn jobs(s: &DepthStudy) -> Result<Vec<(Structure, f64)>, StudyError> {
    if s.depths.is_empty() || s.controllers.is_empty() {
        return Err(StudyError::Invalid("the depth study needs at least one depth and one controller".into()));
    }
    if let Some(d) = s.depths.iter().find(|d| !(d.is_finite() && **d >= 0.0)) {
        return Err(StudyError::Invalid(format!("depth {d} m: depths must be finite and not negative")));
    }
    Ok(s.controllers.iter().flat_map(|&c| s.depths.iter().map(move |&d| (c, d))).collect())
}

/// Header of `depth_study.csv`.
pub const CSV_HEADER: &str = "controller,depth_mm,band_peak_um,band_integrated_um,window_rms_um,saturation_duty";

/// One row of `depth_study.csv`.
pub fn csv_row(r: &DepthRow) -> String {
    format!(
        "{},{},{:.6},{:.6},{:.6},{:.6}",
        r.controller.name(),
        r.depth * 1e3,
        r.band_peak * 1e6,
        r.band_integrated * 1e6,
        r.window_rms * 1e6,
        r.saturation_duty
    )
}

/// Run the study on `sys` (the project's closed loop), all runs in parallel; each row is
/// appended to `<out>/depth_study.csv` as its run finishes.
pub fn run(sys: &SystemFile, s: &DepthStudy) -> Result<Vec<DepthRow>, StudyError> {
    let jobs = jobs(s)?;
    let roles = roles(sys)?;
    std::fs::create_dir_all(&s.out).map_err(|e| StudyError::io(&s.out, e))?;
    let path = s.out.join("depth_study.csv");
    let file = std::fs::File::create(&path).map_err(|e| StudyError::io(&path, e))?;
    let csv = Mutex::new(file);
    writeln!(csv.lock().expect("csv lock"), "{CSV_HEADER}").map_err(|e| StudyError::io(&path, e))?;
    let rows: Vec<Result<DepthRow, StudyError>> = jobs
        .par_iter()
        .map(|&(c, d)| {
            let r = one(sys, &roles, s, c, d).map_err(|e| e.within(format!("{} at {} mm", c.name(), d * 1e3)))?;
            let mut f = csv.lock().expect("csv lock");
            writeln!(f, "{}", csv_row(&r)).and_then(|()| f.flush()).map_err(|e| StudyError::io(&path, e))?;
            Ok(r)
        })
        .collect();
    rows.into_iter().collect()
}

/// `depth_study.md` in `s.out` from the rows (in job order), beside the seed's Figure 9 values;
/// `preset` names the gains. Returns the markdown.
pub fn report(s: &DepthStudy, rows: &[DepthRow], preset: &str) -> Result<String, StudyError> {
    let mut md = format!(
        "Depth study (seed 000 Section 5.6.1, 2000 rpm, {preset} gains, noise seed {}, {} s runs; spectrum from {} s; window {}–{} s)\n\n| controller | a_p (mm) | (a) peak 100–200 Hz (µm) | (b) band-integrated (µm) | (c) window RMS (µm) | (d) saturation duty | seed Figure 9 (µm) |\n|---|---|---|---|---|---|---|\n",
        s.seed, s.stop, s.spectrum_from, s.window.0, s.window.1
    );
    for r in rows {
        let k = s.depths.iter().position(|d| d.to_bits() == r.depth.to_bits()).unwrap_or(0);
        let seed = SEED_FIGURE9
            .iter()
            .find(|(c, _)| *c == r.controller)
            .and_then(|(_, v)| v.get(k).copied())
            .filter(|v| v.is_finite() && s.depths.len() == 3)
            .map_or("–".to_string(), |v| format!("{v:.2}"));
        let _ = writeln!(
            md,
            "| {} | {:.2} | {:.3} | {:.3} | {:.3} | {:.1} % | {seed} |",
            r.controller.name(),
            r.depth * 1e3,
            r.band_peak * 1e6,
            r.band_integrated * 1e6,
            r.window_rms * 1e6,
            100.0 * r.saturation_duty
        );
    }
    let path = s.out.join("depth_study.md");
    std::fs::write(&path, &md).map_err(|e| StudyError::io(&path, e))?;
    Ok(md)
}
