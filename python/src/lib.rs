//! # `chatter_fmu._native`: the Rust FMI master and the study cases for Python
//!
//! The extension module under the Python package `chatter_fmu` (`python/chatter_fmu/`, which
//! turns the raw results into numpy arrays). Built as an abi3 wheel by maturin (one wheel for
//! CPython ≥ 3.8); simulations and study runs release the GIL, so Python threads (and Dask
//! workers with several threads) run them in parallel. Every error of the master or of a study
//! becomes a `chatter_fmu.ChatterError` carrying the master's one-line message.

use fmi_master::{Override, Recorder, RunConfig, Simulation, SystemFile};
use model_description::Value;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyDict, PyFloat, PyInt, PyString};
use seed000::main_job::{MainJob, MainJobSpec};
use std::path::{Path, PathBuf};
use study_kit::cases::{self, Selection};

pyo3::create_exception!(_native, ChatterError, PyRuntimeError, "An error of the chatter master or of a study.");

fn err(e: impl std::fmt::Display) -> PyErr {
    ChatterError::new_err(e.to_string())
}

/// A system to simulate: an `.ssp`, an `.ssd` or a single `.fmu`.
#[pyclass(module = "chatter_fmu._native")]
struct System {
    sys: SystemFile,
}

/// One `name = value` override from a Python value: numbers and booleans keep their type,
/// strings are read as the variable's type (enumeration items by name).
fn override_of(name: &str, value: &Bound<'_, PyAny>) -> PyResult<Override> {
    if value.is_instance_of::<PyBool>() {
        Ok(Override::typed(name, Value::Boolean(value.extract()?)))
    } else if value.is_instance_of::<PyInt>() {
        Ok(Override::text(name, value.extract::<i64>()?.to_string()))
    } else if value.is_instance_of::<PyFloat>() {
        Ok(Override::typed(name, Value::Real(value.extract()?)))
    } else if value.is_instance_of::<PyString>() {
        Ok(Override::text(name, value.extract::<String>()?))
    } else {
        Err(ChatterError::new_err(format!("{name}: a parameter value must be a bool, int, float or str")))
    }
}

#[pymethods]
impl System {
    /// Open a system; `fmu_dir` is where a bare `.ssd` finds its FMUs.
    #[new]
    #[pyo3(signature = (path, fmu_dir=None))]
    fn new(path: PathBuf, fmu_dir: Option<PathBuf>) -> PyResult<System> {
        let sys = SystemFile::open(&path, fmu_dir.as_deref()).map_err(err)?;
        Ok(System { sys })
    }

    /// The components and their FMU sources, as `(name, source)` pairs.
    fn components(&self) -> Vec<(String, String)> {
        self.sys.desc.components.iter().map(|c| (c.name.clone(), c.source.clone())).collect()
    }

    /// Run the system. Returns `(names, time, values)`: the recorded column names, the sample
    /// times and the row-major values as native-endian f64 bytes (the Python wrapper makes
    /// numpy arrays of them).
    #[pyo3(signature = (stop_time=None, step=None, start_time=None, parameters=None, record=None, output_interval=None))]
    #[allow(clippy::too_many_arguments)]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        stop_time: Option<f64>,
        step: Option<f64>,
        start_time: Option<f64>,
        parameters: Option<&Bound<'py, PyDict>>,
        record: Option<Vec<String>>,
        output_interval: Option<f64>,
    ) -> PyResult<(Vec<String>, Bound<'py, PyBytes>, Bound<'py, PyBytes>)> {
        let mut overrides = Vec::new();
        if let Some(d) = parameters {
            for (k, v) in d.iter() {
                overrides.push(override_of(&k.extract::<String>()?, &v)?);
            }
        }
        let cfg = RunConfig {
            start: start_time,
            stop: stop_time,
            step,
            overrides,
            record,
            output_interval,
            ..RunConfig::default()
        };
        let sys = &self.sys;
        let rec = py
            .detach(move || -> Result<Recorder, String> {
                let mut sim = Simulation::new(sys, &cfg).map_err(|e| e.to_string())?;
                let mut rec = Recorder::default();
                sim.run(&mut rec, fmi_master::Progress::Off).map_err(|e| e.to_string())?;
                Ok(rec)
            })
            .map_err(ChatterError::new_err)?;
        let time: Vec<u8> = rec.time.iter().flat_map(|t| t.to_ne_bytes()).collect();
        let values: Vec<u8> = rec.rows.iter().flatten().flat_map(|x| x.to_ne_bytes()).collect();
        Ok((rec.names, PyBytes::new(py, &time), PyBytes::new(py, &values)))
    }
}

/// Plan the main job (Table 5) as independent cases into `out`; returns the number of cases.
#[pyfunction]
#[pyo3(signature = (out, fmu_dir, seeds, cases, stop_time=None, step=None, csv_interval=1e-3, overrides=Vec::new(), system=None))]
#[allow(clippy::too_many_arguments)]
fn plan_main_job(
    out: PathBuf,
    fmu_dir: PathBuf,
    seeds: Vec<u32>,
    cases: Vec<(String, String)>,
    stop_time: Option<f64>,
    step: Option<f64>,
    csv_interval: f64,
    overrides: Vec<String>,
    system: Option<PathBuf>,
) -> PyResult<usize> {
    let absolute = |p: &Path| std::path::absolute(p).map_err(err);
    let spec = MainJobSpec {
        system: system.as_deref().map(absolute).transpose()?,
        fmu_dir: absolute(&fmu_dir)?,
        seeds,
        stop: stop_time,
        step,
        csv_interval,
        cases,
        overrides,
    };
    let job = MainJob::new(spec).map_err(err)?;
    cases::plan(&job, &out).map_err(err)
}

/// The case IDs of the study in `dir`, in manifest order.
#[pyfunction]
fn case_ids(dir: PathBuf) -> PyResult<Vec<String>> {
    Ok(cases::manifest::<MainJob>(&dir).map_err(err)?.cases.into_iter().map(|c| c.id).collect())
}

/// Run cases of the study in `dir` that have no result (all, `shard="i/n"`, `index=k` or
/// `ids=[...]`), without the GIL. Returns `(ran, skipped)` IDs; a failed case raises.
#[pyfunction]
#[pyo3(signature = (dir, shard=None, index=None, ids=None))]
fn run_cases(
    py: Python<'_>,
    dir: PathBuf,
    shard: Option<String>,
    index: Option<usize>,
    ids: Option<Vec<String>>,
) -> PyResult<(Vec<String>, Vec<String>)> {
    let sel = match (shard, index, ids) {
        (Some(s), None, None) => s.parse::<Selection>().map_err(err)?,
        (None, Some(k), None) => Selection::Index(k),
        (None, None, Some(v)) => Selection::Ids(v),
        (None, None, None) => Selection::All,
        _ => return Err(ChatterError::new_err("give at most one of shard, index, ids")),
    };
    let s =
        py.detach(|| cases::run::<MainJob>(&dir, &sel).map_err(|e| e.to_string())).map_err(ChatterError::new_err)?;
    if let Some((id, e)) = s.failed.first() {
        return Err(ChatterError::new_err(format!("{} cases failed (first: {id}: {e})", s.failed.len())));
    }
    Ok((s.ran, s.skipped))
}

/// Collect the study in `dir` (its tables and figures); returns the main table as text.
#[pyfunction]
fn collect(py: Python<'_>, dir: PathBuf) -> PyResult<String> {
    py.detach(|| cases::collect::<MainJob>(&dir).map(|c| c.text).map_err(|e| e.to_string()))
        .map_err(ChatterError::new_err)
}

/// The module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("ChatterError", m.py().get_type::<ChatterError>())?;
    m.add_class::<System>()?;
    m.add_function(wrap_pyfunction!(plan_main_job, m)?)?;
    m.add_function(wrap_pyfunction!(case_ids, m)?)?;
    m.add_function(wrap_pyfunction!(run_cases, m)?)?;
    m.add_function(wrap_pyfunction!(collect, m)?)?;
    Ok(())
}
