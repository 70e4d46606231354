use super::*;
use crate::milling::{ForceLaw, Milling, MillingModel, Structure};
use crate::zero_order::{Cutting, LobeProblem, speed_grid};
use approx::assert_relative_eq;
use std::f64::consts::PI;

/// The 3-mode machine of the issue: x modes 600 Hz (2e7 N/m, ζ 0.03) and 1100 Hz (5e7, 0.02),
/// y mode 650 Hz (2.5e7, 0.035).
pub(crate) fn machine() -> Vec<ModeShape> {
    vec![
        ModalReceptance::mode(600.0, 2e7, 0.03, [1.0, 0.0]),
        ModalReceptance::mode(1100.0, 5e7, 0.02, [1.0, 0.0]),
        ModalReceptance::mode(650.0, 2.5e7, 0.035, [0.0, 1.0]),
    ]
}

/// 3 teeth, K_t = 8e8 N/m², K_r = 0.3 K_t, slotting.
pub(crate) fn slotting() -> Cutter {
    let (e, x) = Cutter::immersion(1.0, Milling::Down);
    Cutter::new(3, e, x, 8e8, 0.3 * 8e8, ForceLaw::Linear).unwrap()
}

#[test]
fn eig2_is_accurate_for_both_and_exact_zero_for_a_singular_matrix() {
    let m = Matrix2::new(
        Complex64::new(1.0, 2.0),
        Complex64::new(-0.5, 0.1),
        Complex64::new(3.0, -1.0),
        Complex64::new(0.2, 0.7),
    );
    for l in eig2(&m) {
        let d = (m - Matrix2::identity() * l).determinant();
        assert!(d.norm() < 1e-14, "{l}: det {d}");
    }
    let s = Matrix2::new(
        Complex64::new(2.0, 1.0),
        Complex64::new(0.0, 0.0),
        Complex64::new(3.0, 0.0),
        Complex64::new(0.0, 0.0),
    );
    let e = eig2(&s);
    assert_eq!(e[1], Complex64::new(0.0, 0.0));
    assert_eq!(e[0], Complex64::new(2.0, 1.0));
}

#[test]
fn the_modal_receptance_is_the_structure_of_the_milling_model() {
    // G = C_t (iω − A)⁻¹ B_t of Structure::from_modes
    let modes = machine();
    let s = Structure::from_modes(&modes).unwrap();
    let g = ModalReceptance::new(&modes).unwrap();
    for hz in [100.0, 610.0, 1099.0, 2500.0] {
        let w = 2.0 * PI * hz;
        let n = s.dim();
        let q =
            nalgebra::DMatrix::from_fn(n, n, |i, j| Complex64::new(0.0, if i == j { w } else { 0.0 }) - s.a[(i, j)]);
        let x = q.lu().solve(&s.bt.map(Complex64::from)).unwrap();
        let ss = s.ct.map(Complex64::from) * x;
        let gm = g.receptance(w);
        for i in 0..2 {
            for j in 0..2 {
                assert!((ss[(i, j)] - gm[(i, j)]).norm() <= 1e-12 * gm.norm(), "{hz} Hz ({i}, {j})");
            }
        }
    }
    assert!(ModalReceptance::new(&[]).is_err());
}

#[test]
fn one_direction_equals_the_one_dimensional_solver() {
    // one x mode: G = diag(Φ, 0), the eigenvalues of H̄G are H̄_xx Φ and 0; the 1-D solver with
    // α₀ = −H̄_xx/K_t (its force is −a K_t α₀ Δx) must give the same depths
    let mode = ModalReceptance::mode(600.0, 2e7, 0.03, [1.0, 0.0]);
    for (frac, mill) in [(1.0, Milling::Down), (0.5, Milling::Up), (0.3, Milling::Down), (0.1, Milling::Down)] {
        let (e, x) = Cutter::immersion(frac, mill);
        let cutter = Cutter::new(3, e, x, 8e8, 2.4e8, ForceLaw::Linear).unwrap();
        let zo = ZeroOrder2d::new(ModalReceptance::new(&[mode]).unwrap(), &cutter, (10.0, 3000.0), 3000.0).unwrap();
        let hxx = cutter.mean()[(0, 0)];
        let u = mode.tool[0];
        let phi = move |w: f64| {
            Complex64::new(mode.omega * mode.omega - w * w, 2.0 * mode.zeta * mode.omega * w).inv() * (u * u)
        };
        let cut = Cutting { kt: 8e8, alpha0: -hxx / 8e8, teeth: 3 };
        let one = LobeProblem::new(phi, cut, &GridOptions::new(10.0, 3000.0, 3, 3000.0)).unwrap();
        let mut finite = 0;
        for rpm in speed_grid(3000.0, 30000.0, 181) {
            let (a, b) = (zo.critical_depth(rpm), one.critical_depth(rpm));
            if b.depth.is_finite() {
                finite += 1;
                assert_relative_eq!(a.depth, b.depth, max_relative = 1e-9);
                assert_relative_eq!(a.chatter_hz, b.chatter_hz, max_relative = 1e-9);
            } else {
                assert!(a.depth.is_infinite(), "{frac} {rpm}: {a:?}");
            }
        }
        assert!(finite > 150, "{frac}: only {finite} finite depths");
    }
}

/// The 3-mode machine turned by 30° plus a cross-coupled mode at 800 Hz along 120°: G has
/// off-diagonal terms (G stays symmetric, so only a non-reciprocal G, below, can tell H̄ G from
/// H̄ᵀ G).
pub(crate) fn coupled() -> Vec<ModeShape> {
    let t = 30f64.to_radians();
    let (c, s) = (t.cos(), t.sin());
    vec![
        ModalReceptance::mode(600.0, 2e7, 0.03, [c, s]),
        ModalReceptance::mode(1100.0, 5e7, 0.02, [c, s]),
        ModalReceptance::mode(650.0, 2.5e7, 0.035, [-s, c]),
        ModalReceptance::mode(800.0, 3e7, 0.025, [120f64.to_radians().cos(), 120f64.to_radians().sin()]),
    ]
}

#[test]
fn with_cross_coupled_modes_zero_order_equals_the_exact_boundary() {
    for frac in [1.0, 0.3] {
        let (e, x) = Cutter::immersion(frac, Milling::Up);
        let cutter = Cutter::new(3, e, x, 8e8, 2.4e8, ForceLaw::Linear).unwrap();
        let zo = ZeroOrder2d::new(ModalReceptance::new(&coupled()).unwrap(), &cutter, (10.0, 4000.0), 4000.0).unwrap();
        let ti = MillingModel::new(&Structure::from_modes(&coupled()).unwrap(), cutter, None).unwrap().time_invariant();
        for rpm in speed_grid(4000.0, 30000.0, 27) {
            let ours = zo.critical_depth(rpm);
            let ex = ti.critical_depth(rpm, 40_000).unwrap().unwrap();
            assert_relative_eq!(ours.depth, ex.depth, max_relative = 1e-4);
        }
    }
}

#[test]
fn a_non_reciprocal_receptance_as_a_closure_equals_the_exact_boundary() {
    // the 3-mode machine with a static skew-symmetric feedback F_a = D_c v_a at an actuator point:
    // G = C_t (iω − A − B_a D_c C_a)⁻¹ B_t is not symmetric, so (unlike for a reciprocal
    // structure, where eig(H̄ G) = eig(H̄ᵀ G)) the order of H̄ and G matters
    let mut modes = machine();
    for (m, a) in modes.iter_mut().zip([[0.6, 0.2], [0.9, -0.3], [0.1, 0.7]]) {
        m.actuator = [a[0] * (m.tool[0] + m.tool[1]), a[1] * (m.tool[0] + m.tool[1])];
    }
    let s = Structure::from_modes(&modes).unwrap();
    let dc = nalgebra::DMatrix::from_row_slice(2, 2, &[0.0, 3e6, -3e6, 0.0]);
    let a_cl = &s.a + &s.ba * &dc * &s.ca;
    let (ct, bt) = (s.ct.map(Complex64::from), s.bt.map(Complex64::from));
    let g = move |w: f64| {
        let n = a_cl.nrows();
        let q =
            nalgebra::DMatrix::from_fn(n, n, |i, j| Complex64::new(0.0, if i == j { w } else { 0.0 }) - a_cl[(i, j)]);
        let x = &ct * q.lu().solve(&bt).unwrap();
        Matrix2::new(x[(0, 0)], x[(0, 1)], x[(1, 0)], x[(1, 1)])
    };
    let g0 = g(2.0 * PI * 640.0);
    assert!((g0[(0, 1)] - g0[(1, 0)]).norm() > 0.1 * g0[(0, 1)].norm(), "G is not skew enough: {g0}");
    let (e, x) = Cutter::immersion(0.5, Milling::Up);
    let cutter = Cutter::new(3, e, x, 8e8, 2.4e8, ForceLaw::Linear).unwrap();
    let model = MillingModel::new(&s, cutter.clone(), Some(&crate::milling::Controller::static_gain(dc, 0.0))).unwrap();
    assert!(model.undelayed_poles()[0].re < 0.0);
    let ti = model.time_invariant();
    let zo = ZeroOrder2d::new(g, &cutter, (10.0, 4000.0), 4000.0).unwrap();
    for rpm in speed_grid(4000.0, 30000.0, 27) {
        let ex = ti.critical_depth(rpm, 40_000).unwrap().unwrap();
        assert_relative_eq!(zo.critical_depth(rpm).depth, ex.depth, max_relative = 1e-4);
    }
}

#[test]
fn zero_order_equals_the_exact_boundary_of_the_averaged_system() {
    let modes = machine();
    let cutter = slotting();
    let zo = ZeroOrder2d::new(ModalReceptance::new(&modes).unwrap(), &cutter, (10.0, 4000.0), 4000.0).unwrap();
    let model = MillingModel::new(&Structure::from_modes(&modes).unwrap(), cutter, None).unwrap();
    let ti = model.time_invariant();
    for rpm in speed_grid(4000.0, 30000.0, 53) {
        let ours = zo.critical_depth(rpm);
        let ex = ti.critical_depth(rpm, 40_000).unwrap().unwrap();
        assert_relative_eq!(ours.depth, ex.depth, max_relative = 1e-4);
        assert_relative_eq!(2.0 * PI * ours.chatter_hz, ex.omega, max_relative = 1e-4);
    }
    // the quick check: about 3.19 mm near 10,000 rpm and 2.22 mm near 16,000 rpm; the
    // exact boundary of the averaged system (both methods) is 3.2238 and 2.2302 mm there, on a
    // flank where 100 rpm change the depth by 4.6 % and 1.5 %
    for (rpm, known, ours) in [(10_000.0, 3.19e-3, 3.22380e-3), (16_000.0, 2.22e-3, 2.23023e-3)] {
        let d = zo.critical_depth(rpm).depth;
        assert_relative_eq!(d, ours, max_relative = 2e-6);
        assert!((d / known - 1.0).abs() < 0.015, "{rpm} rpm: {d} m vs {known} m");
    }
}

/// `∫_a^b e^{iκφ} dφ`.
fn exp_integral(kappa: f64, a: f64, b: f64) -> Complex64 {
    if kappa == 0.0 {
        return Complex64::from(b - a);
    }
    (Complex64::from_polar(1.0, kappa * b) - Complex64::from_polar(1.0, kappa * a)) / Complex64::new(0.0, kappa)
}

#[test]
fn harmonics_have_the_closed_form_of_the_linear_law() {
    // one tooth over its engagement: H_r = (z/2π) ∫ H_tooth e^{−irzφ} dφ, H_tooth = c0 + cc cos 2φ + cs sin 2φ
    let (kt, kr) = (8e8, 2.4e8);
    let coef = [
        [(-kr / 2.0, kr / 2.0, -kt / 2.0), (-kt / 2.0, -kt / 2.0, -kr / 2.0)],
        [(kt / 2.0, -kt / 2.0, -kr / 2.0), (-kr / 2.0, -kr / 2.0, kt / 2.0)],
    ];
    for (frac, mill, z) in [(1.0, Milling::Down, 3u32), (0.05, Milling::Down, 2), (0.4, Milling::Up, 4)] {
        let (e, x) = Cutter::immersion(frac, mill);
        let cutter = Cutter::new(z, e, x, kt, kr, ForceLaw::Linear).unwrap();
        let h = directional_harmonics(&cutter, 8);
        for (r, hr) in h.iter().enumerate() {
            let k = -(r as f64) * z as f64;
            let (i0, ip, im) = (exp_integral(k, e, x), exp_integral(k + 2.0, e, x), exp_integral(k - 2.0, e, x));
            let (cos2, sin2) = ((ip + im) * 0.5, (ip - im) / Complex64::new(0.0, 2.0));
            let closed = Matrix2::from_fn(|i, j| {
                let (c0, cc, cs) = coef[i][j];
                (i0 * c0 + cos2 * cc + sin2 * cs) * (z as f64 / (2.0 * PI))
            });
            assert!((closed - hr).norm() <= 1e-12 * h[0].norm(), "{frac}, r = {r}: {closed} vs {hr}");
        }
    }
}

#[test]
fn harmonics_match_sub_interval_averages_for_the_power_law() {
    // independent of the piece splitting: Cutter::averaged over n sub-intervals times the
    // exponential at their midpoints (error O((rzΔφ)²) < 1e-7)
    let law = ForceLaw::Power { x_f: 0.75, feed_per_tooth: 1e-4 };
    for frac in [1.0, 0.3, 0.05] {
        let (e, x) = Cutter::immersion(frac, Milling::Down);
        let cutter = Cutter::new(3, e, x, 8e8, 2.4e8, law).unwrap();
        let h = directional_harmonics(&cutter, 6);
        assert_eq!(h[0], cutter.mean().map(Complex64::from));
        let n = 20_000;
        let d = cutter.pitch() / n as f64;
        for r in [1usize, 3, 6] {
            let mut s = Matrix2::<Complex64>::zeros();
            for q in 0..n {
                let (a, b) = (q as f64 * d, (q + 1) as f64 * d);
                let ph = Complex64::from_polar(1.0, -(r as f64) * 3.0 * 0.5 * (a + b));
                s += cutter.averaged(a, b).map(|v| ph * v);
            }
            s /= Complex64::from(n as f64);
            assert!((s - h[r]).norm() <= 1e-6 * h[0].norm(), "{frac} r = {r}: {s} vs {}", h[r]);
        }
    }
}
