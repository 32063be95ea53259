//! Enums whose values a user types by name: the command line, the Python
//! package, scene and study files and the explorer all read them through the
//! one [`Named`] table of each enum, so a value is spelled in one place.
//!
//! [`named_enum!`](crate::named_enum) defines such an enum from its variants,
//! their names and their doc comments (the help line of each value).

/// An enum whose every value has one name that users type and files store.
pub trait Named: Copy + Sized + 'static {
    /// Every value, in the order help and errors list them.
    const ALL: &'static [Self];

    /// The value's name.
    fn name(self) -> &'static str;

    /// One line on what the value means (the command line's help).
    fn help(self) -> &'static str;

    /// The value of a name, spelled as [`Named::name`] spells it.
    fn parse(text: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|v| v.name() == text)
    }

    /// The names in a sentence: `fast, standard or precise`.
    fn names() -> String {
        let names: Vec<&str> = Self::ALL.iter().map(|v| v.name()).collect();
        match names.split_last() {
            Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
            _ => names.concat(),
        }
    }

    /// ` (did you mean 'fast'?)` for a name close to one of them (a
    /// Jaro–Winkler similarity of at least 0.8, case ignored), else nothing.
    fn meant(got: &str) -> String {
        let names: Vec<&str> = Self::ALL.iter().map(|v| v.name()).collect();
        closest(got, &names).map(|n| format!(" (did you mean '{n}'?)")).unwrap_or_default()
    }

    /// What a name that is none of them is told: `expected fast, standard or
    /// precise, got 'fst' (did you mean 'fast'?)`.
    fn expected(got: &str) -> String {
        format!("expected {}, got '{got}'{}", Self::names(), Self::meant(got))
    }
}

/// The name of `names` closest to `got`, if one is close enough to be the
/// one meant: a Jaro–Winkler similarity of at least 0.8 (clap's threshold for
/// its own suggestions), case ignored.
fn closest<'a>(got: &str, names: &[&'a str]) -> Option<&'a str> {
    let got = got.to_lowercase();
    names
        .iter()
        .map(|&n| (strsim::jaro_winkler(&got, &n.to_lowercase()), n))
        .filter(|&(score, _)| score >= 0.8)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, n)| n)
}

/// Defines an enum of unit variants and its [`Named`] table: each variant's
/// name is the string after `=`, its help line its doc comment. The enum also
/// displays as its name.
///
/// ```
/// scene::named_enum! {
///     /// How a line is drawn.
///     #[derive(Debug, Clone, Copy, PartialEq, Eq)]
///     pub enum Stroke {
///         /// An unbroken line.
///         Solid = "solid",
///         /// Short dashes.
///         Dashed = "dashed",
///     }
/// }
/// use scene::Named;
/// assert_eq!(Stroke::parse("dashed"), Some(Stroke::Dashed));
/// assert_eq!(Stroke::Solid.help(), "An unbroken line.");
/// assert_eq!(Stroke::expected("dahsed"), "expected solid or dashed, got 'dahsed' (did you mean 'dashed'?)");
/// assert_eq!(Stroke::Dashed.to_string(), "dashed");
/// ```
#[macro_export]
macro_rules! named_enum {
    (
        $(#[$meta:meta])*
        $vis:vis enum $name:ident {
            $( $(#[doc = $doc:literal])* $variant:ident = $key:literal, )*
        }
    ) => {
        $(#[$meta])*
        $vis enum $name {
            $( $(#[doc = $doc])* $variant, )*
        }

        impl $crate::Named for $name {
            const ALL: &'static [Self] = &[$($name::$variant),*];

            fn name(self) -> &'static str {
                match self {
                    $($name::$variant => $key,)*
                }
            }

            fn help(self) -> &'static str {
                match self {
                    $($name::$variant => concat!($($doc),*).trim_ascii(),)*
                }
            }
        }

        impl ::std::fmt::Display for $name {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                f.write_str($crate::Named::name(*self))
            }
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    named_enum! {
        /// A test enum.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        enum Three {
            /// The first, whose help
            /// runs over two lines.
            One = "one",
            /// The second.
            Two = "two",
            /// The third.
            Many = "three-and-more",
        }
    }

    #[test]
    fn every_value_reads_back_and_nothing_else_does() {
        for &v in Three::ALL {
            assert_eq!(Three::parse(v.name()), Some(v));
        }
        assert_eq!(Three::parse("One"), None);
        assert_eq!(Three::parse(""), None);
        assert_eq!(Three::names(), "one, two or three-and-more");
        assert_eq!(Three::One.help(), "The first, whose help runs over two lines.");
    }

    #[test]
    fn a_near_miss_is_named_and_a_far_one_is_not() {
        assert_eq!(
            Three::expected("thre-and-more"),
            "expected one, two or three-and-more, got 'thre-and-more' (did you mean 'three-and-more'?)"
        );
        assert_eq!(Three::expected("TWO"), "expected one, two or three-and-more, got 'TWO' (did you mean 'two'?)");
        assert_eq!(Three::expected("zebra"), "expected one, two or three-and-more, got 'zebra'");
        assert_eq!(closest("x", &[]), None);
    }
}
