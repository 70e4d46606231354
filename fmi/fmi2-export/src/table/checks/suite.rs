//! The one list of checks every FMU adapter runs ([`adapter_tests!`](crate::adapter_tests!)),
//! and what an adapter says about the cost of its steps ([`Work`], [`work_is`]).

use super::{STEP_SIZES, ready, work_bound_matches_internal_steps};
use crate::Fmi2Model;

/// What a step of an adapter costs, in the internal steps of
/// [`Fmi2Model::internal_steps`] (`ARCHITECTURE.md`: if a step's work grows with `h`, the
/// adapter declares it, so that masters refuse a too large step before instantiating).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Work {
    /// `h / p + extra` internal steps (or a [scaled](crate::Table::work_bound_scaled) multiple),
    /// `p` the Real parameter of this name, declared with
    /// [`Table::work_bound`](crate::Table::work_bound).
    Bound(&'static str),
    /// The same number of internal steps whatever `h` (a step in closed form, a fixed number
    /// of pieces or lookups): nothing to declare.
    Fixed,
    /// Grows with `h`, but not as `h / p + extra` of one parameter (the reason, in words): the
    /// layer still refuses a step beyond its limit, a master cannot refuse it in advance.
    Undeclared(&'static str),
}

/// `M`'s description and its [`Fmi2Model::internal_steps`] agree with `work`: a
/// [`Work::Bound`] is declared on that parameter and is the model's own cost
/// ([`work_bound_matches_internal_steps`]); a model that declares none costs the same for every
/// `h` ([`Work::Fixed`]) or grows with `h` for a stated reason ([`Work::Undeclared`]).
pub fn work_is<M: Fmi2Model>(work: Work) -> Result<(), String> {
    let declared = M::description().work_bound().map(|w| w.internal_step_parameter.as_str());
    if let Work::Bound(p) = work {
        if declared != Some(p) {
            return Err(format!("the description declares a work bound on {declared:?}, the adapter says on {p}"));
        }
        return work_bound_matches_internal_steps::<M>().map(|_| ());
    }
    if let Some(p) = declared {
        return Err(format!("the description declares a work bound on {p}, the adapter says {work:?}"));
    }
    let inst = ready::<M>();
    let model = inst.model().ok_or("no model after initialization")?;
    let costs = STEP_SIZES.map(|h| model.internal_steps(h));
    let grows = costs.windows(2).any(|c| c[0].to_bits() != c[1].to_bits());
    match work {
        Work::Fixed if grows => Err(format!(
            "a step costs {costs:?} internal steps for h = {STEP_SIZES:?} s: it grows with h, declare a work bound"
        )),
        Work::Undeclared(why) if !grows || why.trim().is_empty() => Err(format!(
            "Work::Undeclared({why:?}) for a step of {costs:?} internal steps at h = {STEP_SIZES:?} s: \
             a cost that does not grow with h is Work::Fixed, one that does needs a reason"
        )),
        _ => Ok(()),
    }
}

/// The checks every FMU adapter runs, as the `#[test]`s of a module `shared_checks` in the test
/// file that invokes it (once per adapter: `packaging/tests/adapter_checks.rs` fails for an
/// adapter of `packaging::PRODUCTS` without the invocation):
///
/// * `description_matches_table`, `direct_paths_match_rows`, `parameter_round_trips` (with
///   `valid`: values for the rows where [`distinct_value`](super::distinct_value) would fail
///   the model's validation), `assignments_round_trip` (the defaults and every set of
///   `params`), `parameter_coverage`, `start_values_are_the_defaults`;
/// * `work_is` (`work`: [`Work`]);
/// * `non_finite_inputs_are_refused` (NaN, ±Inf on every Real input, then a step of `step`);
/// * `parameter_extremes_are_safe` (every parameter and input at NaN, ±Inf, ±1e308, 0, −1, min
///   and max, then three steps of `step`: refused with a message or stepped, no call over 5 s, no
///   non-finite output with OK) and `tunable_parameters_take_effect`;
/// * `corrupted_states_never_panic_or_hang`: `tries` copies of the serialized state of
///   `stepped` with 3 bits flipped (xorshift from `seed`) and resealed, each refused or
///   restored into `fresh()` and stepped by `step` within 2 s; some must be refused.
///
/// ```ignore
/// fmi2_export::adapter_tests! {
///     model: MillingPlant,
///     valid: [("workpiece.modes", Value::Integer(3))],
///     params: [PlantParams { seed: 7, ..Default::default() }],
///     work: Work::Bound("internal_step"),
///     step: 1e-3,
///     states: { stepped: saved_state(), fresh: checks::ready::<MillingPlant>, seed: 0x2545_f491_4f6c_dd1d, tries: 2000 },
/// }
/// ```
/// The arguments are expressions of the invoking module (the generated module imports
/// `super::*`); `Work` is in scope inside the macro.
#[macro_export]
macro_rules! adapter_tests {
    (
        model: $M:ty,
        valid: [$($valid:expr),* $(,)?],
        params: [$($params:expr),* $(,)?],
        work: $work:expr,
        step: $h:expr,
        states: { stepped: $stepped:expr, fresh: $fresh:expr, seed: $seed:expr, tries: $tries:expr $(,)? } $(,)?
    ) => {
        /// The shared checks of `fmi2_export::adapter_tests!`.
        mod shared_checks {
            #[allow(unused_imports)]
            use super::*;
            #[allow(unused_imports)]
            use $crate::table::checks::{self as shared, Work};

            #[test]
            fn description_matches_table() {
                shared::description_matches_table::<$M>().unwrap();
            }

            #[test]
            fn direct_paths_match_rows() {
                shared::direct_paths_match_rows::<$M>().unwrap();
            }

            #[test]
            fn parameter_round_trips() {
                shared::parameter_round_trips::<$M>(&[$($valid),*]).unwrap();
            }

            #[test]
            fn assignments_round_trip() {
                shared::assignments_round_trip::<$M>(&::core::default::Default::default()).unwrap();
                $( shared::assignments_round_trip::<$M>(&$params).unwrap(); )*
            }

            #[test]
            fn parameter_coverage() {
                shared::parameter_coverage::<$M>().unwrap();
            }

            #[test]
            fn start_values_are_the_defaults() {
                shared::start_values_are_the_defaults::<$M>().unwrap();
            }

            #[test]
            fn work_is() {
                shared::work_is::<$M>($work).unwrap();
            }

            #[test]
            fn parameter_extremes_are_safe() {
                let (tried, refused, ran) = shared::parameter_extremes_are_safe::<$M>($h, 3).unwrap();
                println!("{tried} extreme values: {refused} refused with a message, {ran} stepped");
                assert!(ran > 0 && refused > 0, "{tried} tried, {refused} refused, {ran} stepped");
            }

            #[test]
            fn tunable_parameters_take_effect() {
                let n = shared::tunable_parameters_take_effect::<$M>($h).unwrap();
                println!("{n} tunable parameters honoured between steps");
            }

            #[test]
            fn non_finite_inputs_are_refused() {
                shared::non_finite_inputs_are_refused::<$M>($h).unwrap();
            }

            #[test]
            fn corrupted_states_never_panic_or_hang() {
                let bytes = $stepped.snapshot().serialize().expect("a serializable state");
                let (refused, loaded) =
                    shared::corrupted_states_never_panic_or_hang::<$M>(&bytes, $seed, $tries, $fresh, $h);
                println!("random corruptions: {refused} refused, {loaded} loaded and stepped without panic");
                assert!(refused > 0, "no corrupted state refused in {} tries", $tries);
            }
        }
    };
}
