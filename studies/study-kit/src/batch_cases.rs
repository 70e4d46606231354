//! A batch of independent runs as a case study: the one [`CaseStudy`] behind the map, the
//! robustness sample, the feed and engagement sweeps, the depth study, the lobes over speed
//! chunks and the PSO runs.
//!
//! Such a study is a fixed list of runs ("jobs") that a machine rebuilds from the study's spec,
//! plus a report over every run's output. It implements [`RunBatch`] (its spec, its job list,
//! the manifest parameters and ID of a job, one run, the report), and [`Batch`] turns it into a
//! [`CaseStudy`]: the cases are the jobs in order, a case is found again by its ID, and the
//! manifest's parameters must equal the rebuilt job's (a manifest from another version of the
//! study is refused instead of run on the wrong job). The local command and `collect` call the
//! same report function, so they write the same tables.

use crate::StudyError;
use crate::cases::{CaseStudy, Collected};
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::collections::HashMap;
use std::fmt::Debug;
use std::path::Path;

type Result<T> = std::result::Result<T, StudyError>;

/// A study that is a fixed list of independent runs and a report over their outputs.
pub trait RunBatch: Sync + Sized {
    /// The study's name in the manifest.
    const KIND: &'static str;
    /// Everything that defines the study (the command's choices).
    type Spec: Serialize + DeserializeOwned + Clone;
    /// One run, resolved (overrides, parameters).
    type Job: Sync;
    /// The manifest parameters of one run.
    type Case: Serialize + DeserializeOwned + Sync + PartialEq + Debug;
    /// The output of one run.
    type Output: Serialize + DeserializeOwned + Send;
    /// The study's spec.
    fn spec(&self) -> &Self::Spec;
    /// The study from its spec (on any machine that reads the manifest).
    fn from_spec(spec: Self::Spec) -> Result<Self>;
    /// Every run, in a fixed order.
    fn jobs(&self) -> &[Self::Job];
    /// A run's stable ID (letters, digits, `-`, `_`, `.`) and its manifest parameters.
    fn case_of(&self, job: &Self::Job) -> (String, Self::Case);
    /// Run one job.
    fn run_job(&self, job: &Self::Job) -> Result<Self::Output>;
    /// One progress line about a finished run.
    fn describe(&self, job: &Self::Job, out: &Self::Output) -> String;
    /// Write the tables and figures into `dir` from every run's output (in job order).
    fn report(&self, dir: &Path, runs: &[(&Self::Job, &Self::Output)]) -> Result<Collected>;
}

/// A [`RunBatch`] as a [`CaseStudy`].
pub struct Batch<B: RunBatch> {
    inner: B,
    index: HashMap<String, usize>,
}

impl<B: RunBatch> Batch<B> {
    /// Wrap a batch (its job IDs must be unique).
    pub fn new(inner: B) -> Result<Self> {
        let mut index = HashMap::new();
        for (k, j) in inner.jobs().iter().enumerate() {
            let id = inner.case_of(j).0;
            if index.insert(id.clone(), k).is_some() {
                return Err(StudyError::Invalid(format!("{}: two runs have the ID {id:?}", B::KIND)));
            }
        }
        Ok(Batch { inner, index })
    }

    /// The batch.
    pub fn inner(&self) -> &B {
        &self.inner
    }

    fn find(&self, id: &str, case: &B::Case) -> Result<&B::Job> {
        let job = self
            .index
            .get(id)
            .map(|&k| &self.inner.jobs()[k])
            .ok_or_else(|| StudyError::Invalid(format!("case {id}: not a run of this {} study", B::KIND)))?;
        let (_, rebuilt) = self.inner.case_of(job);
        if &rebuilt != case {
            return Err(StudyError::Invalid(format!(
                "case {id}: the manifest says {case:?} but the study rebuilds {rebuilt:?} (planned by another version?)"
            )));
        }
        Ok(job)
    }
}

impl<B: RunBatch> CaseStudy for Batch<B> {
    const KIND: &'static str = B::KIND;
    type Spec = B::Spec;
    type Case = B::Case;
    type Output = B::Output;

    fn spec(&self) -> &B::Spec {
        self.inner.spec()
    }

    fn from_spec(spec: B::Spec) -> Result<Self> {
        Batch::new(B::from_spec(spec)?)
    }

    fn cases(&self) -> Result<Vec<(String, B::Case)>> {
        Ok(self.inner.jobs().iter().map(|j| self.inner.case_of(j)).collect())
    }

    fn run_case(&self, _dir: &Path, id: &str, case: &B::Case, say: &(dyn Fn(String) + Sync)) -> Result<B::Output> {
        let job = self.find(id, case)?;
        let out = self.inner.run_job(job).map_err(|e| e.within(format!("case {id}")))?;
        say(format!("{id}: {}", self.inner.describe(job, &out)));
        Ok(out)
    }

    fn collect(&self, dir: &Path, results: &[(String, B::Case, B::Output)]) -> Result<Collected> {
        let runs = results.iter().map(|(id, c, o)| Ok((self.find(id, c)?, o))).collect::<Result<Vec<_>>>()?;
        self.inner.report(dir, &runs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cases::{Selection, collect, plan, run};

    /// Toy batch: job k doubles k; the report writes the outputs in order.
    struct Doubles {
        n: u32,
        jobs: Vec<u32>,
    }

    impl RunBatch for Doubles {
        const KIND: &'static str = "doubles";
        type Spec = u32;
        type Job = u32;
        type Case = u32;
        type Output = u64;
        fn spec(&self) -> &u32 {
            &self.n
        }
        fn from_spec(n: u32) -> Result<Self> {
            Ok(Doubles { n, jobs: (0..n).collect() })
        }
        fn jobs(&self) -> &[u32] {
            &self.jobs
        }
        fn case_of(&self, j: &u32) -> (String, u32) {
            (format!("j{j}"), *j)
        }
        fn run_job(&self, j: &u32) -> Result<u64> {
            Ok(2 * u64::from(*j))
        }
        fn describe(&self, _: &u32, o: &u64) -> String {
            o.to_string()
        }
        fn report(&self, dir: &Path, runs: &[(&u32, &u64)]) -> Result<Collected> {
            let text = runs.iter().map(|(j, o)| format!("{j}:{o}")).collect::<Vec<_>>().join(",");
            std::fs::write(dir.join("r.txt"), &text).unwrap();
            Ok(Collected { text, written: vec![] })
        }
    }

    #[test]
    fn a_batch_runs_as_cases_and_refuses_a_manifest_that_does_not_match() {
        let tmp = tempfile::tempdir().unwrap();
        let d = tmp.path();
        plan(&Batch::<Doubles>::from_spec(3).unwrap(), d).unwrap();
        run::<Batch<Doubles>>(d, &Selection::Shard { index: 2, count: 2 }).unwrap();
        run::<Batch<Doubles>>(d, &Selection::Shard { index: 1, count: 2 }).unwrap();
        assert_eq!(collect::<Batch<Doubles>>(d).unwrap().text, "0:0,1:2,2:4");
        // a case whose parameters differ from the rebuilt job is refused
        let b = Batch::<Doubles>::from_spec(3).unwrap();
        let say = |_: String| {};
        assert!(b.run_case(d, "j1", &2, &say).unwrap_err().to_string().contains("rebuilds"));
        assert!(b.run_case(d, "j9", &9, &say).is_err());
        assert_eq!(b.run_case(d, "j2", &2, &say).unwrap(), 4);
    }
}
