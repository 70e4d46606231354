//! Lobe diagrams over a speed range ([`delay_stability::zero_order`], [`crate::loop_frf`]) as independent
//! cases ([`study_kit::batch_cases`]): one case per chunk of consecutive speeds of the grid, every
//! controller at those speeds, so `chatter plan lobes …`, `chatter run` and `chatter collect`
//! write the `lobes.csv` and `lobes.png` of a local `chatter lobes`.
//!
//! The critical depth at a speed is solved at that speed alone, on the FRF grid that the
//! lowest speed of the whole range sets ([`crate::loop_frf::problem`] with the range's
//! `rpm_min`, as the local command), so a chunk gives exactly the points of the full diagram.

use crate::loop_frf;
use chatter_control::ControllerParams;
use delay_stability::zero_order::{CriticalPoint, Extremes, speed_grid};
use milling_plant::PlantParams;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;
use study_kit::StudyError;
use study_kit::batch_cases::{Batch, RunBatch};
use study_kit::cases::Collected;
use study_kit::output::{Series, plot_png, write_csv};

type Result<T> = std::result::Result<T, StudyError>;

/// Everything that defines a lobe study (the `chatter lobes` machine, controllers and grid).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LobesSpec {
    /// The figure's title.
    pub title: String,
    /// The plant.
    pub plant: PlantParams,
    /// The controllers (legend name and parameters; `off` = open loop).
    pub controllers: Vec<(String, ControllerParams)>,
    /// Lowest speed [rpm].
    pub rpm_min: f64,
    /// Highest speed [rpm].
    pub rpm_max: f64,
    /// Number of speeds.
    pub points: usize,
    /// Speeds per case.
    pub chunk: usize,
}

impl LobesSpec {
    /// The speed grid.
    pub fn grid(&self) -> Vec<f64> {
        speed_grid(self.rpm_min, self.rpm_max, self.points)
    }

    /// Check every choice.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(StudyError::Invalid(m));
        if !(self.rpm_min.is_finite() && self.rpm_min > 0.0 && self.rpm_max.is_finite() && self.rpm_max > self.rpm_min)
        {
            return bad(format!("the speed range [{}, {}] rpm is empty or not positive", self.rpm_min, self.rpm_max));
        }
        if self.points < 2 || self.chunk == 0 || self.controllers.is_empty() {
            return bad(format!(
                "{} speeds in chunks of {} for {} controllers: need at least 2 speeds, chunks of at least 1, a controller",
                self.points,
                self.chunk,
                self.controllers.len()
            ));
        }
        self.plant.validate().map_err(|e| StudyError::Invalid(format!("plant: {e}")))?;
        for (n, c) in &self.controllers {
            c.validate().map_err(|e| StudyError::Invalid(format!("{n}: {e}")))?;
        }
        Ok(())
    }

    /// The lobe problem of controller `c` on the whole range's FRF grid.
    fn problem(
        &self,
        c: &ControllerParams,
    ) -> Result<delay_stability::zero_order::LobeProblem<impl Fn(f64) -> num_complex::Complex64 + Sync + use<>>> {
        let rpm_min = self.grid().iter().copied().fold(f64::INFINITY, f64::min);
        loop_frf::problem(&self.plant, Some(c), rpm_min).map_err(|e| StudyError::Invalid(e.to_string()))
    }
}

/// `b_min … at … rpm (… Hz), b_max … at … rpm` (as `chatter lobes` prints it).
pub fn fmt_extremes(ex: &Extremes) -> String {
    format!(
        "b_min {:.3} mm at {:.1} rpm ({:.2} Hz), b_max {:.3} mm at {:.1} rpm",
        ex.min.depth * 1e3,
        ex.min.rpm,
        ex.min.chatter_hz,
        ex.max.depth * 1e3,
        ex.max.rpm
    )
}

/// The lobe study's chunks, ready to run as cases.
pub struct LobesRuns {
    spec: LobesSpec,
    grid: Vec<f64>,
    chunks: Vec<(usize, usize)>,
}

/// Lobes over speed chunks as a [`CaseStudy`](study_kit::cases::CaseStudy).
pub type LobesCases = Batch<LobesRuns>;

/// One chunk of speeds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LobesCase {
    /// Index of the first speed in the grid.
    pub first: usize,
    /// Number of speeds.
    pub count: usize,
    /// The chunk's speed range [rpm] (for readers of the manifest).
    pub rpm: (f64, f64),
}

impl RunBatch for LobesRuns {
    const KIND: &'static str = "lobes";
    type Spec = LobesSpec;
    /// (first index, count)
    type Job = (usize, usize);
    type Case = LobesCase;
    /// Per controller, the critical points of the chunk.
    type Output = Vec<Vec<CriticalPoint>>;

    fn spec(&self) -> &LobesSpec {
        &self.spec
    }

    fn from_spec(spec: LobesSpec) -> Result<Self> {
        spec.validate()?;
        let grid = spec.grid();
        let chunks = (0..grid.len()).step_by(spec.chunk).map(|k| (k, spec.chunk.min(grid.len() - k))).collect();
        Ok(LobesRuns { spec, grid, chunks })
    }

    fn jobs(&self) -> &[(usize, usize)] {
        &self.chunks
    }

    fn case_of(&self, &(first, count): &(usize, usize)) -> (String, LobesCase) {
        let c = LobesCase { first, count, rpm: (self.grid[first], self.grid[first + count - 1]) };
        (format!("speeds-{first:06}"), c)
    }

    fn run_job(&self, &(first, count): &(usize, usize)) -> Result<Vec<Vec<CriticalPoint>>> {
        let rpm = &self.grid[first..first + count];
        self.spec.controllers.iter().map(|(_, c)| Ok(self.spec.problem(c)?.diagram(rpm))).collect()
    }

    fn describe(&self, &(first, count): &(usize, usize), _: &Vec<Vec<CriticalPoint>>) -> String {
        format!("{count} speeds from {} rpm", self.grid[first])
    }

    fn report(&self, dir: &Path, runs: &[(&(usize, usize), &Vec<Vec<CriticalPoint>>)]) -> Result<Collected> {
        std::fs::create_dir_all(dir).map_err(|e| StudyError::io(dir, e))?;
        let mut text = String::new();
        let mut series = Vec::new();
        for (k, (name, c)) in self.spec.controllers.iter().enumerate() {
            let points: Vec<CriticalPoint> = runs.iter().flat_map(|(_, o)| o[k].iter().copied()).collect();
            if points.len() != self.grid.len() {
                return Err(StudyError::Invalid(format!("{name}: {} of {} speeds", points.len(), self.grid.len())));
            }
            let ex = self
                .spec
                .problem(c)?
                .extremes(&points)
                .ok_or_else(|| StudyError::Invalid("empty speed grid".into()))?;
            let _ = writeln!(text, "{name:>11}: {}  [{} speeds]", fmt_extremes(&ex), points.len());
            series.push(Series { name: name.clone(), points });
        }
        let (csv, png) = (dir.join("lobes.csv"), dir.join("lobes.png"));
        write_csv(&csv, &series)?;
        plot_png(&png, &self.spec.title, &series, 1200, 800)?;
        Ok(Collected { text, written: vec![csv, png] })
    }
}
