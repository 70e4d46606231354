//! Reading a machine file's TOML with the field path in every message: unknown keys (with the
//! nearest known key), missing fields, wrong types, wrong units and implausible magnitudes
//! (with the unit the number probably meant) each give one error naming the field and the fix.

use crate::units::{self, Dim, Quantity};
use std::cell::RefCell;
use std::collections::BTreeSet;
use std::fmt;

/// A problem in a machine file: where, what, and how to fix it.
#[derive(Clone, Debug, PartialEq)]
pub struct MachineError {
    /// The file (or `<dict>` for a machine given as a mapping).
    pub file: String,
    /// The field path, e.g. `structure.x[1].stiffness` (empty: the whole file).
    pub field: String,
    /// What is wrong and how to fix it.
    pub message: String,
}

impl fmt::Display for MachineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.field.is_empty() {
            write!(f, "{}: {}", self.file, self.message)
        } else {
            write!(f, "{}: {}: {}", self.file, self.field, self.message)
        }
    }
}

impl std::error::Error for MachineError {}

/// What a quantity field takes: its dimension, SI unit, physical range and likely slips.
#[derive(Clone, Copy, Debug)]
pub struct Field {
    /// The quantity's name in messages (`K_t`).
    pub what: &'static str,
    /// Dimension.
    pub dim: Dim,
    /// The SI unit a bare number is read in (as written in messages).
    pub si_unit: &'static str,
    /// The unit the field is reported in and its factor from SI (e.g. `Hz`, 1/(2π)).
    pub report: (&'static str, f64),
    /// Physically plausible range in SI (inclusive).
    pub range: (f64, f64),
    /// Likely slips: a bare number meant in this unit would be SI × factor.
    pub slips: &'static [(f64, &'static str)],
    /// An example value with its unit.
    pub example: &'static str,
}

/// A TOML table being read, with its path and the keys used so far.
pub struct Node<'a> {
    file: &'a str,
    path: String,
    table: &'a toml::Table,
    used: RefCell<BTreeSet<String>>,
}

/// Edit distance (for "did you mean").
fn distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for i in 1..=a.len() {
        let mut cur = vec![i; b.len() + 1];
        for j in 1..=b.len() {
            let sub = prev[j - 1] + usize::from(a[i - 1] != b[j - 1]);
            cur[j] = sub.min(prev[j] + 1).min(cur[j - 1] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

impl<'a> Node<'a> {
    /// The root table of `file`.
    pub fn root(file: &'a str, table: &'a toml::Table) -> Node<'a> {
        Node { file, path: String::new(), table, used: RefCell::new(BTreeSet::new()) }
    }

    /// The path of `key` in this table.
    pub fn path_of(&self, key: &str) -> String {
        if self.path.is_empty() { key.to_string() } else { format!("{}.{key}", self.path) }
    }

    /// An error at `key` of this table (or at the table itself for an empty key).
    pub fn err(&self, key: &str, message: impl Into<String>) -> MachineError {
        MachineError {
            file: self.file.to_string(),
            field: if key.is_empty() { self.path.clone() } else { self.path_of(key) },
            message: message.into(),
        }
    }

    /// The raw value of `key`, if present (marks it used).
    pub fn get(&self, key: &str) -> Option<&'a toml::Value> {
        let v = self.table.get(key);
        if v.is_some() {
            self.used.borrow_mut().insert(key.to_string());
        }
        v
    }

    /// The keys of this table.
    pub fn keys(&self) -> Vec<String> {
        self.table.keys().cloned().collect()
    }

    /// Is `key` present?
    pub fn has(&self, key: &str) -> bool {
        self.table.contains_key(key)
    }

    /// A missing required field.
    pub fn missing(&self, key: &str, what: &str) -> MachineError {
        self.err(key, format!("missing: {what} (add `{key} = ...`)"))
    }

    /// A sub-table.
    pub fn table(&self, key: &str) -> Result<Option<Node<'a>>, MachineError> {
        match self.get(key) {
            None => Ok(None),
            Some(toml::Value::Table(t)) => Ok(Some(self.child(self.path_of(key), t))),
            Some(other) => {
                Err(self.err(key, format!("expected a table ([{}]), found a {}", self.path_of(key), other.type_str())))
            }
        }
    }

    fn child(&self, path: String, table: &'a toml::Table) -> Node<'a> {
        Node { file: self.file, path, table, used: RefCell::new(BTreeSet::new()) }
    }

    /// An array of tables (`[[key]]` or `key = [{...}, ...]`); absent is empty.
    pub fn tables(&self, key: &str) -> Result<Vec<Node<'a>>, MachineError> {
        match self.get(key) {
            None => Ok(Vec::new()),
            Some(toml::Value::Array(items)) => items
                .iter()
                .enumerate()
                .map(|(i, v)| match v {
                    toml::Value::Table(t) => Ok(self.child(format!("{}[{i}]", self.path_of(key)), t)),
                    other => Err(self.err(
                        key,
                        format!(
                            "item {i}: expected a table ({{ frequency = ..., ... }}), found a {}",
                            other.type_str()
                        ),
                    )),
                })
                .collect(),
            Some(toml::Value::Table(t)) => Ok(vec![self.child(format!("{}[0]", self.path_of(key)), t)]),
            Some(other) => Err(self.err(key, format!("expected a list of tables, found a {}", other.type_str()))),
        }
    }

    /// A string.
    pub fn string(&self, key: &str) -> Result<Option<String>, MachineError> {
        match self.get(key) {
            None => Ok(None),
            Some(toml::Value::String(s)) => Ok(Some(s.clone())),
            Some(other) => Err(self.err(key, format!("expected a string in quotes, found a {}", other.type_str()))),
        }
    }

    /// One of `choices` (a string).
    pub fn choice(&self, key: &str, choices: &[&str]) -> Result<Option<String>, MachineError> {
        let Some(s) = self.string(key)? else { return Ok(None) };
        if choices.contains(&s.as_str()) {
            Ok(Some(s))
        } else {
            Err(self.err(key, format!("{s:?} is not one of {}", choices.join(", "))))
        }
    }

    /// A positive integer within `range`.
    pub fn integer(&self, key: &str, range: (i64, i64)) -> Result<Option<i64>, MachineError> {
        match self.get(key) {
            None => Ok(None),
            Some(toml::Value::Integer(i)) if (range.0..=range.1).contains(i) => Ok(Some(*i)),
            Some(toml::Value::Integer(i)) => Err(self.err(key, format!("{i} is outside [{}, {}]", range.0, range.1))),
            Some(other) => Err(self.err(key, format!("expected an integer, found a {}", other.type_str()))),
        }
    }

    /// A number or a string with a unit, checked against `field` (see [`Field`]); the value
    /// in SI (angles in rad, frequencies in rad/s).
    pub fn quantity(&self, key: &str, field: &Field) -> Result<Option<f64>, MachineError> {
        let Some(v) = self.get(key) else { return Ok(None) };
        self.quantity_value(key, v, field).map(Some)
    }

    /// [`Node::quantity`] of a given value (an array item, say).
    pub fn quantity_value(&self, key: &str, v: &toml::Value, field: &Field) -> Result<f64, MachineError> {
        let (q, raw) = match v {
            toml::Value::Integer(i) => {
                (Quantity { si: *i as f64, dim: field.dim, had_unit: false, angular: false }, i.to_string())
            }
            toml::Value::Float(x) => {
                (Quantity { si: *x, dim: field.dim, had_unit: false, angular: false }, units::short(*x))
            }
            toml::Value::String(s) => {
                let mut q = units::parse_quantity(s)
                    .map_err(|e| self.err(key, format!("{e}; write e.g. {}", field.example)))?;
                if !q.had_unit {
                    q.dim = field.dim;
                }
                (q, s.clone())
            }
            other => {
                return Err(self.err(
                    key,
                    format!(
                        "expected a number or a string with a unit (e.g. {}), found a {}",
                        field.example,
                        other.type_str()
                    ),
                ));
            }
        };
        if q.had_unit && !units::same_dim(q.dim, field.dim) {
            return Err(self.err(
                key,
                format!(
                    "{raw:?} is {}, but {} is {} (e.g. {})",
                    units::describe(q.dim),
                    field.what,
                    units::describe(field.dim),
                    field.example
                ),
            ));
        }
        if units::same_dim(field.dim, units::FREQUENCY) && q.had_unit && !q.angular {
            return Err(self.err(
                key,
                format!("{raw:?}: a frequency in 1/s is ambiguous (cycles or radians?): write Hz or rad/s"),
            ));
        }
        if !q.si.is_finite() {
            return Err(self.err(key, format!("{raw} is not a finite number")));
        }
        let (lo, hi) = field.range;
        if q.si < lo || q.si > hi {
            let (unit, f) = field.report;
            let unit = if unit.is_empty() { String::new() } else { format!(" {unit}") };
            let mut m = format!(
                "{} = {}{unit} is outside the physical range [{}, {}]{unit}",
                field.what,
                units::short(q.si * f),
                units::short(lo * f),
                units::short(hi * f)
            );
            if q.si <= 0.0 && lo > 0.0 {
                m = format!(
                    "{} = {raw} must be positive (physical range [{}, {}]{unit})",
                    field.what,
                    units::short(lo * f),
                    units::short(hi * f)
                );
            } else if !q.had_unit {
                let ratio = if q.si < lo { lo / q.si.abs().max(f64::MIN_POSITIVE) } else { q.si / hi };
                m = format!(
                    "{} = {raw} {} is {:.0e} times {} the physical range [{}, {}] {}",
                    field.what,
                    field.si_unit,
                    ratio.max(1.0),
                    if q.si < lo { "below" } else { "above" },
                    units::short(lo),
                    units::short(hi),
                    field.si_unit
                );
                if let Some((factor, slip)) = field.slips.iter().find(|(k, _)| (lo..=hi).contains(&(q.si * k))) {
                    m.push_str(&format!(
                        ": did you mean \"{raw} {slip}\" (= {} {})? A bare number is read in SI ({}).",
                        units::short(q.si * factor),
                        field.si_unit,
                        field.si_unit
                    ));
                } else {
                    m.push_str(&format!("; write the value with its unit, e.g. {}", field.example));
                }
            }
            return Err(self.err(key, m));
        }
        Ok(q.si)
    }

    /// Refuse keys this table does not know, naming the nearest known one.
    pub fn finish(&self, known: &[&str]) -> Result<(), MachineError> {
        for key in self.table.keys() {
            if !known.contains(&key.as_str()) {
                let near = known.iter().min_by_key(|k| distance(key, k)).filter(|k| distance(key, k) <= 3);
                let hint = match near {
                    Some(k) => format!("did you mean `{k}`?"),
                    None => format!("known keys: {}", known.join(", ")),
                };
                return Err(self.err(key, format!("unknown key; {hint}")));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::PRESSURE;

    const KT: Field = Field {
        what: "K_t",
        dim: PRESSURE,
        si_unit: "N/m^2",
        report: ("N/mm^2", 1e-6),
        range: (5e7, 2e10),
        slips: &[(1e6, "N/mm^2")],
        example: "\"800 N/mm^2\"",
    };

    fn node_of(text: &str) -> toml::Table {
        text.parse::<toml::Table>().unwrap()
    }

    #[test]
    fn a_bare_number_in_the_wrong_unit_gets_the_probable_unit() {
        let t = node_of("kt = 800");
        let e = Node::root("m.toml", &t).quantity("kt", &KT).unwrap_err().to_string();
        assert!(
            e.starts_with("m.toml: kt: K_t = 800 N/m^2 is 6e4 times below the physical range [5e7, 2e10] N/m^2"),
            "{e}"
        );
        assert!(e.contains("did you mean \"800 N/mm^2\" (= 8e8 N/m^2)?"), "{e}");
        let t = node_of("kt = \"800 N/mm^2\"");
        assert_eq!(Node::root("m.toml", &t).quantity("kt", &KT).unwrap(), Some(8e8));
    }

    #[test]
    fn wrong_units_and_keys_are_named() {
        let t = node_of("kt = \"800 mm\"\nfrequncy = 3");
        let n = Node::root("m.toml", &t);
        let e = n.quantity("kt", &KT).unwrap_err().to_string();
        assert!(e.contains("\"800 mm\" is a length, but K_t is a pressure"), "{e}");
        let e = n.finish(&["kt", "frequency"]).unwrap_err().to_string();
        assert_eq!(e, "m.toml: frequncy: unknown key; did you mean `frequency`?");
    }
}
