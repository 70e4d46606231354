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

impl LastCut {
    /// The remembered cut if it was evaluated at exactly these arguments. Compared one argument
    /// at a time from the registers: building the key on the stack and comparing it as a block
    /// made the loads wait on the narrower stores that wrote it (no store forwarding, `perf`).
    #[inline]
    fn at(&self, theta: f64, x: f64, fz: f64, omega: f64) -> Option<Cut> {
        let k = &self.key;
        let same = k[0] == theta.to_bits() && k[1] == x.to_bits() && k[2] == fz.to_bits() && k[3] == omega.to_bits();
        same.then_some(self.cut)
    }
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
        if let Some(cut) = self.last_cut.as_ref().and_then(|l| l.at(theta, x, fz, omega)) {
            return cut;
        }
        let (model, apkt) = (c.model, c.axial_depth * c.kt);
        let dx = x - self.delayed(theta - geo.pitch).map_or(0.0, |(_, xp)| xp);
        match model {
            CuttingModel::Averaged => Cut { force: apkt * (fz * self.static_coef - self.alpha0 * dx), chip: fz },
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

    /// `(t*, x(t*))` at history angle `q`, remembered for the next lookup at the same angle
    /// (the cell's end, the outputs and the delay all look up `θ − 2π/Z` of the same instant).
    pub(super) fn delayed(&mut self, q: f64) -> Option<(f64, f64)> {
        if let Some((bits, r)) = self.lookup
            && bits == q.to_bits()
        {
            #[cfg(test)]
            assert_eq!(format!("{r:?}"), format!("{:?}", self.history.at_angle(q)), "stale lookup at {q}");
            return r;
        }
        let r = self.history.at_angle(q);
        self.lookup = Some((q.to_bits(), r));
        r
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

#[cfg(test)]
mod tests {
    use crate::{Plant, PlantInputs, PlantParams};

    /// The remembered lookup is never stale (checked on every hit in test builds): cutting,
    /// speed changes, a stop at 0 rpm and restart, communication steps on and off the grid.
    #[test]
    fn remembered_lookups_equal_fresh_ones() {
        let mut plant = Plant::new(&PlantParams::default()).unwrap();
        let mut inputs = PlantInputs::default();
        for (k, h) in (0..6000).zip([1e-5, 2e-5, 1.5e-5, 1e-5].into_iter().cycle()) {
            inputs.spindle_speed_rpm = match k {
                0..2000 => 2000.0,
                2000..2500 => 0.0,
                2500..4000 => 1500.0 + (k % 7) as f64,
                _ => 3000.0,
            };
            plant.step(h, &inputs).unwrap();
        }
        assert!(plant.outputs().delay > 0.0);
    }
}
