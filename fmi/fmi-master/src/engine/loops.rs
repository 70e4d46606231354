//! Algebraic loops: connections that close a cycle through outputs which depend directly on
//! inputs (direct feedthrough, declared in each FMU's `ModelStructure/Outputs` as the
//! `dependencies` of an output). A fixed-step master that steps such a system in sequence
//! silently uses a value from the previous communication point on one edge of the cycle; the
//! result depends on the order and is not the coupled solution.
//!
//! [`find`] reads the declared dependencies and returns one cycle, if any. The master refuses
//! such a system before instantiating ([`AlgebraicLoops::Refuse`](super::config::AlgebraicLoops),
//! the default), or, with `--algebraic-loops iterate`, solves it at every communication point
//! by fixed-point iteration of the components (`Components::solve_loop`): set
//! their inputs from the connected outputs, read their outputs, until no output changes by
//! more than [`LOOP_TOLERANCE`] (relative to its size, plus the same absolute) or
//! [`MAX_LOOP_ITERATIONS`] passes end with an error.
//!
//! An output without a `dependencies` attribute is taken as *not* depending on the inputs: FMI
//! 2.0 allows reading it as "depends on all", but co-simulation FMUs that declare nothing are
//! nearly always state outputs, and refusing every such closed loop would refuse most
//! third-party systems. Only declared feedthrough closes a loop.

use super::ports::Components;
use crate::error::{SetupError, SimError};
use crate::import::Fmu;
use model_description::{Causality, ModelDescription};

/// Passes of the fixed-point iteration per communication point before it is an error.
pub const MAX_LOOP_ITERATIONS: usize = 100;
/// Convergence of the fixed-point iteration: every output of the loop changes by at most this
/// times (1 + its magnitude) in the last pass.
pub const LOOP_TOLERANCE: f64 = 1e-12;

/// The value references of the inputs each output of `md` depends on directly, as declared
/// (`(output vr, [input vr])`; outputs without a `dependencies` attribute are left out).
fn feedthrough(md: &ModelDescription) -> Vec<(u32, Vec<u32>)> {
    let vars = md.variables();
    let Some(outputs) = &md.model_structure.outputs else { return Vec::new() };
    let mut out = Vec::new();
    for u in &outputs.unknowns {
        let (Some(deps), Some(o)) = (&u.dependencies, u.index.checked_sub(1).and_then(|i| vars.get(i))) else {
            continue;
        };
        let inputs: Vec<u32> = deps
            .split_whitespace()
            .filter_map(|d| d.parse::<usize>().ok()?.checked_sub(1).and_then(|i| vars.get(i)))
            .filter(|v| v.causality == Causality::Input)
            .map(|v| v.value_reference)
            .collect();
        if !inputs.is_empty() {
            out.push((o.value_reference, inputs));
        }
    }
    out
}

/// One connection by value references: `(source component, output vr) → (end component, input vr)`.
pub(crate) type Edge = ((usize, u32), (usize, u32));

/// An algebraic loop among `edges`: the cycle of connections, as `a.y → b.u` labels in order,
/// or None. `names` are the component names.
pub(crate) fn find(fmus: &[Fmu], names: &[String], edges: &[Edge]) -> Option<Vec<String>> {
    let ft: Vec<Vec<(u32, Vec<u32>)>> = fmus.iter().map(|f| feedthrough(f.model_description())).collect();
    if ft.iter().all(Vec::is_empty) {
        return None;
    }
    // graph on connections: connection k → connection j when k ends at an input of component e
    // on which an output of e depends that starts connection j
    let next: Vec<Vec<usize>> = edges
        .iter()
        .map(|&(_, (e, input))| {
            let outs: Vec<u32> = ft[e].iter().filter(|(_, ins)| ins.contains(&input)).map(|(o, _)| *o).collect();
            (0..edges.len()).filter(|&j| edges[j].0.0 == e && outs.contains(&edges[j].0.1)).collect()
        })
        .collect();
    // iterative depth-first search with colours (0 new, 1 on the path, 2 done)
    let mut colour = vec![0u8; edges.len()];
    for root in 0..edges.len() {
        if colour[root] != 0 {
            continue;
        }
        let mut path: Vec<(usize, usize)> = vec![(root, 0)];
        colour[root] = 1;
        while let Some(&mut (k, ref mut child)) = path.last_mut() {
            if let Some(&j) = next[k].get(*child) {
                *child += 1;
                match colour[j] {
                    0 => {
                        colour[j] = 1;
                        path.push((j, 0));
                    }
                    1 => {
                        let start = path.iter().position(|&(p, _)| p == j).unwrap_or(0);
                        return Some(path[start..].iter().map(|&(p, _)| label(fmus, names, &edges[p])).collect());
                    }
                    _ => {}
                }
            } else {
                colour[k] = 2;
                path.pop();
            }
        }
    }
    None
}

fn label(fmus: &[Fmu], names: &[String], &((s, so), (e, ei)): &Edge) -> String {
    let name = |c: usize, vr: u32, causality: Causality| {
        fmus[c]
            .model_description()
            .variables()
            .iter()
            .find(|v| v.value_reference == vr && v.causality == causality)
            .map_or_else(|| vr.to_string(), |v| v.name.clone())
    };
    format!("{}.{} → {}.{}", names[s], name(s, so, Causality::Output), names[e], name(e, ei, Causality::Input))
}

/// The refusal of a system with the algebraic loop `cycle`.
pub(crate) fn refusal(cycle: &[String]) -> SetupError {
    SetupError::Invalid(format!(
        "algebraic loop: the connections {} close a cycle through outputs that depend directly on inputs \
         (the FMUs declare this direct feedthrough in ModelStructure/Outputs); a fixed-step master would use a \
         value from the previous step on one of them. Break the loop (e.g. a delay or a filter in one FMU), or \
         pass --algebraic-loops iterate to solve it by fixed-point iteration at every communication point",
        cycle.join(", ")
    ))
}

impl Components {
    /// Solve the algebraic loops at the current communication point by fixed-point iteration
    /// of every component (see the module documentation); `t` names the point in errors.
    pub(crate) fn solve_loop(&mut self, t: f64) -> Result<(), SimError> {
        let members: Vec<usize> = (0..self.len()).collect();
        let mut before: Vec<f64> = Vec::new();
        for pass in 0..MAX_LOOP_ITERATIONS {
            before.clear();
            for &i in &members {
                before.extend_from_slice(self[i].outputs.reals());
            }
            for &i in &members {
                self.set_inputs(i)?;
                self.read_outputs(i)?;
            }
            let mut k = 0;
            let mut worst = 0.0f64;
            for &i in &members {
                for &x in self[i].outputs.reals() {
                    let d = (x - before[k]).abs() / (1.0 + x.abs());
                    worst = if d.is_nan() { f64::INFINITY } else { worst.max(d) };
                    k += 1;
                }
            }
            if worst <= LOOP_TOLERANCE && pass > 0 {
                return Ok(());
            }
        }
        Err(SimError::AlgebraicLoop(format!(
            "the algebraic loop did not converge at t = {t} in {MAX_LOOP_ITERATIONS} fixed-point passes \
             (tolerance {LOOP_TOLERANCE:e}); the loop gain may be 1 or more"
        )))
    }
}
