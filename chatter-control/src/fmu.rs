//! `ChatterController`: the FMI 2.0 co-simulation variable table and stepping of the
//! controller (the export layer in `fmi2-export` does the rest).
//!
//! # Timing and feedthrough
//!
//! The controller samples at `t_s = t_start + k·T` (`t_start`: the first communication point).
//! `fmi2DoStep(t, h)` takes every sample instant in `[t, t + h)`, each with the inputs `y, r`
//! set before the call (held over the step; no input interpolation), so a step `h = n·T` runs
//! exactly `n` samples; other step sizes run the samples that fall inside (possibly none).
//! The outputs at `t + h` are those of the last sample taken, i.e. the command being applied
//! at `t + h` was computed from the input held over the step. The outputs at a communication
//! point therefore do **not** depend on the inputs set at that point: no direct feedthrough,
//! declared as empty dependencies in `ModelStructure`. Stepped with `h = T`, the response from
//! `y(t_k)` to `u(t_{k+1})` is `e^{−iωT}C(e^{iωT})` ([`crate::Controller::sampled_response`]).
//! Before the first step the outputs are zero.

use crate::controller::{Controller, ControllerOutput};
use crate::fopid::FopidGains;
use crate::fractional::{FractionalMethod, FractionalParams};
use crate::params::{AdrcParams, ControllerParams, DEFAULT_PARAMS, Structure};
use crate::pid::PidGains;
use fmi2_export::model_description::{
    Causality as C, ModelBuilder, ModelDescription, ScalarVariable as V, Value, Variability as Va,
};
use fmi2_export::{Environment, Fmi2Model, ModelLog, Severity, StepError, Values};
use serde::{Deserialize, Serialize};
use std::sync::OnceLock;

/// Value references (Real unless noted).
pub mod vr {
    #![allow(missing_docs)]
    pub const Y: u32 = 0;
    pub const R: u32 = 1;
    pub const U: u32 = 2;
    pub const E: u32 = 3;
    pub const Z1: u32 = 4;
    pub const Z2: u32 = 5;
    pub const Z3: u32 = 6;
    pub const U_MAX: u32 = 10;
    pub const TS: u32 = 11;
    pub const PID_KP: u32 = 20;
    pub const PID_KI: u32 = 21;
    pub const PID_KD: u32 = 22;
    pub const PID_TF: u32 = 23;
    pub const FOPID_KP: u32 = 30;
    pub const FOPID_KI: u32 = 31;
    pub const FOPID_KD: u32 = 32;
    pub const FOPID_LAMBDA: u32 = 33;
    pub const FOPID_MU: u32 = 34;
    pub const ADRC_KP: u32 = 40;
    pub const ADRC_KI: u32 = 41;
    pub const ADRC_KD: u32 = 42;
    pub const ADRC_LAMBDA: u32 = 43;
    pub const ADRC_MU: u32 = 44;
    pub const ADRC_OMEGA_O: u32 = 45;
    pub const ADRC_B0: u32 = 46;
    pub const ADRC_TD_R: u32 = 47;
    pub const ADRC_TD_H: u32 = 48;
    pub const FRAC_OMEGA_B: u32 = 60;
    pub const FRAC_OMEGA_H: u32 = 61;
    /// Integer (enumeration `Structure`).
    pub const STRUCTURE: u32 = 0;
    /// Integer (enumeration `FractionalMethod`).
    pub const FRAC_METHOD: u32 = 1;
    /// Integer.
    pub const FRAC_MEMORY: u32 = 2;
    /// Integer.
    pub const FRAC_ORDER: u32 = 3;
    /// Boolean.
    pub const SATURATED: u32 = 0;
}

/// Long documentation of the FMU (packaged as `documentation/index.html`).
pub const DOCUMENTATION: &str = r#"# ChatterController

Active chatter controllers for milling (Soufi et al., seed 000, Section 4): `off`, classical
`pid`, standalone `fopid`, and `adrc_fopid` (tracking differentiator + linear extended state
observer + fractional-order PID, u = (u0 - z3)/b0). Input: measured tip displacement `y` [m] and
reference `r` [m] (default 0). Output: actuator force command `u` [N], saturated at +-`u_max`
(flag `saturated`), tracking error `e = r - y` [m], observer estimates `z1` [m], `z2` [m/s],
`z3` [m/s2] (the ESO runs in every structure; only `adrc_fopid` uses it).

## Discrete time
The controller is a sampled system with period `Ts` (default 10 us). Sample instants are
t_start + k Ts; a communication step [t, t+h) runs every sample instant inside it with the inputs
held (h = n Ts runs exactly n samples). The outputs at t+h are those of the last sample: they do
not depend on the inputs set at t+h (no direct feedthrough; ModelStructure declares no
dependencies). Stepped with h = Ts, u(t_{k+1}) responds to y(t_k): one sample of delay.

## Control laws
- PID: u = Kp e + Ki I + D, I_k = I_{k-1} + Ts e_k, D_k = (Tf D_{k-1} + Kd (e_k - e_{k-1}))/(Tf + Ts);
  anti-windup by conditional integration (the integrator holds while the previous command was
  saturated and e pushes further).
- FOPID (Eq. 28): u = Kp e + Ki D^-lambda e + Kd D^mu e. Each operator D^alpha is split into
  alpha = m + r, m = floor(alpha), r in [0,1): the integer part is an exact backward difference or
  running sum (anti-windup as for the PID), the fractional part r is either Grunwald-Letnikov with
  short memory `fractional.memory_length` (FIR, weights w_j = w_{j-1}(1 - (r+1)/j), scaled Ts^-r)
  or Oustaloup's recursive filter of order `fractional.order` (2N+1 sections), accurate within
  0.5 dB / 2 deg over [`fractional.omega_b`, `fractional.omega_h`] (the poles and zeros are spread
  over that band widened 50x on each side), discretised section by section with Tustin prewarped
  at the band's geometric centre.
- ADRC-FOPID: Han's tracking differentiator (fhan, speed factor `adrc.td_r` [m/s2], filter factor
  `adrc.td_h` [s]) turns r into v1, v2; linear ESO with bandwidth `adrc.omega_o` (beta = 3wo,
  3wo^2, wo^3 in continuous time) discretised exactly: ZOH model of x'' = f + b0 u and a current
  observer whose error dynamics have the triple eigenvalue exp(-wo Ts); it is fed the SATURATED
  command actually applied, so saturation does not wind it up. e1 = v1 - z1, e2 = v2 - z2,
  u0 = Kp e1 + Ki D^-lambda e1 + Kd D^(mu-1) e2 (acceleration units), u = (u0 - z3)/`adrc.b0`.

## Units of the gains (reading of the paper's Table 2)
Table 2 is read in SI with e in m and u in N: PID Kp 2.3e3 N/m, Ki 0.012 N/(m s), Kd 180 N s/m;
FOPID Kp 1.8e3 N/m, Ki 0.45 N/(m s^lambda), Kd 240 N s^mu/m, lambda 0.85, mu 1.15 (at 5 um and
143 Hz these ask about 1-3 N of the 27 N available). The ADRC inner FOPID produces an
acceleration; its gains are the same force gains times b0 = 1/30 kg^-1 (Kp 60 1/s2, Ki 0.015,
Kd 8), so the FOPID part of the ADRC command equals the standalone FOPID force. Fractional gains
have non-integer unit exponents and carry no declared unit.

## Default gains
The start values are gains tuned by particle swarm optimisation on the MillingPlant FMU's
default plant (`stability tune`, seed Section 4.4: maximise the minimum critical depth over
1000-3000 rpm without exceeding 27 N under the 50 N RMS disturbance): PID Kp 1e5 N/m, Ki 1e-3,
Kd 1e3 N s/m; FOPID Kp 1e5, Ki 1e4, Kd 1e3, lambda 0.8735, mu 1.2788; ADRC-FOPID force-equivalent
Kp 1e5, Ki 1e4, Kd 1e3, lambda 0.1, mu 0.3942 with omega_o 8705.4 rad/s and b0 1/3 1/kg (the
seed fixes omega_o and b0, but with them no gains pass the saturation check). Several gains sit
on the bounds of the seed's Table 3 search space. The paper's Table 2 values are the named
preset `ControllerParams::paper_table2()`; `ClosedLoopTable2.ssp` binds them as SSP parameters.

## Note on the observer bandwidth
z3/f = wo^3/(s + wo)^3: at 143 Hz with wo = 2699.3 rad/s the disturbance estimate lags 55 deg
and has 85 % of the amplitude. The paper's rule "error (w/wo)^3" (Eq. 26a) understates this.
"#;

/// The FMU model: a [`Controller`] plus its sample clock.
#[derive(Clone, Serialize, Deserialize)]
pub struct ChatterController {
    ctrl: Controller,
    ts: f64,
    t_base: Option<f64>,
    k_next: u64,
    last: ControllerOutput,
    reported_saturation: bool,
}

fn params_from(v: &Values) -> Result<ControllerParams, String> {
    let structure = Structure::from_index(v.integer(vr::STRUCTURE))
        .ok_or_else(|| format!("structure = {} is not an item", v.integer(vr::STRUCTURE)))?;
    let method = match v.integer(vr::FRAC_METHOD) {
        1 => FractionalMethod::GrunwaldLetnikov,
        2 => FractionalMethod::Oustaloup,
        m => return Err(format!("fractional.method = {m} is not an item")),
    };
    let fopid = |b: u32| FopidGains {
        kp: v.real(b),
        ki: v.real(b + 1),
        kd: v.real(b + 2),
        lambda: v.real(b + 3),
        mu: v.real(b + 4),
    };
    Ok(ControllerParams {
        structure,
        ts: v.real(vr::TS),
        u_max: v.real(vr::U_MAX),
        pid: PidGains {
            kp: v.real(vr::PID_KP),
            ki: v.real(vr::PID_KI),
            kd: v.real(vr::PID_KD),
            tf: v.real(vr::PID_TF),
        },
        fopid: fopid(vr::FOPID_KP),
        adrc: AdrcParams {
            fopid: fopid(vr::ADRC_KP),
            omega_o: v.real(vr::ADRC_OMEGA_O),
            b0: v.real(vr::ADRC_B0),
            td_r: v.real(vr::ADRC_TD_R),
            td_h: v.real(vr::ADRC_TD_H),
        },
        fractional: FractionalParams {
            method,
            memory_length: usize::try_from(v.integer(vr::FRAC_MEMORY)).map_err(|e| e.to_string())?,
            omega_b: v.real(vr::FRAC_OMEGA_B),
            omega_h: v.real(vr::FRAC_OMEGA_H),
            order: usize::try_from(v.integer(vr::FRAC_ORDER)).map_err(|e| e.to_string())?,
        },
    })
}

impl ChatterController {
    /// The parameters of the running controller.
    pub fn params(&self) -> &ControllerParams {
        self.ctrl.params()
    }
}

/// The FMU's parameters (and the `structure` enumeration) holding `p`, as (variable name, value)
/// pairs: what a master sets (`--set controller.NAME=VALUE`, SSP parameter bindings) to run the
/// FMU with `p`. Generated from the same variable table as `modelDescription.xml`, so the names
/// cannot drift from the FMU's.
pub fn parameter_assignments(p: &ControllerParams) -> Vec<(String, Value)> {
    describe(p)
        .variables()
        .iter()
        .filter(|v| v.causality == C::Parameter)
        .filter_map(|v| Some((v.name.clone(), v.start_value()?)))
        .collect()
}

/// The variable table with the start values of `d`.
fn describe(d: &ControllerParams) -> ModelDescription {
    let d = *d;
    let par = |name: &str, vr: u32, start: f64, desc: &str| {
        V::real(name, vr, C::Parameter, Va::Fixed).start(start).describe(desc)
    };
    let out = |name: &str, vr: u32, unit: &str, desc: &str| {
        V::real(name, vr, C::Output, Va::Discrete).unit_of(unit).describe(desc).depends_on(&[])
    };
    let fop = |b: ModelBuilder, grp: &str, base: u32, g: FopidGains, force: bool| {
        let (kp_unit, what) = if force { ("N/m", "u in N") } else { ("1/s2", "u0 in m/s2") };
        b.var(
            par(&format!("{grp}.kp"), base, g.kp, &format!("proportional gain ({what})"))
                .unit_of(kp_unit)
                .bounds(-1e12, 1e12),
        )
        .var(
            par(
                &format!("{grp}.ki"),
                base + 1,
                g.ki,
                &format!(
                    "fractional integral gain ({what}; unit {})",
                    if force { "N/(m s^lambda)" } else { "s^(lambda-2)" }
                ),
            )
            .bounds(0.0, 1e12),
        )
        .var(
            par(
                &format!("{grp}.kd"),
                base + 2,
                g.kd,
                &format!("fractional derivative gain ({what}; unit {})", if force { "N s^mu/m" } else { "s^(mu-2)" }),
            )
            .bounds(-1e12, 1e12),
        )
        .var(par(&format!("{grp}.lambda"), base + 3, g.lambda, "integral order lambda").bounds(0.0, 3.0))
        .var(par(&format!("{grp}.mu"), base + 4, g.mu, "derivative order mu").bounds(0.0, 3.0))
    };
    let b = ModelBuilder::new("ChatterController", "ChatterController")
        .description("Active chatter controllers for milling: off, PID, FOPID, ADRC-FOPID (seed 000)")
        .author_version("chatter-fmu", env!("CARGO_PKG_VERSION"))
        .unit("m", [0, 1, 0, 0, 0, 0, 0, 0])
        .unit("m/s", [0, 1, -1, 0, 0, 0, 0, 0])
        .unit("m/s2", [0, 1, -2, 0, 0, 0, 0, 0])
        .unit("N", [1, 1, -2, 0, 0, 0, 0, 0])
        .unit("s", [0, 0, 1, 0, 0, 0, 0, 0])
        .unit("N/m", [1, 0, -2, 0, 0, 0, 0, 0])
        .unit("N.s/m", [1, 0, -1, 0, 0, 0, 0, 0])
        .unit("N/(m.s)", [1, 0, -3, 0, 0, 0, 0, 0])
        .unit("1/s2", [0, 0, -2, 0, 0, 0, 0, 0])
        .unit("rad/s", [0, 0, -1, 0, 0, 0, 0, 1])
        .unit("1/kg", [-1, 0, 0, 0, 0, 0, 0, 0])
        .enumeration(
            "Structure",
            "controller structure",
            &[
                ("off", "no control (u = 0)"),
                ("pid", "classical PID with anti-windup"),
                ("fopid", "fractional-order PID (Eq. 28)"),
                ("adrc_fopid", "TD + linear ESO + FOPID, u = (u0 - z3)/b0"),
            ],
        )
        .enumeration(
            "FractionalMethod",
            "realisation of the non-integer part of the fractional operators",
            &[
                ("grunwald_letnikov", "Grunwald-Letnikov, short memory"),
                ("oustaloup", "Oustaloup recursive filter, Tustin with prewarping"),
            ],
        )
        .default_experiment(0.0, 0.1, d.ts)
        .var(
            V::real("y", vr::Y, C::Input, Va::Continuous).start(0.0).unit_of("m").describe("measured tip displacement"),
        )
        .var(V::real("r", vr::R, C::Input, Va::Continuous).start(0.0).unit_of("m").describe("reference displacement"))
        .var(out("u", vr::U, "N", "actuator force command, saturated at +-u_max"))
        .var(out("e", vr::E, "m", "tracking error r - y of the last sample"))
        .var(out("z1", vr::Z1, "m", "ESO displacement estimate"))
        .var(out("z2", vr::Z2, "m/s", "ESO velocity estimate"))
        .var(out("z3", vr::Z3, "m/s2", "ESO total-disturbance estimate (acceleration)"))
        .var(
            V::boolean("saturated", vr::SATURATED, C::Output, Va::Discrete)
                .describe("the unsaturated command exceeded u_max at the last sample")
                .depends_on(&[]),
        )
        .var(
            V::enumeration("structure", vr::STRUCTURE, C::Parameter, Va::Fixed, "Structure")
                .start(d.structure.index())
                .describe("controller structure"),
        )
        .var(par("u_max", vr::U_MAX, d.u_max, "actuator command limit").unit_of("N").bounds(0.0, 1e9))
        .var(par("Ts", vr::TS, d.ts, "sample period").unit_of("s").bounds(1e-9, 1.0))
        .var(par("pid.kp", vr::PID_KP, d.pid.kp, "PID proportional gain").unit_of("N/m").bounds(-1e12, 1e12))
        .var(par("pid.ki", vr::PID_KI, d.pid.ki, "PID integral gain").unit_of("N/(m.s)").bounds(0.0, 1e12))
        .var(par("pid.kd", vr::PID_KD, d.pid.kd, "PID derivative gain").unit_of("N.s/m").bounds(-1e12, 1e12))
        .var(
            par("pid.tf", vr::PID_TF, d.pid.tf, "PID derivative filter time constant (0: none)")
                .unit_of("s")
                .bounds(0.0, 1.0),
        );
    let b = fop(b, "fopid", vr::FOPID_KP, d.fopid, true);
    let b = fop(b, "adrc", vr::ADRC_KP, d.adrc.fopid, false)
        .var(
            par("adrc.omega_o", vr::ADRC_OMEGA_O, d.adrc.omega_o, "ESO bandwidth (error poles at -omega_o)")
                .unit_of("rad/s")
                .bounds(1e-3, 1e9),
        )
        .var(par("adrc.b0", vr::ADRC_B0, d.adrc.b0, "nominal input gain 1/Mw").unit_of("1/kg").bounds(1e-9, 1e9))
        .var(par("adrc.td_r", vr::ADRC_TD_R, d.adrc.td_r, "TD speed factor r0").unit_of("m/s2").bounds(1e-12, 1e12))
        .var(par("adrc.td_h", vr::ADRC_TD_H, d.adrc.td_h, "TD filter factor h0").unit_of("s").bounds(1e-9, 1.0))
        .var(
            V::enumeration("fractional.method", vr::FRAC_METHOD, C::Parameter, Va::Fixed, "FractionalMethod")
                .start(match d.fractional.method {
                    FractionalMethod::GrunwaldLetnikov => 1,
                    FractionalMethod::Oustaloup => 2,
                })
                .describe("realisation of the fractional part"),
        )
        .var(
            V::integer("fractional.memory_length", vr::FRAC_MEMORY, C::Parameter, Va::Fixed)
                .start(d.fractional.memory_length as i32)
                .bounds(1.0, 1e6)
                .describe("Grunwald-Letnikov short-memory length L (samples)"),
        )
        .var(
            par("fractional.omega_b", vr::FRAC_OMEGA_B, d.fractional.omega_b, "Oustaloup band, lower edge")
                .unit_of("rad/s")
                .bounds(1e-6, 1e9),
        )
        .var(
            par("fractional.omega_h", vr::FRAC_OMEGA_H, d.fractional.omega_h, "Oustaloup band, upper edge")
                .unit_of("rad/s")
                .bounds(1e-6, 1e9),
        )
        .var(
            V::integer("fractional.order", vr::FRAC_ORDER, C::Parameter, Va::Fixed)
                .start(d.fractional.order as i32)
                .bounds(1.0, 50.0)
                .describe("Oustaloup order N (2N+1 sections)"),
        );
    fmi2_export::with_log_categories(b).build().expect("valid ChatterController table")
}

impl Fmi2Model for ChatterController {
    fn description() -> &'static ModelDescription {
        static MD: OnceLock<ModelDescription> = OnceLock::new();
        MD.get_or_init(|| describe(&DEFAULT_PARAMS))
    }

    fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
        let p = params_from(values)?;
        let ctrl = Controller::new(&p)?;
        Ok(ChatterController {
            ctrl,
            ts: p.ts,
            t_base: None,
            k_next: 0,
            last: ControllerOutput::default(),
            reported_saturation: false,
        })
    }

    fn update_outputs(&self, v: &mut Values) {
        let o = &self.last;
        v.set_real(vr::U, o.u);
        v.set_real(vr::E, o.e);
        v.set_real(vr::Z1, o.z1);
        v.set_real(vr::Z2, o.z2);
        v.set_real(vr::Z3, o.z3);
        v.set_boolean(vr::SATURATED, o.saturated);
    }

    fn do_step(&mut self, v: &mut Values, t: f64, h: f64, log: &mut dyn ModelLog) -> Result<(), StepError> {
        let (y, r) = (v.real(vr::Y), v.real(vr::R));
        let base = *self.t_base.get_or_insert(t);
        let end = t + h - 1e-6 * self.ts;
        while base + self.k_next as f64 * self.ts < end {
            self.last = self.ctrl.sample(y, r);
            self.k_next += 1;
            if self.last.saturated && !self.reported_saturation {
                self.reported_saturation = true;
                let ts = base + (self.k_next - 1) as f64 * self.ts;
                log.log(Severity::Info, &format!("command saturated at t = {ts} (further saturations not logged)"));
            }
        }
        self.update_outputs(v);
        Ok(())
    }
}
