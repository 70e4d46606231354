//! Observers: what receives the recorded values of a run. The engine calls
//! [`Observer::start`] with the column names, [`Observer::sample`] at every
//! output point, and [`Observer::finish`] at the end, also after a failure.
//! [`Recorder`] keeps everything in memory; [`NoObserver`] keeps nothing; the
//! streaming CSV writer is [`crate::csv::CsvWriter`].

use crate::error::SimError;

/// Receives the recorded values.
pub trait Observer {
    /// Called once before the first sample with the column names.
    fn start(&mut self, names: &[String]) -> Result<(), SimError>;
    /// One row: time and the recorded values (integers and booleans as f64).
    fn sample(&mut self, t: f64, values: &[f64]) -> Result<(), SimError>;
    /// Called at the end of the run, also after a failure.
    fn finish(&mut self) -> Result<(), SimError>;
}

/// An observer that keeps nothing.
pub struct NoObserver;

impl Observer for NoObserver {
    fn start(&mut self, _: &[String]) -> Result<(), SimError> {
        Ok(())
    }
    fn sample(&mut self, _: f64, _: &[f64]) -> Result<(), SimError> {
        Ok(())
    }
    fn finish(&mut self) -> Result<(), SimError> {
        Ok(())
    }
}

/// An observer that keeps every sample in memory (short runs, tests).
#[derive(Clone, Debug, Default)]
pub struct Recorder {
    /// Column names (without `time`).
    pub names: Vec<String>,
    /// Sample times.
    pub time: Vec<f64>,
    /// One row of values per sample time.
    pub rows: Vec<Vec<f64>>,
}

impl Recorder {
    /// The column of the recorded variable `name` (e.g. `plant.x`).
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.names.iter().position(|n| n == name)?;
        Some(self.rows.iter().map(|r| r[i]).collect())
    }
}

impl Observer for Recorder {
    fn start(&mut self, names: &[String]) -> Result<(), SimError> {
        self.names = names.to_vec();
        Ok(())
    }
    fn sample(&mut self, t: f64, values: &[f64]) -> Result<(), SimError> {
        self.time.push(t);
        self.rows.push(values.to_vec());
        Ok(())
    }
    fn finish(&mut self) -> Result<(), SimError> {
        Ok(())
    }
}
