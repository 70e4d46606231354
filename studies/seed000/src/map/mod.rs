//! Seed 000, Section 5.6.6 (Figure 16): the speed × depth map through the FMUs.
//!
//! Grid: a_p 0.5:0.25:2.5 mm × N 1000:200:2800 rpm (90 cells) per controller, every other value
//! the Table 5 scenario of the system; per cell the raw RMS over `(t_from, T]` and the growth
//! ratio (detrended RMS of the last second over the first). The seed runs 5 s per cell and
//! takes the RMS over 1–5 s; the run length is a setting.
//!
//! Check (can fail): with noise and drift off, the open loop grows (last-second RMS > 3× the
//! first second) exactly where a_p > b_lim(N) on the lobe solver, allowing one cell of
//! tolerance at the boundary: a cell may disagree only if one of its four neighbours lies on
//! the other side of the lobe ([`disagreements`]).

mod cases;

use crate::batch::{Metrics, RowSink, Windows, run_all, run_one};
use crate::loop_frf;
use crate::robustness::{base_plant, plant_overrides};
use crate::scenario::roles;
pub use cases::*;
use chatter_control::Structure;
use fmi_master::{Override, SystemFile};
use model_description::Value;
use model_kit::Choice;
use std::fmt::Write as _;
use std::path::PathBuf;
use study_kit::StudyError;
use study_kit::figures::{Heat, heat_maps};
use study_kit::fmu_params::resolve;

/// Growth threshold of the check: last-second RMS over the first.
pub const GROWTH: f64 = 3.0;

/// The seed's Figure 16 peaks (µm).
pub const SEED_PEAKS: [(Structure, &str); 4] = [
    (Structure::Off, "74.9 at (2.5 mm, 1000 rpm); > 35 region; second hot spot near 2000 rpm"),
    (Structure::Pid, "15.2"),
    (Structure::Fopid, "12.0"),
    (Structure::AdrcFopid, "> 6.0 only at (2.5 mm, 2500 rpm)"),
];

/// The map's settings.
#[derive(Clone, Debug)]
pub struct MapStudy {
    /// Axial depths \[m\] (rows).
    pub depths: Vec<f64>,
    /// Speeds \[rpm\] (columns).
    pub rpm: Vec<f64>,
    /// Controllers.
    pub controllers: Vec<Structure>,
    /// Noise seed.
    pub seed: i32,
    /// Windows.
    pub windows: Windows,
    /// Noise and drift off.
    pub quiet: bool,
    /// Controller gains as overrides.
    pub gains: Vec<Override>,
    /// Output directory (`map.csv`).
    pub out: PathBuf,
}

/// The seed's grid: depths 0.5:0.25:2.5 mm, speeds 1000:200:2800 rpm.
pub fn seed_grid() -> (Vec<f64>, Vec<f64>) {
    (
        (0..9).map(|i| (0.5 + 0.25 * f64::from(i)) * 1e-3).collect(),
        (0..10).map(|j| 1000.0 + 200.0 * f64::from(j)).collect(),
    )
}

/// One cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    /// Controller.
    pub controller: Structure,
    /// Row (depth index).
    pub i: usize,
    /// Column (speed index).
    pub j: usize,
    /// Through the FMUs.
    pub metrics: Metrics,
    /// The lobe solver's critical depth at this speed for this controller \[m\].
    pub b_lim: f64,
}

impl Cell {
    /// Last-second over first-second detrended RMS.
    pub fn growth(&self) -> f64 {
        self.metrics.late / self.metrics.early
    }
}

/// One run of the map: a controller at a (depth, speed) cell.
#[derive(Clone, Debug)]
pub struct MapJob {
    /// Controller.
    pub controller: Structure,
    /// Row (depth index).
    pub i: usize,
    /// Column (speed index).
    pub j: usize,
    /// The lobe solver's critical depth at this speed for this controller \[m\].
    pub b_lim: f64,
    /// Every override of the run.
    pub overrides: Vec<Override>,
}

/// Every run of the map (controller × speed × depth), with the lobe solver's b_lim per speed.
pub fn jobs(sys: &SystemFile, s: &MapStudy) -> Result<Vec<MapJob>, StudyError> {
    if s.depths.is_empty() || s.rpm.is_empty() || s.controllers.is_empty() {
        return Err(StudyError::Invalid("the map needs at least one depth, one speed and one controller".into()));
    }
    if let Some(d) = s.depths.iter().find(|d| !(d.is_finite() && **d > 0.0)) {
        return Err(StudyError::Invalid(format!("depth {d} m: depths must be positive")));
    }
    if let Some(r) = s.rpm.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
        return Err(StudyError::Invalid(format!("speed {r} rpm: speeds must be positive")));
    }
    s.windows.validate()?;
    let roles = roles(sys)?;
    let base = base_plant(sys, &roles)?;
    let rpm_min = s.rpm.iter().copied().fold(f64::INFINITY, f64::min);
    let mut jobs = Vec::new();
    for &c in &s.controllers {
        let mut o0 = s.gains.clone();
        o0.push(Override::typed(format!("{}.structure", roles.controller), Value::Integer(c.index())));
        let (mut p, _) = base.clone();
        if s.quiet {
            p.disturbance.noise = false;
            p.disturbance.drift = false;
        }
        let ctrl = resolve::<fmu_controller::ChatterController>(sys, &roles.controller, &o0)?.params;
        let lobes = loop_frf::problem(&p, Some(&ctrl), rpm_min)
            .map_err(|e| StudyError::Invalid(format!("{}: {e}", c.name())))?;
        for (j, &rpm) in s.rpm.iter().enumerate() {
            let b_lim = lobes.critical_depth(rpm).depth;
            for (i, &d) in s.depths.iter().enumerate() {
                let (mut p, mut inp) = (p.clone(), base.1);
                p.cutting.axial_depth = d;
                p.seed = u64::try_from(s.seed).unwrap_or(0);
                inp.spindle_speed_rpm = rpm;
                let mut o = o0.clone();
                o.extend(plant_overrides(&roles, &(p, inp)));
                jobs.push(MapJob { controller: c, i, j, b_lim, overrides: o });
            }
        }
    }
    Ok(jobs)
}

/// Header of `map.csv`.
pub const CSV_HEADER: &str =
    "controller,depth_mm,rpm,rms_um,rms_detrended_um,growth_last_over_first,saturation_duty,b_lim_mm";

/// One row of `map.csv`.
pub fn csv_row(s: &MapStudy, x: &Cell) -> String {
    format!(
        "{},{},{},{:.6},{:.6},{:.6},{:.6},{:.6}",
        x.controller.name(),
        s.depths[x.i] * 1e3,
        s.rpm[x.j],
        x.metrics.rms * 1e6,
        x.metrics.rms_detrended * 1e6,
        x.growth(),
        x.metrics.saturation_duty,
        x.b_lim * 1e3
    )
}

/// Run the map (rows streamed to `<out>/map.csv`).
pub fn run(sys: &SystemFile, s: &MapStudy) -> Result<Vec<Cell>, StudyError> {
    let jobs = jobs(sys, s)?;
    let roles = roles(sys)?;
    let sink = RowSink::create(&s.out.join("map.csv"), CSV_HEADER)?;
    run_all(
        &jobs,
        "map",
        &sink,
        |j| format!("{} at {} mm, {} rpm", j.controller.name(), s.depths[j.i] * 1e3, s.rpm[j.j]),
        |j| {
            let metrics = run_one(sys, &roles, j.overrides.clone(), &s.windows)?;
            Ok(Cell { controller: j.controller, i: j.i, j: j.j, metrics, b_lim: j.b_lim })
        },
        |_, x| csv_row(s, x),
    )
}

/// `map.md` and `map.png` in `s.out` from the cells: the summary table under `title` (peak,
/// cells above 35 and 6 µm, the growth check against the lobes, the seed's figure), the lobe
/// solver's b_lim per speed and the heat maps on a common colour scale. Returns the markdown.
pub fn write_report(s: &MapStudy, cells: &[Cell], title: &str) -> Result<(String, Vec<PathBuf>), StudyError> {
    let mut md = format!(
        "{title}\n\n| controller | peak raw RMS (µm) at (a_p mm, rpm) | cells > 35 µm | cells > 6 µm | growth check: cells where 'last/first > {GROWTH}' ≠ 'a_p > b_lim' (tolerated at the boundary) | seed Figure 16 |\n|---|---|---|---|---|---|\n"
    );
    let mut panels = Vec::new();
    let mut vmax: f64 = 0.0;
    for &c in &s.controllers {
        let m = matrix(s, cells, c, |x| x.metrics.rms * 1e6);
        let Some(peak) =
            cells.iter().filter(|x| x.controller == c).max_by(|x, y| x.metrics.rms.total_cmp(&y.metrics.rms))
        else {
            return Err(StudyError::Invalid(format!("no cell of {}", c.name())));
        };
        let count = |t: f64| cells.iter().filter(|x| x.controller == c && x.metrics.rms * 1e6 > t).count();
        let d = disagreements(s, cells, c);
        let bad = d.iter().filter(|x| !x.2).count();
        let seed = SEED_PEAKS.iter().find(|(x, _)| *x == c).map_or("–", |(_, v)| v);
        let _ = writeln!(
            md,
            "| {} | {:.2} at ({}, {}) | {} | {} | {} ({} tolerated) | {seed} |",
            c.name(),
            peak.metrics.rms * 1e6,
            s.depths[peak.i] * 1e3,
            s.rpm[peak.j],
            count(35.0),
            count(6.0),
            d.len(),
            d.len() - bad
        );
        vmax = vmax.max(peak.metrics.rms * 1e6);
        panels.push((c.name().to_string(), m));
    }
    let _ = write!(md, "\nLobe solver b_lim(N) (mm), per controller:\n\n| controller |");
    for r in &s.rpm {
        let _ = write!(md, " {r} |");
    }
    let _ = writeln!(md, "\n|---|{}", "---|".repeat(s.rpm.len()));
    for &c in &s.controllers {
        let _ = write!(md, "| {} |", c.name());
        for j in 0..s.rpm.len() {
            let b = cells.iter().find(|x| x.controller == c && x.j == j).map_or(f64::NAN, |x| x.b_lim * 1e3);
            let _ = write!(md, " {b:.3} |");
        }
        md.push('\n');
    }
    let mut written = Vec::new();
    let md_path = s.out.join("map.md");
    std::fs::write(&md_path, &md).map_err(|e| StudyError::io(&md_path, e))?;
    written.push(md_path);
    if s.depths.len() >= 2 && s.rpm.len() >= 2 {
        let png = s.out.join("map.png");
        let depths_mm: Vec<f64> = s.depths.iter().map(|d| d * 1e3).collect();
        let heats: Vec<Heat<'_>> = panels.iter().map(|(t, v)| Heat { title: t.clone(), values: v }).collect();
        heat_maps(
            &png,
            &format!("Raw RMS tip displacement (common colour scale 0–{vmax:.1} µm; cf. seed Figure 16)"),
            ("spindle speed [rpm]", &s.rpm),
            ("axial depth [mm]", &depths_mm),
            &heats,
            vmax,
            "RMS [µm]",
        )?;
        written.push(png);
    }
    Ok((md, written))
}

/// The cells of one controller as a depth × speed matrix of `f`.
pub fn matrix(s: &MapStudy, cells: &[Cell], c: Structure, f: impl Fn(&Cell) -> f64) -> Vec<Vec<f64>> {
    let mut m = vec![vec![f64::NAN; s.rpm.len()]; s.depths.len()];
    for x in cells.iter().filter(|x| x.controller == c) {
        m[x.i][x.j] = f(x);
    }
    m
}

/// The growth check for controller `c`: the cells where "grows" (growth > [`GROWTH`]) differs
/// from "a_p > b_lim(N)", as `(i, j, tolerated)`; a disagreement is tolerated when one of the
/// four neighbours is on the other side of the lobe.
pub fn disagreements(s: &MapStudy, cells: &[Cell], c: Structure) -> Vec<(usize, usize, bool)> {
    let (n, m) = (s.depths.len(), s.rpm.len());
    let mut above = vec![vec![false; m]; n];
    for x in cells.iter().filter(|x| x.controller == c) {
        above[x.i][x.j] = s.depths[x.i] > x.b_lim;
    }
    let mut out = Vec::new();
    for x in cells.iter().filter(|x| x.controller == c) {
        let (i, j) = (x.i, x.j);
        if (x.growth() > GROWTH) == above[i][j] {
            continue;
        }
        let mut nb = Vec::new();
        if i > 0 {
            nb.push((i - 1, j));
        }
        if i + 1 < n {
            nb.push((i + 1, j));
        }
        if j > 0 {
            nb.push((i, j - 1));
        }
        if j + 1 < m {
            nb.push((i, j + 1));
        }
        out.push((i, j, nb.iter().any(|&(a, b)| above[a][b] != above[i][j])));
    }
    out
}
