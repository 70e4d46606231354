//! `chatter plan | run | collect`: a study as independent cases, for running anywhere
//! (shards, Slurm array jobs, Dask tasks); see `study_kit::cases`.

use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand};
use seed000::depth_study::DepthCases;
use seed000::lobes_cases::LobesCases;
use seed000::main_job::MainJob;
use seed000::map::MapCases;
use seed000::robustness::RobustnessCases;
use seed000::sweeps::SweepCases;
use seed000::tune_cases::TuneCases;
use std::path::{Path, PathBuf};
use study_kit::cases::{self, CaseStudy, Selection};

#[derive(Subcommand)]
pub enum PlanCmd {
    /// The main job (Table 5): one case per controller × noise seed; `--out` is the study folder.
    MainJob(crate::main_job::MainJobArgs),
    /// The robustness sample (Table 7): one case per controller × point × noise seed; `--out`
    /// is the study folder.
    Robustness(seed000::robustness::RobustnessSpec),
    /// The speed × depth map (Figure 16): one case per controller × speed × depth; `--out` is
    /// the study folder.
    Map(seed000::map::MapSpec),
    /// The feed or engagement sweep (Figure 15): one case per controller × value; `--out` is
    /// the study folder.
    Sweep(seed000::sweeps::SweepSpec),
    /// The depth study (Figures 9–10): one case per controller × depth; `--out` is the study
    /// folder.
    DepthStudy(seed000::depth_study::DepthSpec),
    /// Lobe diagrams: one case per chunk of `--chunk` speeds (every controller); `--out` is the
    /// study folder (lobes.csv, lobes.png).
    Lobes(crate::lobes::LobesPlanArgs),
    /// PSO tuning: one case per structure × independent run (its seed); `--out` is the study
    /// folder (table_a1.md, tuned_*.json, tuning_runs.csv).
    Tune(crate::tune::TuneArgs),
}

#[derive(Args)]
pub struct RunArgs {
    /// The study folder (with manifest.json, from `chatter plan`).
    pub dir: PathBuf,
    /// Run shard I of N (cases k with k mod N = I − 1).
    #[arg(long, conflicts_with_all = ["index", "case", "slurm_array"])]
    pub shard: Option<String>,
    /// Run the case at this 0-based position of the manifest.
    #[arg(long, conflicts_with_all = ["case", "slurm_array"])]
    pub index: Option<usize>,
    /// Run the cases with these IDs (comma-separated).
    #[arg(long, value_delimiter = ',', conflicts_with = "slurm_array")]
    pub case: Vec<String>,
    /// Run the case at position $SLURM_ARRAY_TASK_ID (a Slurm array job; see studies/slurm/).
    #[arg(long)]
    pub slurm_array: bool,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

#[derive(Args)]
pub struct CollectArgs {
    /// The study folder.
    pub dir: PathBuf,
}

pub fn plan(cmd: &PlanCmd) -> Result<()> {
    match cmd {
        PlanCmd::MainJob(a) => {
            let job = MainJob::new(a.spec()?)?;
            let n = cases::plan(&job, &a.out)?;
            println!("planned {n} cases of {} in {}", MainJob::KIND, a.out.display());
        }
        PlanCmd::Robustness(s) => planned(&RobustnessCases::from_spec(s.resolved())?, &s.out)?,
        PlanCmd::Map(s) => planned(&MapCases::from_spec(s.resolved())?, &s.out)?,
        PlanCmd::Sweep(s) => planned(&SweepCases::from_spec(s.resolved()?)?, &s.out)?,
        PlanCmd::DepthStudy(s) => planned(&DepthCases::from_spec(s.resolved())?, &s.out)?,
        PlanCmd::Lobes(a) => planned(&LobesCases::from_spec(a.spec()?)?, &a.lobes.out)?,
        PlanCmd::Tune(a) => planned(&TuneCases::from_spec(a.spec()?)?, &a.out)?,
    }
    Ok(())
}

fn planned<S: CaseStudy>(study: &S, out: &Path) -> Result<()> {
    let n = cases::plan(study, out)?;
    println!("planned {n} cases of {} in {}", S::KIND, out.display());
    Ok(())
}

fn selection(a: &RunArgs) -> Result<Selection> {
    Ok(if let Some(s) = &a.shard {
        s.parse()?
    } else if let Some(k) = a.index {
        Selection::Index(k)
    } else if !a.case.is_empty() {
        Selection::Ids(a.case.clone())
    } else if a.slurm_array {
        let v = std::env::var("SLURM_ARRAY_TASK_ID").context("--slurm-array: SLURM_ARRAY_TASK_ID is not set")?;
        Selection::Index(v.trim().parse().with_context(|| format!("SLURM_ARRAY_TASK_ID={v:?}"))?)
    } else {
        Selection::All
    })
}

fn run_as<S: CaseStudy>(dir: &Path, sel: &Selection) -> Result<()> {
    let s = cases::run::<S>(dir, sel)?;
    println!("{} cases run, {} already done, {} failed", s.ran.len(), s.skipped.len(), s.failed.len());
    if let Some((id, e)) = s.failed.first() {
        bail!("{} cases failed (first: {id}: {e}); the finished ones are kept", s.failed.len());
    }
    Ok(())
}

pub fn run(a: &RunArgs) -> Result<()> {
    if let Some(n) = a.threads {
        rayon::ThreadPoolBuilder::new().num_threads(n).build_global().context("configuring the thread pool")?;
    }
    let sel = selection(a)?;
    match cases::kind(&a.dir)?.as_str() {
        MainJob::KIND => run_as::<MainJob>(&a.dir, &sel),
        RobustnessCases::KIND => run_as::<RobustnessCases>(&a.dir, &sel),
        MapCases::KIND => run_as::<MapCases>(&a.dir, &sel),
        SweepCases::KIND => run_as::<SweepCases>(&a.dir, &sel),
        DepthCases::KIND => run_as::<DepthCases>(&a.dir, &sel),
        LobesCases::KIND => run_as::<LobesCases>(&a.dir, &sel),
        TuneCases::KIND => run_as::<TuneCases>(&a.dir, &sel),
        other => bail!("{}: unknown study {other:?}", a.dir.display()),
    }
}

pub fn collect(a: &CollectArgs) -> Result<()> {
    let collected = match cases::kind(&a.dir)?.as_str() {
        MainJob::KIND => cases::collect::<MainJob>(&a.dir)?,
        RobustnessCases::KIND => cases::collect::<RobustnessCases>(&a.dir)?,
        MapCases::KIND => cases::collect::<MapCases>(&a.dir)?,
        SweepCases::KIND => cases::collect::<SweepCases>(&a.dir)?,
        DepthCases::KIND => cases::collect::<DepthCases>(&a.dir)?,
        LobesCases::KIND => cases::collect::<LobesCases>(&a.dir)?,
        TuneCases::KIND => cases::collect::<TuneCases>(&a.dir)?,
        other => bail!("{}: unknown study {other:?}", a.dir.display()),
    };
    println!("{}", collected.text);
    println!(
        "wrote {}",
        collected.written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join("\n      ")
    );
    Ok(())
}
