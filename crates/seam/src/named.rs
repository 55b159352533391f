//! Options known by name: one name per value, the same in case files, on the
//! command line, in summaries and in Python.

use std::fmt;

/// An enum whose values have names ("standard", "dual", …). The serde and
/// clap derives (features `serde`, `clap`) give the same names; `from_name`
/// serves the other front ends (Python).
pub trait Named: Copy + Sized + 'static {
    /// What a value is, for messages ("multiplier").
    const WHAT: &'static str;
    /// Every value, in the order messages list them.
    const ALL: &'static [Self];

    /// The value's name.
    fn name(self) -> &'static str;

    /// The value called `name`.
    fn from_name(name: &str) -> Result<Self, UnknownName> {
        Self::ALL.iter().copied().find(|v| v.name() == name).ok_or_else(|| UnknownName {
            what: Self::WHAT,
            given: name.to_string(),
            names: Self::ALL.iter().map(|v| v.name()).collect(),
        })
    }
}

/// A name that is none of a [`Named`] enum's names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownName {
    /// What was named ("multiplier").
    pub what: &'static str,
    /// The name given.
    pub given: String,
    /// The names there are.
    pub names: Vec<&'static str>,
}

impl fmt::Display for UnknownName {
    /// `unknown multiplier "mortar": expected "standard", "dual" or "lumped"`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown {} {:?}: expected ", self.what, self.given)?;
        for (i, name) in self.names.iter().enumerate() {
            let sep = match i {
                0 => "",
                _ if i + 1 == self.names.len() => " or ",
                _ => ", ",
            };
            write!(f, "{sep}{name:?}")?;
        }
        Ok(())
    }
}

impl std::error::Error for UnknownName {}

/// Implements [`Named`] from a table of values and names.
#[macro_export]
macro_rules! named {
    ($ty:ty, $what:literal, { $($value:ident => $name:literal),+ $(,)? }) => {
        impl $crate::Named for $ty {
            const WHAT: &'static str = $what;
            const ALL: &'static [Self] = &[$(<$ty>::$value),+];
            fn name(self) -> &'static str {
                match self {
                    $(<$ty>::$value => $name),+
                }
            }
        }
    };
}
