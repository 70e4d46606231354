//! The five benchmark controllers of seed 000's Table 8 (the Ozsoy et al. benchmark), each a
//! design from a few parameters on a [`DesignPlant`], delivered as `u = K(s) x` in SI (`u` the
//! actuator command in N, `x` the measured displacement in m; the negative feedback is in K).
//!
//! The seed names the classes and the PSO variables only (Section 5.7); the structures here
//! are our readings, documented in the book (seed 000, Table 8):
//!
//! * **DVF** (one gain g): `K = −g s ω_f/(s + ω_f)`, a differentiator filtered at `f_f`
//!   (5 kHz).
//! * **VPA** (virtual passive absorber of mass `μ_v m`, tuned to `r_v ωₙ` with damping ratio
//!   `ζ_v`): the force of that absorber on the structure,
//!   `K = −(c_v D_f(s) + k_v) m_v s²/(m_v s² + c_v s + k_v)` with `D_f = s ω_f/(s + ω_f)` the
//!   filtered velocity its damper sees (as `ω_f → ∞`: `−m_v s²(c_v s + k_v)/(m_v s² + c_v s + k_v)`,
//!   the absorber's dynamic mass). States: absorber position and velocity, the filter.
//! * **LQR** with a steady-state Kalman observer (LQG): state feedback on `[x̃, x̃', z_a]`
//!   (normalised mode + actuator, [`crate::plant`]) with `Q = diag(q₁, q₂, 0, 0)`, `R`; the
//!   observer for the disturbance force (white, the variance of the seed's 50 N RMS in its
//!   2 kHz band) and a sensor noise (10 nm RMS in the same band, our choice), the command known
//!   to it: `ξ' = (A − B K − L C) ξ + L y`, `u = −K ξ` (order 4).
//! * **H∞** mixed sensitivity on the disturbance force: `‖[W_S S; W_T T]‖∞` with `S = x̃/d`
//!   (the closed-loop receptance over the static compliance: 1 at DC for an inertial actuator)
//!   and `T = −F_a/d` (the actuator force per disturbance force), `W_S` low-pass and `W_T`
//!   high-pass, each given by its DC gain and crossover (first order, HF gain = 1/DC gain); the
//!   full-order central controller of [`crate::synthesis::hinfsyn`] at 5 % above the optimal
//!   level (order 6).
//! * **μ** ([`crate::mu_design`]): the same weights, plus the stiffness `k ± 15 %` and the
//!   regenerative cutting force of a design depth `b_d` at every speed with `K_t + 15 %` as
//!   complex uncertainties, by D–K iteration with constant scalings (order 6).

use crate::DesignError;
use crate::plant::{DesignPlant, MixedSensitivity, Weight, generalized};
use crate::riccati::{kalman, lqr};
use crate::ss::StateSpace;
use crate::synthesis::hinfsyn;
use nalgebra::DMatrix;
use num_complex::Complex64;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

type Mat = DMatrix<f64>;

/// DVF parameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Dvf {
    /// Velocity gain g \[N·s/m\].
    pub gain: f64,
    /// Differentiator filter corner \[Hz\].
    pub filter_hz: f64,
}

/// VPA parameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Vpa {
    /// Absorber mass over the modal mass.
    pub mass_ratio: f64,
    /// Absorber natural frequency over ωₙ.
    pub frequency_ratio: f64,
    /// Absorber damping ratio.
    pub damping_ratio: f64,
    /// Filter corner of the damper's velocity \[Hz\].
    pub filter_hz: f64,
}

impl Vpa {
    /// Den Hartog's optimal absorber of mass ratio μ: `r = 1/(1 + μ)`,
    /// `ζ = √(3μ/(8(1 + μ)³))`.
    pub fn den_hartog(mass_ratio: f64, filter_hz: f64) -> Vpa {
        let mu = mass_ratio;
        Vpa {
            mass_ratio: mu,
            frequency_ratio: 1.0 / (1.0 + mu),
            damping_ratio: (3.0 * mu / (8.0 * (1.0 + mu).powi(3))).sqrt(),
            filter_hz,
        }
    }
}

/// LQR + Kalman parameters (weights on the normalised states, module docs).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Lqr {
    /// q₁ on x̃².
    pub q1: f64,
    /// q₂ on x̃'².
    pub q2: f64,
    /// R on u² \[1/N²\].
    pub r: f64,
    /// Disturbance force RMS \[N\] over `bandwidth_hz`.
    pub disturbance_rms: f64,
    /// Sensor noise RMS \[m\] over `bandwidth_hz`.
    pub sensor_rms: f64,
    /// The band of both \[Hz\].
    pub bandwidth_hz: f64,
}

/// H∞ parameters: the weights, each a symmetric first-order weight given by its DC gain and its
/// crossover \[Hz\] (HF gain = 1/DC gain): `W_S` low-pass, `W_T` high-pass.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Hinf {
    /// W_S DC gain (> 1).
    pub ws_dc: f64,
    /// W_S crossover \[Hz\].
    pub ws_hz: f64,
    /// W_T DC gain (< 1).
    pub wt_dc: f64,
    /// W_T crossover \[Hz\].
    pub wt_hz: f64,
    /// Relative back-off of the controller's level above the optimum.
    pub backoff: f64,
    /// Sensor-noise regularisation ε.
    pub noise: f64,
    /// Command-weight regularisation ε_u.
    pub control: f64,
}

impl Hinf {
    /// The weights in normalised frequency.
    pub fn weights(&self, plant: &DesignPlant) -> MixedSensitivity {
        let w = 2.0 * PI / plant.omega_n();
        MixedSensitivity {
            ws: Weight { dc: self.ws_dc, crossover: self.ws_hz * w, hf: 1.0 / self.ws_dc },
            wt: Weight { dc: self.wt_dc, crossover: self.wt_hz * w, hf: 1.0 / self.wt_dc },
            noise: self.noise,
            control: self.control,
        }
    }
}

/// The default filter corner of DVF and VPA \[Hz\].
pub const FILTER_HZ: f64 = 5000.0;

/// The defaults of the calibrated designs (module docs; the μ defaults are in
/// [`crate::mu_design`]).
pub const DEFAULT_LQR: Lqr =
    Lqr { q1: 0.0, q2: 1.0, r: 1.0, disturbance_rms: 50.0, sensor_rms: 1e-8, bandwidth_hz: 2000.0 };

/// The default weights of the H∞ and μ designs (the calibrated mode varies `wt_hz`: above its
/// crossover `|W_T| ≈ ω/ω_c` up to the HF gain, so the crossover sets how much actuator force
/// the level allows at the mode).
pub const DEFAULT_HINF: Hinf =
    Hinf { ws_dc: 10.0, ws_hz: 300.0, wt_dc: 1e-3, wt_hz: 1.0, backoff: 0.05, noise: 1e-3, control: 1e-3 };

/// What a design reports besides its controller.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// H∞/μ: the controller's level γ (the bound it was synthesised for).
    pub gamma: f64,
    /// H∞/μ: the optimal level of the last synthesis.
    pub gamma_opt: f64,
    /// H∞: `‖[W_S S; W_T T]‖∞` of the closed loop (the `d` channel), computed independently.
    pub achieved: f64,
    /// μ: the largest μ upper bound over frequency (frequency-dependent D scalings).
    pub mu_peak: f64,
    /// μ: the robust-stability bound (uncertainty channels alone); below 1 certifies
    /// chatter-free cutting at the design depth at every speed with `K_t + 15 %`, `k ± 15 %`.
    pub mu_rs: f64,
    /// μ: D–K iterations done.
    pub dk_steps: usize,
    /// μ: the constant scalings `(d_k, d_c)` of the kept controller.
    pub scalings: [f64; 2],
}

/// A designed controller.
#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    /// `u = K(s) x` in SI (N per m).
    pub controller: StateSpace,
    /// Levels and bounds (zero where they do not apply).
    pub report: Report,
}

/// `−g s ω_f/(s + ω_f)` (module docs).
pub fn dvf(p: &Dvf) -> Result<Design, DesignError> {
    let wf = 2.0 * PI * p.filter_hz;
    if !(p.gain.is_finite() && wf > 0.0 && wf.is_finite()) {
        return Err(DesignError::Invalid(format!("DVF: need a finite gain and a filter > 0 Hz (got {p:?})")));
    }
    let g = p.gain;
    let controller = StateSpace::new(
        Mat::from_element(1, 1, -wf),
        Mat::from_element(1, 1, wf),
        Mat::from_element(1, 1, g * wf),
        Mat::from_element(1, 1, -g * wf),
    )?;
    Ok(Design { controller: controller.io_balanced(), report: Report::default() })
}

/// The DVF transfer function evaluated from its formula (the reference for [`dvf`]).
pub fn dvf_at(p: &Dvf, omega: f64) -> Complex64 {
    let s = Complex64::new(0.0, omega);
    let wf = 2.0 * PI * p.filter_hz;
    -s * p.gain * wf / (s + wf)
}

fn vpa_constants(plant: &DesignPlant, p: &Vpa) -> (f64, f64, f64, f64) {
    let mv = p.mass_ratio * plant.mass;
    let wv = p.frequency_ratio * plant.omega_n();
    (mv, 2.0 * p.damping_ratio * mv * wv, mv * wv * wv, 2.0 * PI * p.filter_hz)
}

/// The virtual passive absorber (module docs). States: absorber position `x_v`, velocity
/// `ẋ_v`, the velocity filter's state `ξ` (`D_f x = ω_f (x − ξ)`).
pub fn vpa(plant: &DesignPlant, p: &Vpa) -> Result<Design, DesignError> {
    plant.validate()?;
    if !(p.mass_ratio > 0.0 && p.frequency_ratio > 0.0 && p.damping_ratio >= 0.0 && p.filter_hz > 0.0) {
        return Err(DesignError::Invalid(format!("VPA: need μ_v, r_v, f_f > 0 and ζ_v ≥ 0 (got {p:?})")));
    }
    let (mv, cv, kv, wf) = vpa_constants(plant, p);
    // m_v ẍ_v = c_v (ω_f (x − ξ) − ẋ_v) + k_v (x − x_v);  F = −m_v ẍ_v
    let a = Mat::from_row_slice(3, 3, &[0.0, 1.0, 0.0, -kv / mv, -cv / mv, -cv * wf / mv, 0.0, 0.0, -wf]);
    let b = Mat::from_column_slice(3, 1, &[0.0, (cv * wf + kv) / mv, wf]);
    let c = Mat::from_row_slice(1, 3, &[kv, cv, cv * wf]);
    let d = Mat::from_element(1, 1, -(cv * wf + kv));
    Ok(Design { controller: StateSpace::new(a, b, c, d)?.io_balanced(), report: Report::default() })
}

/// The VPA transfer function from its formula (the reference for [`vpa`]).
pub fn vpa_at(plant: &DesignPlant, p: &Vpa, omega: f64) -> Complex64 {
    let (mv, cv, kv, wf) = vpa_constants(plant, p);
    let s = Complex64::new(0.0, omega);
    let df = s * wf / (s + wf);
    -(df * cv + kv) * s * s * mv / (s * s * mv + s * cv + kv)
}

/// LQR with the steady-state Kalman observer (module docs).
pub fn lqg(plant: &DesignPlant, p: &Lqr) -> Result<Design, DesignError> {
    plant.validate()?;
    if !(p.q1 >= 0.0 && p.q2 >= 0.0 && p.r > 0.0 && p.disturbance_rms > 0.0 && p.sensor_rms > 0.0) {
        return Err(DesignError::Invalid(format!("LQR: need q₁, q₂ ≥ 0, R > 0 and positive noise levels ({p:?})")));
    }
    let (a, bu, bd, cx, _, _) = plant.model(0.0);
    let q = Mat::from_diagonal(&nalgebra::DVector::from_vec(vec![p.q1, p.q2, 0.0, 0.0]));
    let (k, _) = lqr(&a, &bu, &q, &Mat::from_element(1, 1, p.r))?;
    // white-noise intensities (variance over the two-sided band 2B), in normalised time (× ωₙ)
    let wn = plant.omega_n();
    let w_int = p.disturbance_rms.powi(2) / (2.0 * p.bandwidth_hz) * wn;
    let v_int = (plant.stiffness * p.sensor_rms).powi(2) / (2.0 * p.bandwidth_hz) * wn;
    let (l, _) = kalman(&a, &cx, &(&bd * bd.transpose() * w_int), &Mat::from_element(1, 1, v_int))?;
    let ak = &a - &bu * &k - &l * &cx;
    let kn = StateSpace::new(ak, l, -k, Mat::zeros(1, 1))?;
    Ok(Design { controller: plant.to_physical(&kn), report: Report::default() })
}

/// The H∞ mixed-sensitivity design (module docs); reports γ, γ_opt and the achieved norm of
/// the `d` channel, computed on the closed loop by [`crate::norm::hinf_norm`].
pub fn hinf(plant: &DesignPlant, p: &Hinf) -> Result<Design, DesignError> {
    plant.validate()?;
    let w = p.weights(plant);
    let (gp, _) = generalized(plant, &w, None)?;
    let s = hinfsyn(&gp, 1e-4, p.backoff)?;
    let achieved = channel_norm(&gp, &s.controller, 0)?;
    Ok(Design {
        controller: plant.to_physical(&s.controller),
        report: Report { gamma: s.gamma, gamma_opt: s.gamma_opt, achieved, ..Report::default() },
    })
}

/// `‖w_j → z‖∞` of the closed loop of `gp` with the normalised controller `k`.
pub fn channel_norm(gp: &crate::ss::Generalized, k: &StateSpace, j: usize) -> Result<f64, DesignError> {
    let cl = gp.close(k);
    let single = StateSpace {
        a: cl.a.clone(),
        b: cl.b.columns(j, 1).into_owned(),
        c: cl.c.clone(),
        d: cl.d.columns(j, 1).into_owned(),
    };
    Ok(crate::norm::hinf_norm(&single, 1e-8)?.value)
}

/// The closed loop of the design model with a physical controller `u = K x` (no cutting):
/// the continuous state matrix (states: mode `[x, ẋ]` in SI, actuator, controller).
pub fn loop_matrix(plant: &DesignPlant, k: &StateSpace) -> Mat {
    let (m, c, kk) = (plant.mass, plant.damping(), plant.stiffness);
    let nk = k.order();
    let n = 4 + nk;
    let mut a = Mat::zeros(n, n);
    // plant: ẍ = (−k x − c ẋ + F_a)/m, F_a = C_a z + D_a u, ż = A_a z + B_a u, u = C_k ξ + D_k x
    let dk = k.d[(0, 0)];
    a[(0, 1)] = 1.0;
    a[(1, 0)] = (-kk + plant.actuator_d * dk) / m;
    a[(1, 1)] = -c / m;
    a[(1, 2)] = plant.actuator_c[0] / m;
    a[(1, 3)] = plant.actuator_c[1] / m;
    for i in 0..2 {
        for j in 0..2 {
            a[(2 + i, 2 + j)] = plant.actuator_a[i][j];
        }
        a[(2 + i, 0)] = plant.actuator_b[i] * dk;
    }
    for j in 0..nk {
        a[(1, 4 + j)] = plant.actuator_d * k.c[(0, j)] / m;
        for i in 0..2 {
            a[(2 + i, 4 + j)] = plant.actuator_b[i] * k.c[(0, j)];
        }
        a[(4 + j, 0)] = k.b[(j, 0)];
        for l in 0..nk {
            a[(4 + j, 4 + l)] = k.a[(j, l)];
        }
    }
    a
}

/// The spectral radius of the loop of [`loop_matrix`] as a master steps it every `h`
/// (Gauss–Seidel, controller first): the plant exactly discretised with the command held,
/// the controller exactly discretised with its input held (the `LinearController` steps),
/// `u_k = C_d ξ_k + D x_k`.
pub fn sampled_loop_radius(plant: &DesignPlant, k: &StateSpace, h: f64) -> f64 {
    let nk = k.order();
    // open plant (u as an input): states [x, ẋ, z]
    let zero = StateSpace::gain(0.0);
    let mut ap = loop_matrix(plant, &zero);
    ap = ap.view((0, 0), (4, 4)).into_owned();
    let bp =
        Mat::from_column_slice(4, 1, &[0.0, plant.actuator_d / plant.mass, plant.actuator_b[0], plant.actuator_b[1]]);
    let exp_of = |a: &Mat, b: &Mat| -> (Mat, Mat) {
        let (n, m) = (a.nrows(), b.ncols());
        let mut big = Mat::zeros(n + m, n + m);
        big.view_mut((0, 0), (n, n)).copy_from(&(a * h));
        big.view_mut((0, n), (n, m)).copy_from(&(b * h));
        let e = big.exp();
        (e.view((0, 0), (n, n)).into_owned(), e.view((0, n), (n, m)).into_owned())
    };
    let (phi_p, gam_p) = exp_of(&ap, &bp);
    let (phi_c, gam_c) = if nk > 0 { exp_of(&k.a, &k.b) } else { (Mat::zeros(0, 0), Mat::zeros(0, 1)) };
    let cp = Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]);
    let n = 4 + nk;
    let mut m = Mat::zeros(n, n);
    m.view_mut((0, 0), (4, 4)).copy_from(&(&phi_p + &gam_p * &k.d * &cp));
    m.view_mut((0, 4), (4, nk)).copy_from(&(&gam_p * &k.c));
    m.view_mut((4, 0), (nk, 4)).copy_from(&(&gam_c * &cp));
    m.view_mut((4, 4), (nk, nk)).copy_from(&phi_c);
    m.complex_eigenvalues().iter().map(|l| l.norm()).fold(0.0, f64::max)
}

/// The DVF gain at which the loop with the inertial actuator loses stability (no cutting), by
/// bisection on log g in `[lo, hi]`: continuous root locus (`h = None`, the spectral abscissa
/// of [`loop_matrix`]) or the loop stepped every `h` ([`sampled_loop_radius`]).
pub fn dvf_gain_limit(
    plant: &DesignPlant,
    filter_hz: f64,
    h: Option<f64>,
    (mut lo, mut hi): (f64, f64),
) -> Result<f64, DesignError> {
    let unstable = |g: f64| -> Result<bool, DesignError> {
        let k = dvf(&Dvf { gain: g, filter_hz })?.controller;
        Ok(match h {
            None => crate::riccati::abscissa(&loop_matrix(plant, &k)) >= 0.0,
            Some(h) => sampled_loop_radius(plant, &k, h) >= 1.0,
        })
    };
    if unstable(lo)? || !unstable(hi)? {
        return Err(DesignError::Invalid(format!("DVF: [{lo}, {hi}] does not bracket the stability limit")));
    }
    while hi / lo - 1.0 > 1e-9 {
        let mid = (lo * hi).sqrt();
        if unstable(mid)? {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok((lo * hi).sqrt())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    pub(crate) fn ozsoy() -> DesignPlant {
        let k = 2.43e7;
        let wn = 2.0 * PI * 142.1;
        DesignPlant {
            mass: k / (wn * wn),
            stiffness: k,
            damping_ratio: 0.0088,
            actuator_a: [[-15.834, -2785.6], [1.0, 0.0]],
            actuator_b: [1.0, 0.0],
            actuator_c: [-15.834, -2785.6],
            actuator_d: 1.0,
        }
    }

    /// The state-space realisations equal their transfer functions (module docs).
    #[test]
    fn dvf_and_vpa_realise_their_formulas() {
        let plant = ozsoy();
        let d = Dvf { gain: 735.0, filter_hz: FILTER_HZ };
        let v = Vpa::den_hartog(0.05, FILTER_HZ);
        let (kd, kv) = (dvf(&d).unwrap().controller, vpa(&plant, &v).unwrap().controller);
        for w in [10.0, 500.0, 892.8, 5e3, 1e5] {
            assert!((kd.at(w) - dvf_at(&d, w)).norm() < 1e-12 * dvf_at(&d, w).norm());
            assert!((kv.at(w) - vpa_at(&plant, &v, w)).norm() < 1e-10 * vpa_at(&plant, &v, w).norm());
        }
        // a VPA is the absorber's dynamic mass at low frequency: K ≈ m_v ω² (a negative stiffness)
        let w = 50.0;
        assert!((kv.at(w).re / (0.05 * plant.mass * w * w) - 1.0).abs() < 0.02);
        assert!((v.damping_ratio - 0.1273).abs() < 1e-3 && (v.frequency_ratio - 0.95238).abs() < 1e-4);
    }

    /// Pure velocity weighting (`q₁ = 0`) gives a damping controller: at the mode the LQG's
    /// force opposes the velocity (`Re(K(iω)/(iω)) < 0`), and the closed loop on the design
    /// model is stable.
    #[test]
    fn lqg_with_velocity_weight_damps_the_mode() {
        let plant = ozsoy();
        let d = lqg(&plant, &Lqr { q2: 1e-3, ..DEFAULT_LQR }).unwrap();
        let wn = plant.omega_n();
        let k = d.controller.at(wn);
        let c_eq = -(k / Complex64::new(0.0, wn)).re;
        assert!(c_eq > 0.0, "equivalent damping {c_eq}");
        assert_eq!(d.controller.order(), 4);
        assert!(d.controller.spectral_abscissa() < 0.0 || d.controller.poles().iter().all(|p| p.re < 1e-9));
    }

    /// The DVF's inertial-actuator limit (reading guide [computed]: 1.377e5 N·s/m at the 8.4 Hz
    /// suspension mode): the continuous root locus gives it within 2 %, and Routh's condition
    /// on the low-frequency cubic `ε s³ + s² + 2ζ_aω_a s + ω_a² (ε = g/k)` gives `g < 2ζ_a k/ω_a`
    /// = 1.381e5 within 1 %; the loop stepped at 10 µs loses stability at 1/(1 + ω_f h/2) of it.
    #[test]
    fn dvf_actuator_limit_by_root_locus() {
        let plant = ozsoy();
        let g = dvf_gain_limit(&plant, FILTER_HZ, None, (1e3, 1e7)).unwrap();
        let routh = 15.834 / 2785.6 * plant.stiffness;
        eprintln!("DVF limit: root locus {g:.5e} N·s/m, Routh {routh:.5e}");
        assert!((g / 1.377e5 - 1.0).abs() < 0.02, "{g}");
        assert!((g / routh - 1.0).abs() < 0.01, "{g} vs {routh}");
        // the oscillation at the limit is the actuator's 8.4 Hz suspension mode
        let k = dvf(&Dvf { gain: g, filter_hz: FILTER_HZ }).unwrap().controller;
        let top =
            loop_matrix(&plant, &k).complex_eigenvalues().iter().copied().max_by(|a, b| a.re.total_cmp(&b.re)).unwrap();
        assert!((top.im.abs() / (2.0 * PI) - 8.4).abs() < 0.3, "{top}");
        let gs = dvf_gain_limit(&plant, FILTER_HZ, Some(1e-5), (1e3, 1e7)).unwrap();
        eprintln!("sampled at 10 µs: {gs:.5e}");
        let factor = 1.0 + 2.0 * PI * FILTER_HZ * 1e-5 / 2.0;
        assert!((g / gs / factor - 1.0).abs() < 0.01, "{}", g / gs);
    }

    /// The H∞ design: order 6, stable closed loop, its `d`-channel norm between the optimal level
    /// and the controller's level, and at least `W_S(0)` (an inertial actuator cannot act at DC,
    /// so S(0) = 1).
    #[test]
    fn hinf_design_achieves_its_level() {
        let plant = ozsoy();
        let d = hinf(&plant, &DEFAULT_HINF).unwrap();
        let r = d.report;
        eprintln!("H∞: {r:?}");
        assert_eq!(d.controller.order(), 6);
        assert!(r.achieved <= r.gamma * (1.0 + 1e-6), "{r:?}");
        assert!(r.achieved >= DEFAULT_HINF.ws_dc * (1.0 - 1e-6), "{r:?}");
        assert!(r.achieved >= r.gamma_opt * (1.0 - 1e-3), "{r:?}");
        assert!(r.gamma_opt <= r.gamma);
        // the reported norm equals an independent frequency sweep of the same closed loop
        let (gp, _) = generalized(&plant, &DEFAULT_HINF.weights(&plant), None).unwrap();
        let cl = gp.close(&d.controller.rescaled(1.0 / plant.omega_n(), 1.0 / plant.stiffness, 1.0));
        let single = StateSpace {
            a: cl.a.clone(),
            b: cl.b.columns(0, 1).into_owned(),
            c: cl.c,
            d: cl.d.columns(0, 1).into_owned(),
        };
        let sweep = crate::norm::sweep_norm(&single, 1e-4, 1e3, 4001);
        eprintln!("H∞ achieved {} vs sweep {} at {}", r.achieved, sweep.value, sweep.omega);
        assert!((sweep.value / r.achieved - 1.0).abs() < 1e-6, "sweep {sweep:?} vs {r:?}");
    }
}
