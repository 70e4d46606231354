//! Named choices: enums whose items have a stable name, a 1-based index and a description.
//!
//! A core declares a choice once with [`choice!`](crate::choice!); the FMU adapters turn it into
//! an FMI enumeration type (items in declaration order, values `1..=n`), the command lines parse
//! it by name, and nothing else repeats the item list:
//!
//! ```
//! model_kit::choice! {
//!     /// Milling direction.
//!     pub enum Milling ("MillingMode", "milling direction") {
//!         /// Conventional.
//!         Up = "up", "up-milling (conventional)";
//!         /// Climb.
//!         Down = "down", "down-milling (climb)";
//!     }
//! }
//! use model_kit::Choice;
//! assert_eq!(Milling::Down.index(), 2);
//! assert_eq!(Milling::from_index(1), Some(Milling::Up));
//! assert_eq!(Milling::from_name("down"), Some(Milling::Down));
//! assert_eq!(Milling::Up.name(), "up");
//! assert!(model_kit::parse_choice::<Milling>("sideways").unwrap_err().contains("up, down"));
//! ```

/// An enum with a fixed list of named items.
///
/// Implemented by [`choice!`](crate::choice!), which declares the enum and its item list in one
/// place, so that a variant cannot exist without its name and description.
pub trait Choice: Copy + PartialEq + Sized + 'static {
    /// Type name (the FMI enumeration type, e.g. `CuttingModel`).
    const TYPE_NAME: &'static str;
    /// What the choice selects.
    const DESCRIPTION: &'static str;
    /// Every item in order: `(value, name, description)`. Item `i` (0-based) has index `i + 1`.
    const ITEMS: &'static [(Self, &'static str, &'static str)];

    /// 1-based index of the item (the FMI enumeration value).
    fn index(self) -> i32 {
        let i = Self::ITEMS.iter().position(|(v, _, _)| *v == self).expect("choice! lists every variant");
        i as i32 + 1
    }

    /// The item with 1-based index `i`.
    fn from_index(i: i32) -> Option<Self> {
        usize::try_from(i).ok().and_then(|i| i.checked_sub(1)).and_then(|i| Self::ITEMS.get(i)).map(|(v, _, _)| *v)
    }

    /// The item's name.
    fn name(self) -> &'static str {
        Self::ITEMS[self.index() as usize - 1].1
    }

    /// The item called `name`.
    fn from_name(name: &str) -> Option<Self> {
        Self::ITEMS.iter().find(|(_, n, _)| *n == name).map(|(v, _, _)| *v)
    }

    /// All item names, in order.
    fn names() -> Vec<&'static str> {
        Self::ITEMS.iter().map(|(_, n, _)| *n).collect()
    }
}

/// Parse an item by name; the error lists the valid names.
pub fn parse_choice<T: Choice>(name: &str) -> Result<T, String> {
    T::from_name(name).ok_or_else(|| format!("{name:?} is not a {} (one of {})", T::TYPE_NAME, T::names().join(", ")))
}

/// Declare an enum and its [`Choice`] items in one place.
///
/// ```text
/// choice! {
///     /// docs, attributes (e.g. #[derive(Serialize, Deserialize)])
///     pub enum Name ("TypeName", "what it selects") {
///         /// variant docs
///         Variant = "item_name", "item description";
///         …
///     }
/// }
/// ```
/// The enum derives `Clone, Copy, Debug, PartialEq, Eq, Hash`; add others with attributes.
#[macro_export]
macro_rules! choice {
    (
        $(#[$meta:meta])*
        $vis:vis enum $name:ident ($type_name:literal, $desc:literal) {
            $( $(#[$vmeta:meta])* $variant:ident = $item:literal, $idesc:literal; )+
        }
    ) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        $vis enum $name {
            $( $(#[$vmeta])* $variant, )+
        }
        impl $crate::Choice for $name {
            const TYPE_NAME: &'static str = $type_name;
            const DESCRIPTION: &'static str = $desc;
            const ITEMS: &'static [(Self, &'static str, &'static str)] = &[ $( ($name::$variant, $item, $idesc), )+ ];
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    crate::choice! {
        /// Test choice.
        enum Three ("Three", "three items") {
            /// a
            A = "a", "first";
            /// b
            B = "b", "second";
            /// c
            C = "c", "third";
        }
    }

    #[test]
    fn indices_names_and_round_trips() {
        for (i, (v, n, _)) in Three::ITEMS.iter().enumerate() {
            assert_eq!(v.index(), i as i32 + 1);
            assert_eq!(Three::from_index(v.index()), Some(*v));
            assert_eq!(v.name(), *n);
            assert_eq!(Three::from_name(n), Some(*v));
        }
        assert_eq!(Three::from_index(0), None);
        assert_eq!(Three::from_index(4), None);
        assert_eq!(Three::from_index(-1), None);
        assert_eq!(Three::from_name("d"), None);
        assert_eq!(Three::names(), ["a", "b", "c"]);
        assert_eq!(parse_choice::<Three>("b"), Ok(Three::B));
        assert_eq!(parse_choice::<Three>("x").unwrap_err(), "\"x\" is not a Three (one of a, b, c)");
    }
}
