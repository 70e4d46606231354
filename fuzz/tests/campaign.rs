//! The bounded fuzzing campaign of CI: every target, a fixed seed, a fixed
//! number of inputs (and a wall-time cap), each input under a time limit.
//! A panic or a hang fails the test and prints the input; keep it with
//! `cargo run --release -p fuzz -- --target NAME --seed N` (which
//! writes `fuzz/regressions/`).

use fuzz::{Campaign, Target, targets};
use std::time::Duration;

fn campaign(target: Target, inputs: u64) {
    let r = Campaign {
        target,
        seed: 0x5EED,
        max_inputs: inputs,
        max_time: Duration::from_secs(25),
        limit: Duration::from_secs(3),
    }
    .run();
    eprintln!(
        "{}: {} inputs in {:.1} s, {} classes, {} known defects hit",
        target.name,
        r.inputs,
        r.wall.as_secs_f64(),
        r.classes,
        r.known
    );
    assert!(r.inputs > 100, "the campaign ran");
    let found: Vec<String> =
        r.findings.iter().map(|f| format!("{} ({}): {:02x?}", f.what, f.file_name(), f.input)).collect();
    assert!(found.is_empty(), "{found:#?}");
}

#[test]
fn model_description_parsing_survives_mutation() {
    campaign(targets::MODEL_DESCRIPTION, 20_000);
}

#[test]
fn ssd_parsing_survives_mutation() {
    campaign(targets::SSD, 50_000);
}

#[test]
fn fmu_state_deserialisation_and_steps_survive_mutation() {
    campaign(targets::FMU_STATE, 100_000);
}

#[test]
fn fmi_call_sequences_survive_mutation() {
    campaign(targets::CALL_SEQUENCE, 20_000);
}

/// The harness itself can fail: a target that panics on some inputs is caught.
#[test]
fn the_harness_reports_a_panic_and_a_hang() {
    let t = Target {
        name: "selftest",
        seeds: || vec![b"ok".to_vec()],
        dict: &["boom", "hang"],
        max_len: 64,
        known_panics: &[],
        known_hangs: false,
        run: |d| {
            let s = String::from_utf8_lossy(d);
            if s.contains("boom") {
                panic!("boom");
            }
            if s.contains("hang") {
                std::thread::sleep(Duration::from_secs(2));
            }
            "ok".into()
        },
    };
    let r = Campaign {
        target: t,
        seed: 1,
        max_inputs: 400,
        max_time: Duration::from_secs(20),
        limit: Duration::from_millis(200),
    }
    .run();
    assert!(r.findings.iter().any(|f| f.what == "panic: boom"), "{:?}", r.findings);
    assert!(r.findings.iter().any(|f| f.what.starts_with("hang")), "{:?}", r.findings);
}
