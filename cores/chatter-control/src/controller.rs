//! The sampled controller: one [`Controller::sample`] per period T, and its linear
//! frequency response computed from the same discrete coefficients.
//!
//! # One sample
//!
//! ```text
//! e_k = r_k − y_k
//! z_k = ESO update with y_k and the applied command u_{k−1}        (all structures)
//! off:        u_c = 0
//! pid:        u_c = PID(e_k)
//! fopid:      u_c = Kp e + Ki D^(−λ) e + Kd D^μ e
//! adrc_fopid: (v1, v2) = TD(r_k);  u0 = FOPID(e1 = v1 − z1, e2 = v2 − z2);  u_c = (u0 − z3)/b0
//! u_k = clamp(u_c, ±u_max),  saturated = |u_c| > u_max;  the ESO stores u_k (saturated)
//! ```
//!
//! `u_k` depends on `y_k` (direct feedthrough inside the sample); its discrete transfer
//! from `y` to `u` with `r = 0` and no saturation is `C(z)` ([`Controller::discrete_response`]).
//!
//! # Frequency responses (sign included: negative feedback, `U/Y ≈ −Kp` at low frequency)
//!
//! * [`Controller::discrete_response`] `= C(e^{iωT})`: the core, `u_k` from `y_k`.
//! * [`Controller::sampled_response`] `= e^{−iωT} C(e^{iωT})`: what the FMU gives at its
//!   communication points when stepped with `h = T` (input `y(t_k)` → output `u(t_{k+1})`,
//!   no direct feedthrough at the FMU boundary, see [`crate::fmu`]).
//! * [`Controller::frequency_response`] `= e^{−iωT} C(e^{iωT}) · (1 − e^{−iωT})/(iωT)`:
//!   the sampled response times the zero-order hold, i.e. the fundamental of the staircase
//!   force a continuous plant receives from a master that steps plant and controller with
//!   `h = T` (Jacobi). This is the `Hc` for `Φ_cl = Φ/(1 − Φ·Ga·Hc)` with a continuous `Φ`.
//!   The hold and the communication delay together lag 1.5 samples (0.77° at 143 Hz).
//!
//! For ADRC the ESO closes an inner loop through the applied command: with
//! `Ẑ = a(z)·U + b(z)·Y` ([`crate::eso::Eso::response`]) and `w = [F_pi, F_d, 1]`
//! (`U = −(w·Ẑ)/b0` at r = 0), `C(z) = −(w·b)/(b0 + w·a)`.

use crate::eso::Eso;
use crate::fopid::Fopid;
use crate::params::{ControllerParams, Structure};
use crate::pid::{Pid, PidGains};
use crate::td::TrackingDifferentiator;
use num_complex::Complex64;
use serde::{Deserialize, Serialize};

/// Result of one sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ControllerOutput {
    /// Applied (saturated) command \[N\].
    pub u: f64,
    /// Tracking error `r − y` \[m\].
    pub e: f64,
    /// ESO displacement estimate \[m\].
    pub z1: f64,
    /// ESO velocity estimate \[m/s\].
    pub z2: f64,
    /// ESO total-disturbance estimate \[m/s²\].
    pub z3: f64,
    /// The unsaturated command exceeded ±u_max.
    pub saturated: bool,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
enum Law {
    Off,
    Pid(Pid),
    Fopid(Fopid),
    Adrc { td: TrackingDifferentiator, fopid: Fopid },
}

/// A sampled chatter controller (see the module documentation).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Controller {
    params: ControllerParams,
    law: Law,
    eso: Eso,
    /// Saturation direction of the previous sample (−1, 0, +1), for anti-windup.
    sat_dir: f64,
    /// Feed the ESO the unsaturated command (only to show windup in tests).
    #[serde(skip)]
    pub(crate) eso_sees_unsaturated: bool,
}

impl Controller {
    /// Build from parameters (validated).
    pub fn new(p: &ControllerParams) -> Result<Controller, String> {
        p.validate()?;
        let law = match p.structure {
            Structure::Off => Law::Off,
            Structure::Pid => Law::Pid(Pid::new(p.pid, p.ts)),
            Structure::Fopid => Law::Fopid(Fopid::new(p.fopid, p.fopid.mu, p.ts, &p.fractional)),
            Structure::AdrcFopid => Law::Adrc {
                td: TrackingDifferentiator::new(p.adrc.td_r, p.adrc.td_h, p.ts),
                fopid: Fopid::new(p.adrc.fopid, p.adrc.fopid.mu - 1.0, p.ts, &p.fractional),
            },
        };
        Ok(Controller {
            params: *p,
            law,
            eso: Eso::new(p.adrc.omega_o, p.adrc.b0, p.ts),
            sat_dir: 0.0,
            eso_sees_unsaturated: false,
        })
    }

    /// Is this a state the controller can continue from? The parameters pass the validation of
    /// [`Controller::new`], every configuration value (taps, gains, sections) is the one they
    /// give, and every state value is finite. Run on every restored FMU state.
    pub fn validate_state(&self) -> Result<(), String> {
        let fresh = Controller::new(&self.params)?;
        match (&self.law, &fresh.law) {
            (Law::Off, Law::Off) => {}
            (Law::Pid(a), Law::Pid(b)) => a.check(b)?,
            (Law::Fopid(a), Law::Fopid(b)) => a.check(b)?,
            (Law::Adrc { td, fopid }, Law::Adrc { td: td0, fopid: fopid0 }) => {
                td.check(td0)?;
                fopid.check(fopid0)?;
            }
            _ => return Err("the control law does not match the structure parameter".into()),
        }
        self.eso.check(&fresh.eso)?;
        if ![-1.0, 0.0, 1.0].iter().any(|d: &f64| d.to_bits() == self.sat_dir.to_bits()) {
            return Err("the saturation direction is not -1, 0 or 1".into());
        }
        Ok(())
    }

    /// Change the gains (`kp`, `ki`, `kd` of PID, FOPID and ADRC-FOPID) while running, keeping
    /// every state (integrators, fractional memories, ESO, tracking differentiator): what an FMU
    /// does with a tunable parameter set between steps. `p` must equal the current parameters but
    /// for these gains and pass their validation.
    pub fn retune(&mut self, p: &ControllerParams) -> Result<(), String> {
        let mut only_gains = self.params;
        only_gains.pid = PidGains { kp: p.pid.kp, ki: p.pid.ki, kd: p.pid.kd, ..only_gains.pid };
        for (mine, theirs) in [(&mut only_gains.fopid, &p.fopid), (&mut only_gains.adrc.fopid, &p.adrc.fopid)] {
            (mine.kp, mine.ki, mine.kd) = (theirs.kp, theirs.ki, theirs.kd);
        }
        if only_gains != *p {
            return Err("only the gains kp, ki, kd can change while the controller runs".into());
        }
        p.validate()?;
        self.params = *p;
        match &mut self.law {
            Law::Off => {}
            Law::Pid(pid) => pid.set_gains(p.pid.kp, p.pid.ki, p.pid.kd),
            Law::Fopid(f) => f.set_gains(p.fopid.kp, p.fopid.ki, p.fopid.kd),
            Law::Adrc { fopid, .. } => fopid.set_gains(p.adrc.fopid.kp, p.adrc.fopid.ki, p.adrc.fopid.kd),
        }
        Ok(())
    }

    /// The parameters this controller was built from.
    pub fn params(&self) -> &ControllerParams {
        &self.params
    }

    /// One sample: input `y` (and reference `r`) at this sample instant, held over T;
    /// returns the command applied over the coming period and diagnostics.
    #[inline]
    pub fn sample(&mut self, y: f64, r: f64) -> ControllerOutput {
        let e = r - y;
        let [z1, z2, z3] = self.eso.update(y);
        let sat_dir = self.sat_dir;
        let uc = match &mut self.law {
            Law::Off => 0.0,
            Law::Pid(p) => p.step(e, sat_dir),
            Law::Fopid(f) => f.step(e, e, sat_dir),
            Law::Adrc { td, fopid } => {
                let (v1, v2) = td.step(r);
                let u0 = fopid.step(v1 - z1, v2 - z2, sat_dir);
                (u0 - z3) / self.params.adrc.b0
            }
        };
        let umax = self.params.u_max;
        let u = uc.clamp(-umax, umax);
        let saturated = uc.abs() > umax;
        self.sat_dir = if saturated { uc.signum() } else { 0.0 };
        self.eso.set_applied(if self.eso_sees_unsaturated { uc } else { u });
        ControllerOutput { u, e, z1, z2, z3, saturated }
    }

    /// `C(z)`: linear transfer y → u of [`sample`](Self::sample) (r = 0, no saturation) at any `z`.
    pub fn transfer(&self, z: Complex64) -> Complex64 {
        match &self.law {
            Law::Off => Complex64::new(0.0, 0.0),
            Law::Pid(p) => -p.response(z),
            Law::Fopid(f) => -(f.response_pi(z) + f.response_d(z)),
            Law::Adrc { fopid, .. } => {
                let (a, b) = self.eso.response(z);
                let w = [fopid.response_pi(z), fopid.response_d(z), Complex64::new(1.0, 0.0)];
                let wa: Complex64 = (0..3).map(|i| w[i] * a[i]).sum();
                let wb: Complex64 = (0..3).map(|i| w[i] * b[i]).sum();
                -wb / (self.params.adrc.b0 + wa)
            }
        }
    }

    /// `C(e^{iωT})` at `omega` \[rad/s\].
    pub fn discrete_response(&self, omega: f64) -> Complex64 {
        self.transfer(Complex64::from_polar(1.0, omega * self.params.ts))
    }

    /// `e^{−iωT} C(e^{iωT})`: the FMU's communication-point response at `h = T`.
    pub fn sampled_response(&self, omega: f64) -> Complex64 {
        let z = Complex64::from_polar(1.0, omega * self.params.ts);
        self.transfer(z) / z
    }

    /// Sampled response times the zero-order hold `(1 − e^{−iωT})/(iωT)` (see the module doc).
    pub fn frequency_response(&self, omega: f64) -> Complex64 {
        self.sampled_response(omega) * zoh(omega, self.params.ts)
    }
}

/// Zero-order hold factor `(1 − e^{−iωT})/(iωT)` (→ 1 as ω → 0).
pub fn zoh(omega: f64, ts: f64) -> Complex64 {
    let x = omega * ts;
    if x.abs() < 1e-8 {
        return Complex64::new(1.0, -x / 2.0);
    }
    (Complex64::new(1.0, 0.0) - Complex64::from_polar(1.0, -x)) / Complex64::new(0.0, x)
}

impl ControllerParams {
    /// Linear frequency response U/Y at `omega` \[rad/s\] (r = 0, saturation excluded, sampling,
    /// communication delay and hold included): [`Controller::frequency_response`] of a
    /// controller built from these parameters, i.e. from the very coefficients the FMU steps.
    ///
    /// # Panics
    /// If the parameters are invalid (see [`ControllerParams::validate`]).
    pub fn frequency_response(&self, omega: f64) -> Complex64 {
        Controller::new(self).expect("valid controller parameters").frequency_response(omega)
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;
    use crate::eso::tests::DoubleIntegrator;
    use crate::fractional::reference::phasor;
    use crate::fractional::{FractionalMethod, FractionalParams};
    use crate::params::AdrcParams;
    use std::f64::consts::PI;

    /// The five test frequencies of the issue, 100..200 Hz.
    pub(crate) const FREQS: [f64; 5] = [100.0, 125.0, 143.0, 170.0, 200.0];

    pub(crate) fn variants() -> Vec<(String, ControllerParams)> {
        let base = ControllerParams::paper_table2();
        let mut v = Vec::new();
        for s in [Structure::Pid, Structure::Fopid, Structure::AdrcFopid] {
            for m in [FractionalMethod::GrunwaldLetnikov, FractionalMethod::Oustaloup] {
                if s == Structure::Pid && m == FractionalMethod::Oustaloup {
                    continue;
                }
                let p = ControllerParams {
                    structure: s,
                    fractional: FractionalParams { method: m, ..base.fractional },
                    ..base
                };
                v.push((format!("{s:?}/{m:?}"), p));
            }
        }
        v
    }

    /// Measured U/Y at `f` \[Hz\] from stepping `sample` with `y = a sin(ωt)` (a = 0.1 µm, no
    /// saturation), phasors fitted over the last 0.1 s of 0.3 s.
    fn measure_core(p: &ControllerParams, f: f64) -> Complex64 {
        let w = 2.0 * PI * f;
        let mut c = Controller::new(p).unwrap();
        let n = 30_000;
        let a = 1e-7;
        let mut u = Vec::with_capacity(n);
        for k in 0..n {
            let o = c.sample(a * (w * p.ts * k as f64).sin(), 0.0);
            assert!(!o.saturated);
            u.push(o.u);
        }
        phasor(&u, 0.0, p.ts, w, n - 10_000..n) / Complex64::new(0.0, -a)
    }

    /// Stepping the core with a sine reproduces C(e^{iωT}) to 1e-4 (the same coefficients), and
    /// the analysis response `frequency_response` within 1 % in magnitude; the phase differs by
    /// exactly the communication delay and the hold of the FMU boundary, 1.5 samples (1.08° at
    /// 200 Hz). The FMU-level comparison (1 %, 1°) is in `tests/fmu.rs`.
    #[test]
    fn stepped_core_matches_frequency_response() {
        for (name, p) in variants() {
            let c = Controller::new(&p).unwrap();
            for f in FREQS {
                let w = 2.0 * PI * f;
                let got = measure_core(&p, f);
                let exact = c.discrete_response(w);
                let rel = (got - exact).norm() / exact.norm();
                assert!(rel < 1e-4, "{name} {f} Hz: stepped {got} vs C(z) {exact} (rel {rel:.2e})");
                let h = p.frequency_response(w);
                let mag = (got.norm() / h.norm() - 1.0).abs();
                let ph = (got / h).arg().to_degrees().abs();
                let lag = 1.5 * w * p.ts * 180.0 / PI; // delay + hold of the FMU boundary
                assert!(mag < 0.01 && (ph - lag).abs() < 0.01, "{name} {f} Hz: {mag:.4} rel, {ph:.3} deg");
                eprintln!(
                    "{name:32} {f:5} Hz |U/Y| = {:10.4e} arg = {:8.3} deg, vs analysis {mag:.2e} rel {ph:.3} deg",
                    got.norm(),
                    got.arg().to_degrees()
                );
            }
        }
    }

    #[test]
    fn low_frequency_sign_is_negative_feedback() {
        let p = ControllerParams { structure: Structure::Pid, ..ControllerParams::paper_table2() };
        let h = p.frequency_response(2.0 * PI * 1.0);
        assert!(h.re < 0.0 && (h.re / -p.pid.kp - 1.0).abs() < 0.01, "{h}");
        let off = ControllerParams { structure: Structure::Off, ..p };
        assert!(off.frequency_response(1000.0).norm() < f64::MIN_POSITIVE);
    }

    /// Random large inputs: |u| never exceeds u_max, and `saturated` flags it.
    #[test]
    fn output_never_exceeds_u_max() {
        let mut seed: u64 = 0x2545_F491_4F6C_DD1D;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for (name, p) in variants() {
            let mut c = Controller::new(&p).unwrap();
            let mut n_sat = 0;
            for k in 0..20_000 {
                let y = 1e-3 * rnd() * if k % 1000 < 500 { 1.0 } else { 1e-4 };
                let o = c.sample(y, 0.0);
                assert!(o.u.abs() <= p.u_max, "{name}: u = {}", o.u);
                if o.saturated {
                    n_sat += 1;
                    assert!((o.u.abs() - p.u_max).abs() < 1e-12);
                }
            }
            assert!(n_sat > 100, "{name}: the test did not saturate ({n_sat})");
        }
    }

    /// Result of the windup scenario: (overshoot ratio, peak excursion \[m\], settling time \[s\]).
    pub(crate) fn windup_scenario(eso_sees_unsaturated: bool) -> (f64, f64, f64) {
        // ADRC with a PD-type inner law (λ irrelevant, Ki = 0, μ = 1 → Kd·e2) placing the
        // nominal double-integrator poles at −ωc (double), ωc = 300 rad/s.
        let wc = 300.0;
        let base = ControllerParams::paper_table2();
        let p = ControllerParams {
            structure: Structure::AdrcFopid,
            adrc: AdrcParams {
                fopid: crate::fopid::FopidGains { kp: wc * wc, ki: 0.0, kd: 2.0 * wc, lambda: 0.85, mu: 1.0 },
                ..base.adrc
            },
            ..base
        };
        let b0 = p.adrc.b0;
        let mut c = Controller::new(&p).unwrap();
        c.eso_sees_unsaturated = eso_sees_unsaturated;
        let mut plant = DoubleIntegrator { x: 0.0, v: 0.0, t: 0.0 };
        // disturbance: 2·u_max·b0 (needs 54 N, actuator gives 27 N) for 10 ms, then released
        let (t_on, t_off) = (0.01, 0.02);
        let mut peak: f64 = 0.0;
        let mut under: f64 = 0.0;
        let mut settled_at = 0.0;
        for k in 0..100_000 {
            let t = k as f64 * p.ts;
            let f = if (t_on..t_off).contains(&t) { 2.0 * p.u_max * b0 } else { 0.0 };
            let o = c.sample(plant.x, 0.0);
            plant.step(b0 * o.u, f, 0.0, 1.0, p.ts);
            if t < t_off + 0.002 {
                peak = peak.max(plant.x);
            } else {
                under = under.min(plant.x);
            }
            if plant.x.abs() > 0.02 * peak {
                settled_at = t;
            }
        }
        (-under / peak, peak, settled_at - t_off)
    }

    /// No observer windup: the ESO sees the saturated command, so after the disturbance is
    /// released the displacement returns with an undershoot below 5 % of its peak and settles
    /// (2 % band) within 50 ms. Fed the unsaturated command instead, the same loop winds up
    /// (this is what makes the test able to fail).
    #[test]
    fn no_observer_windup() {
        let (ov, peak, ts) = windup_scenario(false);
        eprintln!("saturated-fed ESO: peak {peak:.3e} m, overshoot {ov:.4}, settling {ts:.4} s");
        assert!(ov < 0.05 && ts < 0.05, "overshoot {ov}, settling {ts}");
        let (ov2, peak2, ts2) = windup_scenario(true);
        eprintln!("unsaturated-fed ESO: peak {peak2:.3e} m, overshoot {ov2:.4}, settling {ts2:.4} s");
        assert!(ov2 > 2.0 * ov.max(0.01) || ts2 > 2.0 * ts || peak2 > 2.0 * peak);
    }
}
