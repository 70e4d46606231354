//! Axes a reader can read: ticks at 1, 2, 2.5 or 5 × 10ᵏ (1, 2, 5 × 10ᵏ on a logarithmic
//! axis) labelled with exactly the decimals their step needs — "30", not "30.0"; "0.25", "0.50",
//! not a label repeated because it was cut to too few digits — and quantities scaled by an SI
//! prefix into a readable range ("x [µm]" instead of ticks of 1e-6 m).

use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, Ranged, ValueFormatter};
use std::ops::Range;

/// A numeric plotters axis, linear or logarithmic, with its own ticks and tick labels.
#[derive(Clone, Debug)]
pub struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
    ticks: Vec<f64>,
    minor: Vec<f64>,
    decimals: usize,
}

/// The "nice" step (1, 2, 2.5 or 5 × 10ᵏ) that puts at most `max_ticks` ticks on `span`.
pub fn nice_step(span: f64, max_ticks: usize) -> f64 {
    let raw = span.abs() / max_ticks.max(2).saturating_sub(1) as f64;
    if !(raw.is_finite() && raw > 0.0) {
        return 1.0;
    }
    let mag = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 2.5, 5.0, 10.0].iter().map(|m| m * mag).find(|s| *s >= raw * (1.0 - 1e-9)).unwrap_or(10.0 * mag)
}

/// The fewest decimals that write every multiple of `step` exactly (0.25 → 2, 5 → 0).
fn decimals_of(step: f64) -> usize {
    (0..=12).find(|&d| ((step * 10f64.powi(d as i32)).round() - step * 10f64.powi(d as i32)).abs() < 1e-6).unwrap_or(12)
}

impl Axis {
    /// A linear axis over `[lo, hi]` with at most `max_ticks` ticks.
    pub fn linear(lo: f64, hi: f64, max_ticks: usize) -> Axis {
        let step = nice_step(hi - lo, max_ticks);
        let first = (lo / step - 1e-9).ceil() as i64;
        let last = (hi / step + 1e-9).floor() as i64;
        let at = |k: i64| if k == 0 { 0.0 } else { k as f64 * step };
        let ticks: Vec<f64> = (first..=last).map(at).collect();
        let parts = if (step / 10f64.powf(step.log10().floor()) - 2.0).abs() < 1e-9 { 4 } else { 5 };
        let sub = step / parts as f64;
        let minor =
            ((lo / sub - 1e-9).ceil() as i64..=(hi / sub + 1e-9).floor() as i64).map(|k| k as f64 * sub).collect();
        Axis { lo, hi, log: false, ticks, minor, decimals: decimals_of(step) }
    }

    /// A linear axis whose ends are widened to the nearest ticks outside `[lo, hi]`.
    pub fn linear_rounded(lo: f64, hi: f64, max_ticks: usize) -> Axis {
        let step = nice_step(hi - lo, max_ticks);
        Axis::linear((lo / step + 1e-9).floor() * step, (hi / step - 1e-9).ceil() * step, max_ticks)
    }

    /// A logarithmic axis over `[lo, hi]` (`0 < lo < hi`): ticks at 1, 2, 5 × 10ᵏ, or at the
    /// powers of ten alone when that would be more than `max_ticks`; minor ticks at 1…9 × 10ᵏ.
    pub fn log(lo: f64, hi: f64, max_ticks: usize) -> Axis {
        let (k0, k1) = (lo.log10().floor() as i32 - 1, hi.log10().ceil() as i32 + 1);
        let within = |v: &f64| *v >= lo * (1.0 - 1e-9) && *v <= hi * (1.0 + 1e-9);
        let at = |mantissas: &[f64]| -> Vec<f64> {
            (k0..=k1).flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k))).filter(within).collect()
        };
        let mut ticks = at(&[1.0, 2.0, 5.0]);
        if ticks.len() > max_ticks {
            ticks = at(&[1.0]);
        }
        let minor = at(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]);
        Axis { lo, hi, log: true, ticks, minor, decimals: 0 }
    }

    /// A logarithmic axis whose ends are widened to the nearest 1, 2 or 5 × 10ᵏ outside `[lo, hi]`.
    pub fn log_rounded(lo: f64, hi: f64, max_ticks: usize) -> Axis {
        let steps = |k: i32| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(k));
        let (klo, khi) = (lo.log10().floor() as i32, hi.log10().floor() as i32);
        let below = steps(klo).into_iter().filter(|v| *v <= lo * (1.0 + 1e-9)).fold(lo, |_, v| v);
        let above = steps(khi).into_iter().chain([10f64.powi(khi + 1)]).find(|v| *v >= hi * (1.0 - 1e-9)).unwrap_or(hi);
        Axis::log(below, above, max_ticks)
    }

    /// The labelled ticks.
    pub fn ticks(&self) -> &[f64] {
        &self.ticks
    }

    /// The axis' ends.
    pub fn ends(&self) -> (f64, f64) {
        (self.lo, self.hi)
    }

    /// The label of a tick.
    pub fn label(&self, v: f64) -> String {
        let d = if self.log { (-(v.log10() + 1e-9).floor()).max(0.0) as usize } else { self.decimals };
        let s = format!("{v:.d$}");
        // no "-0"
        if s.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
            s.trim_start_matches('-').into()
        } else {
            s
        }
    }

    /// Where `v` is along the axis, 0 at `lo` and 1 at `hi`.
    fn fraction(&self, v: f64) -> f64 {
        if self.log {
            (v.log10() - self.lo.log10()) / (self.hi.log10() - self.lo.log10())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }
}

impl Ranged for Axis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let t = self.fraction(*v);
        let len = f64::from(limit.1 - limit.0);
        if !t.is_finite() {
            return if t > 0.0 { limit.1 } else { limit.0 };
        }
        // as plotters' own f64 axis rounds
        limit.0 + if len >= 0.0 { (len * t + 1e-3).floor() } else { (len * t - 1e-3).ceil() } as i32
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        if hint.weight().allow_light_points() { self.minor.clone() } else { self.ticks.clone() }
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

impl ValueFormatter<f64> for Axis {
    fn format_ext(&self, v: &f64) -> String {
        self.label(*v)
    }
}

/// What a y axis shows: the data times `scale`, under `label` ("x [µm]" for metres × 1e6).
#[derive(Clone, Debug, PartialEq)]
pub struct Quantity {
    /// Factor from the data to the plotted values.
    pub scale: f64,
    /// Axis label, with the unit in brackets.
    pub label: String,
}

impl Quantity {
    /// `name [unit]`, unscaled.
    pub fn new(name: &str, unit: &str, scale: f64) -> Quantity {
        let label = if unit.is_empty() { name.to_string() } else { format!("{name} [{unit}]") };
        Quantity { scale, label }
    }

    /// `name [unit]` with the values brought into 1…1000 for data of magnitude `extent`: by an
    /// SI prefix where the unit takes one (m → µm, N → kN), else by a power of ten in the label
    /// (`[10^-6 rpm]`); unscaled when the values are already within 0.01…10000.
    pub fn scaled(name: &str, unit: &str, extent: f64) -> Quantity {
        if !(extent.is_finite() && extent > 0.0) || (1e-2..1e4).contains(&extent) {
            return Quantity::new(name, unit, 1.0);
        }
        let e3 = ((extent.log10() / 3.0).floor() as i32 * 3).clamp(-12, 9);
        let scale = 10f64.powi(-e3);
        let prefix = match e3 {
            -12 => "p",
            -9 => "n",
            -6 => "µ",
            -3 => "m",
            3 => "k",
            6 => "M",
            9 => "G",
            _ => "",
        };
        if takes_prefix(unit) && !prefix.is_empty() {
            Quantity::new(name, &format!("{prefix}{unit}"), scale)
        } else if unit.is_empty() {
            Quantity { scale, label: format!("{name} [×10^{e3}]") }
        } else {
            Quantity::new(name, &format!("10^{e3} {unit}"), scale)
        }
    }
}

/// Does `unit` take an SI prefix as a whole: does it start with a coherent SI symbol that has
/// no prefix of its own (m, m/s, N, N/m, rad/s; not mm, kg, rpm, 1/s)?
pub fn takes_prefix(unit: &str) -> bool {
    let first = unit.split(['/', '.', '*', '·', '^', ' ']).next().unwrap_or("");
    let first = first.trim_end_matches(|c: char| c.is_ascii_digit());
    ["m", "s", "N", "Pa", "Hz", "J", "W", "V", "A", "rad", "Ω", "ohm"].contains(&first)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(a: &Axis) -> Vec<String> {
        a.ticks().iter().map(|v| a.label(*v)).collect()
    }

    #[test]
    fn linear_ticks_are_nice_and_labelled_with_the_decimals_of_their_step() {
        assert_eq!(labels(&Axis::linear(0.0, 30.0, 8)), ["0", "5", "10", "15", "20", "25", "30"]);
        assert_eq!(labels(&Axis::linear(-36.0, 36.0, 9)), ["-30", "-20", "-10", "0", "10", "20", "30"]);
        assert_eq!(
            labels(&Axis::linear(1000.0, 3000.0, 11)),
            ["1000", "1200", "1400", "1600", "1800", "2000", "2200", "2400", "2600", "2800", "3000"]
        );
        assert_eq!(labels(&Axis::linear(0.0, 1.0, 5)), ["0.00", "0.25", "0.50", "0.75", "1.00"]);
        // tiny values (a displacement in metres) keep distinct labels
        let tiny = labels(&Axis::linear(-3e-6, 3e-6, 7));
        let distinct: std::collections::BTreeSet<&String> = tiny.iter().collect();
        assert_eq!(distinct.len(), tiny.len(), "{tiny:?}");
        assert_eq!(tiny[0], "-0.000003");
        // rounding the ends out to ticks
        assert_eq!(Axis::linear_rounded(113.0, 171.0, 8).ends(), (110.0, 180.0));
    }

    #[test]
    fn log_ticks_are_one_two_five() {
        assert_eq!(labels(&Axis::log(1.1, 130.0, 10)), ["2", "5", "10", "20", "50", "100"]);
        assert_eq!(labels(&Axis::log(0.04, 0.6, 10)), ["0.05", "0.1", "0.2", "0.5"]);
        assert_eq!(labels(&Axis::log(1e-3, 1e3, 5)), ["0.001", "0.01", "0.1", "1", "10", "100", "1000"]);
        assert_eq!(Axis::log_rounded(1.17, 137.0, 10).ends(), (1.0, 200.0));
        assert_eq!(Axis::log_rounded(0.03, 4.0, 10).ends(), (0.02, 5.0));
        let a = Axis::log(1.0, 100.0, 10);
        assert_eq!(a.map(&10.0, (0, 200)), 100);
    }

    #[test]
    fn quantities_take_an_si_prefix_or_a_power_of_ten() {
        assert_eq!(Quantity::scaled("plant.x", "m", 3.6e-5), Quantity { scale: 1e6, label: "plant.x [µm]".into() });
        assert_eq!(Quantity::scaled("controller.u", "N", 27.0).label, "controller.u [N]");
        assert_eq!(Quantity::scaled("k", "N/m", 2.4e7).label, "k [MN/m]");
        assert_eq!(Quantity::scaled("d", "mm", 2e-5).label, "d [10^-6 mm]");
        assert_eq!(Quantity::scaled("ratio", "", 2e-5).label, "ratio [×10^-6]");
        assert!(!takes_prefix("kg") && !takes_prefix("rpm") && !takes_prefix("1/s") && takes_prefix("m/s"));
    }
}
