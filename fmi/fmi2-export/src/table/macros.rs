//! [`variables!`](crate::variables!): the rows of an FMU's variable table, and the per-step
//! functions generated from the same rows.

/// Declare an FMU's variables, one row each, and get a [`Variables`](crate::table::Variables) value.
///
/// ```text
/// fmi2_export::variables! {
///     inputs MyInputs {
///         0 "u" [u] "N" [] "actuator command";
///     }
///     outputs MyOutputs {
///         10 "x" [x] "m" [] "displacement";
///         discrete 11 "u_applied" [u] "N" [] "sampled command";
///     }
///     parameters MyParams {
///         100 "mass" [mass] "kg" [1e-9, 1e9] "modal mass";
///         1 "model" [enum model] "" [] "force model";
///         101 "frequency" [get |p| p.frequency(), set |p, f| p.set_frequency(f)] "Hz" [] "…";
///     }
/// }
/// ```
/// A row is `[discrete] VR "name" [ACCESS] "unit" [BOUNDS] "description";` where ACCESS is a
/// field path of the group's struct (`a.b`, `a.m[0][1]`), `enum PATH` for a [`model_kit::Choice`](crate::model_kit::Choice) field, or
/// `get CLOSURE, set CLOSURE` for a computed variable; BOUNDS is empty or `min, max`; the unit is
/// a name of [`model_description::units::UNITS`](crate::model_description::units::UNITS) or `""`.
#[macro_export]
macro_rules! variables {
    (
        inputs $I:ty { $($irow:tt)* }
        outputs $O:ty { $($orow:tt)* }
        parameters $P:ty { $($prow:tt)* }
    ) => {
        $crate::table::Variables::<$P, $I, $O> {
            inputs: $crate::__rows!($I; $($irow)*),
            outputs: $crate::__rows!($O; $($orow)*),
            parameters: $crate::__rows!($P; $($prow)*),
            direct: $crate::table::Direct {
                read_inputs: |v: &$crate::Values, s: &mut $I| {
                    let _ = (&v, &s);
                    $crate::__direct!(load v, s; $($irow)*);
                },
                write_outputs: |s: &$O, v: &mut $crate::Values| {
                    let _ = (&v, &s);
                    $crate::__direct!(store v, s; $($orow)*);
                },
            },
        }
    };
}

/// The statements of a [`Direct`](crate::table::Direct) function: one per field row (`f64` and `bool` fields move, the others
/// compile to nothing), enumeration and computed rows none.
#[doc(hidden)]
#[macro_export]
macro_rules! __direct {
    ($op:ident $v:ident, $s:ident; $( $($kw:ident)? $vr:literal $name:literal [$($acc:tt)+] $unit:literal [$($b:tt)*] $desc:literal ; )* ) => {
        $( $crate::__direct_row!($op $v, $s, $vr; $($acc)+); )*
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __direct_row {
    ($op:ident $v:ident, $s:ident, $vr:literal; enum $($f:ident).+) => {};
    ($op:ident $v:ident, $s:ident, $vr:literal; get $get:expr, set $set:expr) => {};
    (load $v:ident, $s:ident, $vr:literal; $($path:tt)+) => {
        $crate::table::Scalar::load_direct(&mut $s.$($path)+, $v, $vr)
    };
    (store $v:ident, $s:ident, $vr:literal; $($path:tt)+) => {
        $crate::table::Scalar::store_direct(&$s.$($path)+, $v, $vr)
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __rows {
    ($S:ty; $( $($kw:ident)? $vr:literal $name:literal [$($acc:tt)+] $unit:literal [$($b:tt)*] $desc:literal ; )* ) => {
        vec![ $(
            $crate::__access!($S; $crate::table::Attrs {
                vr: $vr,
                name: $name,
                unit: $unit,
                bounds: $crate::__bounds!($($b)*),
                description: $desc,
                discrete: $crate::__discrete!($($kw)?),
            }; $($acc)+)
        ),* ]
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __bounds {
    () => {
        None
    };
    ($lo:expr, $hi:expr) => {
        Some(($lo as f64, $hi as f64))
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __discrete {
    () => {
        false
    };
    (discrete) => {
        true
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __access {
    ($S:ty; $attrs:expr; enum $($f:ident).+) => {
        $crate::table::Row::<$S>::choice($attrs, |s: &$S| &s.$($f).+, |s: &mut $S| &mut s.$($f).+)
    };
    ($S:ty; $attrs:expr; get $get:expr, set $set:expr) => {
        $crate::table::Row::<$S>::computed($attrs, $get, $set)
    };
    ($S:ty; $attrs:expr; $($path:tt)+) => {
        $crate::table::Row::<$S>::field($attrs, |s: &$S| &s.$($path)+, |s: &mut $S| &mut s.$($path)+)
    };
}
