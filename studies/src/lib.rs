//! # studies
//!
//! Every analysis and experiment of the seed papers, behind the `chatter` command: stability
//! lobes (zero-order, open and closed loop), PSO tuning under actuator saturation, the seed's
//! tables, time-domain validation on the cores and through the FMUs (seed 000, Sections 4.4,
//! 5.5, 5.7, Appendix A).
//!
//! ## The core is generic
//!
//! [`LobeProblem`] takes any receptance closure `Fn(f64) -> Complex64` (ω in rad/s, result in
//! m/N) and the cutting constants `K_t`, α₀, Z; it returns the **exact** critical depth at any
//! speed (phase condition solved at that speed with the exact FRF, no resampling of lobe
//! curves), the envelope on a speed grid, and b_min / b_max refined by golden-section search:
//!
//! ```
//! use num_complex::Complex64;
//! use studies::{Cutting, GridOptions, LobeProblem, lobes::speed_grid};
//! let (m, k, zeta) = (30.0, 2.4e7, 0.0088);
//! let c = 2.0 * zeta * (m * k as f64).sqrt();
//! let sdof = move |w: f64| Complex64::new(k - m * w * w, c * w).inv();
//! let cutting = Cutting { kt: 760e6, alpha0: 0.4565, teeth: 4 };
//! let p = LobeProblem::new(sdof, cutting, &GridOptions::new(10.0, 2000.0, 4, 1000.0)).unwrap();
//! let d = p.diagram(&speed_grid(1000.0, 3000.0, 2001)); // 1 rpm steps
//! let ex = p.extremes(&d).unwrap();
//! let analytic = 2.0 * k * zeta * (1.0 + zeta) / (cutting.kt * cutting.alpha0);
//! assert!((ex.min.depth / analytic - 1.0).abs() < 1e-6);
//! ```
//!
//! [`loop_frf`] builds that closure from the plant core (`milling_plant::PlantParams`: receptance
//! of the enabled modes, actuator) and the controller core (`chatter_control`: the sampled
//! controller's frequency response, the same coefficients the FMU steps), as the exact closed
//! loop `Φ_cl = Φ/(1 − Φ G_a H_c)` — not the seed's Eq. 32 "effective damping" approximation.
//! [`validation`] checks the lobes against the time-domain cores ([`closed_loop::CoreLoop`],
//! decay 1 % below the boundary, growth 1 % above); [`fmu_validation`] does the same through
//! the FMUs and the Rust master, and bisects the time-domain boundary (`chatter validate`).
//!
//! ## Tuning
//!
//! [`tuning`] minimises `J = −min_{N ∈ {1000, 1050, …, 3000}} b_crit(N) [mm] + 1000·I_sat` with
//! [`pso`] (40 particles, 60 iterations, inertia 0.9 → 0.4, c1 = c2 = 2, velocity clamp 30 %),
//! over Table 3's bounds (gains on log10); `I_sat` is a precisely defined time-domain check
//! ([`tuning::SaturationCheck`]).
//!
//! ## The `chatter` binary
//!
//! ```text
//! chatter lobes  --controllers off,pid,fopid,adrc_fopid [--pid kp,ki,kd] [--fopid ..] [--adrc ..]
//! chatter tune   --structures pid,fopid,adrc_fopid --runs 10
//! chatter tables          # Table 6 and the uncontrolled Table 8 row beside the seed's values
//! chatter check  --fopid kp,ki,kd,λ,μ --seeds 10   # decay + saturation check over noise seeds
//! ```
//!
//! `tune --margin 0.1` counts a command above 90 % of u_max as exceeding (the seed's check has
//! no margin, so its optimum sits exactly on the limit for one noise realisation);
//! `tune --adrc-observer` also tunes the ADRC's ω_o and b0 (an extension: the seed fixes them,
//! and with them every ADRC-FOPID candidate saturates under the 50 N RMS disturbance).
//!
//! | module | holds |
//! |---|---|
//! | [`lobes`] | the generic lobe solver: any FRF closure `Fn(f64) -> Complex64`, cutting constants, exact per-speed critical depth, b_min/b_max |
//! | [`output`] | CSV and PNG of several diagrams on common axes |
//! | [`loop_frf`] | plant (+ controller) as an FRF: `Φ_cl = Φ/(1 − Φ G_a H_c)`; the seed and Ozsoy benchmark plants; closed-loop decay check |
//! | [`closed_loop`] | the one closed loop on the cores (plant core + controller core, Gauss–Seidel or Jacobi, any speed) |
//! | [`pso`] | particle swarm optimisation (Section 4.4), seeded, parallel over particles |
//! | [`tuning`] | Table 3 search spaces, the saturation check, the cost of Eq. 31 |
//! | [`validation`] | time-domain cross-check of the lobes with the plant and controller cores |
//! | [`fmu_validation`] | the same check through the plant and controller FMUs in the Rust FMI master |
//! | [`sd_lobes`] | semi-discretisation lobes ([`delay_stability`]): seed 000 plant by its FMU parameters, seed 002 presets; flip/Hopf |
//! | [`sd_validation`] | the SD boundary through `MillingPlant.fmu` (time-domain cutting, feed on): decay below, growth above, flip points included |
//! | [`batch`] | many short FMU runs in parallel: windows, metrics, the streamed crash-safe results CSV, Table 7 statistics |
//! | [`figures`] | line plots and heat maps on a common colour scale |
//! | [`robustness`] | seed 000 Table 7: the 19-point × 2-seed sample and its statistics |
//! | [`robustness_cases`] | the robustness sample as independent cases (`chatter plan robustness`, `run`, `collect`) |
//! | [`sweeps`] | seed 000 Figure 15: feed and engagement sweeps, harmonic balance, closed-form lobe minimum |
//! | [`sweep_cases`] | the sweeps as independent cases (`chatter plan sweep`, `run`, `collect`) |
//! | [`depth_cases`] | the depth study as independent cases (`chatter plan depth-study`, `run`, `collect`) |
//! | [`tune_cases`] | PSO runs as independent cases (`chatter plan tune`, `run`, `collect`): Table A1, tuned JSON |
//! | [`lobes_cases`] | lobe diagrams over speed chunks as independent cases (`chatter plan lobes`, `run`, `collect`) |
//! | [`map`] | seed 000 Figure 16: the speed × depth map and its growth check against the lobes |
//! | [`map_cases`] | the map as independent cases (`chatter plan map`, `run`, `collect`) |
//! | [`batch_cases`] | the one case study of a batch of independent runs (map, robustness, sweeps, depth study, lobe chunks, PSO runs) |
//! | [`cases`] | a study as independent cases: plan (manifest), run any subset anywhere (shards, Slurm arrays, Dask), collect |

pub mod afrac;
pub mod afrac_fmu;
pub mod batch;
pub mod batch_cases;
pub mod cases;
pub mod closed_loop;
pub mod decomposed;
pub mod depth_cases;
pub mod depth_study;
pub mod dsmc;
mod error;
pub mod figures;
pub mod fmu_params;
pub mod fmu_validation;
pub mod froh;
pub mod lobes;
pub mod lobes_cases;
pub mod loop_frf;
pub mod main_job;
pub mod map;
pub mod map_cases;
pub mod output;
pub mod pso;
pub mod robustness;
pub mod robustness_cases;
pub mod scenario;
pub mod sd_lobes;
pub mod sd_validation;
pub mod seed002;
pub mod sweep_cases;
pub mod sweeps;
pub mod synth;
pub mod table8;
pub mod tune_cases;
pub mod tuning;
pub mod validation;

pub use error::StudyError;
pub use lobes::{Cutting, GridOptions, LobeProblem};
