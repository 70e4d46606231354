//! Seed 000 Section 5.6 studies (robustness, sweeps, map): what each study's definition says,
//! checked through the FMUs (quick variants, seconds each).

use chatter_control::Structure;
use seed000::batch::{Windows, run_one};
use seed000::robustness::{Group, Robustness, core_open_loop_rms, runs};
use seed000::scenario::{closed_loop_system, roles};
use std::collections::BTreeSet;
use std::path::PathBuf;
use std::process::Command;
use study_kit::fmu_params::resolve;

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("chatter-s11-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn chatter(args: &[&str]) -> (bool, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_chatter")).args(args).output().expect("run chatter");
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn system() -> fmi_master::SystemFile {
    packaging::packaged("ClosedLoop.ssp");
    closed_loop_system(&packaging::fmu_dir()).unwrap()
}

/// Our reading of the seed's "38-point sample": 19 distinct points × noise seeds 1 and 2 per
/// controller, and each run's overrides, resolved through the plant FMU's own table, give
/// exactly the stated parameter set (Table 1 values × the point's factors, Table 5 scenario).
#[test]
fn robustness_sample_is_19_points_times_2_seeds_with_the_stated_parameters() {
    let sys = system();
    let r = roles(&sys).unwrap();
    let s = Robustness::default();
    let all = runs(&sys, &s).unwrap();
    assert_eq!(all.len(), 4 * 38);
    let names: BTreeSet<&str> = s.points.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names.len(), 19);
    for g in [(Group::Plant, 8), (Group::Disturbance, 6), (Group::Speed, 5)] {
        assert_eq!(s.points.iter().filter(|p| p.group == g.0).count(), g.1, "{:?}", g.0);
    }
    let mut seen = BTreeSet::new();
    for run in &all {
        let pt = &s.points[run.point];
        let p = resolve::<fmu_plant::MillingPlant>(&sys, &r.plant, &run.overrides).unwrap();
        let c = resolve::<fmu_controller::ChatterController>(&sys, &r.controller, &run.overrides).unwrap();
        assert_eq!(c.params.structure, run.controller);
        assert_eq!((p.params.clone(), p.inputs), run.plant, "{}", pt.name);
        // the stated values, independently of Point::plant
        let (mass, k, kt, noise, rpm) = match pt.name.as_str() {
            "nominal" | "noise x1" => (30.0, 2.4e7, 760e6, 50.0, 2000.0),
            "m-15%" => (25.5, 2.4e7, 760e6, 50.0, 2000.0),
            "m+15%" => (34.5, 2.4e7, 760e6, 50.0, 2000.0),
            "k-15%" => (30.0, 2.04e7, 760e6, 50.0, 2000.0),
            "k+15%" => (30.0, 2.76e7, 760e6, 50.0, 2000.0),
            "Kt-15%" => (30.0, 2.4e7, 646e6, 50.0, 2000.0),
            "Kt+15%" => (30.0, 2.4e7, 874e6, 50.0, 2000.0),
            "worst (m+15%, k-15%, Kt+15%)" => (34.5, 2.04e7, 874e6, 50.0, 2000.0),
            n if n.starts_with("noise x") => (30.0, 2.4e7, 760e6, 50.0 * n[7..].parse::<f64>().unwrap(), 2000.0),
            n => (30.0, 2.04e7, 760e6, 50.0, n[8..n.len() - 4].parse::<f64>().unwrap()),
        };
        let q = &p.params;
        let close = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-12;
        assert!(close(q.workpiece.first.mass, mass) && close(q.workpiece.first.stiffness, k), "{}", pt.name);
        assert!(close(q.cutting.kt, kt) && close(q.disturbance.noise_rms, noise), "{}", pt.name);
        assert!(close(p.inputs.spindle_speed_rpm, rpm), "{}", pt.name);
        assert!(close(q.cutting.axial_depth, 1e-3) && close(p.inputs.feed_per_tooth, 5e-5));
        assert!(q.disturbance.noise && q.disturbance.drift && close(q.workpiece.first.damping_ratio, 0.0088));
        assert!(seen.insert((run.controller.name_str(), run.point, run.seed)), "duplicate run");
        assert!([1, 2].contains(&run.seed) && q.seed == run.seed as u64);
    }
}

trait NameStr {
    fn name_str(self) -> &'static str;
}
impl NameStr for Structure {
    fn name_str(self) -> &'static str {
        model_kit::Choice::name(self)
    }
}

/// Through the FMUs the open-loop RMS is the plant core's own at three robustness points.
#[test]
fn fmu_open_loop_rms_equals_the_plant_core_at_three_points() {
    let sys = system();
    let r = roles(&sys).unwrap();
    let s = Robustness { controllers: vec![Structure::Off], ..Robustness::default() };
    let all = runs(&sys, &s).unwrap();
    let w = Windows::rms(1.2, 0.2);
    for name in ["m+15%", "noise x2", "k-15% @ 2800 rpm"] {
        let run = all.iter().find(|x| s.points[x.point].name == name && x.seed == 1).unwrap();
        let fmu = run_one(&sys, &r, run.overrides.clone(), &w).unwrap().rms;
        let core = core_open_loop_rms(&run.plant, &w).unwrap();
        assert!((fmu / core - 1.0).abs() < 1e-12, "{name}: FMU {fmu:e} core {core:e}");
        assert!(fmu > 1e-7, "{name}: {fmu:e}");
    }
}

/// The noise-free k −15 % speed sweep (forced response alone) peaks within ±150 rpm of the speed
/// where tooth passing meets the shifted first mode, 60·f₁/Z = 1969 rpm.
#[test]
fn robustness_quick_speed_sweep_peaks_at_the_resonance() {
    let d = out_dir("rob");
    let (ok, stdout, err) = chatter(&[
        "robustness",
        "--quick",
        "--controllers",
        "off",
        "--groups",
        "speed",
        "--quiet",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(!d.join("robustness.csv.incomplete").exists());
    let csv = std::fs::read_to_string(d.join("robustness.csv")).unwrap();
    let rows: Vec<(f64, f64)> = csv
        .lines()
        .skip(1)
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (c[8].parse().unwrap(), c[9].parse().unwrap())
        })
        .collect();
    assert_eq!(rows.len(), 5, "{csv}");
    let peak = rows.iter().max_by(|a, b| a.1.total_cmp(&b.1)).unwrap().0;
    let f1 = (2.04e7f64 / 30.0).sqrt() / (2.0 * std::f64::consts::PI);
    assert!((peak - 60.0 * f1 / 4.0).abs() <= 150.0, "peak at {peak} rpm\n{stdout}");
    for f in ["robustness.md", "robustness.png"] {
        assert!(d.join(f).metadata().unwrap().len() > 100, "{f}");
    }
    std::fs::remove_dir_all(&d).unwrap();
}

fn csv_rows(path: &std::path::Path) -> Vec<Vec<String>> {
    let csv = std::fs::read_to_string(path).unwrap();
    csv.lines().skip(1).map(|l| l.split(',').map(str::to_string).collect()).collect()
}

/// Feed sweep, noise and drift off: the FMU's RMS about the mean equals the harmonic balance
/// `√(Σ X_k²/2)` of tooth-passing harmonics 1–10 through Φ_cl, within 2 %, open loop and PID.
#[test]
fn feed_sweep_quick_matches_the_harmonic_balance() {
    let d = out_dir("feed");
    let (ok, stdout, err) = chatter(&[
        "sweep",
        "feed",
        "--quick",
        "--quiet",
        "--controllers",
        "off,pid",
        "--values",
        "0.025,0.12",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let rows = csv_rows(&d.join("sweep_feed.csv"));
    assert_eq!(rows.len(), 4);
    for r in &rows {
        let (fmu, hb): (f64, f64) = (r[3].parse().unwrap(), r[4].parse().unwrap());
        assert!(hb > 0.5 && (fmu / hb - 1.0).abs() < 0.02, "{r:?}\n{stdout}");
    }
    assert!(stdout.contains("RMS slope against f_z, off"), "{stdout}");
    assert!(d.join("sweep_feed.png").metadata().unwrap().len() > 100);
    std::fs::remove_dir_all(&d).unwrap();
}

/// Engagement sweep: the lobe solver's open-loop minimum equals 2kζ(1 ± ζ)/(K_t |α₀(a_e)|) to
/// 1e-6 at every a_e (α₀ from the plant core at φ_ex = arccos(1 − a_e/R)).
#[test]
fn engagement_sweep_lobe_minimum_is_the_closed_form() {
    let d = out_dir("eng");
    let (ok, stdout, err) = chatter(&[
        "sweep",
        "engagement",
        "--quick",
        "--controllers",
        "off",
        "--values",
        "4,8,14",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let mut rows = csv_rows(&d.join("sweep_engagement.csv"));
    assert_eq!(rows.len(), 3);
    // rows are streamed as the parallel runs finish: order them by a_e
    rows.sort_by(|a, b| a[1].parse::<f64>().unwrap().total_cmp(&b[1].parse::<f64>().unwrap()));
    let mut seen = Vec::new();
    for r in &rows {
        let (solver, closed): (f64, f64) = (r[6].parse().unwrap(), r[7].parse().unwrap());
        assert!((solver / closed - 1.0).abs() < 1e-6, "{r:?}\n{stdout}");
        // independently: α₀ of half immersion (8 mm) gives Table 6's 1.228 mm
        if r[1] == "8" {
            assert!((closed - 1.2283).abs() < 1e-3, "{closed}");
        }
        seen.push(closed);
    }
    assert!(seen[0] > seen[1] && seen[2] > seen[1], "{seen:?}");
    std::fs::remove_dir_all(&d).unwrap();
}

/// Bad input: one line, non-zero exit, no CSV.
#[test]
fn studies_refuse_bad_input_with_one_line() {
    let d = out_dir("bad");
    let out = d.to_str().unwrap();
    for (args, expect) in [
        (vec!["sweep", "depth"], "expected feed or engagement"),
        (vec!["sweep", "feed", "--values", "0.05,-1"], "give positive values"),
        (vec!["robustness", "--groups", "x"], "expected plant, disturbance or speed"),
        (vec!["robustness", "--speeds", "0"], "give positive speeds"),
        (vec!["map", "--depths", "0.5,-1"], "depths must be positive"),
        (vec!["map", "--rpm", "2000,1000"], "speed range"),
        (vec!["map", "--controllers", "lqr"], "unknown controller"),
    ] {
        let mut all = args.clone();
        all.extend(["--out", out]);
        let (ok, _, err) = chatter(&all);
        assert!(!ok, "{args:?} succeeded");
        assert!(err.contains(expect) && err.trim().lines().count() == 1, "{args:?}: {err}");
        assert!(!d.exists(), "{args:?} wrote output");
    }
}

/// The noise-free open-loop map grows (last-second RMS > 3× the first) exactly where
/// a_p > b_lim(N) on the lobe solver, one cell of tolerance at the boundary; both sides occur.
#[test]
fn map_quick_noise_free_open_loop_grows_exactly_above_the_lobes() {
    let d = out_dir("map");
    let (ok, stdout, err) = chatter(&[
        "map",
        "--quick",
        "--quiet",
        "--controllers",
        "off",
        "--depths",
        "1,2",
        "--rpm",
        "1200,2800,400",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let rows = csv_rows(&d.join("map.csv"));
    assert_eq!(rows.len(), 10);
    let (mut grow, mut stable) = (0, 0);
    for r in &rows {
        let (depth, growth, b_lim): (f64, f64, f64) =
            (r[1].parse().unwrap(), r[5].parse().unwrap(), r[7].parse().unwrap());
        if depth > b_lim {
            grow += 1;
        } else {
            stable += 1;
        }
        // away from the boundary (±15 % in depth) the classification must agree exactly
        if (depth / b_lim - 1.0).abs() > 0.15 {
            assert_eq!(growth > 3.0, depth > b_lim, "{r:?}\n{stdout}");
        }
    }
    assert!(grow >= 2 && stable >= 2, "both sides of the lobe: {grow} above, {stable} below");
    let untolerated: usize = stdout
        .lines()
        .find(|l| l.starts_with("| off |"))
        .map(|l| {
            let c: Vec<&str> = l.split('|').map(str::trim).collect();
            let (n, tol) = c[5].split_once(" (").unwrap();
            n.parse::<usize>().unwrap() - tol.split(' ').next().unwrap().parse::<usize>().unwrap()
        })
        .unwrap();
    assert_eq!(untolerated, 0, "{stdout}");
    assert_eq!(&std::fs::read(d.join("map.png")).unwrap()[1..4], b"PNG");
    std::fs::remove_dir_all(&d).unwrap();
}

/// The robust saturation constraint is the union over its noise seeds: the FOPID tuned with the
/// seed's single check passes that check (noise seed 7) but not every seed of 1..=10.
#[test]
fn robust_saturation_constraint_fails_if_any_seed_fails() {
    use seed000::tuning::TuningProblem;
    // the FOPID gains the seed's single-seed check (noise seed 7) selected: on its saturation
    // boundary (the shipped defaults before the robust re-tuning)
    let fopid = chatter_control::FopidGains {
        kp: 1.0e5,
        ki: 1.0e4,
        kd: 1.0e3,
        lambda: 0.873_490_392_164_647_1,
        mu: 1.278_802_491_355_317_5,
    };
    let c = chatter_control::ControllerParams { structure: Structure::Fopid, fopid, ..Default::default() };
    let mut p = TuningProblem::new(milling_plant::PlantParams::default(), Structure::Fopid);
    let single = p.saturation(&c).unwrap();
    assert!(!single.exceeded, "{single:?}");
    p.check_seeds = (1..=10).collect();
    let robust = p.saturation(&c).unwrap();
    assert!(robust.exceeded && robust.saturated_samples > 0, "{robust:?}");
    assert!(p.evaluate(&c).cost > 1e3, "infeasible under the robust constraint");
}
