//! Names at the edges: one list of values, one name per value, one parser, for every closed set
//! a user names on the command line, in a scene file or from Python (the integration method,
//! the engine, the linear solver, event kinds, ...).
//!
//! A type lists its values once ([`Named::ALL`]) and names each once ([`Named::name`]); parsing
//! ([`Named::parse`]), the list of accepted names in messages ([`Named::expected`]) and the CLI's
//! possible values are derived from those two, so they cannot disagree.

use std::fmt;

/// A closed set of named values.
pub trait Named: Copy + PartialEq + Sized + 'static {
    /// What the value is called in messages (`"method"`, `"engine"`).
    const WHAT: &'static str;
    /// Every value, in the order messages list them.
    const ALL: &'static [Self];
    /// The name used on the command line, in files and in Python.
    fn name(self) -> &'static str;
    /// One line of help for the value (the CLI shows it), empty by default.
    fn help(self) -> &'static str {
        ""
    }

    /// The value named `s`, or an error listing every name.
    fn parse(s: &str) -> Result<Self, UnknownName> {
        Self::ALL
            .iter()
            .copied()
            .find(|v| v.name() == s)
            .ok_or_else(|| UnknownName {
                what: Self::WHAT,
                got: s.to_string(),
                expected: Self::expected(),
            })
    }

    /// Every name, quoted, as a message lists them: `"a", "b" or "c"`.
    fn expected() -> String {
        let names: Vec<String> = Self::ALL
            .iter()
            .map(|v| format!("\"{}\"", v.name()))
            .collect();
        match names.split_last() {
            None => String::new(),
            Some((last, [])) => last.clone(),
            Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        }
    }
}

/// A name that is not one of a [`Named`] type's values.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownName {
    /// What was named (`"method"`).
    pub what: &'static str,
    /// The name given.
    pub got: String,
    /// The accepted names, as [`Named::expected`] lists them.
    pub expected: String,
}

impl fmt::Display for UnknownName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "expected {}, got \"{}\"", self.expected, self.got)
    }
}

impl std::error::Error for UnknownName {}

/// `Display` (the name) and `FromStr` ([`Named::parse`]) for [`Named`] types.
#[macro_export]
macro_rules! display_and_from_str {
    ($t:ty) => {
        impl ::std::fmt::Display for $t {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                f.write_str($crate::names::Named::name(*self))
            }
        }
        impl ::std::str::FromStr for $t {
            type Err = $crate::names::UnknownName;
            fn from_str(s: &str) -> Result<Self, Self::Err> {
                <$t as $crate::names::Named>::parse(s)
            }
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Fruit {
        Apple,
        Pear,
        Plum,
    }

    impl Named for Fruit {
        const WHAT: &'static str = "fruit";
        const ALL: &'static [Self] = &[Fruit::Apple, Fruit::Pear, Fruit::Plum];
        fn name(self) -> &'static str {
            match self {
                Fruit::Apple => "apple",
                Fruit::Pear => "pear",
                Fruit::Plum => "plum",
            }
        }
    }
    display_and_from_str!(Fruit);

    #[test]
    fn every_name_parses_back_to_its_value() {
        for &f in Fruit::ALL {
            assert_eq!(f.to_string().parse::<Fruit>(), Ok(f));
        }
    }

    #[test]
    fn an_unknown_name_lists_every_name() {
        let e = "fig".parse::<Fruit>().unwrap_err();
        assert_eq!(
            e.to_string(),
            r#"expected "apple", "pear" or "plum", got "fig""#
        );
        assert_eq!(e.what, "fruit");
    }
}
