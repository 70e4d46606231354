//! Closed-loop lobes of a controller on the user's machine, with the actuator's limit.
//!
//! * **Stability**: the frequency-domain method of the machine's immersion
//!   ([`Method::for_immersion`]) on the closed-loop receptance ([`ClosedLoop`]). The
//!   semi-discretisation of the sampled controllers (fractional, ESO) is not implemented: where
//!   the open-loop frequency-domain method lies above the semi-discretisation
//!   ([`MachineLobes::disagreements`]) the closed-loop value is flagged as likely unsafe too.
//! * **Saturation**: the cut's own force drives the loop. Per unit depth the static chip force
//!   `F(t)` (linear law: `F_t = K_t f_z sin φ + K_te`, `F_r = K_r f_z sin φ + K_re` per tooth,
//!   on the tool `(−F_t cos φ − F_r sin φ, F_t sin φ − F_r cos φ)`, tooth-period periodic) has
//!   harmonics `F_k` at `kω_T`; the command it asks for is `u(t) = 2 Re Σ_{k≥1} T(kω_T) F_k
//!   e^{ikω_T t}` with `T = H_c dᵀ G_cl` ([`ClosedLoop::command_per_force`]). The mean (k = 0)
//!   is left out: an inertial actuator makes no static force, and the integral actions here
//!   are slow (it would drift by `K_i y₀` per second). The **saturation-limited depth** is
//!   `a_sat = u_max / max_t |u(t)|`: above it the steady cut alone drives the command past the
//!   actuator's limit, so the loop is no longer the linear one the stability lobe describes.
//!   The usable depth is `min(a_stability, a_sat)`, and the output says which limits it.

use crate::lobes::{self, MachineLobes, Method};
use crate::machine::{Law, Machine};
use crate::models::{ClosedLoop, ModelError};
use chatter_control::ControllerParams;
use num_complex::Complex64;
use std::f64::consts::PI;

/// Samples of the tooth period for the force harmonics.
const SAMPLES: usize = 512;
/// Harmonics of the tooth-passing frequency in the command.
const HARMONICS: usize = 60;

/// What limits the usable depth at a speed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Limit {
    /// The closed-loop stability boundary.
    Stability,
    /// The actuator's force limit under the steady cut.
    Saturation,
}

/// One speed of a closed-loop diagram.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosedPoint {
    /// Speed \[rpm\].
    pub rpm: f64,
    /// Closed-loop stability boundary \[m\].
    pub stability: f64,
    /// Saturation-limited depth \[m\].
    pub saturation: f64,
    /// Chatter frequency at the stability boundary \[Hz\].
    pub chatter_hz: f64,
    /// The open-loop frequency-domain method lies above the semi-discretisation here.
    pub method_unsafe: bool,
}

impl ClosedPoint {
    /// `min(stability, saturation)`.
    pub fn usable(&self) -> f64 {
        self.stability.min(self.saturation)
    }

    /// Which limit applies.
    pub fn limit(&self) -> Limit {
        if self.saturation < self.stability { Limit::Saturation } else { Limit::Stability }
    }
}

/// The static chip force per unit depth on the tool over one tooth period (`SAMPLES` points),
/// at feed `f_z`.
fn static_force(m: &Machine) -> Vec<[f64; 2]> {
    let (entry, exit) = m.engagement();
    let z = m.tool.teeth as usize;
    let pitch = 2.0 * PI / z as f64;
    let mat = &m.material;
    let fz = m.operation.feed_per_tooth;
    (0..SAMPLES)
        .map(|n| {
            let phi0 = pitch * n as f64 / SAMPLES as f64;
            let mut f = [0.0; 2];
            for j in 0..z {
                let phi = (phi0 + pitch * j as f64).rem_euclid(2.0 * PI);
                if phi < entry || phi > exit {
                    continue;
                }
                let h = fz * phi.sin();
                if h <= 0.0 {
                    continue;
                }
                let (ft, fr) = match mat.law {
                    Law::Linear => (mat.kt * h + mat.kte, mat.kr * h + mat.kre),
                    Law::Power { x_f } => (mat.kt * h.powf(x_f), mat.kr * h.powf(x_f)),
                };
                let (s, c) = phi.sin_cos();
                f[0] += -ft * c - fr * s;
                f[1] += ft * s - fr * c;
            }
            f
        })
        .collect()
}

/// The saturation-limited depth at `rpm` \[m\] (module docs).
pub fn saturation_depth(m: &Machine, cl: &ClosedLoop<'_>, u_max: f64, rpm: f64) -> f64 {
    let force = static_force(m);
    let wt = 2.0 * PI * rpm / 60.0 * m.tool.teeth as f64;
    // harmonics F_k = (1/N) Σ F(t_n) e^{−ik 2π n/N}
    let harm: Vec<[Complex64; 2]> = (1..=HARMONICS)
        .map(|k| {
            let mut s = [Complex64::new(0.0, 0.0); 2];
            for (n, f) in force.iter().enumerate() {
                let e = Complex64::from_polar(1.0, -2.0 * PI * (k * n) as f64 / SAMPLES as f64);
                s[0] += e * f[0];
                s[1] += e * f[1];
            }
            [s[0] / SAMPLES as f64, s[1] / SAMPLES as f64]
        })
        .collect();
    let uk: Vec<Complex64> = harm
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let t = cl.command_per_force((i + 1) as f64 * wt);
            t[0] * f[0] + t[1] * f[1]
        })
        .collect();
    let peak = (0..SAMPLES)
        .map(|n| {
            let u: f64 = uk
                .iter()
                .enumerate()
                .map(|(i, c)| {
                    2.0 * (c * Complex64::from_polar(1.0, 2.0 * PI * ((i + 1) * n) as f64 / SAMPLES as f64)).re
                })
                .sum();
            u.abs()
        })
        .fold(0.0, f64::max);
    if peak > 0.0 { u_max / peak } else { f64::INFINITY }
}

/// The closed-loop diagram of `ctrl` on the machine at `speeds`; `open` (the open-loop lobes at
/// the same speeds, if computed) marks the speeds where the frequency-domain method is unsafe.
pub fn closed_loop_lobes(
    m: &Machine,
    ctrl: &ControllerParams,
    speeds: &[f64],
    open: Option<&MachineLobes>,
) -> Result<Vec<ClosedPoint>, ModelError> {
    let cl = ClosedLoop::new(m, ctrl)?;
    let method = Method::for_immersion(m);
    let frf = |w: f64| cl.receptance(w);
    let diagram = lobes::frequency_diagram(m, method, &frf, speeds)?;
    let unsafe_at: Vec<f64> = open
        .map(|o| o.disagreements().iter().filter(|d| d.method == method && d.ratio > 1.0).map(|d| d.rpm).collect())
        .unwrap_or_default();
    Ok(diagram
        .iter()
        .map(|p| ClosedPoint {
            rpm: p.rpm,
            stability: p.depth,
            saturation: saturation_depth(m, &cl, ctrl.u_max, p.rpm),
            chatter_hz: p.chatter_hz,
            method_unsafe: unsafe_at.contains(&p.rpm),
        })
        .collect())
}
