//! Tests of the table's per-step paths.

use super::*;

#[derive(Default)]
struct S {
    a: f64,
    b: f64,
    flag: bool,
}

fn attrs(vr: ValueReference, name: &'static str) -> Attrs {
    Attrs { vr, name, unit: "", bounds: None, description: "", discrete: false }
}

/// The per-step lists: the `f64` field rows with their value references in row order, the
/// others (Boolean, computed) by index, every row in exactly one of them.
#[test]
fn per_step_lists_split_the_rows() {
    let rows = [
        Row::<S>::field(attrs(4, "a"), |s| &s.a, |s| &mut s.a),
        Row::<S>::field(attrs(0, "flag"), |s| &s.flag, |s| &mut s.flag),
        Row::<S>::computed(attrs(2, "twice_a"), |s| 2.0 * s.a, |s, x| s.a = x / 2.0),
        Row::<S>::field(attrs(1, "b"), |s| &s.b, |s| &mut s.b),
    ];
    let (real, other) = split_real(&rows);
    assert_eq!(real.iter().map(|(vr, _)| *vr).collect::<Vec<_>>(), [4, 1]);
    assert_eq!(other, [1, 2]);
    let mut s = S::default();
    *(real[0].1.write)(&mut s) = 2.5;
    *(real[1].1.write)(&mut s) = -1.0;
    assert_eq!((s.a.to_bits(), s.b.to_bits()), (2.5f64.to_bits(), (-1.0f64).to_bits()), "the fields of a and b");
}

/// The per-step path of `f64` rows ([`RealField`], used by `read_inputs`/`write_outputs`)
/// reads and writes the same field as the row's `get`/`set`; other types have none.
#[test]
fn real_fields_are_the_rows_fields() {
    let rows = [
        Row::<S>::field(attrs(0, "a"), |s| &s.a, |s| &mut s.a),
        Row::<S>::field(attrs(1, "b"), |s| &s.b, |s| &mut s.b),
        Row::<S>::field(attrs(0, "flag"), |s| &s.flag, |s| &mut s.flag),
        Row::<S>::computed(attrs(2, "twice_a"), |s| 2.0 * s.a, |s, x| s.a = x / 2.0),
    ];
    assert!(rows[0].real.is_some() && rows[1].real.is_some());
    assert!(rows[2].real.is_none() && rows[3].real.is_none(), "only plain f64 fields bypass Value");
    for (k, r) in rows.iter().take(2).enumerate() {
        let f = r.real.unwrap();
        let mut s = S::default();
        *(f.write)(&mut s) = 1.5 + k as f64;
        assert_eq!(r.get(&s), Value::Real(1.5 + k as f64));
        r.set(&mut s, &Value::Real(-3.0)).unwrap();
        assert_eq!((f.read)(&s).to_bits(), (-3.0f64).to_bits());
        let other = if k == 0 { s.b } else { s.a };
        assert_eq!(other.to_bits(), 0.0f64.to_bits(), "row {k} wrote another field");
    }
}
