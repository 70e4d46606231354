//! The time-domain process: chip thickness from the surface the previous teeth left, tooth
//! forces, engagement, loss of contact, multiple regeneration.
//!
//! # Equations
//!
//! With `r(t) = u_tool(t) − u_workpiece(t)` (the inputs) and the tool angle `θ(t) = ∫Ω dt`,
//! tooth `j` at `φ_j = θ + ψ_j` in the engagement window cuts the chip
//!
//! `h_j = min_{k=1..K} [ f_z (Z/2π) G_{j,k} sin φ_j + (r(t) − r(t*_{j,k}))·r̂(φ_j) ]`,
//!
//! where `G_{j,k}` is the sum of the `k` gaps in front of tooth `j` and `θ(t*_{j,k}) = θ(t) −
//! G_{j,k}` (the instant the k-th tooth before passed this angle: a variable delay at varying
//! speed). `K = Z` with multiple regeneration (the surface is the innermost of one revolution
//! of passes), else `K = 1`. A tooth with `h_j ≤ 0` has left the cut (no force). Before the
//! history starts the surface is taken as flat (`r = 0`).
//!
//! With `depth_ramp_time = T_r > 0` the depth in the cut rises linearly over the first `T_r`
//! after the start: the force is multiplied by `min(1, (t − t_0)/T_r)`. A full engagement at
//! once is a force step of the mean cutting force, which rings the structure with about its
//! static deflection; a ramp of a few periods of the lowest mode excites it by about
//! `1/(π f T_r)` of that (a ramp's spectrum), so the regenerative growth or decay that follows
//! starts from the small vibration the linear stability analysis describes.
//!
//! # Timing
//!
//! A step `[t, t + h]` advances the angle with the speed held, takes the displacement inputs as
//! the values at `t + h` (a master that steps the structure first, then the process, gives
//! exactly these), stores them in the history and evaluates the force at `t + h`. The structure
//! then holds that force over its next step: the force reaches the structure one step late on
//! average by `h/2` (the "one-step coupling" of the decomposed plant).

use crate::history::{History, MAX_SAMPLES, XySample};
use crate::params::{ProcessParams, tool_force};
use model_kit::rem_two_pi;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Why the process refused to start or to step.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ProcessError {
    /// A parameter is out of range.
    #[error("invalid parameter: {0}")]
    Parameter(String),
    /// An input is out of range (the step was not taken).
    #[error("invalid input: {0}")]
    Input(String),
    /// The force left any physical range.
    #[error("the cutting force is not finite at t = {t} s")]
    Diverged {
        /// Time [s].
        t: f64,
    },
}

/// Inputs held over a step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ProcessInputs {
    /// Tool displacement at the cutting point (x, y) [m].
    pub tool: [f64; 2],
    /// Workpiece displacement at the cutting point (x, y) [m].
    pub workpiece: [f64; 2],
    /// Spindle speed [rpm] (≥ 0).
    pub spindle_speed_rpm: f64,
    /// Feed per tooth [m] (≥ 0).
    pub feed_per_tooth: f64,
}

impl Default for ProcessInputs {
    fn default() -> Self {
        ProcessInputs { tool: [0.0; 2], workpiece: [0.0; 2], spindle_speed_rpm: 2000.0, feed_per_tooth: 0.05e-3 }
    }
}

/// Outputs at the current time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ProcessOutputs {
    /// Cutting force on the tool (x, y) [N].
    pub force: [f64; 2],
    /// Cutting force on the workpiece (x, y) [N] (= −force).
    pub workpiece_force: [f64; 2],
    /// Largest chip thickness among the cutting teeth [m] (0 if none cuts).
    pub chip_thickness: f64,
    /// Regenerative delay of tooth 0: time since the tooth before it passed its angle [s]
    /// (0 before the first full gap).
    pub delay: f64,
    /// Tool angle θ mod 2π [rad].
    pub tool_angle: f64,
}

/// The process.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Process {
    p: ProcessParams,
    offsets: Vec<f64>,
    gaps: Vec<f64>,
    engagement: (f64, f64),
    /// Start time (the depth ramp's origin).
    t0: f64,
    t: f64,
    theta: f64,
    history: History<XySample>,
    out: ProcessOutputs,
}

fn check_inputs(i: &ProcessInputs) -> Result<(), ProcessError> {
    for (name, v) in
        [("tool_x", i.tool[0]), ("tool_y", i.tool[1]), ("workpiece_x", i.workpiece[0]), ("workpiece_y", i.workpiece[1])]
    {
        if !(v.is_finite() && v.abs() < 1.0) {
            return Err(ProcessError::Input(format!("{name} = {v} m is not a finite displacement below 1 m")));
        }
    }
    if !(i.spindle_speed_rpm.is_finite() && i.spindle_speed_rpm >= 0.0) {
        return Err(ProcessError::Input(format!(
            "spindle_speed = {} rpm must be finite and >= 0",
            i.spindle_speed_rpm
        )));
    }
    if !(i.feed_per_tooth.is_finite() && i.feed_per_tooth >= 0.0) {
        return Err(ProcessError::Input(format!("feed_per_tooth = {} m must be finite and >= 0", i.feed_per_tooth)));
    }
    Ok(())
}

impl Process {
    /// A process at time `t0`, tool angle 0, on a flat surface.
    pub fn new_at(p: &ProcessParams, t0: f64) -> Result<Process, ProcessError> {
        p.validate().map_err(ProcessError::Parameter)?;
        let mut pr = Process {
            p: p.clone(),
            offsets: p.tooth_offsets(),
            gaps: p.gaps(),
            engagement: p.engagement(),
            t0,
            t: t0,
            theta: 0.0,
            history: History::default(),
            out: ProcessOutputs::default(),
        };
        pr.history.push(XySample { t: t0, theta: 0.0, r: [0.0; 2] });
        pr.out = pr.evaluate(&ProcessInputs::default(), 0.0);
        Ok(pr)
    }

    /// A process at time 0.
    pub fn new(p: &ProcessParams) -> Result<Process, ProcessError> {
        Process::new_at(p, 0.0)
    }

    /// The parameters.
    pub fn params(&self) -> &ProcessParams {
        &self.p
    }

    /// Current time [s].
    pub fn time(&self) -> f64 {
        self.t
    }

    /// Outputs at the current time.
    pub fn outputs(&self) -> ProcessOutputs {
        self.out
    }

    /// Number of history samples.
    pub fn history_len(&self) -> usize {
        self.history.len()
    }

    /// How far back (in tool angle) a lookup can reach [rad].
    fn lookback(&self) -> f64 {
        if self.p.multiple_regeneration { 2.0 * PI } else { self.gaps.iter().cloned().fold(0.0, f64::max) }
    }

    /// Take new inputs as the values at the current instant (e.g. during initialization): the
    /// newest history sample and the outputs are recomputed.
    pub fn set_inputs(&mut self, inputs: &ProcessInputs) -> Result<(), ProcessError> {
        check_inputs(inputs)?;
        let r = relative(inputs);
        self.history.set_newest(XySample { t: self.t, theta: self.theta, r });
        self.out = self.evaluate(inputs, self.out.delay);
        Ok(())
    }

    /// Advance by `h` [s]: the speed is held, the displacement inputs are the values at `t + h`.
    pub fn step(&mut self, h: f64, inputs: &ProcessInputs) -> Result<(), ProcessError> {
        check_inputs(inputs)?;
        if !(h.is_finite() && h >= 0.0) {
            return Err(ProcessError::Input(format!("step size {h} must be finite and >= 0")));
        }
        let omega = inputs.spindle_speed_rpm * 2.0 * PI / 60.0;
        if h > 0.0 && omega > 0.0 && self.p.axial_depth > 0.0 {
            let samples = self.lookback() / (omega * h);
            if samples > (MAX_SAMPLES / 2) as f64 {
                return Err(ProcessError::Input(format!(
                    "spindle_speed = {} rpm is too slow for the history at step {h} s ({samples:.0} samples per \
                     look-back, at most {}); use 0 rpm to stop or a longer step",
                    inputs.spindle_speed_rpm,
                    MAX_SAMPLES / 2
                )));
            }
        }
        self.t += h;
        self.theta += omega * h;
        self.history.push(XySample { t: self.t, theta: self.theta, r: relative(inputs) });
        self.history.prune(self.theta - self.lookback());
        let delay = self.history.at_angle(self.theta - self.gaps[0]).map_or(0.0, |(ts, _)| self.t - ts);
        self.out = self.evaluate(inputs, delay);
        if !(self.out.force.iter().all(|f| f.is_finite())) {
            return Err(ProcessError::Diverged { t: self.t });
        }
        Ok(())
    }

    /// Force and chip at the current angle with the current displacement.
    fn evaluate(&self, inputs: &ProcessInputs, delay: f64) -> ProcessOutputs {
        let mut out = ProcessOutputs { delay, tool_angle: rem_two_pi(self.theta), ..Default::default() };
        let omega = inputs.spindle_speed_rpm;
        if omega <= 0.0 || self.p.axial_depth == 0.0 {
            return out;
        }
        let r = relative(inputs);
        let (st, ex) = self.engagement;
        let z = self.offsets.len();
        let feed_per_rad = inputs.feed_per_tooth * z as f64 / (2.0 * PI);
        let k_max = if self.p.multiple_regeneration { z } else { 1 };
        for j in 0..z {
            let phi = rem_two_pi(self.theta + self.offsets[j]);
            if phi < st || phi > ex {
                continue;
            }
            let (s, c) = phi.sin_cos();
            let mut back = 0.0;
            let mut h = f64::INFINITY;
            for k in 1..=k_max {
                back += self.gaps[(j + z + 1 - k) % z];
                let prev = self.history.at_angle(self.theta - back).map_or([0.0; 2], |(_, rp)| rp);
                let hk = feed_per_rad * back * s + (r[0] - prev[0]) * s + (r[1] - prev[1]) * c;
                h = h.min(hk);
            }
            if h <= 0.0 {
                continue; // loss of contact
            }
            out.chip_thickness = out.chip_thickness.max(h);
            let (ft, fr) = self.p.tooth_force(h);
            let f = tool_force(phi, ft, fr);
            out.force[0] += f[0];
            out.force[1] += f[1];
        }
        let ramp = self.depth_fraction();
        if ramp < 1.0 {
            out.force = [ramp * out.force[0], ramp * out.force[1]];
        }
        out.workpiece_force = [-out.force[0], -out.force[1]];
        out
    }

    /// Fraction of `axial_depth` in the cut now: `(t − t0)/depth_ramp_time` during the entry
    /// ramp, else 1. The force is scaled by it (exactly the depth's effect for the linear and
    /// power laws, which are proportional to `a_p`; the cubic law's force is scaled the same way).
    pub fn depth_fraction(&self) -> f64 {
        let r = self.p.depth_ramp_time;
        if r > 0.0 { ((self.t - self.t0) / r).clamp(0.0, 1.0) } else { 1.0 }
    }

    /// Is this a state the process can continue from? (Run on every restored FMU state.)
    pub fn validate_state(&self) -> Result<(), String> {
        self.p.validate()?;
        let same =
            |a: &[f64], b: &[f64]| a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
        let eng = self.p.engagement();
        if !same(&self.offsets, &self.p.tooth_offsets())
            || !same(&self.gaps, &self.p.gaps())
            || !same(&[self.engagement.0, self.engagement.1], &[eng.0, eng.1])
        {
            return Err("derived process quantities do not match the parameters".into());
        }
        if !(self.t.is_finite()
            && self.t0.is_finite()
            && self.t >= self.t0
            && self.theta.is_finite()
            && self.theta >= 0.0)
        {
            return Err("the time or the tool angle is not finite".into());
        }
        let o = &self.out;
        let outs = [o.force[0], o.force[1], o.workpiece_force[0], o.workpiece_force[1], o.chip_thickness, o.tool_angle];
        if !(outs.iter().all(|x| x.is_finite()) && o.delay.is_finite() && o.delay >= 0.0) {
            return Err("the outputs are not finite".into());
        }
        self.history.validate()?;
        if self
            .history
            .newest()
            .is_none_or(|n| n.t.to_bits() != self.t.to_bits() || n.theta.to_bits() != self.theta.to_bits())
        {
            return Err("the history does not end at the current instant".into());
        }
        Ok(())
    }
}

fn relative(i: &ProcessInputs) -> [f64; 2] {
    [i.tool[0] - i.workpiece[0], i.tool[1] - i.workpiece[1]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::ForceLaw;

    const H: f64 = 1e-5;

    fn run(
        p: &ProcessParams,
        inputs: impl Fn(usize) -> ProcessInputs,
        n: usize,
        mut each: impl FnMut(usize, &Process),
    ) {
        let mut pr = Process::new(p).unwrap();
        for k in 0..n {
            pr.step(H, &inputs(k)).unwrap();
            each(k, &pr);
        }
    }

    /// With an entry ramp the force of a rigid cut is the unramped force times `t/T_r` (the
    /// same chips: the ramp does not change the surface), and exactly the unramped one after.
    #[test]
    fn the_entry_ramp_scales_the_force_linearly_then_not_at_all() {
        let full = ProcessParams::default();
        let ramped = ProcessParams { depth_ramp_time: 2e-3, ..ProcessParams::default() };
        assert!(ProcessParams { depth_ramp_time: -1.0, ..ProcessParams::default() }.validate().is_err());
        let (mut a, mut b) = (Process::new(&full).unwrap(), Process::new(&ramped).unwrap());
        assert!(b.outputs().force.iter().all(|f| *f == 0.0));
        let mut checked = 0;
        for k in 1..=400 {
            a.step(H, &ProcessInputs::default()).unwrap();
            b.step(H, &ProcessInputs::default()).unwrap();
            let frac = (k as f64 * H / 2e-3).min(1.0);
            assert!((b.depth_fraction() - frac).abs() < 1e-12);
            for i in 0..2 {
                let (fa, fb) = (a.outputs().force[i], b.outputs().force[i]);
                assert!((fb - frac * fa).abs() <= 1e-12 * fa.abs().max(1.0), "k = {k}: {fb} vs {frac} * {fa}");
                if k > 200 {
                    assert_eq!(fb.to_bits(), fa.to_bits());
                }
            }
            let (f, w) = (b.outputs().force, b.outputs().workpiece_force);
            assert!(w[0].to_bits() == (-f[0]).to_bits() && w[1].to_bits() == (-f[1]).to_bits());
            checked += usize::from(a.outputs().force[0] != 0.0 && k < 200);
        }
        assert!(checked > 50, "the ramp was checked while cutting ({checked} steps)");
    }

    #[test]
    fn a_rigid_cut_gives_the_closed_form_mean_force_and_the_tooth_period_delay() {
        // mean force on the tool over a revolution = −Z/(2π) a_p K_t f_z ∫ sin φ [(cos φ, −sin φ) + k_r (sin φ, cos φ)] dφ
        let p = ProcessParams::default();
        let n = 3000; // 2000 rpm: one revolution = 3000 steps of 10 µs
        let mut sum = [0.0; 2];
        let mut delay = 0.0;
        run(
            &p,
            |_| ProcessInputs::default(),
            2 * n,
            |k, pr| {
                if k >= n {
                    sum[0] += pr.outputs().force[0] / n as f64;
                    sum[1] += pr.outputs().force[1] / n as f64;
                }
                delay = pr.outputs().delay;
            },
        );
        let (kt, kr, ap, fz) = (760e6, 210e6 / 760e6, 1e-3, 0.05e-3);
        let c = -4.0 / (2.0 * PI) * ap * kt * fz;
        // ∫_0^{π/2} sin cos = 1/2, sin² = π/4, −sin² = −π/4, sin cos = 1/2
        let exact = [c * (0.5 + kr * PI / 4.0), c * (-PI / 4.0 + kr * 0.5)];
        for i in 0..2 {
            assert!((sum[i] - exact[i]).abs() < 2e-3 * exact[0].abs(), "axis {i}: {} vs {}", sum[i], exact[i]);
        }
        assert!((delay - 7.5e-3).abs() < 1e-9);
    }

    #[test]
    fn tool_and_workpiece_displacements_enter_as_their_difference() {
        let p = ProcessParams::default();
        let a = |k: usize| ProcessInputs { tool: [1e-6 * (k as f64 * 0.01).sin(), 0.0], ..Default::default() };
        let b = |k: usize| ProcessInputs { workpiece: [-1e-6 * (k as f64 * 0.01).sin(), 0.0], ..Default::default() };
        let (mut fa, mut fb) = (Vec::new(), Vec::new());
        run(&p, a, 2000, |_, pr| fa.push(pr.outputs()));
        run(&p, b, 2000, |_, pr| fb.push(pr.outputs()));
        assert_eq!(fa, fb);
        assert!(fa.iter().all(|o| o.workpiece_force.map(f64::to_bits) == [-o.force[0], -o.force[1]].map(f64::to_bits)));
    }

    #[test]
    fn a_skipped_tooth_passes_its_chip_to_the_next_with_multiple_regeneration() {
        // the tool retracts 1 mm for one tooth pass (7.5 ms: the tooth in the cut loses contact),
        // then returns; the next tooth meets the surface of two passes ago: 2 f_z sin φ, 2 f_z at φ = π/2
        let retract = |k: usize| {
            let r = if (1500..2250).contains(&k) { -1e-3 } else { 0.0 };
            ProcessInputs { tool: [r, r], ..Default::default() }
        };
        for (multiple, lo, hi) in [(true, 0.999e-4, 1.0e-4 * 1.0001), (false, 1e-3, 1.0)] {
            let p = ProcessParams { multiple_regeneration: multiple, ..Default::default() };
            let mut peak: f64 = 0.0;
            run(&p, retract, 3001, |k, pr| {
                if k >= 2250 {
                    peak = peak.max(pr.outputs().chip_thickness);
                }
            });
            assert!(peak > lo && peak < hi, "multiple = {multiple}: largest chip {peak}");
        }
    }

    #[test]
    fn variable_pitch_delays_follow_the_gaps_and_all_laws_cut() {
        let mut p = ProcessParams { variable_pitch: true, ..Default::default() };
        p.tooth_angles[..4].copy_from_slice(&[0.0, 1.4, 3.2, 4.6]);
        let mut delay = 0.0;
        run(&p, |_| ProcessInputs::default(), 4000, |_, pr| delay = pr.outputs().delay);
        let omega = 2000.0 * 2.0 * PI / 60.0;
        assert!((delay - (2.0 * PI - 4.6) / omega).abs() < 1e-8, "{delay}");
        for law in [ForceLaw::Power, ForceLaw::Cubic] {
            let mut q = ProcessParams::default();
            q.coefficients.law = law;
            q.coefficients.exponent = 0.744;
            let mut f: f64 = 0.0;
            run(&q, |_| ProcessInputs::default(), 500, |_, pr| f = f.max(pr.outputs().force[0].abs()));
            assert!(f > 0.0 && f.is_finite(), "{law:?}");
        }
    }

    #[test]
    fn non_finite_inputs_and_too_slow_speeds_are_refused_without_a_step() {
        let mut pr = Process::new(&ProcessParams::default()).unwrap();
        let bad = ProcessInputs { tool: [f64::NAN, 0.0], ..Default::default() };
        let e = pr.step(H, &bad).unwrap_err();
        assert!(matches!(e, ProcessError::Input(ref m) if m.contains("tool_x")), "{e}");
        assert!(pr.time().abs() < 1e-300, "the refused step was taken");
        let slow = ProcessInputs { spindle_speed_rpm: 1.0, ..Default::default() };
        assert!(matches!(pr.step(H, &slow), Err(ProcessError::Input(_))));
        // 0 rpm: the history does not grow
        let stop = ProcessInputs { spindle_speed_rpm: 0.0, ..Default::default() };
        for _ in 0..10_000 {
            pr.step(H, &stop).unwrap();
        }
        assert!(pr.history_len() < 5 && pr.validate_state().is_ok());
    }
}
