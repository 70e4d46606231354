//! One cell of the exact scheme ([`crate::exact`]) and the cutting force it evaluates.

use super::{Cut, Plant, PlantInputs, State};
use crate::exact::{DiscreteCache, MAX_DIM};
use crate::params::{CuttingModel, PlantParams};
use crate::teeth::Geometry;
use std::f64::consts::PI;

/// Tip displacement of a state vector of [`crate::exact`] (the summation order of `Plant::tip`).
fn flat_tip(y: &[f64; MAX_DIM], n: usize) -> f64 {
    (0..n).map(|i| y[2 * i]).sum()
}

/// What the exact scheme derives from the parameters (rebuilt after a state is restored).
#[derive(Clone, Debug)]
pub(super) struct Fast {
    pub(super) disc: DiscreteCache,
    pub(super) geo: Geometry,
}

impl Fast {
    pub(super) fn new(p: &PlantParams) -> Box<Fast> {
        Box::new(Fast { disc: DiscreteCache::new(p), geo: Geometry::new(p) })
    }
}

/// The last cutting-force evaluation of the exact scheme with its arguments (θ, x, f_z, Ω bits).
#[derive(Clone, Copy, Debug)]
pub(super) struct LastCut {
    pub(super) key: [u64; 4],
    pub(super) cut: Cut,
}

impl Plant {
    /// One cell of the exact scheme ([`crate::exact`]): predictor with the force at the cell's
    /// start, corrector with the force at its end evaluated on the predicted state.
    pub(super) fn exact_cell(&mut self, dt: f64, omega: f64, inputs: &PlantInputs) {
        let mut fast = self.fast.take().unwrap_or_else(|| Fast::new(&self.p));
        let n = self.modes.len();
        let t = self.time();
        let y0 = self.state.flat(n);
        let (u, _) = self.u_sat(inputs.u);
        let f0 = self.fast_cut(&fast.geo, self.theta, None, self.tip(), omega, inputs).force + self.sine(t);
        let delta_k = self.drift_delta(t + 0.5 * dt);
        let d0 = -delta_k * y0[0];
        let disc = fast.disc.get(dt);
        let mut a = disc.predict(&y0, f0 + self.noise_now, d0, u);
        let theta1 = self.theta + dt * omega;
        let from = Some((self.theta, dt * omega));
        let f1 = self.fast_cut(&fast.geo, theta1, from, flat_tip(&a, n), omega, inputs).force + self.sine(t + dt);
        let d1 = -delta_k * a[0];
        disc.correct(&mut a, f1 - f0, d1 - d0);
        self.state = State::from_flat(&a, n);
        self.theta = theta1;
        self.fast = Some(fast);
    }

    /// The cutting force of the exact scheme (the law of [`Plant::cutting`], tooth angles by
    /// recurrence: `from = (θ_previous, Ω dt)` when `theta` is one cell on from the last angle).
    pub(super) fn fast_cut(
        &mut self,
        geo: &Geometry,
        theta: f64,
        from: Option<(f64, f64)>,
        x: f64,
        omega: f64,
        inputs: &PlantInputs,
    ) -> Cut {
        let c = &self.p.cutting;
        if !c.enabled || omega <= 0.0 || c.axial_depth == 0.0 {
            return Cut::default();
        }
        let fz = inputs.feed_per_tooth;
        let key = [theta.to_bits(), x.to_bits(), fz.to_bits(), omega.to_bits()];
        if let Some(last) = self.last_cut.filter(|l| l.key == key) {
            return last.cut;
        }
        let dx = x - self.history.at_angle(theta - geo.pitch).map_or(0.0, |(_, xp)| xp);
        match c.model {
            CuttingModel::Averaged => {
                Cut { force: c.axial_depth * c.kt * (fz * self.static_coef - self.alpha0 * dx), chip: fz }
            }
            CuttingModel::TimeDomain => {
                let angle = match from {
                    Some((prev, step)) => self.angles.advance(prev, step, theta),
                    None => self.angles.at(theta),
                };
                let (force, chip) = geo.force(angle, fz, dx);
                Cut { force, chip }
            }
        }
    }

    /// The sinusoidal disturbance force at `t`.
    fn sine(&self, t: f64) -> f64 {
        let d = &self.p.disturbance;
        if d.sine_amplitude == 0.0 { 0.0 } else { d.sine_amplitude * (2.0 * PI * d.sine_frequency * t).sin() }
    }

    /// `k_1(t) − K_w` (the drift's stiffness change) at `t`.
    fn drift_delta(&self, t: f64) -> f64 {
        let d = &self.p.disturbance;
        if d.drift {
            self.modes[0].stiffness * d.drift_amplitude * (2.0 * PI * d.drift_frequency * t).sin()
        } else {
            0.0
        }
    }
}
