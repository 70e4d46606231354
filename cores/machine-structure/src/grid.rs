//! The internal cell grid of the time-stepping cores (the structure here, the plant in
//! `milling-plant`): a communication step of length `h` is cut at the boundaries of cells of
//! length `T`, so a core whose communication points lie on the grid takes whole cells only, and
//! one discretisation serves every step.
//!
//! What is left of the step is counted down by the sub-steps taken. Computing it as
//! `t_end − t` loses the grid once the rounding of `t` (≈ t·ε) exceeds the tolerance `1e-9·T`:
//! after ~50 s at T = 10 µs every later step became two partial cells of new lengths, each with a
//! fresh discretisation.

/// The next sub-step of a communication step: `remaining` is what is left of the step (reduced
/// by the sub-step returned), `offset` the time since the last cell boundary, `cell` the cell
/// length. Returns `(dt, completes)`, `completes` when the sub-step ends on a cell boundary
/// (within `1e-9·cell`), or `None` when the step is done.
#[inline]
pub fn next_sub_step(remaining: &mut f64, offset: f64, cell: f64) -> Option<(f64, bool)> {
    let tol = 1e-9 * cell;
    if *remaining <= tol {
        return None;
    }
    let to_cell_end = cell - offset;
    let (dt, completes) = if *remaining >= to_cell_end - tol { (to_cell_end, true) } else { (*remaining, false) };
    *remaining -= dt;
    Some((dt, completes))
}

#[cfg(test)]
mod tests {
    use super::next_sub_step;

    /// Sub-steps of `h` from `offset` on cells of `cell`: (dt, completes) in order.
    fn cuts(mut h: f64, mut offset: f64, cell: f64) -> Vec<(f64, bool)> {
        let mut out = Vec::new();
        while let Some((dt, completes)) = next_sub_step(&mut h, offset, cell) {
            offset = if completes { 0.0 } else { offset + dt };
            out.push((dt, completes));
        }
        out
    }

    #[test]
    fn steps_are_cut_at_cell_boundaries() {
        assert_eq!(cuts(1e-5, 0.0, 1e-5), vec![(1e-5, true)]);
        assert_eq!(cuts(3e-5, 0.0, 1e-5).len(), 3);
        let c = cuts(6e-5, 1e-6, 1e-5);
        assert!(c[0].1 && (c[0].0 - 9e-6).abs() < 1e-20, "{c:?}");
        assert!(!c.last().unwrap().1, "ends inside a cell: {c:?}");
        assert!(cuts(0.0, 0.0, 1e-5).is_empty());
    }
}
