//! Quick end-to-end runs of the `chatter` binary (seconds).

use std::path::PathBuf;
use std::process::Command;

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("chatter-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn run(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_chatter")).args(args).output().expect("run chatter");
    assert!(out.status.success(), "chatter {args:?} failed: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn tables_reproduce_the_uncontrolled_ozsoy_row() {
    let d = out_dir("tables");
    let stdout = run(&["tables", "--points", "401", "--out", d.to_str().unwrap()]);
    let md = std::fs::read_to_string(d.join("tables.md")).unwrap();
    assert_eq!(stdout.lines().next(), md.lines().next());
    // the 1000–3000 rpm row: b_crit and b_max within 3 % of the seed's 1.24 / 43.94 mm
    let row = md.lines().find(|l| l.starts_with("| 1000–3000")).expect("Table 8 row");
    let cols: Vec<&str> = row.split('|').map(str::trim).collect();
    let b: f64 = cols[2].parse().unwrap();
    let bmax: f64 = cols[7].parse().unwrap();
    assert!((b / 1.24 - 1.0).abs() < 0.03, "b_crit {b}");
    assert!((bmax / 43.94 - 1.0).abs() < 0.03, "b_max {bmax}");
    for f in [
        "table6_lobes.csv",
        "table6_lobes.png",
        "table8_ozsoy_lobes.csv",
        "table8_ozsoy_lobes.png",
        "fig18_ozsoy_lobes.csv",
        "fig18_ozsoy_lobes.png",
    ] {
        assert!(d.join(f).metadata().unwrap().len() > 100, "{f}");
    }
    std::fs::remove_dir_all(&d).unwrap();
}

/// `chatter table8 --quick` (≈ 10 s): all nine rows in both modes, the figures, Table A1 and the
/// benchmark designs as parameter sets that read back through the LinearController's table;
/// every calibrated row sits at [8]'s b_crit, and the PSO-tuned DVF exceeds [8]'s 3.2 mm (the
/// finding of the book's Table 8 section).
#[test]
fn table8_quick_writes_every_row_figure_and_design() {
    let d = out_dir("table8");
    let stdout = run(&["table8", "--quick", "--out", d.to_str().unwrap()]);
    for f in [
        "table8.md",
        "table_a1.md",
        "fig17_receptance.csv",
        "fig17_receptance.png",
        "fig18_lobes_500.csv",
        "fig18_lobes_500.png",
        "fig18_lobes_1000.png",
        "benchmark_dvf_calibrated.ssv",
        "benchmark_mu_pso.ssv",
    ] {
        assert!(d.join(f).is_file(), "{f} missing");
    }
    let rows: Vec<Vec<String>> = stdout
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| controller"))
        .map(|l| l.split('|').map(|c| c.trim().to_string()).collect())
        .collect();
    let b = |label: &str, mode: &str| -> f64 {
        let r = rows.iter().find(|r| r[1] == label && r[2] == mode).unwrap_or_else(|| panic!("{label} {mode}"));
        r[3].parse().unwrap()
    };
    for (label, target) in [("DVF", 3.2), ("PID", 3.2), ("LQR", 3.2), ("H∞", 3.1), ("μ", 3.1)] {
        assert!((b(label, "calibrated") / target - 1.0).abs() < 5e-3, "{label}: {}", b(label, "calibrated"));
    }
    for label in ["DVF", "VPA", "PID", "LQR", "H∞", "μ", "FOPID", "ADRC-FOPID"] {
        assert!(b(label, "PSO") > 0.0, "{label}");
    }
    assert!(b("DVF", "PSO") > 3.2, "PSO-tuned DVF {} mm", b("DVF", "PSO"));
    // every controlled row reports the seed's check on the ten fresh seeds; H∞ and μ rows their
    // achieved norm and μ bounds
    for r in rows.iter().filter(|r| r.len() > 10 && r[2] != "–") {
        assert!(r[9].contains("/10 (peak"), "{r:?}");
        match r[1].as_str() {
            "H∞" => assert!(r[10].contains("achieved ‖[W_S S; W_T T]‖∞"), "{r:?}"),
            "μ" => assert!(r[10].contains("μ upper bound RP"), "{r:?}"),
            _ => {}
        }
    }
    let xml = std::fs::read_to_string(d.join("benchmark_dvf_calibrated.ssv")).unwrap();
    let params = ssp::parse_ssv(&xml, "benchmark_dvf_calibrated.ssv", "").unwrap();
    assert!(params.iter().any(|p| p.name == "n_c") && params.iter().any(|p| p.name == "Dc[1,1]"));
}

#[test]
fn lobes_writes_csv_and_png() {
    let d = out_dir("lobes");
    let stdout = run(&[
        "lobes",
        "--controllers",
        "off,pid",
        "--pid",
        "2300,0.012,180",
        "--points",
        "201",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(stdout.contains("b_min"), "{stdout}");
    let csv = std::fs::read_to_string(d.join("lobes.csv")).unwrap();
    assert_eq!(csv.lines().count(), 202);
    assert!(csv.starts_with("rpm,b_lim_mm_off,b_lim_mm_pid,f_chatter_hz_off,f_chatter_hz_pid"));
    assert!(d.join("lobes.png").exists());
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn tune_runs_a_tiny_swarm() {
    let d = out_dir("tune");
    let stdout = run(&[
        "tune",
        "--structures",
        "pid,fopid",
        "--runs",
        "2",
        "--particles",
        "4",
        "--iterations",
        "2",
        "--check-duration",
        "0.01",
        "--quiet",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(stdout.contains("| pid | 3 |") && stdout.contains("| fopid | 5 |"), "{stdout}");
    let json = std::fs::read_to_string(d.join("tuned_fopid.json")).unwrap();
    assert!(json.contains("\"lambda\"") && json.contains("\"b_min_mm\""));
    assert_eq!(std::fs::read_to_string(d.join("tuning_runs.csv")).unwrap().lines().count(), 5);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn a_short_main_job_writes_its_table_csvs_and_plots() {
    assert!(packaging::fmu_dir().join("ClosedLoop.ssp").is_file(), "run `cargo run --release -p packaging` first");
    let out = std::env::temp_dir().join(format!("chatter-main-job-{}", std::process::id()));
    let o = Command::new(env!("CARGO_BIN_EXE_chatter"))
        .args(["main-job", "--seeds", "2", "--stop-time", "0.05", "--csv-interval", "1e-4", "--out"])
        .arg(&out)
        .output()
        .expect("run chatter");
    let (stdout, err) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "{err}");
    for label in ["| Open loop |", "| PID |", "| FOPID |", "| ADRC-FOPID |", "3.78 ± 0.21", "68.5 % ± 1.5 %"] {
        assert!(stdout.contains(label), "missing {label} in\n{stdout}");
    }
    assert!(stdout.contains("tooth passing 133.3 Hz"), "{stdout}");
    let table = std::fs::read_to_string(out.join("table5.md")).unwrap();
    assert!(table.contains("| ADRC-FOPID |"), "{table}");
    // the system by its file name, not the folders of this machine
    assert!(table.starts_with("Nominal scenario (ClosedLoop.ssp; 2 seeds"), "{table}");
    for f in ["fig6_time_history.png", "fig7_spectrum.png"] {
        let bytes = std::fs::read(out.join(f)).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{f}");
    }
    let run_csv = out.join("runs/adrc_fopid_seed01.csv");
    let t = fmi_master::csv::read_csv(&run_csv).unwrap();
    assert_eq!(t.names, vec!["time", "plant.x", "controller.u"]);
    assert_eq!(t.columns[0].len(), 501, "0.05 s at the 0.1 ms CSV interval");
    let markers: Vec<_> = std::fs::read_dir(out.join("runs"))
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".incomplete"))
        .map(|e| e.file_name())
        .collect();
    assert!(markers.is_empty(), "finished runs keep no .incomplete marker: {markers:?}");
    let summary = std::fs::read_to_string(out.join("runs_summary.csv")).unwrap();
    assert_eq!(summary.lines().count(), 1 + 4 * 2, "{summary}");
    std::fs::remove_dir_all(&out).unwrap();
}

fn chatter(args: &[&str]) -> (bool, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_chatter")).args(args).output().expect("run chatter");
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// The b_min (mm) of the first controller printed by `chatter lobes`.
fn b_min(stdout: &str) -> f64 {
    let s = stdout.split("b_min ").nth(1).expect("b_min printed");
    s.split(' ').next().unwrap().parse().unwrap()
}

/// The machine is described with the plant FMU's own parameter names: the Ozsoy benchmark
/// through `--set` gives Table 8's uncontrolled row without the hard-wired preset.
#[test]
fn lobes_of_the_ozsoy_plant_through_set() {
    let d = out_dir("lobes-ozsoy");
    let stdout = run(&[
        "lobes",
        "--controllers",
        "off",
        "--set",
        "plant.workpiece.stiffness=2.43e7",
        "--set",
        "plant.workpiece.mass=30.483047374097595",
        "--set",
        "plant.cutting.milling=down",
        "--set",
        "plant.cutting.direction_angle=1.5707963267948966",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!((b_min(&stdout) - 1.244).abs() < 0.001, "{stdout}");
    assert!(stdout.contains("b_max 45.20"), "{stdout}");
    let csv = std::fs::read_to_string(d.join("lobes.csv")).unwrap();
    assert!(csv.starts_with("rpm,b_lim_mm_off,f_chatter_hz_off\n"), "{}", &csv[..60]);
    std::fs::remove_dir_all(&d).unwrap();
}

/// A machine that is neither the seed's nor Ozsoy's: its lobe minimum is the closed form
/// 2kζ(1+ζ)/(K_t α₀) of its own parameters, α₀ from the plant core.
#[test]
fn lobes_of_another_machine_match_the_closed_form() {
    let mut p = milling_plant::PlantParams::default();
    p.workpiece.first = milling_plant::Mode { mass: 12.0, stiffness: 5e7, damping_ratio: 0.02 };
    p.cutting.teeth = 3;
    p.cutting.kt = 600e6;
    p.cutting.kr = 150e6;
    p.cutting.radial_engagement = 5e-3;
    let alpha0 = p.directional_coefficient();
    assert!(alpha0 > 0.0);
    let analytic = 2.0 * 5e7 * 0.02 * 1.02 / (600e6 * alpha0) * 1e3;
    let d = out_dir("lobes-other");
    let stdout = run(&[
        "lobes",
        "--controllers",
        "off",
        "--rpm-min",
        "1500",
        "--rpm-max",
        "6000",
        "--set",
        "plant.workpiece.mass=12",
        "--set",
        "plant.workpiece.stiffness=5e7",
        "--set",
        "plant.workpiece.damping_ratio=0.02",
        "--set",
        "plant.cutting.teeth=3",
        "--set",
        "plant.cutting.kt=600e6",
        "--set",
        "plant.cutting.kr=150e6",
        "--set",
        "plant.cutting.radial_engagement=5e-3",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!((b_min(&stdout) / analytic - 1.0).abs() < 1e-3, "analytic {analytic} mm\n{stdout}");
    std::fs::remove_dir_all(&d).unwrap();
}

/// The controller gains can come from an SSP's parameter bindings: ClosedLoopTable2.ssp binds
/// the paper's Table 2, so `--preset tuned` is overridden and the PID b_min is Table 6's 1.704 mm.
#[test]
fn lobes_take_the_gains_of_a_system() {
    let ssp = packaging::packaged("ClosedLoopTable2.ssp");
    let d = out_dir("lobes-ssp");
    let stdout = run(&[
        "lobes",
        "--controllers",
        "pid",
        "--preset",
        "tuned",
        "--system",
        ssp.to_str().unwrap(),
        "--points",
        "2001",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!((b_min(&stdout) - 1.704).abs() < 0.001, "{stdout}");
    std::fs::remove_dir_all(&d).unwrap();
}

/// Bad input is a one-line error, a non-zero exit, and no lobes.csv.
#[test]
fn lobes_refuse_bad_input_with_one_line() {
    let d = out_dir("lobes-bad");
    let out = d.to_str().unwrap();
    for (args, expect) in [
        (vec!["--set", "plant.workpiece.mas=3"], "did you mean workpiece.mass"),
        (vec!["--set", "plant.workpiece.damping_ratio=2"], "outside its bounds [0, 0.99]"),
        (vec!["--set", "plant.cutting.kt=800"], "did you mean 800 N/mm² = 800000000 N/m2?"),
        (vec!["--set", "plant.cutting.axial_depth=3"], "did you mean 3 mm = 0.003 m?"),
        (vec!["--set", "controller.structure=lqr"], "'lqr' is not an item of enumeration 'structure'"),
        (vec!["--set", "table.kt=1"], "`plant` or `controller`"),
        (vec!["--rpm-min", "3000", "--rpm-max", "1000"], "speed range [3000, 1000] rpm is empty"),
        (vec!["--rpm-min=-5"], "not positive"),
    ] {
        let mut all = vec!["lobes", "--controllers", "off", "--points", "11", "--out", out];
        all.extend(args.iter().copied());
        let (ok, _, err) = chatter(&all);
        assert!(!ok, "{args:?} succeeded");
        assert!(err.contains(expect) && err.trim().lines().count() == 1, "{args:?}: {err}");
        assert!(!d.join("lobes.csv").exists(), "{args:?} wrote a CSV");
    }
}

/// `chatter depth-study --quick`: the open-loop peak in 100–200 Hz rises monotonically with the
/// depth (forced response growing with the cutting force), and every run's row is in the CSV.
#[test]
fn depth_study_quick_open_loop_peak_rises_with_depth() {
    packaging::packaged("ClosedLoop.ssp");
    let d = out_dir("depth");
    let (ok, stdout, err) =
        chatter(&["depth-study", "--quick", "--controllers", "off,fopid", "--out", d.to_str().unwrap()]);
    assert!(ok, "{err}");
    let csv = std::fs::read_to_string(d.join("depth_study.csv")).unwrap();
    let mut off: Vec<(f64, f64)> = csv
        .lines()
        .skip(1)
        .filter(|l| l.starts_with("off,"))
        .map(|l| {
            let c: Vec<f64> = l.split(',').skip(1).map(|x| x.parse().unwrap()).collect();
            (c[0], c[1])
        })
        .collect();
    assert_eq!(csv.lines().count(), 1 + 6, "{csv}");
    off.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert!(off.windows(2).all(|w| w[1].1 > w[0].1), "open-loop peaks {off:?}\n{stdout}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn sd_lobes_quick_runs_both_machines() {
    let d = out_dir("sd-lobes");
    let stdout = run(&["sd-lobes", "--quick", "--preset", "seed002-6.1", "--out", d.to_str().unwrap()]);
    assert!(stdout.contains("a_lim min"), "{stdout}");
    let csv = std::fs::read_to_string(d.join("sd_lobes.csv")).unwrap();
    assert_eq!(csv.lines().count(), 6, "{csv}");
    assert!(csv.starts_with("rpm,a_lim_mm,kind,"));
    // 38000 rpm: exact D-subdivision 1.57352 mm; the converged default is within its bracket
    // (1e-3 in --quick), the semi-discretisation at m = 10 within 1 %
    let last: Vec<&str> = csv.lines().last().unwrap().split(',').collect();
    let a: f64 = last[1].parse().unwrap();
    assert!((a / 1.57352 - 1.0).abs() < 1e-3, "{a}");
    assert_eq!(last[2], "hopf");
    let stdout =
        run(&["sd-lobes", "--quick", "--preset", "seed002-6.1", "--method", "sd", "--out", d.to_str().unwrap()]);
    assert!(stdout.contains("semi-discretisation, m = 10"), "{stdout}");
    let csv = std::fs::read_to_string(d.join("sd_lobes.csv")).unwrap();
    let a: f64 = csv.lines().last().unwrap().split(',').nth(1).unwrap().parse().unwrap();
    assert!((a / 1.57352 - 1.0).abs() < 0.01 && (a / 1.57352 - 1.0).abs() > 1e-4, "{a}");
    assert!(d.join("sd_lobes.png").metadata().unwrap().len() > 1000);
    // a shipped design (Table II n_c = 2): its lobes stay above its own ā_p = 1.650 mm, the
    // SD box check of the synthesis (the quick m = 10 within a few %)
    let nc2 = packaging::fmu_dir().join("designs/table2_nc2.ssv");
    let stdout = run(&["sd-lobes", "--quick", "--design", nc2.to_str().unwrap(), "--out", d.to_str().unwrap()]);
    assert!(stdout.contains("n_c = 2, x_F = 0.744") && stdout.contains("34000"), "{stdout}");
    let csv = std::fs::read_to_string(d.join("sd_lobes.csv")).unwrap();
    for line in csv.lines().skip(1) {
        let a: f64 = line.split(',').nth(1).unwrap().parse().unwrap();
        assert!(a > 1.6, "{line}");
    }
    // the seed 000 plant by its FMU parameter names: low-immersion down-milling
    let stdout = run(&[
        "sd-lobes",
        "--quick",
        "--set",
        "plant.cutting.milling=down",
        "--set",
        "plant.cutting.radial_engagement=0.0008",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(stdout.contains("seed plant"), "{stdout}");
    let csv = std::fs::read_to_string(d.join("sd_lobes.csv")).unwrap();
    assert_eq!(csv.lines().count(), 6, "{csv}");
    // a bad parameter name is refused with the FMU's message
    let out = Command::new(env!("CARGO_BIN_EXE_chatter"))
        .args(["sd-lobes", "--quick", "--set", "plant.cutting.kt_typo=1", "--out", d.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("no parameter or input"));
    std::fs::remove_dir_all(&d).unwrap();
}

/// The robustness sample as independent cases: planned, run in three shards (one of them
/// interrupted and re-run: only the missing cases run) and collected, it gives the tables of a
/// local `chatter robustness` run (rows in manifest order instead of completion order; the
/// local title adds the wall time).
#[test]
fn robustness_as_cases_in_shards_collects_the_local_runs_tables() {
    let args = ["--quick", "--controllers", "off,pid", "--groups", "speed", "--speeds", "1900,2350"];
    let local = out_dir("rob-local");
    let mut a: Vec<&str> = vec!["robustness"];
    a.extend(args);
    let l = local.to_str().unwrap();
    a.extend(["--out", l]);
    run(&a);
    let study = out_dir("rob-cases");
    let sdir = study.to_str().unwrap();
    let mut p: Vec<&str> = vec!["plan", "robustness"];
    p.extend(args);
    p.extend(["--out", sdir]);
    assert!(run(&p).contains("planned 4 cases of robustness"));
    run(&["run", sdir, "--shard", "1/3"]);
    // shard 2 "interrupted" after its first case: drop one result and run the shard again
    run(&["run", sdir, "--shard", "2/3"]);
    let results: Vec<_> = std::fs::read_dir(study.join("cases")).unwrap().map(|e| e.unwrap().path()).collect();
    // cases in manifest order: off-p00, off-p01, pid-p00, pid-p01; shard 2/3 is the second
    let dropped = results.iter().find(|p| p.to_string_lossy().contains("off-p01")).expect("shard 2 ran off-p01");
    std::fs::remove_file(dropped).unwrap();
    let again = run(&["run", sdir, "--shard", "2/3"]);
    assert!(again.contains("1 cases run, 0 already done"), "{again}");
    run(&["run", sdir, "--shard", "3/3"]);
    run(&["collect", sdir]);
    let read = |d: &PathBuf, f: &str| std::fs::read_to_string(d.join(f)).unwrap();
    let mut lc: Vec<String> = read(&local, "robustness.csv").lines().map(String::from).collect();
    let mut cc: Vec<String> = read(&study, "robustness.csv").lines().map(String::from).collect();
    assert_eq!(lc.len(), 5, "header + 4 runs");
    lc.sort();
    cc.sort();
    assert_eq!(lc, cc, "the same runs with the same numbers");
    let (lm, cm) = (read(&local, "robustness.md"), read(&study, "robustness.md"));
    let body = |s: &str| s.lines().skip(1).map(String::from).collect::<Vec<_>>();
    assert_eq!(body(&lm), body(&cm), "the same tables");
    assert!(lm.lines().next().unwrap().starts_with(cm.lines().next().unwrap()), "titles: {lm:.120} / {cm:.120}");
    assert!(study.join("robustness.png").is_file());
    std::fs::remove_dir_all(&local).unwrap();
    std::fs::remove_dir_all(&study).unwrap();
}

/// `chatter <study> ARGS --out LOCAL` and `chatter plan <study> ARGS --out DIR` + `run --shard
/// k/n` for every k + `collect DIR` write the same `<csv>` rows (in manifest order instead of
/// completion order) and the same `<md>` tables (the local title adds the wall time).
fn cases_match_local(study: &str, args: &[&str], n: usize, csv: &str, md: &str) -> usize {
    let (local, cases) = (out_dir(&format!("{study}-local")), out_dir(&format!("{study}-cases")));
    let (l, c) = (local.to_str().unwrap(), cases.to_str().unwrap());
    run(&[&[study], args, &["--out", l]].concat());
    run(&[&["plan", study], args, &["--out", c]].concat());
    for k in 1..=n {
        run(&["run", c, "--shard", &format!("{k}/{n}")]);
    }
    run(&["collect", c]);
    let read = |d: &PathBuf, f: &str| std::fs::read_to_string(d.join(f)).unwrap();
    let sorted = |s: String| {
        let mut v: Vec<String> = s.lines().map(String::from).collect();
        v.sort();
        v
    };
    let rows = sorted(read(&local, csv));
    assert_eq!(rows, sorted(read(&cases, csv)), "{study}: the same runs with the same numbers");
    let (lm, cm) = (read(&local, md), read(&cases, md));
    let body = |s: &str| s.lines().skip(1).map(String::from).collect::<Vec<_>>();
    assert_eq!(body(&lm), body(&cm), "{study}: the same tables");
    assert!(lm.lines().next().unwrap().starts_with(cm.lines().next().unwrap()), "{study} titles");
    std::fs::remove_dir_all(&local).unwrap();
    std::fs::remove_dir_all(&cases).unwrap();
    rows.len() - 1
}

#[test]
fn the_map_as_cases_in_shards_collects_the_local_maps_tables() {
    let args = ["--quick", "--controllers", "off", "--depths", "0.5,2.5", "--rpm", "1000,1200,200", "--quiet"];
    assert_eq!(cases_match_local("map", &args, 2, "map.csv", "map.md"), 4);
}

/// `chatter spindle validate` with a shipped design (the CLI path of `tests/seed002.rs`), and its
/// refusals: a ramp longer than a fifth of the run, a design file that does not exist, a design
/// naming a parameter LinearController does not have.
#[test]
fn spindle_validate_runs_a_shipped_design_and_refuses_bad_input() {
    let designs = packaging::fmu_dir().join("designs");
    let nc2 = designs.join("table2_nc2.ssv");
    let nc2 = nc2.to_str().unwrap();
    let (ok, stdout, stderr) =
        chatter(&["spindle", "validate", "--design", nc2, "--x-f", "0.744", "--rpm", "36000", "--duration", "0.1"]);
    assert!(ok, "{stderr}");
    let ratios: Vec<f64> = stdout.split([':', ',']).filter_map(|s| s.trim().split(' ').next()?.parse().ok()).collect();
    assert!(stdout.contains("growth ratio at 0.97"), "{stdout}");
    let (below, above) = (ratios[ratios.len() - 2], ratios[ratios.len() - 1]);
    assert!(below < 1.0 && above > 1.0, "{stdout}: {ratios:?}");
    let bad = std::env::temp_dir().join(format!("chatter-cli-bad-{}.ssv", std::process::id()));
    std::fs::write(&bad, std::fs::read_to_string(nc2).unwrap().replace("Ac[1,2]", "Ax[1,2]")).unwrap();
    for (args, want) in [
        (vec!["--ramp", "0.05", "--duration", "0.1"], "first fifth"),
        (vec!["--design", "/nonexistent/design.ssv"], "design.ssv"),
        (vec!["--design", bad.to_str().unwrap()], "Ax[1,2]"),
    ] {
        let mut a = vec!["spindle", "validate", "--quick"];
        a.extend(args);
        let (ok, _, stderr) = chatter(&a);
        assert!(!ok && stderr.contains(want), "{a:?}: {stderr}");
    }
    let _ = std::fs::remove_file(bad);
}
