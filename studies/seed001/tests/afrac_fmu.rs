//! `chatter afrac --fmu` as a library call: every case of the seed 001 study run through the
//! packaged FMUs (`Afrac.ssd` for the controlled cases, `TurningProcess.fmu` alone for the open
//! loop) gives the core loop's trace bitwise, so the summary table is the core one.

use seed001::afrac::{self, AfracStudy};
use seed001::afrac_fmu::run_fmu;

#[test]
fn every_case_through_the_fmus_equals_the_core_loop_bitwise() {
    packaging::packaged("AfracController.fmu");
    let s = AfracStudy { duration: 0.8, betas: vec![1.75], ..Default::default() };
    let (n0, f0) = (s.controller.initial_speed, s.controller.initial_feed);
    for case in s.cases() {
        let core = afrac::run(&case).unwrap();
        let fmu = run_fmu(&case, &packaging::fmu_dir()).unwrap();
        assert_eq!(core.len(), fmu.len(), "{}", case.label);
        for (k, (c, f)) in core.iter().zip(&fmu).enumerate() {
            let bits = |p: &afrac::Point| [p.t, p.x, p.v, p.force, p.speed, p.feed, p.beta].map(f64::to_bits);
            assert_eq!(bits(c), bits(f), "{}: point {k}: core {c:?}, FMUs {f:?}", case.label);
        }
        assert_eq!(afrac::summarise(&case.label, &core, n0, f0), afrac::summarise(&case.label, &fmu, n0, f0));
    }
}
