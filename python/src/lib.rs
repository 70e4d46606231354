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
/// Fit modes to measured FRF files: (modes CSV, stabilisation CSV, the report, the machine
/// file's `[structure]` table, the band \[Hz\]).
/// (modes CSV, stabilisation CSV, report, `[structure]` TOML, band).
type FitTexts = (String, String, String, String, (f64, f64));

#[pyfunction]
#[pyo3(signature = (files, band=None, max_order=40))]
fn fit_frf(py: Python<'_>, files: Vec<PathBuf>, band: Option<(f64, f64)>, max_order: usize) -> PyResult<FitTexts> {
    py.detach(|| {
        let frf = machine::frf::MeasuredFrf::read(&files).map_err(|e| e.to_string())?;
        let o = machine::frf_fit::FitOptions { band_hz: band, max_order };
        let f = machine::frf_fit::fit(&frf, &o).map_err(|e| format!("{}: {e}", frf.source))?;
        let names: Vec<String> = files
            .iter()
            .map(|p| p.canonicalize().map(|c| c.display().to_string()).map_err(|e| format!("{}: {e}", p.display())))
            .collect::<Result<_, _>>()?;
        Ok::<_, String>((f.modes_csv(), f.stabilisation_csv(), f.report(&frf), f.structure_toml(&names), f.band_hz))
    })
    .map_err(ChatterError::new_err)
}

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

/// Speeds, stability and saturation-limited depths (bytes of f64) and the controller's label.
type ClosedLobes<'py> = (Bound<'py, PyBytes>, Bound<'py, PyBytes>, Bound<'py, PyBytes>, String);

/// A user's machine from a machine file (`machine::Machine`).
#[pyclass(module = "chatter_fmu._native")]
struct Machine {
    m: machine::Machine,
}

/// A JSON value as TOML (a machine given as a Python dict).
fn toml_of(v: &serde_json::Value) -> PyResult<toml::Value> {
    use serde_json::Value as J;
    Ok(match v {
        J::Bool(b) => toml::Value::Boolean(*b),
        J::Number(n) => match n.as_i64() {
            Some(i) => toml::Value::Integer(i),
            None => toml::Value::Float(n.as_f64().unwrap_or(f64::NAN)),
        },
        J::String(s) => toml::Value::String(s.clone()),
        J::Array(a) => toml::Value::Array(a.iter().map(toml_of).collect::<PyResult<_>>()?),
        J::Object(o) => {
            toml::Value::Table(o.iter().map(|(k, v)| Ok((k.clone(), toml_of(v)?))).collect::<PyResult<_>>()?)
        }
        J::Null => return Err(ChatterError::new_err("a machine has no null values")),
    })
}

/// Numbers as native-endian f64 bytes (the Python wrapper makes numpy arrays of them).
fn f64_bytes<'py>(py: Python<'py>, v: impl IntoIterator<Item = f64>) -> Bound<'py, PyBytes> {
    let b: Vec<u8> = v.into_iter().flat_map(f64::to_ne_bytes).collect();
    PyBytes::new(py, &b)
}

#[pymethods]
impl Machine {
    /// Read a machine file (TOML).
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Machine> {
        Ok(Machine { m: machine::Machine::from_file(&path).map_err(err)? })
    }

    /// A machine from the JSON text of a mapping with the machine file's tables.
    #[staticmethod]
    fn from_json(text: &str, name: &str) -> PyResult<Machine> {
        let v: serde_json::Value = serde_json::from_str(text).map_err(err)?;
        let toml::Value::Table(t) = toml_of(&v)? else { return Err(ChatterError::new_err("a machine is a mapping")) };
        Ok(Machine { m: machine::Machine::from_table(&t, name).map_err(err)? })
    }

    /// What the file describes (the `chatter machine check` text).
    fn summary(&self) -> String {
        machine::workflow::summary(&self.m)
    }

    /// The speed range of the file \[rpm\].
    fn speed_range(&self) -> (f64, f64) {
        self.m.operation.speed_range_rpm
    }

    /// Open-loop lobes at `points` speeds over `(rpm_min, rpm_max)`: speeds and the zero-order,
    /// multi-frequency and time-periodic depths \[m\] as bytes (the last converged, or by the
    /// semi-discretisation of order `sd_m`), its kind per speed, and the report.
    #[pyo3(signature = (points=200, rpm_min=None, rpm_max=None, sd_m=None))]
    #[allow(clippy::type_complexity)]
    fn lobes<'py>(
        &self,
        py: Python<'py>,
        points: usize,
        rpm_min: Option<f64>,
        rpm_max: Option<f64>,
        sd_m: Option<usize>,
    ) -> PyResult<(
        Bound<'py, PyBytes>,
        Bound<'py, PyBytes>,
        Bound<'py, PyBytes>,
        Bound<'py, PyBytes>,
        Vec<String>,
        String,
    )> {
        let (lo, hi) = self.m.operation.speed_range_rpm;
        let speeds = machine::workflow::speeds(rpm_min.unwrap_or(lo), rpm_max.unwrap_or(hi), points.max(2));
        let m = &self.m;
        let l = py
            .detach(|| {
                machine::lobes::MachineLobes::compute(m, &speeds, machine::lobes::discretisation(sd_m), &|_, _| {})
                    .map_err(|e| e.to_string())
            })
            .map_err(ChatterError::new_err)?;
        let kinds = l.sd.iter().map(|p| p.critical.kind().map_or("none", |k| k.name()).to_string()).collect();
        Ok((
            f64_bytes(py, speeds.iter().copied()),
            f64_bytes(py, l.zero_order.iter().map(|p| p.depth)),
            f64_bytes(py, l.multi_frequency.iter().map(|p| p.depth)),
            f64_bytes(py, (0..speeds.len()).map(|i| l.sd_depth(i))),
            kinds,
            l.report(m),
        ))
    }

    /// Closed-loop lobes of the file's controller (or of `structure` with the shipped gains) at
    /// `points` speeds: speeds, stability and saturation-limited depths \[m\] as bytes, the
    /// label.
    #[pyo3(signature = (structure=None, points=200, rpm_min=None, rpm_max=None))]
    fn closed_loop_lobes<'py>(
        &self,
        py: Python<'py>,
        structure: Option<String>,
        points: usize,
        rpm_min: Option<f64>,
        rpm_max: Option<f64>,
    ) -> PyResult<ClosedLobes<'py>> {
        let m = &self.m;
        let (lo, hi) = m.operation.speed_range_rpm;
        let speeds = machine::workflow::speeds(rpm_min.unwrap_or(lo), rpm_max.unwrap_or(hi), points.max(2));
        let name = match structure.or_else(|| m.controller.as_ref().map(|c| c.structure.clone())) {
            Some(s) => s,
            None => return Err(ChatterError::new_err("the machine file has no [controller]: give structure=...")),
        };
        let (label, c) = machine::workflow::controller_for(m, &name)
            .map_err(err)?
            .ok_or_else(|| ChatterError::new_err("structure off: no closed loop"))?;
        let pts = py
            .detach(|| machine::closed::closed_loop_lobes(m, &c, &speeds, None).map_err(|e| e.to_string()))
            .map_err(ChatterError::new_err)?;
        Ok((
            f64_bytes(py, pts.iter().map(|p| p.rpm)),
            f64_bytes(py, pts.iter().map(|p| p.stability)),
            f64_bytes(py, pts.iter().map(|p| p.saturation)),
            label,
        ))
    }

    /// Zero-order lobes on the file's measured FRFs and on its modes (same band) at `points`
    /// speeds: speeds, data depths, modes' depths (empty without modes) \[m\] as bytes, the report.
    #[pyo3(signature = (points=200, rpm_min=None, rpm_max=None))]
    #[allow(clippy::type_complexity)]
    fn measured_lobes<'py>(
        &self,
        py: Python<'py>,
        points: usize,
        rpm_min: Option<f64>,
        rpm_max: Option<f64>,
    ) -> PyResult<(Bound<'py, PyBytes>, Bound<'py, PyBytes>, Bound<'py, PyBytes>, String)> {
        let (lo, hi) = self.m.operation.speed_range_rpm;
        let speeds = machine::workflow::speeds(rpm_min.unwrap_or(lo), rpm_max.unwrap_or(hi), points.max(2));
        let m = &self.m;
        let l = py
            .detach(|| machine::lobes::MeasuredLobes::compute(m, &speeds).map_err(|e| e.to_string()))
            .map_err(ChatterError::new_err)?;
        Ok((
            f64_bytes(py, speeds.iter().copied()),
            f64_bytes(py, l.measured.iter().map(|p| p.depth)),
            f64_bytes(py, l.modal.iter().flatten().map(|p| p.depth)),
            l.report(m),
        ))
    }

    /// A synthetic tap test of the machine's modes written to `path` (.csv or .uff; refused if
    /// it exists): `resolution` Hz over 0–`max_hz`, relative complex `noise`, `seed`.
    #[pyo3(signature = (path, noise=0.05, seed=1, resolution=1.0, max_hz=5000.0, binary=false))]
    #[allow(clippy::too_many_arguments)]
    fn tap_test(
        &self,
        path: PathBuf,
        noise: f64,
        seed: u64,
        resolution: f64,
        max_hz: f64,
        binary: bool,
    ) -> PyResult<()> {
        let t = machine::frf_fit::synth::TapTest { range_hz: (0.0, max_hz), resolution_hz: resolution, noise, seed };
        let frf = machine::frf_fit::synth::tap_test(&self.m, &t).map_err(ChatterError::new_err)?;
        machine::frf::write_new(&frf, &path, binary).map_err(err)
    }

    /// The time-periodic boundary at `rpm` (converged, or by the semi-discretisation of order
    /// `sd_m`) checked through the FMUs: (boundary \[m\], kind, growth ratio at 0.97, growth
    /// ratio at 1.03); an error if stable up to 100 mm.
    #[pyo3(signature = (rpm, sd_m=None))]
    fn validate(&self, py: Python<'_>, rpm: f64, sd_m: Option<usize>) -> PyResult<(f64, String, f64, f64)> {
        let m = &self.m;
        let v = py
            .detach(|| {
                machine::workflow::validate(m, rpm, machine::lobes::discretisation(sd_m)).map_err(|e| e.to_string())
            })
            .map_err(ChatterError::new_err)?;
        let v =
            v.ok_or_else(|| ChatterError::new_err(format!("{rpm} rpm: stable up to 100 mm: nothing to validate")))?;
        Ok((v.boundary, v.kind.map_or("none", |k| k.name()).to_string(), v.below.ratio, v.above.ratio))
    }

    /// Run the machine's FMUs at `rpm` and `depth` \[m\] for `stop_time` seconds in the Rust
    /// master: `(names, time, values)` like `System.simulate`.
    #[pyo3(signature = (rpm, depth, stop_time, record=None))]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        rpm: f64,
        depth: f64,
        stop_time: f64,
        record: Option<Vec<String>>,
    ) -> PyResult<(Vec<String>, Bound<'py, PyBytes>, Bound<'py, PyBytes>)> {
        let m = &self.m;
        let rec = py
            .detach(|| {
                m.simulate(&machine::workflow::fmu_dir(), rpm, depth, stop_time, record).map_err(|e| e.to_string())
            })
            .map_err(ChatterError::new_err)?;
        Ok((
            rec.names.clone(),
            f64_bytes(py, rec.time.iter().copied()),
            f64_bytes(py, rec.rows.iter().flatten().copied()),
        ))
    }

    /// Tune `structures` on the machine (`chatter tune --machine`): per structure
    /// `(structure, gains, closed-loop b_min [m], its speed [rpm], fresh seeds passed of 10,
    /// the SSV parameter set)`.
    #[pyo3(signature = (structures=vec!["pid".to_string(), "fopid".to_string(), "adrc_fopid".to_string()], runs=10, particles=40, iterations=60, seed=1))]
    #[allow(clippy::type_complexity)]
    fn tune(
        &self,
        py: Python<'_>,
        structures: Vec<String>,
        runs: usize,
        particles: usize,
        iterations: usize,
        seed: u64,
    ) -> PyResult<Vec<(String, Vec<f64>, f64, f64, usize, String)>> {
        let structures =
            structures.iter().map(|s| machine::workflow::structure(s)).collect::<Result<Vec<_>, _>>().map_err(err)?;
        let o = machine::tune::TuneOptions {
            structures,
            runs,
            seed,
            pso: study_kit::optim::pso::PsoConfig { particles, iterations, ..Default::default() },
            ..Default::default()
        };
        let m = &self.m;
        let res = py.detach(|| machine::tune::tune(m, &o, &|_, _, _| {})).map_err(ChatterError::new_err)?;
        res.iter()
            .map(|r| {
                let name = machine::workflow::structure_name(r.structure).to_string();
                let ssv = machine::tune::controller_ssv(&format!("tuned_{name}"), &r.best.params)
                    .map_err(ChatterError::new_err)?;
                Ok((
                    name,
                    r.best.gains.clone(),
                    r.best.breakdown.b_min_mm * 1e-3,
                    r.best.breakdown.rpm_at_min,
                    r.fresh.passed,
                    ssv,
                ))
            })
            .collect()
    }

    /// Write the machine's SSP at `rpm` and `depth` \[m\] (refused if `path` exists).
    #[pyo3(signature = (path, rpm, depth, stop_time=1.0))]
    fn write_ssp(&self, path: PathBuf, rpm: f64, depth: f64, stop_time: f64) -> PyResult<()> {
        if path.exists() {
            return Err(ChatterError::new_err(format!("{} exists: nothing is overwritten", path.display())));
        }
        self.m.write_ssp(&path, &machine::workflow::fmu_dir(), rpm, depth, stop_time).map_err(err)
    }
}

/// The module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("ChatterError", m.py().get_type::<ChatterError>())?;
    m.add_class::<System>()?;
    m.add_class::<Machine>()?;
    m.add_function(wrap_pyfunction!(plan_main_job, m)?)?;
    m.add_function(wrap_pyfunction!(case_ids, m)?)?;
    m.add_function(wrap_pyfunction!(fit_frf, m)?)?;
    m.add_function(wrap_pyfunction!(run_cases, m)?)?;
    m.add_function(wrap_pyfunction!(collect, m)?)?;
    Ok(())
}
