//! `chatter afrac --quick` as a library call: the open loop grows at 5 mm and decays at 2 mm,
//! every controller turns the growth into a decay, β = 1.75 moves the speed more than β = 1
//! and is faster; the GA runs reproducibly.

use seed001::afrac::{self, AfracStudy, Ga};

#[test]
fn quick_afrac_study_reproduces_the_qualitative_claims() {
    let s = AfracStudy { duration: 1.6, betas: vec![1.0, 1.75], ..Default::default() };
    let runs = s.run().unwrap();
    let get = |l: &str| runs.iter().find(|r| r.0.label == l).unwrap_or_else(|| panic!("{l}"));
    let (open5, open2) = (&get("open loop 5 mm").0, &get("open loop 2 mm").0);
    assert!(open5.t_peak > 1.3 && open5.t10.is_none(), "5 mm open loop must grow: {open5:?}");
    assert!(open2.t1.is_some(), "2 mm open loop must decay: {open2:?}");
    let (b1, b175) = (&get("beta = 1").0, &get("beta = 1.75").0);
    let bumpless = &get("AFrAC bumpless").0;
    for r in [b1, b175, bumpless] {
        // the largest |x| is the response to the pulse: the growth is stopped
        assert!(r.t_peak < 0.1, "{} must stop the growth: {r:?}", r.label);
    }
    assert!(b175.speed_excursion > 2.0 * b1.speed_excursion, "{b175:?} vs {b1:?}");
    assert!(b175.mean_abs_x < b1.mean_abs_x, "{b175:?} vs {b1:?}");
    assert!(bumpless.t1.is_some_and(|t| t < 1.5), "{bumpless:?}");
    println!("{}", afrac::summary_markdown(&runs.iter().map(|r| r.0.clone()).collect::<Vec<_>>()));
}

#[test]
fn the_ga_is_reproducible() {
    let s = AfracStudy { duration: 0.8, ..Default::default() };
    let g = Ga { population: 4, generations: 2, seed: 7, ..Default::default() };
    let a = afrac::ga(&s, &g, true).unwrap();
    let b = afrac::ga(&s, &g, true).unwrap();
    assert_eq!(a, b);
    assert_eq!(a.evaluations, 4 + 2 * 3);
    assert!(a.history.windows(2).all(|w| w[1] <= w[0]), "elitism: the best never gets worse {:?}", a.history);
    assert!(a.times.iter().all(|t| (0.02..=2.4).contains(t)));
}
