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
    for f in ["table6_lobes.csv", "table6_lobes.png", "table8_ozsoy_lobes.csv", "table8_ozsoy_lobes.png"] {
        assert!(d.join(f).metadata().unwrap().len() > 100, "{f}");
    }
    std::fs::remove_dir_all(&d).unwrap();
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
    assert!(csv.starts_with("rpm,off_depth_mm,off_chatter_hz,pid_depth_mm,pid_chatter_hz"));
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
