//! `chatter lobes`: lobe diagrams for several controllers on common axes.

use crate::common::*;
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;
use studies::lobes::speed_grid;
use studies::output::{Series, plot_png, write_csv};

#[derive(Args)]
pub struct LobesArgs {
    /// Plant: `seed` (Tables 1, 4) or `ozsoy` (Section 5.7 benchmark).
    #[arg(long, default_value = "seed")]
    pub plant: String,
    /// Workpiece modes (1 or 3: the seed's higher modes at 895.8 and 2499.8 Hz).
    #[arg(long, default_value_t = 1)]
    pub modes: u32,
    /// Controllers to draw.
    #[arg(long, value_delimiter = ',', default_value = "off,pid,fopid,adrc_fopid")]
    pub controllers: Vec<String>,
    #[command(flatten)]
    pub gains: GainArgs,
    /// Lowest speed [rpm].
    #[arg(long, default_value_t = 1000.0)]
    pub rpm_min: f64,
    /// Highest speed [rpm].
    #[arg(long, default_value_t = 3000.0)]
    pub rpm_max: f64,
    /// Number of speeds (2001 over 1000–3000 rpm = 1 rpm steps).
    #[arg(long, default_value_t = 2001)]
    pub points: usize,
    /// Output directory.
    #[arg(long, default_value = "stability-out")]
    pub out: PathBuf,
}

pub fn lobes(a: &LobesArgs) -> Result<()> {
    let mut plant = plant_by_name(&a.plant)?;
    plant.workpiece.modes = a.modes;
    plant.validate().map_err(anyhow::Error::msg)?;
    std::fs::create_dir_all(&a.out)?;
    let rpm = speed_grid(a.rpm_min, a.rpm_max, a.points);
    let mut series = Vec::new();
    for name in &a.controllers {
        let c = controller(structure_by_name(name)?, &a.gains)?;
        let t = Instant::now();
        let (d, ex) = diagram(&plant, &c, &rpm)?;
        let secs = t.elapsed().as_secs_f64();
        let (stable, sat) = loop_checks(&plant, &c)?;
        println!("{name:>11}: {}  [{} speeds in {secs:.2} s]", fmt_ex(&ex), rpm.len());
        println!("{:>11}  closed loop stable without cutting: {stable}; saturation check exceeded: {sat}", "");
        series.push(Series { name: name.clone(), points: d });
    }
    let csv = a.out.join("lobes.csv");
    let png = a.out.join("lobes.png");
    write_csv(&csv, &series)?;
    plot_png(&png, &format!("Stability lobes, {} plant", a.plant), &series, 1200, 800)?;
    println!("wrote {} and {}", csv.display(), png.display());
    Ok(())
}
