//! The memory budget of one model instance: what a core may allocate for the state that its
//! parameters size (delay lines, memories, histories), checked when the core is built, so that a
//! legal but extreme combination of parameters is refused with a message naming them instead of
//! asking the allocator for hundreds of gigabytes (which aborts the host: `ToolXyPlant` with
//! `spindle_speed = 1` and `max_step = 1e-9` asked for 480 GB).

/// The most bytes of parameter-sized state one model instance holds: 256 MiB. A serialized FMU
/// state and a saved state (`fmi2GetFMUstate`) each hold a copy besides.
pub const MAX_STATE_BYTES: f64 = 256.0 * 1024.0 * 1024.0;

/// `Ok` if `bytes` fits [`MAX_STATE_BYTES`]; else the error `what` (the parameters that size the
/// state and what to change) with the size and the budget.
pub fn check_state_bytes(bytes: f64, what: impl FnOnce() -> String) -> Result<(), String> {
    if bytes.is_finite() && bytes <= MAX_STATE_BYTES {
        return Ok(());
    }
    Err(format!(
        "{} needs {} of state, more than the memory budget of {} per instance",
        what(),
        human(bytes),
        human(MAX_STATE_BYTES)
    ))
}

/// `bytes` as `12.3 MiB`, `480 GB`-style text.
fn human(bytes: f64) -> String {
    if !bytes.is_finite() {
        return "an unbounded amount".into();
    }
    let units = ["B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let mut x = bytes;
    let mut u = 0;
    while x >= 1024.0 && u + 1 < units.len() {
        x /= 1024.0;
        u += 1;
    }
    if u == 0 { format!("{x:.0} B") } else { format!("{x:.1} {}", units[u]) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_budget_names_the_size() {
        assert!(check_state_bytes(1e6, || unreachable!()).is_ok());
        let e = check_state_bytes(480e9, || "the delay line".into()).unwrap_err();
        assert_eq!(e, "the delay line needs 447.0 GiB of state, more than the memory budget of 256.0 MiB per instance");
        assert!(check_state_bytes(f64::INFINITY, || "x".into()).unwrap_err().contains("an unbounded amount"));
        assert!(check_state_bytes(f64::NAN, || "x".into()).is_err());
    }
}
