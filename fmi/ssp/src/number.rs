//! Numbers in SSP attributes (`xs:double`): written in the shortest form
//! that reads back to the same double, read with a message naming the attribute.

use crate::error::{SspError, invalid};

/// Shortest round-tripping decimal form of a double, valid as `xs:double`
/// (`1e-5`, `30.0`, `INF`, `NaN`).
pub(crate) fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:?}")
    } else if x.is_nan() {
        "NaN".into()
    } else if x > 0.0 {
        "INF".into()
    } else {
        "-INF".into()
    }
}

/// Parse the attribute `what` of `file`.
pub(crate) fn parse_f64(file: &str, what: &str, s: &str) -> Result<f64, SspError> {
    s.trim().parse::<f64>().map_err(|_| invalid(file, format!("{what}: '{s}' is not a number")))
}

/// Parse an optional attribute.
pub(crate) fn opt_f64(file: &str, what: &str, s: Option<&str>) -> Result<Option<f64>, SspError> {
    s.map(|v| parse_f64(file, what, v)).transpose()
}
