//! Table II n_c = 4 from many starts: the design's θ read back from its `.ssv`, the starts
//! (distinct, of the three kinds), and a tiny run that streams, resumes and re-runs a row cut short.

use robust_synthesis::dk::DkOptions;
use seed002::multistart::{run, starts, theta_from_ssv};
use seed002::synth::{Case, SynthOptions, initial, ssv};
use std::sync::Mutex;

fn nc2() -> Vec<f64> {
    let path = packaging::workspace_root().join("packaging/designs/table2_nc2.ssv");
    theta_from_ssv(&std::fs::read_to_string(&path).unwrap(), "table2_nc2.ssv").unwrap()
}

#[test]
fn a_design_reads_back_from_its_ssv() {
    let th = nc2();
    assert_eq!(th.len(), 16);
    let par = Case::Table2 { nc: 2 }.parameterisation();
    let c = par.controller(&th, 1.0);
    // writing the controller again gives the shipped file's values
    let again = theta_from_ssv(&ssv("x", &c), "x").unwrap();
    for (a, b) in th.iter().zip(&again) {
        assert!((a - b).abs() <= 1e-12 * a.abs().max(1.0), "{a} vs {b}");
    }
    assert!(c.dc.norm() > 0.0 && c.ac.norm() > 0.0);
}

#[test]
fn the_starts_are_distinct_and_of_three_kinds() {
    let base = nc2();
    let s = starts(7, &base, 1);
    assert_eq!(s[0].theta, initial(Case::Table2 { nc: 4 }, Some(&base), 1), "start 0 is chatter synth's own");
    let kinds: Vec<&str> = s.iter().map(|s| s.kind).collect();
    assert_eq!(kinds, ["from_nc2", "from_nc2", "random_d_nc2", "scratch", "from_nc2", "random_d_nc2", "scratch"]);
    for (i, a) in s.iter().enumerate() {
        assert_eq!(a.theta.len(), 28);
        assert!(a.theta.iter().all(|x| x.is_finite()));
        for b in &s[i + 1..] {
            assert_ne!(a.theta, b.theta, "starts {} and {}", a.index, b.index);
        }
        match a.kind {
            // the n_c = 2 design's block (θ 0–3) and D_c (θ 24–27) kept
            "from_nc2" => assert!(a.theta[..4] == base[..4] && a.theta[24..] == base[12..]),
            "random_d_nc2" => assert!(a.theta[..4] != base[..4] && a.theta[24..] == base[12..]),
            _ => assert!(a.theta[24..].iter().all(|x| x.to_bits() == 0)),
        }
    }
    // reproducible alone
    assert_eq!(starts(3, &base, 1)[2], s[2]);
}

#[test]
fn a_tiny_multistart_streams_resumes_and_reruns_a_row_cut_short() {
    let o = SynthOptions {
        dk: DkOptions {
            freqs_hz: DkOptions::grid(50.0, 6000.0, 40),
            max_steps: 2,
            check_hz: DkOptions::grid(20.0, 10000.0, 80),
            ..DkOptions::default()
        },
        hi: 1.5e-3,
        resolution: 0.5e-3,
        sd_m: 6,
        sd_speeds: 2,
        seed: 1,
    };
    let dir = tempfile::tempdir().unwrap();
    let s = starts(1, &nc2(), 1);
    let log = Mutex::new(Vec::<String>::new());
    let progress = |m: &str| log.lock().unwrap().push(m.to_string());
    let out = run(dir.path(), &s, 1, &o, &progress).unwrap();
    assert_eq!(out.len(), 1);
    assert!(out[0].ap_max_mm > 0.0 && out[0].ap_max_mm.is_finite(), "{out:?}");
    let csv = std::fs::read_to_string(dir.path().join("multistart.csv")).unwrap();
    assert_eq!(csv.lines().count(), 2, "{csv}");
    let started = |log: &Mutex<Vec<String>>| log.lock().unwrap().iter().filter(|m| m.starts_with("start ")).count();
    assert_eq!(started(&log), 1);
    // a re-run finds the start done
    assert_eq!(run(dir.path(), &s, 1, &o, &progress).unwrap(), out);
    assert_eq!(started(&log), 1);
    // a row cut short is not trusted: run again, the file repaired
    let cut = &csv[..csv.trim_end().rfind(',').unwrap()];
    std::fs::write(dir.path().join("multistart.csv"), cut).unwrap();
    assert_eq!(run(dir.path(), &s, 1, &o, &progress).unwrap(), out);
    assert_eq!(started(&log), 2);
    assert_eq!(std::fs::read_to_string(dir.path().join("multistart.csv")).unwrap(), csv);
}
