//! The generalised plant against the physical loop, and the gradients against finite differences.

use delay_stability::presets::{SEED002_GAINS, seed002, seed002_cutter, seed002_structure};
use nalgebra::DMatrix;
use num_complex::Complex64;
use robust_synthesis::mu::CMat;
use robust_synthesis::plant::{Parameterisation, Problem, Weight, close, close_n, controller_frf, scaled_gain};

fn problem(x_f: f64, abar: f64) -> Problem {
    Problem {
        structure: seed002_structure(),
        hbar: seed002_cutter(x_f).unwrap().mean(),
        abar,
        rpm: (34000.0, 36000.0),
        teeth: 4,
        weight: Weight::SEED002_62,
        beta: 1.0,
    }
}

fn theta_nc2() -> Vec<f64> {
    // A block, B (2×2), C (2×2), D (2×2)
    vec![-0.3, 2.4, -2.4, -0.3, 0.05, -0.02, 0.03, 0.04, -0.06, 0.02, 0.01, 0.05, 0.4, -0.6, 0.7, 0.3]
}

#[test]
fn eliminating_the_uncertainty_gives_the_physical_loop() {
    let pr = problem(0.744, 2.0e-3);
    let par = Parameterisation::Full { nc: 2 };
    let c = par.controller(&theta_nc2(), 1.0);
    let (tau0, dtmax) = pr.delays();
    let st = &pr.structure;
    for (w, dt_frac, da) in [
        (2.0 * std::f64::consts::PI * 1300.0, 0.7, Complex64::new(0.3, -0.4)),
        (2.0e4, -1.0, Complex64::new(-0.9, 0.1)),
    ] {
        let dtau = dt_frac * dtmax;
        let p = pr.generalized(w).unwrap();
        let (k, _, _) = controller_frf(&c, w).unwrap();
        let l = close(&p, &k).unwrap();
        // upper LFT with Δ̃ = diag((e^{−iωδτ} − 1)/Ω I₄, δa I₂): r → z
        let om = pr.omega_bound(w);
        let dl = (Complex64::new(0.0, -w * dtau).exp() - 1.0) / om;
        let mut delta = CMat::zeros(6, 6);
        for i in 0..4 {
            delta[(i, i)] = dl;
        }
        delta[(4, 4)] = da;
        delta[(5, 5)] = da;
        let n11 = l.n.view((0, 0), (6, 6)).into_owned();
        let n12 = l.n.view((0, 6), (6, 2)).into_owned();
        let n21 = l.n.view((6, 0), (2, 6)).into_owned();
        let n22 = l.n.view((6, 6), (2, 2)).into_owned();
        let inner = (CMat::identity(6, 6) - &n11 * &delta).try_inverse().unwrap();
        let lft = n22 + n21 * &delta * inner * n12;
        // physical: a_p = ½ā(1 + δa) (complex here: the formula is analytic in it), τ = τ₀ + δτ
        let ap = 0.5 * pr.abar * (Complex64::from(1.0) + da);
        let s = Complex64::new(0.0, w);
        let e = (-s * (tau0 + dtau)).exp();
        let cx = |m: &DMatrix<f64>| m.map(Complex64::from);
        let bh = cx(&(&st.bt * DMatrix::from_fn(2, 2, |i, j| pr.hbar[(i, j)])));
        let m = CMat::identity(8, 8) * s - cx(&st.a) - bh * cx(&st.ct) * (ap * (Complex64::from(1.0) - e));
        let xf = m.try_inverse().unwrap() * cx(&st.ba);
        let loop_ = (CMat::identity(2, 2) - &k * cx(&st.ca) * xf * (Complex64::from(1.0) - e)).try_inverse().unwrap();
        let phys = loop_ * &k * pr.weight.at(w);
        let err = (&lft - &phys).norm() / phys.norm();
        assert!(err < 1e-9, "ω = {w}: LFT {lft} vs physical {phys} ({err})");
    }
}

#[test]
fn the_loop_alone_is_the_loop_of_close_bit_for_bit() {
    // the D-step and the K-step's sweep use close_n: it must be N of close exactly (the synthesis
    // keeps its results byte for byte)
    let pr = problem(0.744, 1.5e-3);
    let par = Parameterisation::Full { nc: 2 };
    let c = par.controller(&theta_nc2(), 1.0);
    for hz in [20.0, 640.0, 1250.0, 2517.0, 7900.0] {
        let w = 2.0 * std::f64::consts::PI * hz;
        let p = pr.generalized(w).unwrap();
        let (k, _, _) = controller_frf(&c, w).unwrap();
        let full = close(&p, &k).unwrap().n;
        let alone = close_n(&p, &k).unwrap();
        assert!(
            full.iter()
                .zip(alone.iter())
                .all(|(a, b)| a.re.to_bits() == b.re.to_bits() && a.im.to_bits() == b.im.to_bits()),
            "{hz} Hz"
        );
    }
}

#[test]
fn gain_gradient_matches_finite_differences() {
    let pr = problem(0.744, 1.5e-3);
    let par = Parameterisation::Full { nc: 2 };
    let th = theta_nc2();
    let w = 2.0 * std::f64::consts::PI * 1250.0;
    let p = pr.generalized(w).unwrap();
    let d = CMat::from_fn(8, 8, |i, j| {
        if i == j {
            Complex64::from(1.0 + 0.1 * i as f64)
        } else if i > j && i < 4 {
            Complex64::new(0.1, 0.05)
        } else {
            Complex64::from(0.0)
        }
    });
    let dinv = d.clone().try_inverse().unwrap();
    let f = |t: &[f64]| {
        let c = par.controller(t, 1.0);
        let (k, _, _) = controller_frf(&c, w).unwrap();
        scaled_gain(&close(&p, &k).unwrap(), &d, &dinv, &c, w, &par).unwrap()
    };
    let (_, g) = f(&th);
    for k in 0..th.len() {
        let h = 1e-6;
        let (mut tp, mut tm) = (th.clone(), th.clone());
        tp[k] += h;
        tm[k] -= h;
        let fd = (f(&tp).0 - f(&tm).0) / (2.0 * h);
        assert!(
            (fd - g[k]).abs() < 1e-5 * (1.0 + g.iter().map(|v| v.abs()).fold(0.0, f64::max)),
            "θ{k}: {fd} vs {}",
            g[k]
        );
    }
}

#[test]
fn abscissa_matches_the_semi_discretisation_and_its_gradient_finite_differences() {
    // x_F = 1: H(t) ≡ H̄, so the nominal loop is the time-invariant milling model at τ₀, ½ā
    let (k1, k2) = SEED002_GAINS;
    let mut pr = problem(1.0, 3.0e-3);
    pr.rpm = (36000.0, 38000.0);
    let par = Parameterisation::Structured;
    let th = [k1 * 1e-3, k2 * 1e-3];
    let (psi, g) = pr.abscissa(&par, &th, 24).unwrap();
    let (tau0, _) = pr.delays();
    let model = seed002(1.0, Some(par.controller(&th, 1.0).dc)).unwrap();
    let rpm0 = 60.0 / (4.0 * tau0);
    let mult = delay_stability::sd::critical_multiplier(&model.at(rpm0, 0.5 * pr.abar).unwrap(), 60).unwrap();
    let sd = mult.rho.ln();
    println!("Ψτ₀ = {psi}, SD ln ρ = {sd}");
    assert!((psi - sd).abs() < 2e-3, "{psi} vs {sd}");
    for k in 0..2 {
        let h = 1e-6;
        let mut tp = th;
        tp[k] += h;
        let mut tm = th;
        tm[k] -= h;
        let fd = (pr.abscissa(&par, &tp, 24).unwrap().0 - pr.abscissa(&par, &tm, 24).unwrap().0) / (2.0 * h);
        assert!((fd - g[k]).abs() < 1e-5 * (1.0 + fd.abs()), "θ{k}: {fd} vs {}", g[k]);
    }
    // the gradient of the nc = 2 loop too
    let par2 = Parameterisation::Full { nc: 2 };
    let t2 = theta_nc2();
    let pr2 = problem(0.744, 1.0e-3);
    let (_, g2) = pr2.abscissa(&par2, &t2, 24).unwrap();
    for k in [0, 5, 9, 14] {
        let h = 1e-6;
        let (mut tp, mut tm) = (t2.clone(), t2.clone());
        tp[k] += h;
        tm[k] -= h;
        let fd = (pr2.abscissa(&par2, &tp, 24).unwrap().0 - pr2.abscissa(&par2, &tm, 24).unwrap().0) / (2.0 * h);
        assert!((fd - g2[k]).abs() < 1e-4 * (1.0 + fd.abs()), "nc2 θ{k}: {fd} vs {}", g2[k]);
    }
}
