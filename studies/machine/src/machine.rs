//! The machine file (schema version 1): one description of a user's machine that every
//! analysis reads.
//!
//! ```toml
//! version = 1
//! name = "12 mm 3-flute end mill"          # optional
//!
//! [tool]
//! teeth = 3
//! diameter = "12 mm"
//! # pitch = ["0 deg", "115 deg", "240 deg"] # optional: tooth angles (default: uniform)
//! # helix = "30 deg"                        # optional; not modelled (a warning says so)
//!
//! [structure]                              # the tool-point receptance; x = feed, y = normal
//! x = [ { frequency = "600 Hz", damping = 0.03, stiffness = "2e7 N/m" },
//!       { frequency = "1100 Hz", damping = 0.02, stiffness = "5e7 N/m" } ]
//! y = [ { frequency = "650 Hz", damping = "3.5 %", stiffness = "2.5e7 N/m" } ]
//! # modes = [ { frequency = "900 Hz", damping = 0.02, mass = "0.5 kg", shape = [1, 1] } ]
//!
//! [material]
//! kt = "800 N/mm^2"                        # tangential cutting coefficient
//! kr = "240 N/mm^2"                        # or kr_ratio = 0.3
//! # kte = "20 N/mm", kre = "10 N/mm"       # edge coefficients (static force only)
//! # law = "power", x_f = 0.744             # K in N/m^(1+x_F), SI numbers
//!
//! [operation]
//! immersion = 1.0                          # radial immersion a_e/D (1 = slotting)
//! milling = "down"                         # or "up"
//! feed_per_tooth = "0.05 mm"
//! # axial_depth = "2 mm"                   # for time-domain runs
//! # spindle_speed = "10000 rpm"            # for time-domain runs
//! # speed_range = ["2000 rpm", "20000 rpm"] # lobes (default from the modes)
//!
//! # [actuator]                             # optional: an inertial actuator at the tool point
//! # axis = "x"                             # it pushes along, and the controller measures, this axis
//! # frequency = "8.4 Hz", damping = 0.15, force_limit = "27 N"
//!
//! # [controller]                           # optional: ChatterController on the actuator
//! # structure = "fopid"                    # off, pid, fopid, adrc_fopid
//! # parameters = "tuned_fopid.ssv"         # an SSV written by `chatter tune --machine`
//! # set = { "fopid.kp" = 1e5 }             # or parameters by the FMU's names
//! ```
//!
//! Every quantity is an SI number or a string with its unit; a value outside the physical
//! range of its quantity is refused, naming the unit it probably meant. A mode given along `x`
//! or `y` (or with a `shape`, normalised to unit length) has the stiffness along that
//! direction, `k = m ω_n²`; its receptance is `s sᵀ/(m(ω_n² − ω² + 2iζω_nω))`.

use std::f64::consts::PI;
use std::path::PathBuf;

/// The schema version this crate reads and writes.
pub const VERSION: i64 = 1;

/// Up- or down-milling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Milling {
    /// Conventional.
    Up,
    /// Climb.
    Down,
}

/// A direction of the machine frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// Along the feed.
    X,
    /// Normal to the feed.
    Y,
}

impl Axis {
    /// The unit vector.
    pub fn unit(self) -> [f64; 2] {
        match self {
            Axis::X => [1.0, 0.0],
            Axis::Y => [0.0, 1.0],
        }
    }

    /// `x` or `y`.
    pub fn name(self) -> &'static str {
        match self {
            Axis::X => "x",
            Axis::Y => "y",
        }
    }
}

/// The cutter.
#[derive(Clone, Debug, PartialEq)]
pub struct Tool {
    /// Number of teeth.
    pub teeth: u32,
    /// Diameter \[m\].
    pub diameter: f64,
    /// Tooth angles \[rad\] (None: uniform pitch).
    pub pitch: Option<Vec<f64>>,
    /// Helix angle \[rad\] (not modelled).
    pub helix: f64,
}

/// One mode of the tool-point receptance.
#[derive(Clone, Debug, PartialEq)]
pub struct Mode {
    /// Where it came from (`x[0]`, `modes[1]`).
    pub label: String,
    /// Natural frequency \[Hz\].
    pub frequency_hz: f64,
    /// Damping ratio.
    pub damping: f64,
    /// Modal stiffness along `shape` \[N/m\].
    pub stiffness: f64,
    /// Unit direction of the mode's displacement at the tool point (x, y).
    pub shape: [f64; 2],
}

impl Mode {
    /// ω_n \[rad/s\].
    pub fn omega(&self) -> f64 {
        2.0 * PI * self.frequency_hz
    }

    /// Modal mass `k/ω_n²` \[kg\].
    pub fn mass(&self) -> f64 {
        self.stiffness / (self.omega() * self.omega())
    }
}

/// The cutting-force law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Law {
    /// `F = a_p (K h + K_e)`.
    Linear,
    /// `F = a_p K h^{x_F}`.
    Power {
        /// Exponent x_F ∈ (0, 1].
        x_f: f64,
    },
}

/// The workpiece material's cutting coefficients.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Force law.
    pub law: Law,
    /// Tangential coefficient K_t \[N/m² linear, N/m^(1+x_F) power\].
    pub kt: f64,
    /// Radial coefficient K_r (same unit).
    pub kr: f64,
    /// Tangential edge coefficient \[N/m\].
    pub kte: f64,
    /// Radial edge coefficient \[N/m\].
    pub kre: f64,
}

/// The cut.
#[derive(Clone, Debug, PartialEq)]
pub struct Operation {
    /// Radial immersion a_e/D ∈ (0, 1].
    pub immersion: f64,
    /// Up or down.
    pub milling: Milling,
    /// Feed per tooth \[m\].
    pub feed_per_tooth: f64,
    /// Axial depth for time-domain runs \[m\].
    pub axial_depth: Option<f64>,
    /// Spindle speed for time-domain runs \[rpm\].
    pub spindle_speed_rpm: Option<f64>,
    /// Speed range of the lobes \[rpm\].
    pub speed_range_rpm: (f64, f64),
}

/// An inertial actuator at the tool point: `F/u = s²/(s² + 2ζω s + ω²)`, clipped at ±f_max.
#[derive(Clone, Debug, PartialEq)]
pub struct Actuator {
    /// The axis it pushes along (and the controller measures).
    pub axis: Axis,
    /// Suspension frequency \[Hz\].
    pub frequency_hz: f64,
    /// Suspension damping ratio.
    pub damping: f64,
    /// Command limit \[N\].
    pub force_limit: f64,
}

impl Default for Actuator {
    /// Seed 000's actuator (Section 3.3): 8.4 Hz, ζ = 0.15, ±27 N.
    fn default() -> Self {
        let w = 2785.6f64.sqrt();
        Actuator { axis: Axis::X, frequency_hz: w / (2.0 * PI), damping: 15.834 / (2.0 * w), force_limit: 27.0 }
    }
}

/// The controller of the file's `[controller]` table.
#[derive(Clone, Debug, PartialEq)]
pub struct ControllerChoice {
    /// Structure item name (`off`, `pid`, `fopid`, `adrc_fopid`).
    pub structure: String,
    /// An SSV parameter set for `ChatterController` (resolved against the file's folder).
    pub parameters: Option<PathBuf>,
    /// Parameters by the FMU's names, as text.
    pub set: Vec<(String, String)>,
}

/// A user's machine (module docs): everything in SI.
#[derive(Clone, Debug, PartialEq)]
pub struct Machine {
    /// Its name.
    pub name: String,
    /// The cutter.
    pub tool: Tool,
    /// The modes of the tool-point receptance (empty when the structure is measured FRFs only).
    pub modes: Vec<Mode>,
    /// Measured tool-point FRFs (`[structure] frf`), if given.
    pub frf: Option<crate::frf::MeasuredFrf>,
    /// The material.
    pub material: Material,
    /// The cut.
    pub operation: Operation,
    /// The actuator, if any.
    pub actuator: Option<Actuator>,
    /// The controller, if any.
    pub controller: Option<ControllerChoice>,
    /// What the file asks for that the models do not represent (said with every result).
    pub warnings: Vec<String>,
}

impl Machine {
    /// Entry and exit angles of the cut \[rad\], from +y clockwise (Altintas–Budak).
    pub fn engagement(&self) -> (f64, f64) {
        let phi_c = (1.0 - 2.0 * self.operation.immersion).clamp(-1.0, 1.0).acos();
        match self.operation.milling {
            Milling::Up => (0.0, phi_c),
            Milling::Down => (PI - phi_c, PI),
        }
    }

    /// The highest natural frequency \[Hz\].
    pub fn highest_mode_hz(&self) -> f64 {
        self.modes.iter().map(|m| m.frequency_hz).fold(0.0, f64::max)
    }

    /// The lowest natural frequency \[Hz\].
    pub fn lowest_mode_hz(&self) -> f64 {
        self.modes.iter().map(|m| m.frequency_hz).fold(f64::INFINITY, f64::min)
    }

    /// The static receptance matrix `Σ s sᵀ/k` \[m/N\] (for reports).
    pub fn static_compliance(&self) -> [[f64; 2]; 2] {
        let mut c = [[0.0; 2]; 2];
        for m in &self.modes {
            for (row, si) in c.iter_mut().zip(m.shape) {
                for (cij, sj) in row.iter_mut().zip(m.shape) {
                    *cij += si * sj / m.stiffness;
                }
            }
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = include_str!("../examples/end_mill.toml");

    fn err(text: &str) -> String {
        Machine::from_toml(text, "m.toml").unwrap_err().to_string()
    }

    #[test]
    fn the_example_reads_in_si() {
        let m = Machine::from_toml(GOOD, "end_mill.toml").unwrap();
        assert_eq!((m.tool.teeth, m.modes.len()), (3, 3));
        assert!((m.tool.diameter - 0.012).abs() < 1e-15 && (m.material.kt - 8e8).abs() < 1e-3);
        assert!((m.material.kr - 0.3 * 8e8).abs() < 1e-3 && (m.operation.feed_per_tooth - 5e-5).abs() < 1e-18);
        assert_eq!(m.operation.spindle_speed_rpm.map(|r| r.round()), Some(10000.0));
        assert!(m.modes[2].shape[0].abs() < 1e-15 && (m.modes[2].shape[1] - 1.0).abs() < 1e-15);
        assert!(m.warnings.is_empty());
        assert_eq!(m.engagement(), (0.0, PI));
    }

    /// Each bad file gives one error naming the field and the fix.
    #[test]
    fn bad_files_name_the_field_and_the_fix() {
        let cases = [
            (GOOD.replace("teeth = 3\n", ""), "m.toml: tool.teeth: missing: the number of teeth (add `teeth = ...`)"),
            (GOOD.replace("diameter =", "diamter ="), "m.toml: tool.diamter: unknown key; did you mean `diameter`?"),
            (GOOD.replace("\"800 N/mm^2\"", "\"800 mm\""), "\"800 mm\" is a length, but K_t is a pressure"),
            (GOOD.replace("\"800 N/mm^2\"", "800"), "did you mean \"800 N/mm^2\" (= 8e8 N/m^2)?"),
            (
                GOOD.replace("damping = 0.03,", "damping = -0.03,"),
                "structure.x[0].damping: a damping ratio = -0.03 must be positive",
            ),
            (GOOD.replace("damping = 0.03,", "damping = 3,"), "did you mean \"3 %\" (= 0.03 (ratio))?"),
            (GOOD.replace("\"2 mm\"", "3"), "operation.axial_depth: the axial depth = 3 m is 2e1 times above"),
            (GOOD.replace("\"600 Hz\"", "\"600 1/s\""), "a frequency in 1/s is ambiguous"),
            (GOOD.replace("version = 1", "version = 2"), "schema version 2 is not known"),
            (
                GOOD.replace("immersion = 1.0", "immersion = 1.5"),
                "operation.immersion: the radial immersion a_e/D must be a number in (0, 1]",
            ),
            (
                GOOD.replace("[actuator]\naxis = \"x\"", "[actuator]\naxis = \"z\""),
                "actuator.axis: \"z\" is not one of x, y",
            ),
            (GOOD.replace("\"2e7 N/m\" },", "\"2e7 N/m\", mass = 1 },"), "give either stiffness or mass, not both"),
            ("version = 1\n[tool".to_string(), "m.toml: not valid TOML"),
        ];
        for (text, want) in cases {
            let e = err(&text);
            assert!(e.contains(want), "want {want:?} in {e:?}");
            assert_eq!(e.lines().count(), 1, "{e}");
        }
    }

    #[test]
    fn helix_and_pitch_are_read_and_said() {
        let text = GOOD.replace(
            "diameter = \"12 mm\"",
            "diameter = \"12 mm\"\nhelix = \"30 deg\"\npitch = [\"0 deg\", \"115 deg\", \"240 deg\"]",
        );
        let m = Machine::from_toml(&text, "m.toml").unwrap();
        assert!(m.warnings[0].contains("helix = 30.0 deg is not modelled"));
        assert_eq!(m.tool.pitch.as_ref().map(Vec::len), Some(3));
        let uniform =
            GOOD.replace("diameter = \"12 mm\"", "diameter = \"12 mm\"\npitch = [\"0 deg\", \"120 deg\", \"240 deg\"]");
        assert_eq!(Machine::from_toml(&uniform, "m.toml").unwrap().tool.pitch, None);
        assert!(
            err(&GOOD.replace("diameter = \"12 mm\"", "diameter = \"12 mm\"\npitch = [\"0 deg\", \"120 deg\"]"))
                .contains("2 angles for 3 teeth")
        );
    }
}
