//! `chatter tables`: Table 6, Table 8 (uncontrolled row, our controllers' rows, the
//! equivalent-damping reading of every row).

use crate::common::*;
use crate::lobes::gains_title;
use anyhow::Result;
use chatter_control::{ControllerParams, Structure};
use clap::Args;
use delay_stability::zero_order::speed_grid;
use seed000::loop_frf;
use std::fmt::Write as _;
use std::path::PathBuf;
use study_kit::output::{Series, plot_png, write_csv};

#[derive(Args)]
pub struct TablesArgs {
    #[command(flatten)]
    pub gains: GainArgs,
    /// Number of speeds over each range.
    #[arg(long, default_value_t = 2001)]
    pub points: usize,
    /// Output directory (CSV/PNG of the diagrams and tables.md).
    #[arg(long, default_value = "stability-out")]
    pub out: PathBuf,
}

pub fn tables(a: &TablesArgs) -> Result<()> {
    std::fs::create_dir_all(&a.out)?;
    let mut md = String::new();
    // Table 6: seed plant, 1000–3000 rpm
    let plant = loop_frf::seed_plant();
    let rpm = speed_grid(1000.0, 3000.0, a.points);
    let seed6 = [("off", 1.00, 23.17), ("pid", 1.50, 27.50), ("fopid", 2.00, 30.83), ("adrc_fopid", 2.67, 37.67)];
    let _ = writeln!(
        md,
        "Table 6 (seed plant: Tables 1 and 4, 1000–3000 rpm, {} speeds; gains: Table 2 unless given)\n\n| scenario | b_min ours (mm) | at rpm | b_min seed (mm) | b_max ours (mm) | at rpm | b_max seed (mm) | loop stable w/o cutting | saturation check: exceeded (samples), peak u |\n|---|---|---|---|---|---|---|---|---|",
        a.points
    );
    let mut series = Vec::new();
    for (name, bmin, bmax) in seed6 {
        let c = controller(structure_by_name(name)?, &a.gains)?;
        let (d, ex) = diagram(&plant, &c, &rpm)?;
        let (stable, sat) = loop_checks(&plant, &c)?;
        let _ = writeln!(
            md,
            "| {name} | {:.3} | {:.1} | {bmin:.2} | {:.3} | {:.1} | {bmax:.2} | {stable} | {sat} |",
            ex.min.depth * 1e3,
            ex.min.rpm,
            ex.max.depth * 1e3,
            ex.max.rpm
        );
        series.push(Series { name: name.to_string(), points: d });
    }
    write_csv(&a.out.join("table6_lobes.csv"), &series)?;
    let title = format!("Table 6: stability lobes of the seed 000 plant (Tables 1, 4)\n{}", gains_title(&a.gains));
    plot_png(&a.out.join("table6_lobes.png"), &title, &series, 1200, 800)?;
    // analytic SDOF check of the open loop
    let cut = loop_frf::cutting_of(&plant);
    let m = plant.workpiece.first;
    let analytic = 2.0 * m.stiffness * m.damping_ratio * (1.0 + m.damping_ratio) / (cut.kt * cut.alpha0);
    let _ = writeln!(
        md,
        "\nOpen-loop analytic minimum 2kζ(1+ζ)/(K_t α₀) = {:.4} mm (α₀ = {:.5}).\n",
        analytic * 1e3,
        cut.alpha0
    );
    // Table 8 uncontrolled row: Ozsoy plant
    let oz = loop_frf::ozsoy_plant();
    let _ = writeln!(
        md,
        "Table 8, uncontrolled row (Ozsoy et al. plant: 142.1 Hz, ζ 0.88 %, k 2.43e7 N/m, Z = 4, half immersion)\n\n| speed range (rpm) | b_crit ours (mm) | at rpm | b_crit seed (mm) | b_crit [8] (mm) | Δ vs seed % | b_max ours (mm) | at rpm | b_max seed (mm) | b_max [8] (mm) | Δ vs seed % |\n|---|---|---|---|---|---|---|---|---|---|---|"
    );
    let off = ControllerParams { structure: Structure::Off, ..ControllerParams::paper_table2() };
    let mut oz_series = Vec::new();
    let mut notes = Vec::new();
    for (lo, hi) in [(1000.0, 3000.0), (500.0, 3000.0)] {
        let n = ((hi - lo) as usize).max(a.points - 1) + 1;
        let r = speed_grid(lo, hi, n);
        let (d, ex) = diagram(&oz, &off, &r)?;
        let (b, bx) = (ex.min.depth * 1e3, ex.max.depth * 1e3);
        let _ = writeln!(
            md,
            "| {lo:.0}–{hi:.0} | {b:.3} | {:.1} | 1.24 | 1.2 | {:+.2} | {bx:.2} | {:.1} | 43.94 | 45.1 | {:+.2} |",
            ex.min.rpm,
            100.0 * (b / 1.24 - 1.0),
            ex.max.rpm,
            100.0 * (bx / 43.94 - 1.0)
        );
        let grid_max = d.iter().map(|c| c.depth).fold(0.0, f64::max) * 1e3;
        notes.push(format!(
            "{lo:.0}–{hi:.0} rpm: largest depth on the {}-speed grid itself {grid_max:.3} mm (refined cusp {bx:.3} mm)",
            r.len()
        ));
        if lo < 600.0 {
            oz_series.push(Series { name: "uncontrolled".into(), points: d });
        }
    }
    for n in notes {
        let _ = writeln!(md, "\n{n}");
    }
    table8_rows(a, &oz, &mut md)?;
    write_csv(&a.out.join("table8_ozsoy_lobes.csv"), &oz_series)?;
    let title = "Table 8: stability lobes of the Ozsoy et al. benchmark plant, uncontrolled";
    plot_png(&a.out.join("table8_ozsoy_lobes.png"), title, &oz_series, 1200, 800)?;
    // Figure 18: the Table 8 lobes our controllers fill, on the uncontrolled one's 500–3000 rpm grid
    let grid: Vec<f64> = oz_series[0].points.iter().map(|p| p.rpm).collect();
    let mut fig18 = oz_series.clone();
    for name in ["pid", "fopid", "adrc_fopid"] {
        let c = controller(structure_by_name(name)?, &a.gains)?;
        fig18.push(Series { name: name.into(), points: diagram(&oz, &c, &grid)?.0 });
    }
    write_csv(&a.out.join("fig18_ozsoy_lobes.csv"), &fig18)?;
    plot_png(
        &a.out.join("fig18_ozsoy_lobes.png"),
        &format!("Table 8 lobes of the Ozsoy et al. benchmark plant (cf. seed Figure 18)\n{}", gains_title(&a.gains)),
        &fig18,
        1200,
        800,
    )?;
    std::fs::write(a.out.join("tables.md"), &md)?;
    println!("{md}");
    println!("wrote {}", a.out.join("tables.md").display());
    Ok(())
}

/// Table 8: our PID, FOPID and ADRC-FOPID rows on the Ozsoy plant, and every seed row read as
/// equivalent damping (`seed000::table8`).
fn table8_rows(a: &TablesArgs, oz: &milling_plant::PlantParams, md: &mut String) -> Result<()> {
    use seed000::table8::{SEED_TABLE8, equivalent_damping};
    let _ = writeln!(
        md,
        "\nTable 8, the rows our controllers fill (Ozsoy plant, exact closed-loop lobes, gains: --preset {}; the seed's gains for this plant are not given)\n\n| controller | range (rpm) | b_crit ours (mm) | b_crit seed (mm) | b_max ours (mm) | b_max seed (mm) |\n|---|---|---|---|---|---|",
        a.gains.preset
    );
    for (name, label) in [("pid", "PID"), ("fopid", "FOPID"), ("adrc_fopid", "ADRC-FOPID")] {
        let c = controller(structure_by_name(name)?, &a.gains)?;
        let seed = SEED_TABLE8.iter().find(|r| r.0 == label).expect("row");
        for (lo, hi) in [(1000.0, 3000.0), (500.0, 3000.0)] {
            let n = ((hi - lo) as usize).max(a.points - 1) + 1;
            match seed000::table8::controller_row(oz, &c, lo, hi, n) {
                Some(ex) => {
                    let _ = writeln!(
                        md,
                        "| {label} | {lo:.0}–{hi:.0} | {:.3} | {:.2} | {:.2} | {:.2} |",
                        ex.min.depth * 1e3,
                        seed.1,
                        ex.max.depth * 1e3,
                        seed.3
                    );
                }
                None => {
                    let _ = writeln!(md, "| {label} | {lo:.0}–{hi:.0} | – | {:.2} | – | {:.2} |", seed.1, seed.3);
                }
            }
        }
    }
    let _ = writeln!(
        md,
        "\nTable 8 read as equivalent damping: each row's b_crit = 2kζ(1+ζ)/(K_t α₀) gives ζ_eq, the peak receptance 1/(2kζ√(1−ζ²)) (cf. Figure 17: 2.34 µm/N uncontrolled, 0.9–1.0 for the six benchmark controllers, 0.69 FOPID, 0.40 ADRC-FOPID) and the exact lobes' b_max over 1000–3000 rpm\n\n| row | b_crit seed (mm) | ζ_eq | predicted peak (µm/N) | predicted b_max (mm) | b_max seed (mm) | b_max [8] (mm) |\n|---|---|---|---|---|---|---|"
    );
    for (name, b, _, bmax, bmax8) in SEED_TABLE8 {
        let e = equivalent_damping(oz, b * 1e-3, 1000.0, 3000.0, a.points);
        let ref8 = if bmax8.is_nan() { "novel".to_string() } else { format!("{bmax8:.2}") };
        let _ = writeln!(
            md,
            "| {name} | {b:.2} | {:.5} | {:.3} | {:.2} | {bmax:.2} | {ref8} |",
            e.zeta,
            e.peak * 1e6,
            e.lobes.max.depth * 1e3
        );
    }
    Ok(())
}
