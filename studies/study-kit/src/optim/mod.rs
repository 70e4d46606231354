//! The optimisers the studies share: [`pso`] (seed 000's tuning, Section 4.4) and [`ga`] (seed
//! 001's switch-time search, Table 4). Seed 002's nonsmooth optimiser (HANSO) is part of the
//! synthesis core (`robust_synthesis::optim`), where its gradients are.

pub mod ga;
pub mod pso;
