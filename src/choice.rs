//! Closed sets of named values (mesh kinds, shape families, layouts, stress rows, backends): one name
//! per value, used by the command line, the case format and reports alike.

/// A closed set of named values.
pub trait Choice: Copy + Sized + Send + Sync + 'static {
    /// Every value, in the order help text and reports list them.
    const ALL: &'static [Self];
    fn name(self) -> &'static str;
    fn from_name(s: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|v| v.name() == s)
    }
}

/// Implement [`Choice`] for a fieldless enum from `Variant => "name"` pairs.
#[macro_export]
macro_rules! choice {
    ($t:ty { $($v:ident => $n:literal),* $(,)? }) => {
        impl $crate::choice::Choice for $t {
            const ALL: &'static [Self] = &[$(<$t>::$v),*];
            fn name(self) -> &'static str {
                match self { $(<$t>::$v => $n),* }
            }
        }
    };
}
