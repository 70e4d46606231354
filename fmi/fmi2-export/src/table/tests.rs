//! Tests of the table's per-step paths.

use super::*;

#[derive(Clone, Debug, Default, PartialEq)]
struct S {
    a: f64,
    b: f64,
    c: f64,
    flag: bool,
    n: i32,
    inner: Inner,
}

#[derive(Clone, Debug, Default, PartialEq)]
struct Inner {
    m: [[f64; 2]; 2],
}

fn table() -> Table<S, S, S> {
    let vars = crate::variables! {
        inputs S {
            4 "a" [a] "1" [] "";
            0 "flag" [flag] "" [] "";
            2 "twice_c" [get |s: &S| 2.0 * s.c, set |s: &mut S, x: f64| s.c = x / 2.0] "1" [] "";
            1 "b" [b] "1" [] "";
            3 "m01" [inner.m[0][1]] "1" [] "";
            5 "n" [n] "" [] "";
        }
        outputs S {
            14 "a_out" [a] "1" [] "";
            10 "flag_out" [flag] "" [] "";
            12 "twice_c_out" [get |s: &S| 2.0 * s.c, set |s: &mut S, x: f64| s.c = x / 2.0] "1" [] "";
            11 "b_out" [b] "1" [] "";
            13 "m10_out" [inner.m[1][0]] "1" [] "";
        }
        parameters S {
            20 "p" [a] "1" [] "";
        }
    };
    Table::new(Header { model_name: "T", identifier: "T", description: "", default_experiment: (0.0, 1.0, 0.1) }, vars)
}

/// Only the `f64` and `bool` field rows are on the direct path; the others (Integer,
/// computed) are listed for the `Value` path, every row in exactly one of the two.
#[test]
fn direct_path_takes_exactly_the_f64_and_bool_field_rows() {
    let t = table();
    let direct: Vec<&str> = t.vars.inputs.iter().filter(|r| r.direct).map(|r| r.attrs.name).collect();
    assert_eq!(direct, ["a", "flag", "b", "m01"]);
    assert_eq!(t.other_inputs, [2, 5]);
    assert_eq!(t.other_outputs, [2]);
}

/// A Real row without a unit makes no description: every Real variable says its unit ("1"
/// when dimensionless; issue 31 counted 203 Real variables without one).
#[test]
fn a_real_variable_without_a_unit_is_refused() {
    let vars = crate::variables! {
        inputs S { 4 "a" [a] "1" [] ""; }
        outputs S { 14 "a_out" [a] "" [] ""; }
        parameters S { 0 "flag" [flag] "" [] ""; }
    };
    let t = Table::new(
        Header { model_name: "T", identifier: "T", description: "", default_experiment: (0.0, 1.0, 0.1) },
        vars,
    );
    let e = t.model_description(&S::default()).unwrap_err();
    assert!(format!("{e:?}").contains("the Real variable a_out has no unit"), "{e:?}");
}

/// The generated functions move the rows' own fields with the rows' value references: the
/// result of `read_inputs`/`write_outputs` equals setting/getting each row through `Value`.
#[test]
fn direct_path_moves_what_the_rows_move() {
    let t = table();
    let md = t.model_description(&S::default()).unwrap();
    let mut v = Values::from_description(&md);
    for (vr, x) in [(4, 1.5), (2, 3.0), (1, -2.0), (3, 7.0)] {
        v.set_real(vr, x);
    }
    v.set_boolean(0, true);
    v.set_integer(5, 9);
    let fast = t.read_inputs(&v).unwrap();
    let mut reference = S::default();
    for r in &t.vars.inputs {
        r.set(&mut reference, &v.get(r.ty.api_type(), r.attrs.vr)).unwrap();
    }
    assert_eq!(fast, reference);
    let inner = Inner { m: [[0.0, 7.0], [0.0, 0.0]] };
    assert_eq!(fast, S { a: 1.5, b: -2.0, c: 1.5, flag: true, n: 9, inner });

    let o = S { a: 0.25, b: -4.0, c: 8.0, flag: true, n: 3, inner: Inner { m: [[1.0, 2.0], [3.0, 4.0]] } };
    let mut fast = Values::from_description(&md);
    t.write_outputs(&o, &mut fast);
    let mut reference = Values::from_description(&md);
    for r in &t.vars.outputs {
        reference.set(r.attrs.vr, &r.get(&o));
    }
    assert_eq!(fast, reference);
    let written: Vec<f64> = [14, 11, 12, 13].iter().map(|&vr| fast.real(vr)).collect();
    assert_eq!(written, [0.25, -4.0, 16.0, 3.0]);
}
