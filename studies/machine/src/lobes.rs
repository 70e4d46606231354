//! The lobes of a user's machine by three methods, side by side, with the places where they
//! disagree and which to trust there.
//!
//! * **Zero-order** (Altintas–Budak, 2-D): the tooth-period average of the directional matrix
//!   with the 2×2 receptance; exact per speed, fast; takes measured FRFs. Accurate when the
//!   directional matrix is nearly constant (many teeth in the cut); it misses what the
//!   time-periodic force adds at low immersion (added lobes, flip lobes).
//! * **Multi-frequency** (Budak–Altintas): the directional matrix's harmonics couple the
//!   receptance at `ω + kω_T`; recovers the low-immersion lobes.
//! * **Time-periodic** (the delay system itself, Hopf and flip): the reference the others are
//!   checked against. By default converged ([`Discretisation::Auto`]: the spectral collocation
//!   of `delay_stability`, its order raised per speed until the depth moves by less than 0.1 %
//!   to the next order); `chatter lobes --machine … --sd-m M` takes the first-order
//!   semi-discretisation (Insperger–Stépán, M steps per period, converging as 1/M²) instead, the
//!   reference the converged method is tested against.
//!
//! At every speed the report compares the approximate methods with the time-periodic boundary:
//! a method more than [`TOLERANCE`] above it claims a deeper stable cut than the linear
//! time-periodic model allows (the unsafe side) and is flagged; below it, conservative.

use crate::machine::Machine;
use crate::models::ModelError;
use delay_stability::frequency::{CriticalPoint, Lobes, MultiFrequency, Receptance, ZeroOrder2d};
use delay_stability::{Bifurcation, LobeOptions, LobePoint, Method as Discretisation, lobes_with};
use std::fmt::Write as _;

/// Relative disagreement that is reported (5 %).
pub const TOLERANCE: f64 = 0.05;

/// A lobe method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// 2-D zero-order.
    ZeroOrder,
    /// Multi-frequency.
    MultiFrequency,
    /// Semi-discretisation.
    SemiDiscretisation,
}

impl Method {
    /// The CSV/CLI name.
    pub fn name(self) -> &'static str {
        match self {
            Method::ZeroOrder => "zero-order",
            Method::MultiFrequency => "multi-frequency",
            Method::SemiDiscretisation => "semi-discretisation",
        }
    }

    /// The frequency-domain method for a machine: zero-order, or multi-frequency at low
    /// immersion (a_e/D ≤ 0.2) where the zero-order method misses the time-periodic force.
    pub fn for_immersion(m: &Machine) -> Method {
        if m.is_low_immersion() { Method::MultiFrequency } else { Method::ZeroOrder }
    }
}

/// The time-periodic method of a user's choice: converged ([`Discretisation::default`]) unless
/// a semi-discretisation order `sd_m` is given.
pub fn discretisation(sd_m: Option<usize>) -> Discretisation {
    sd_m.map_or_else(Discretisation::default, |m| Discretisation::Sd { m })
}

/// The frequency band of the chatter search \[Hz\]: 1 Hz (the actuator's suspension) to 3× the
/// highest mode.
pub fn band(m: &Machine) -> (f64, f64) {
    (1.0, 3.0 * m.highest_mode_hz())
}

/// The frequency-domain solver of `method` for `frf` (the machine's own receptance or a closed
/// loop's) over speeds down to `rpm_min`.
pub fn solver<'a, R: Receptance>(
    m: &Machine,
    method: Method,
    frf: &'a R,
    rpm_min: f64,
) -> Result<Box<dyn Lobes + 'a>, ModelError> {
    let cutter = m.cutter()?;
    let err = |e: delay_stability::zero_order::LobeError| ModelError::Unsupported(e.to_string());
    let g = move |w: f64| frf.receptance(w);
    Ok(match method {
        Method::ZeroOrder => Box::new(ZeroOrder2d::new(g, &cutter, band(m), rpm_min).map_err(err)?),
        Method::MultiFrequency => Box::new(MultiFrequency::new(g, &cutter, band(m), rpm_min).map_err(err)?),
        Method::SemiDiscretisation => {
            return Err(ModelError::Unsupported("semi-discretisation is not a frequency-domain method".into()));
        }
    })
}

/// Frequency-domain lobes of `frf` by `method` at `speeds`.
pub fn frequency_diagram<R: Receptance>(
    m: &Machine,
    method: Method,
    frf: &R,
    speeds: &[f64],
) -> Result<Vec<CriticalPoint>, ModelError> {
    let rpm_min = speeds.iter().copied().fold(f64::INFINITY, f64::min);
    Ok(solver(m, method, frf, rpm_min)?.diagram(speeds))
}

/// The smallest critical depth of `frf` over `speeds` by `method`, refined by golden-section
/// search around the best speed.
pub fn min_depth<R: Receptance>(
    m: &Machine,
    method: Method,
    frf: &R,
    speeds: &[f64],
) -> Result<CriticalPoint, ModelError> {
    let rpm_min = speeds.iter().copied().fold(f64::INFINITY, f64::min);
    let s = solver(m, method, frf, rpm_min)?;
    s.extremes(&s.diagram(speeds)).map(|e| e.min).ok_or_else(|| ModelError::Unsupported("empty speed set".into()))
}

/// The machine's open-loop lobes by every method.
#[derive(Clone, Debug)]
pub struct MachineLobes {
    /// Speeds \[rpm\].
    pub speeds: Vec<f64>,
    /// Zero-order boundary per speed.
    pub zero_order: Vec<CriticalPoint>,
    /// Multi-frequency boundary per speed.
    pub multi_frequency: Vec<CriticalPoint>,
    /// Time-periodic boundary per speed (with the kind of instability), by `discretisation`.
    pub sd: Vec<LobePoint>,
    /// The discretisation of the time-periodic boundary (converged by default).
    pub discretisation: Discretisation,
}

/// One speed where a method disagrees with the time-periodic boundary by more than [`TOLERANCE`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disagreement {
    /// Index of the speed in the grid.
    pub index: usize,
    /// Speed \[rpm\].
    pub rpm: f64,
    /// The method.
    pub method: Method,
    /// Its depth / the time-periodic boundary's.
    pub ratio: f64,
    /// The time-periodic boundary's kind of instability there.
    pub kind: Option<Bifurcation>,
}

impl MachineLobes {
    /// Compute the open-loop lobes at `speeds`, the time-periodic boundary by `discretisation`
    /// ([`Discretisation::default`]: converged); `progress(done, total)` after each
    /// time-periodic speed.
    pub fn compute(
        m: &Machine,
        speeds: &[f64],
        discretisation: Discretisation,
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<MachineLobes, ModelError> {
        m.require_modes("the lobes of the modes (zero-order, multi-frequency, semi-discretisation)")?;
        let frf = |w: f64| m.receptance(w);
        let zero_order = frequency_diagram(m, Method::ZeroOrder, &frf, speeds)?;
        let multi_frequency = frequency_diagram(m, Method::MultiFrequency, &frf, speeds)?;
        let model = m.sd_model()?;
        let lo = zero_order.iter().chain(&multi_frequency).map(|p| p.depth).fold(f64::INFINITY, f64::min);
        let o = LobeOptions {
            method: discretisation,
            start: (lo * 0.05).clamp(1e-6, 1e-3),
            growth: 1.1,
            max: 0.1,
            rel_tol: 1e-4,
        };
        let sd = lobes_with(speeds, |rpm, a| model.at(rpm, a), &o, progress)?;
        Ok(MachineLobes { speeds: speeds.to_vec(), zero_order, multi_frequency, sd, discretisation })
    }

    /// The time-periodic depth at speed index `i` \[m\] (∞ if stable up to the scan's end).
    pub fn sd_depth(&self, i: usize) -> f64 {
        self.sd[i].critical.value.unwrap_or(f64::INFINITY)
    }

    /// Every speed and method that disagrees with the time-periodic boundary by more than
    /// [`TOLERANCE`].
    pub fn disagreements(&self) -> Vec<Disagreement> {
        let mut out = Vec::new();
        for i in 0..self.speeds.len() {
            let sd = self.sd_depth(i);
            for (method, p) in
                [(Method::ZeroOrder, &self.zero_order[i]), (Method::MultiFrequency, &self.multi_frequency[i])]
            {
                let ratio = p.depth / sd;
                if sd.is_finite() && (ratio - 1.0).abs() > TOLERANCE {
                    out.push(Disagreement {
                        index: i,
                        rpm: self.speeds[i],
                        method,
                        ratio,
                        kind: self.sd[i].critical.kind(),
                    });
                }
            }
        }
        out
    }

    /// Flip (period-doubling) lobes of the time-periodic boundary: indices of the speeds where the
    /// critical multiplier is −1.
    pub fn flip_speeds(&self) -> Vec<usize> {
        (0..self.sd.len()).filter(|&i| self.sd[i].critical.kind() == Some(Bifurcation::Flip)).collect()
    }

    /// The CSV: one row per speed, the three depths \[mm\], the SD's kind, chatter frequencies.
    pub fn csv(&self) -> String {
        let mut s =
            String::from("rpm,zero_order_mm,multi_frequency_mm,sd_mm,sd_kind,zero_order_hz,multi_frequency_hz\n");
        for i in 0..self.speeds.len() {
            let mm = |d: f64| if d.is_finite() { format!("{:.6}", d * 1e3) } else { "inf".into() };
            let kind = self.sd[i].critical.kind().map_or("none", |k| k.name());
            let _ = writeln!(
                s,
                "{:.3},{},{},{},{kind},{:.3},{:.3}",
                self.speeds[i],
                mm(self.zero_order[i].depth),
                mm(self.multi_frequency[i].depth),
                mm(self.sd_depth(i)),
                self.zero_order[i].chatter_hz,
                self.multi_frequency[i].chatter_hz
            );
        }
        s
    }

    /// The report: the minimum of each method, and where the methods disagree (speed ranges,
    /// by method and side), with which to trust.
    pub fn report(&self, m: &Machine) -> String {
        let mut s = String::new();
        let min = |d: &dyn Fn(usize) -> f64| {
            (0..self.speeds.len())
                .map(|i| (d(i), self.speeds[i]))
                .fold((f64::INFINITY, f64::NAN), |a, b| if b.0 < a.0 { b } else { a })
        };
        let (zo, zr) = min(&|i| self.zero_order[i].depth);
        let (mf, mr) = min(&|i| self.multi_frequency[i].depth);
        let (sd, sr) = min(&|i| self.sd_depth(i));
        let _ = writeln!(s, "| method | smallest critical depth (mm) | at (rpm) |\n|---|---|---|");
        let _ = writeln!(s, "| zero-order (2-D) | {:.3} | {zr:.0} |", zo * 1e3);
        let _ = writeln!(s, "| multi-frequency | {:.3} | {mr:.0} |", mf * 1e3);
        let _ = writeln!(s, "| time-periodic, {} | {:.3} | {sr:.0} |", self.discretisation, sd * 1e3);
        let d = self.disagreements();
        if d.is_empty() {
            let _ = writeln!(s, "\nAll three methods agree within {:.0} % at every speed.", TOLERANCE * 100.0);
        }
        for method in [Method::ZeroOrder, Method::MultiFrequency] {
            for unsafe_side in [true, false] {
                let runs =
                    ranges(d.iter().filter(|x| x.method == method && (x.ratio > 1.0) == unsafe_side), &self.speeds);
                if runs.is_empty() {
                    continue;
                }
                let flips = d
                    .iter()
                    .any(|x| x.method == method && (x.ratio > 1.0) == unsafe_side && x.kind == Some(Bifurcation::Flip));
                let _ = writeln!(
                    s,
                    "\n{} lies more than {:.0} % {} the time-periodic boundary at {}{}. {}",
                    method.name(),
                    TOLERANCE * 100.0,
                    if unsafe_side { "ABOVE (unsafe: it claims a deeper stable cut)" } else { "below (conservative)" },
                    runs.join(", "),
                    if flips { " (flip lobes there)" } else { "" },
                    if unsafe_side {
                        "Trust the time-periodic boundary there: it keeps the time-periodic cutting force that the averaged (zero-order) or truncated (multi-frequency) forms approximate."
                    } else {
                        "The time-periodic boundary is the reference."
                    }
                );
            }
        }
        let flips = self.flip_speeds();
        if !flips.is_empty() {
            let _ = writeln!(
                s,
                "\nFlip (period-doubling) lobes of the time-periodic boundary at {}.",
                ranges_of(&flips, &self.speeds).join(", ")
            );
        }
        for w in &m.warnings {
            let _ = writeln!(s, "\nWarning: {w}");
        }
        s
    }
}

/// Speed ranges ("3000–3400 rpm (ratio up to 1.31)") of consecutive grid speeds in `items`.
fn ranges<'a>(items: impl Iterator<Item = &'a Disagreement>, grid: &[f64]) -> Vec<String> {
    let items: Vec<&Disagreement> = items.collect();
    runs(&items.iter().map(|d| d.index).collect::<Vec<_>>())
        .into_iter()
        .map(|(i, j)| {
            let worst = items
                .iter()
                .filter(|d| (i..=j).contains(&d.index))
                .map(|d| d.ratio)
                .fold(1.0, |a: f64, r| if (r - 1.0).abs() > (a - 1.0).abs() { r } else { a });
            format!("{} (ratio up to {worst:.2})", span(grid, i, j))
        })
        .collect()
}

/// Speed ranges of consecutive grid indices.
fn ranges_of(indices: &[usize], grid: &[f64]) -> Vec<String> {
    runs(indices).into_iter().map(|(i, j)| span(grid, i, j)).collect()
}

/// Runs `(first, last)` of consecutive indices (sorted input).
fn runs(indices: &[usize]) -> Vec<(usize, usize)> {
    let mut out: Vec<(usize, usize)> = Vec::new();
    for &k in indices {
        match out.last_mut() {
            Some((_, last)) if *last + 1 == k => *last = k,
            Some((_, last)) if *last == k => {}
            _ => out.push((k, k)),
        }
    }
    out
}

/// `"3000–3400 rpm"`, or `"3000 rpm"` for one speed.
fn span(grid: &[f64], i: usize, j: usize) -> String {
    if i == j { format!("{:.0} rpm", grid[i]) } else { format!("{:.0}–{:.0} rpm", grid[i], grid[j]) }
}

/// Zero-order lobes computed on measured FRFs directly (no fit), beside the zero-order lobes of
/// the machine's modes on the same band, and their difference.
#[derive(Clone, Debug)]
pub struct MeasuredLobes {
    /// Speeds \[rpm\].
    pub speeds: Vec<f64>,
    /// The chatter-frequency band both use: the measured range from 1 Hz \[Hz\].
    pub band_hz: (f64, f64),
    /// On the measured FRFs (interpolated between the measured frequencies).
    pub measured: Vec<CriticalPoint>,
    /// On the machine's modes (None: the machine has measured FRFs only).
    pub modal: Option<Vec<CriticalPoint>>,
}

/// How far the lobes of the modes are from those of the data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LobeDifference {
    /// The largest |modes/data − 1| over the speeds where both are finite.
    pub max: f64,
    /// Where \[rpm\].
    pub at_rpm: f64,
    /// modes/data − 1 there (> 0: the modes claim a deeper cut than the data).
    pub signed: f64,
    /// The RMS of modes/data − 1.
    pub rms: f64,
    /// The smallest critical depth of the data and of the modes \[m\].
    pub minima: (f64, f64),
    /// Speeds where the modes claim a cut more than 3 % deeper than the data, of `compared`.
    pub above: usize,
    /// Speeds where both are finite.
    pub compared: usize,
}

impl MeasuredLobes {
    /// Compute at `speeds` (the machine must have measured FRFs).
    pub fn compute(m: &Machine, speeds: &[f64]) -> Result<MeasuredLobes, ModelError> {
        let frf = m
            .frf
            .as_ref()
            .ok_or_else(|| ModelError::Unsupported("the machine file has no measured FRFs ([structure] frf)".into()))?;
        let data = crate::frf::MeasuredReceptance::new(frf);
        let (f0, f1) = frf.range_hz();
        let band_hz = (f0.max(1.0), f1);
        let rpm_min = speeds.iter().copied().fold(f64::INFINITY, f64::min);
        let cutter = m.cutter()?;
        let err = |e: delay_stability::zero_order::LobeError| ModelError::Unsupported(e.to_string());
        let g = |w: f64| data.receptance(w);
        let measured = ZeroOrder2d::new(g, &cutter, band_hz, rpm_min).map_err(err)?.diagram(speeds);
        let modal = if m.modes.is_empty() {
            None
        } else {
            let gm = |w: f64| m.receptance(w);
            Some(ZeroOrder2d::new(gm, &cutter, band_hz, rpm_min).map_err(err)?.diagram(speeds))
        };
        Ok(MeasuredLobes { speeds: speeds.to_vec(), band_hz, measured, modal })
    }

    /// The difference of the modes' lobes from the data's (None without modes).
    pub fn difference(&self) -> Option<LobeDifference> {
        let modal = self.modal.as_ref()?;
        let r: Vec<(f64, f64)> = self
            .measured
            .iter()
            .zip(modal)
            .filter(|(a, b)| a.depth.is_finite() && b.depth.is_finite())
            .map(|(a, b)| (a.rpm, b.depth / a.depth - 1.0))
            .collect();
        let worst = r.iter().copied().max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?;
        let min = |p: &[CriticalPoint]| p.iter().map(|x| x.depth).fold(f64::INFINITY, f64::min);
        Some(LobeDifference {
            max: worst.1.abs(),
            at_rpm: worst.0,
            signed: worst.1,
            rms: (r.iter().map(|x| x.1 * x.1).sum::<f64>() / r.len() as f64).sqrt(),
            minima: (min(&self.measured), min(modal)),
            above: r.iter().filter(|x| x.1 > 0.03).count(),
            compared: r.len(),
        })
    }

    /// The CSV: speed, depth from the data and from the modes \[mm\], chatter frequencies.
    pub fn csv(&self) -> String {
        let mm = |d: f64| if d.is_finite() { format!("{:.6}", d * 1e3) } else { "inf".into() };
        let mut s = String::from("rpm,measured_zero_order_mm,modal_zero_order_mm,measured_hz,modal_hz\n");
        for (i, p) in self.measured.iter().enumerate() {
            let q = self.modal.as_ref().map(|v| v[i]);
            let _ = writeln!(
                s,
                "{:.3},{},{},{:.3},{}",
                p.rpm,
                mm(p.depth),
                q.map_or("".into(), |q| mm(q.depth)),
                p.chatter_hz,
                q.map_or("".into(), |q| format!("{:.3}", q.chatter_hz))
            );
        }
        s
    }

    /// The report: both minima, the difference, and what it means.
    pub fn report(&self, m: &Machine) -> String {
        let mut s = String::new();
        let min = self.measured.iter().copied().min_by(|a, b| a.depth.total_cmp(&b.depth));
        if let Some(p) = min {
            let _ = writeln!(
                s,
                "Zero-order lobes on the measured FRFs ({:.0}–{:.0} Hz, no fit): smallest critical depth {:.3} mm at {:.0} rpm (chatter at {:.0} Hz).",
                self.band_hz.0,
                self.band_hz.1,
                p.depth * 1e3,
                p.rpm,
                p.chatter_hz
            );
        }
        if let Some(d) = self.difference() {
            let _ = writeln!(
                s,
                "Zero-order lobes of the modes on the same band: smallest {:.3} mm. The modes' lobes differ from the data's by at most {:.1} % ({:.0} rpm, the modes {} the data), {:.1} % RMS.{}",
                d.minima.1 * 1e3,
                d.max * 100.0,
                d.at_rpm,
                if d.signed > 0.0 { "above" } else { "below" },
                d.rms * 100.0,
                if d.above > 0 {
                    format!(
                        " At {} of {} speeds the modes claim a cut more than 3 % deeper than the measured FRFs. Lobes on measured data scatter with the FRFs' noise (on synthetic tap tests with 5 % complex noise, up to 6 % and 2 % RMS from the true modes' lobes); differences that cluster on one lobe rather than scatter point at the fit (band, orders, residual terms): use the lower of the two there.",
                        d.above, d.compared
                    )
                } else {
                    String::new()
                }
            );
        } else {
            let _ = writeln!(
                s,
                "The machine file has measured FRFs only: the multi-frequency and semi-discretisation lobes, the FMUs and the controllers need modes (chatter frf fit)."
            );
        }
        if m.is_low_immersion() {
            let _ = writeln!(
                s,
                "Warning: at a_e/D = {} the zero-order method misses the lobes of the time-periodic force (added and flip lobes) and can claim a much deeper stable cut: fit modes and use the multi-frequency or semi-discretisation lobes.",
                m.operation.immersion
            );
        }
        for n in m.frf.iter().flat_map(|f| &f.notes) {
            let _ = writeln!(s, "Note: {n}");
        }
        s
    }
}
