//! Reports: what the engine's runs return (`crate::engine`), formatted as markdown tables; each
//! family's own tables are its [`Formats`]. Reports compute nothing and run nothing.

pub mod bench;
pub mod count;
pub mod filters;
pub mod lines;
pub mod methods;
pub mod paper;
pub mod replay;
pub mod scene_info;
pub mod shrink;
pub mod stress;
pub mod verify;

use crate::engine::stress::StressReport;
use crate::family::Family;

/// How a family's reports read.
pub trait Formats: Family {
    /// The stress table (and a campaign's, summed over its rounds).
    fn stress_table(r: &StressReport<Self>) -> String;
}

/// Counts under each labelling (the own first) as table cells: own | min | median | max (the median
/// of an even number is the mean of the middle two, rounded down).
pub(crate) fn relabel_spread(v: &[u64]) -> String {
    let mut s = v.to_vec();
    s.sort_unstable();
    let n = s.len();
    let median = match n {
        0 => 0,
        _ if n.is_multiple_of(2) => (s[n / 2 - 1] + s[n / 2]) / 2,
        _ => s[n / 2],
    };
    format!(
        "{} | {} | {} | {}",
        v.first().copied().unwrap_or(0),
        s.first().copied().unwrap_or(0),
        median,
        s.last().copied().unwrap_or(0)
    )
}

/// `n` and its noun, singular for one: `counted(1, "view", "views")` is "1 view".
pub(crate) fn counted(n: impl Into<u64>, one: &str, many: &str) -> String {
    let n = n.into();
    format!("{n} {}", if n == 1 { one } else { many })
}
