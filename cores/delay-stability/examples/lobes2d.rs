//! Lobes of a 2-D machine as CSV, for cross-checks (`tests/python/test_lobes_2d.py`):
//!
//! ```text
//! cargo run --release -p delay-stability --example lobes2d -- \
//!     --teeth 2 --kt 6e8 --kr 2e8 --immersion 1 --milling up \
//!     --mode x:922:1.342e6:0.011 --mode y:922:1.342e6:0.011 \
//!     --band 50:5000 --rpm 5000:25000:201 [--method zo|mf] [--harmonics h]
//! ```
//!
//! * `--mode AXIS:HZ:K:ZETA`: a mode along AXIS = `x`, `y` or `aDEG` (the direction DEG degrees
//!   from +x towards +y: a cross-coupled mode) of natural frequency HZ, stiffness K \[N/m\] and
//!   damping ratio ZETA (mass-normalised shape `ω_n/√K`);
//! * `--residue AXIS:HZ:ZETA:RE:IM`: a mode of the direct FRF of AXIS given by its residue
//!   `R = RE + i·IM` \[m/N\]: `G = R/(iω − s) + R̄/(iω − s̄)`, `s = −ζω_n + iω_n√(1 − ζ²)` (the
//!   form of Altintas, *Manufacturing Automation*, ch. 2);
//! * `--immersion a_e/D`, `--milling up|down`; K_t, K_r in N/m²;
//! * `--rpm LO:HI:N` speeds, `--band LO:HI` chatter frequencies \[Hz\].
//!
//! Prints `rpm,depth_m,chatter_hz` (depth `inf` where no root), then `# b_min` and `# b_max`
//! lines (refined by golden-section search).

use delay_stability::frequency::{Lobes, ModalReceptance, MultiFrequency, Receptance, ZeroOrder2d};
use delay_stability::milling::{Cutter, ForceLaw, Milling, ModeShape};
use delay_stability::zero_order::{CriticalPoint, speed_grid};
use nalgebra::Matrix2;
use num_complex::Complex64;
use std::f64::consts::PI;

/// A residue-form mode of one direct FRF.
struct Residue {
    axis: usize,
    s: Complex64,
    r: Complex64,
}

/// Modes plus residue terms.
struct Machine {
    modal: Option<ModalReceptance>,
    residues: Vec<Residue>,
}

impl Receptance for Machine {
    fn receptance(&self, w: f64) -> Matrix2<Complex64> {
        let mut g = self.modal.as_ref().map_or_else(Matrix2::zeros, |m| m.receptance(w));
        let iw = Complex64::new(0.0, w);
        for q in &self.residues {
            g[(q.axis, q.axis)] += q.r / (iw - q.s) + q.r.conj() / (iw - q.s.conj());
        }
        g
    }
}

fn nums(s: &str, n: usize, what: &str) -> Result<Vec<f64>, String> {
    let v: Result<Vec<f64>, _> = s.split(':').map(str::parse::<f64>).collect();
    let v = v.map_err(|e| format!("{what} {s}: {e}"))?;
    if v.len() != n {
        return Err(format!("{what} {s}: expected {n} numbers separated by ':'"));
    }
    Ok(v)
}

fn axis(s: &str) -> Result<(usize, &str), String> {
    match s.split_once(':') {
        Some(("x", rest)) => Ok((0, rest)),
        Some(("y", rest)) => Ok((1, rest)),
        _ => Err(format!("{s}: must start with x: or y:")),
    }
}

/// The unit direction of `x`, `y` or `aDEG`.
fn direction(s: &str) -> Result<([f64; 2], &str), String> {
    if let Some((a, rest)) = s.split_once(':')
        && let Some(deg) = a.strip_prefix('a')
    {
        let t = deg.parse::<f64>().map_err(|e| format!("{s}: {e}"))?.to_radians();
        return Ok(([t.cos(), t.sin()], rest));
    }
    let (ax, rest) = axis(s)?;
    Ok((if ax == 0 { [1.0, 0.0] } else { [0.0, 1.0] }, rest))
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (mut teeth, mut kt, mut kr, mut imm, mut milling) = (2u32, 6e8, 2e8, 1.0, Milling::Down);
    let (mut band, mut rpm, mut method, mut harmonics) = ((10.0, 5000.0), (5000.0, 25000.0, 201usize), "zo", None);
    let (mut modes, mut residues): (Vec<ModeShape>, Vec<Residue>) = (Vec::new(), Vec::new());
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let val = it.next().ok_or_else(|| format!("{flag} needs a value"))?;
        let num = |v: &str| v.parse::<f64>().map_err(|e| format!("{flag} {v}: {e}"));
        match flag.as_str() {
            "--teeth" => teeth = val.parse().map_err(|e| format!("--teeth {val}: {e}"))?,
            "--kt" => kt = num(val)?,
            "--kr" => kr = num(val)?,
            "--immersion" => imm = num(val)?,
            "--milling" => {
                milling = match val.as_str() {
                    "up" => Milling::Up,
                    "down" => Milling::Down,
                    _ => return Err(format!("--milling {val}: up or down")),
                }
            }
            "--band" => {
                let v = nums(val, 2, "--band")?;
                band = (v[0], v[1]);
            }
            "--rpm" => {
                let v = nums(val, 3, "--rpm")?;
                rpm = (v[0], v[1], v[2] as usize);
            }
            "--method" => method = if val == "mf" { "mf" } else { "zo" },
            "--harmonics" => harmonics = Some(val.parse::<usize>().map_err(|e| format!("--harmonics {val}: {e}"))?),
            "--mode" => {
                let (dir, rest) = direction(val)?;
                let v = nums(rest, 3, "--mode")?;
                modes.push(ModalReceptance::mode(v[0], v[1], v[2], dir));
            }
            "--residue" => {
                let (ax, rest) = axis(val)?;
                let v = nums(rest, 4, "--residue")?;
                let wn = 2.0 * PI * v[0];
                let s = Complex64::new(-v[1] * wn, wn * (1.0 - v[1] * v[1]).sqrt());
                residues.push(Residue { axis: ax, s, r: Complex64::new(v[2], v[3]) });
            }
            _ => return Err(format!("unknown option {flag}")),
        }
    }
    let modal = if modes.is_empty() { None } else { Some(ModalReceptance::new(&modes).map_err(|e| e.to_string())?) };
    let machine = Machine { modal, residues };
    let (e, x) = Cutter::immersion(imm, milling);
    let cutter = Cutter::new(teeth, e, x, kt, kr, ForceLaw::Linear).map_err(|e| e.to_string())?;
    let speeds = speed_grid(rpm.0, rpm.1, rpm.2);
    let (diagram, ex): (Vec<CriticalPoint>, _) = if method == "mf" {
        let mf = match harmonics {
            Some(h) => MultiFrequency::with_harmonics(machine, &cutter, band, rpm.0, h),
            None => MultiFrequency::new(machine, &cutter, band, rpm.0),
        }
        .map_err(|e| e.to_string())?;
        let d = mf.diagram(&speeds);
        let ex = mf.extremes(&d);
        (d, ex)
    } else {
        let zo = ZeroOrder2d::new(machine, &cutter, band, rpm.0).map_err(|e| e.to_string())?;
        let d = zo.diagram(&speeds);
        let ex = zo.extremes(&d);
        (d, ex)
    };
    println!("rpm,depth_m,chatter_hz");
    for p in &diagram {
        println!("{},{:e},{}", p.rpm, p.depth, p.chatter_hz);
    }
    if let Some(ex) = ex {
        println!("# b_min,{},{:e},{}", ex.min.rpm, ex.min.depth, ex.min.chatter_hz);
        println!("# b_max,{},{:e},{}", ex.max.rpm, ex.max.depth, ex.max.chatter_hz);
    }
    Ok(())
}

fn main() {
    if let Err(e) = run() {
        eprintln!("lobes2d: {e}");
        std::process::exit(2);
    }
}
