//! The machine as the stability core's models: the modes as mass-normalised shapes, the cutter
//! (the same force model for every method), the 2×2 tool-point receptance, and the closed-loop
//! receptance with a controller acting through the actuator.
//!
//! Closed loop (a SISO controller on one axis `d`): the controller measures the tool
//! displacement along `d`, `y = dᵀx`, and the actuator at the tool point pushes along `d` with
//! `F_a = G_a(ω) u`, `u = H_c(ω) y` (`H_c` includes its sign, sampling, the master's one-step
//! communication delay and the hold: [`chatter_control::Controller::frequency_response`]). With
//! `g = dᵀ G d` and `C = G_a H_c`,
//!
//! ```text
//! x = G (F + d C y),  y = dᵀ x   ⇒   G_cl = G + (G d) C (dᵀ G) / (1 − g C),
//! ```
//!
//! which reduces to the one-direction `Φ/(1 − Φ G_a H_c)` of `seed000::loop_frf`.

use crate::machine::{Actuator, Law, Machine, Milling};
use chatter_control::{Controller, ControllerParams};
use delay_stability::StabilityError;
use delay_stability::milling::{Cutter, ForceLaw, MillingModel, ModeShape, Structure};
use nalgebra::Matrix2;
use num_complex::Complex64;

/// Why the machine cannot be analysed by a method (said, never approximated quietly).
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// The machine has something the method does not represent.
    #[error("{0}")]
    Unsupported(String),
    /// The stability core refused.
    #[error(transparent)]
    Stability(#[from] StabilityError),
}

impl Machine {
    /// An error unless the structure has modes (a machine given by measured FRFs alone has
    /// zero-order lobes from the data; everything else needs modes).
    pub fn require_modes(&self, what: &str) -> Result<(), ModelError> {
        if self.modes.is_empty() {
            return Err(ModelError::Unsupported(format!(
                "{what} needs the structure's modes, and this machine file gives measured FRFs only: fit them first (`chatter frf fit --machine <this file>` writes a machine file with the fitted modes)"
            )));
        }
        Ok(())
    }

    /// The modes with mass-normalised shapes at the tool point (`s/√m`); the actuator/sensor
    /// point is the tool point.
    pub fn mode_shapes(&self) -> Vec<ModeShape> {
        self.modes
            .iter()
            .map(|m| {
                let u = 1.0 / m.mass().sqrt();
                let tool = [m.shape[0] * u, m.shape[1] * u];
                ModeShape { omega: m.omega(), zeta: m.damping, tool, actuator: tool }
            })
            .collect()
    }

    /// The cutter of the lobe methods (uniform pitch, straight flutes).
    pub fn cutter(&self) -> Result<Cutter, ModelError> {
        if self.tool.pitch.is_some() {
            return Err(ModelError::Unsupported(
                "tool.pitch: a variable pitch has one delay per tooth gap; the lobe methods here handle one delay \
                 (uniform pitch). Run the time domain (`chatter machine simulate`) for this cutter"
                    .into(),
            ));
        }
        let (entry, exit) = self.engagement();
        let law = match self.material.law {
            Law::Linear => ForceLaw::Linear,
            Law::Power { x_f } => ForceLaw::Power { x_f, feed_per_tooth: self.operation.feed_per_tooth },
        };
        Ok(Cutter::new(self.tool.teeth, entry, exit, self.material.kt, self.material.kr, law)?)
    }

    /// The semi-discretisation model (open loop).
    pub fn sd_model(&self) -> Result<MillingModel, ModelError> {
        self.require_modes("semi-discretisation")?;
        let s = Structure::from_modes(&self.mode_shapes())?;
        Ok(MillingModel::new(&s, self.cutter()?, None)?)
    }

    /// The 2×2 tool-point receptance `G(iω)` \[m/N\] at `omega` \[rad/s\].
    pub fn receptance(&self, omega: f64) -> Matrix2<Complex64> {
        let mut g = Matrix2::zeros();
        for m in &self.modes {
            let wn = m.omega();
            let h = Complex64::new(1.0, 0.0)
                / (m.mass() * Complex64::new(wn * wn - omega * omega, 2.0 * m.damping * wn * omega));
            for i in 0..2 {
                for j in 0..2 {
                    g[(i, j)] += h * m.shape[i] * m.shape[j];
                }
            }
        }
        g
    }

    /// Is the cut a slot or a low immersion, for the choice of method?
    pub fn is_low_immersion(&self) -> bool {
        self.operation.immersion <= 0.2
    }

    /// Up- or down-milling in the stability core's terms.
    pub fn sd_milling(&self) -> delay_stability::milling::Milling {
        match self.operation.milling {
            Milling::Up => delay_stability::milling::Milling::Up,
            Milling::Down => delay_stability::milling::Milling::Down,
        }
    }
}

impl Actuator {
    /// `F/u = s²/(s² + 2ζω s + ω²)` at `omega` \[rad/s\].
    pub fn response(&self, omega: f64) -> Complex64 {
        let w = 2.0 * std::f64::consts::PI * self.frequency_hz;
        let s = Complex64::new(0.0, omega);
        s * s / (s * s + 2.0 * self.damping * w * s + w * w)
    }
}

/// The closed-loop receptance of a machine with a controller on its actuator (module docs).
pub struct ClosedLoop<'a> {
    machine: &'a Machine,
    actuator: &'a Actuator,
    controller: Controller,
}

impl<'a> ClosedLoop<'a> {
    /// The machine's loop with `params` (the machine must have an actuator).
    pub fn new(machine: &'a Machine, params: &ControllerParams) -> Result<ClosedLoop<'a>, ModelError> {
        machine.require_modes("a controller's closed loop")?;
        let actuator = machine
            .actuator
            .as_ref()
            .ok_or_else(|| ModelError::Unsupported("a controller needs the machine's [actuator]".into()))?;
        let controller = Controller::new(params).map_err(ModelError::Unsupported)?;
        Ok(ClosedLoop { machine, actuator, controller })
    }

    /// `G_cl(iω)` \[m/N\].
    pub fn receptance(&self, omega: f64) -> Matrix2<Complex64> {
        let g = self.machine.receptance(omega);
        let d = self.actuator.axis.unit();
        let gd = g * nalgebra::Vector2::new(Complex64::from(d[0]), Complex64::from(d[1]));
        let dg = nalgebra::RowVector2::new(Complex64::from(d[0]), Complex64::from(d[1])) * g;
        let gdd = d[0] * gd[0] + d[1] * gd[1];
        let c = self.actuator.response(omega) * self.controller.frequency_response(omega);
        g + gd * dg * (c / (Complex64::new(1.0, 0.0) - gdd * c))
    }

    /// The command per unit tool displacement force `u/F` along the axis: `dᵀG_cl … ` as a row
    /// (for the forced-response saturation estimate): `u = H_c dᵀ x = H_c dᵀ G_cl F`.
    pub fn command_per_force(&self, omega: f64) -> nalgebra::RowVector2<Complex64> {
        let d = self.actuator.axis.unit();
        let row = nalgebra::RowVector2::new(Complex64::from(d[0]), Complex64::from(d[1])) * self.receptance(omega);
        row * self.controller.frequency_response(omega)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    pub(crate) const USER: &str = r#"
version = 1
name = "ordinary end mill"
[tool]
teeth = 3
diameter = "12 mm"
[structure]
x = [ { frequency = "600 Hz", damping = 0.03, stiffness = "2e7 N/m" },
      { frequency = "1100 Hz", damping = 0.02, stiffness = "5e7 N/m" } ]
y = [ { frequency = "650 Hz", damping = 0.035, stiffness = "2.5e7 N/m" } ]
[material]
kt = "800 N/mm^2"
kr_ratio = 0.3
[operation]
immersion = 1
milling = "down"
feed_per_tooth = "0.05 mm"
"#;

    #[test]
    fn the_receptance_is_the_sum_of_the_modes_and_matches_the_sd_structure() {
        let m = Machine::from_toml(USER, "user.toml").unwrap();
        // static compliance along x: 1/2e7 + 1/5e7
        assert_relative_eq!(m.receptance(0.0)[(0, 0)].re, 1.0 / 2e7 + 1.0 / 5e7, max_relative = 1e-12);
        assert_relative_eq!(m.receptance(0.0)[(1, 1)].re, 1.0 / 2.5e7, max_relative = 1e-12);
        assert!(m.receptance(3000.0)[(0, 1)].norm() < 1e-300, "x and y modes do not couple");
        // the mass-normalised shapes give the same FRF
        let shapes = m.mode_shapes();
        for w in [1000.0, 3770.0, 6900.0] {
            let mut g = Complex64::new(0.0, 0.0);
            for s in &shapes {
                g += s.tool[0] * s.tool[0] / Complex64::new(s.omega * s.omega - w * w, 2.0 * s.zeta * s.omega * w);
            }
            assert_relative_eq!((g - m.receptance(w)[(0, 0)]).norm() / g.norm(), 0.0, epsilon = 1e-12);
        }
        assert!(m.sd_model().is_ok());
    }

    #[test]
    fn a_zero_gain_controller_leaves_the_open_loop() {
        let text = format!("{USER}\n[actuator]\naxis = \"x\"\nforce_limit = \"27 N\"\n");
        let m = Machine::from_toml(&text, "user.toml").unwrap();
        let mut p = ControllerParams::tuned();
        p.structure = chatter_control::Structure::Pid;
        (p.pid.kp, p.pid.ki, p.pid.kd) = (0.0, 0.0, 0.0);
        let cl = ClosedLoop::new(&m, &p).unwrap();
        for w in [500.0, 3770.0] {
            assert_relative_eq!((cl.receptance(w) - m.receptance(w)).norm(), 0.0, epsilon = 1e-20);
        }
        // a derivative gain damps the x mode and leaves y alone
        p.pid.kd = 300.0;
        let cl = ClosedLoop::new(&m, &p).unwrap();
        let w = 2.0 * std::f64::consts::PI * 600.0;
        assert!(cl.receptance(w)[(0, 0)].norm() < 0.8 * m.receptance(w)[(0, 0)].norm());
        assert_relative_eq!((cl.receptance(w)[(1, 1)] - m.receptance(w)[(1, 1)]).norm(), 0.0, epsilon = 1e-20);
    }
}
