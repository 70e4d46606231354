//! # seed000: the studies of seed 000 (Soufi et al., ADRC-FOPID)
//!
//! Stability lobes of the seed plant (zero-order, open and closed loop; semi-discretisation),
//! PSO tuning under actuator saturation, the seed's tables, time-domain validation on the cores
//! and through the FMUs (Sections 4.4, 5.5–5.7, Appendix A), the Table 5 main job.
//!
//! ## Lobes
//!
//! The zero-order solver [`delay_stability::zero_order::LobeProblem`] (in the stability core) takes any receptance closure `Fn(f64) -> Complex64` (ω in rad/s, result in
//! m/N) and the cutting constants `K_t`, α₀, Z; it returns the **exact** critical depth at any
//! speed (phase condition solved at that speed with the exact FRF, no resampling of lobe
//! curves), the envelope on a speed grid, and b_min / b_max refined by golden-section search:
//!
//! ```
//! use num_complex::Complex64;
//! use delay_stability::zero_order::{Cutting, GridOptions, LobeProblem, speed_grid};
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
//! The command line is the `chatter` crate (`chatter --help`).
//!
//! | module | holds |
//! |---|---|
//! | [`loop_frf`] | plant (+ controller) as an FRF: `Φ_cl = Φ/(1 − Φ G_a H_c)`; the seed and Ozsoy benchmark plants; closed-loop decay check |
//! | [`closed_loop`] | the one closed loop on the cores (plant core + controller core, Gauss–Seidel or Jacobi, any speed) |
//! | [`tuning`] | Table 3 search spaces, the saturation check, the cost of Eq. 31 |
//! | [`tune_cases`] | PSO runs as independent cases (`chatter plan tune`, `run`, `collect`): Table A1, tuned JSON |
//! | [`validation`] | time-domain cross-check of the lobes with the plant and controller cores |
//! | [`fmu_validation`] | the same check through the plant and controller FMUs in the Rust FMI master |
//! | [`lobes_cases`] | lobe diagrams over speed chunks as independent cases (`chatter plan lobes`, `run`, `collect`) |
//! | [`table8`] | the Ozsoy benchmark plant: the uncontrolled row of Table 8, the equivalent-damping analysis |
//! | [`sd_lobes`] | semi-discretisation lobes ([`delay_stability`]) of the seed 000 plant by its FMU parameters |
//! | [`sd_validation`] | the SD boundary through `MillingPlant.fmu` (time-domain cutting, feed on): decay below, growth above, flip points included |
//! | [`scenario`] | the shipped closed loop (`ClosedLoop.ssp`), which component is which, the gain presets |
//! | [`main_job`] | Table 5 and Figures 6–7: the nominal scenario over all controllers and noise seeds, as cases |
//! | [`batch`] | many short FMU runs in parallel: windows, metrics, the streamed crash-safe results CSV, Table 7 statistics |
//! | [`robustness`] | Table 7: the 19-point × 2-seed sample and its statistics |
//! | [`sweeps`] | Figure 15: feed and engagement sweeps, harmonic balance, closed-form lobe minimum |
//! | [`depth_study`] | Section 5.6.1 (Figures 9–10): the nominal scenario at several depths |
//! | [`map`] | Figure 16: the speed × depth map and its growth check against the lobes |
//! | [`decomposed`] | the plant as process + structure + actuator FMUs against the monolithic plant |

pub mod batch;
pub mod benchmark;
pub mod benchmark_table;
pub mod closed_loop;
pub mod decomposed;
pub mod depth_study;
pub mod fmu_validation;
pub mod lobes_cases;
pub mod loop_frf;
pub mod main_job;
pub mod map;
pub mod robustness;
pub mod scenario;
pub mod sd_lobes;
pub mod sd_validation;
pub mod sweeps;
pub mod table8;
pub mod tune_cases;
pub mod tuning;
pub mod validation;
