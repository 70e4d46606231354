//! `chatter synth --quick` on §6.1: the D–K iteration with bisection reaches μ < 1 well above
//! the open-loop boundary, and the semi-discretisation confirms the box.

use seed002::synth::{Case, SynthOptions, design, initial, markdown};

#[test]
fn quick_section_61_synthesis_is_robust_and_sd_stable() {
    let o = SynthOptions::quick(1);
    let d = design(Case::Sec61, &initial(Case::Sec61, None, 1), &o, &|s| println!("{s}")).unwrap();
    println!("{}", markdown(std::slice::from_ref(&d)));
    // open loop: 1.57 mm at 38000 rpm; the design must beat it by a margin
    assert!(d.abar >= 1.8e-3, "ā_p = {}", d.abar);
    assert!(d.mu < 1.0 && d.mu_check.0 < 1.0, "μ̂ {} / {:?}", d.mu, d.mu_check);
    assert!(d.psi < 0.0);
    assert!(d.box_stable(), "SD minimum {} below ā_p {}", d.box_min, d.abar);
    assert!(d.ap_max.0 > 0.9 * 3.52e-3, "a_p,max {}", d.ap_max.0);
    // the structured gain keeps its structure
    let k = &d.controller.dc;
    assert!((k[(0, 0)] - k[(1, 1)]).abs() < 1e-9 * k.norm() && (k[(0, 1)] + k[(1, 0)]).abs() < 1e-9 * k.norm());
}
