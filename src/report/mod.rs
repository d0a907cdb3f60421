//! Reports: failure counts per method, as markdown tables and JSON.

pub mod bench;
pub mod count;
pub mod octree;
pub mod paper;
pub mod scene_info;
pub mod standing;
pub mod stress;
pub mod triangle;
pub mod wrong;

/// Counts under the 12 orientation-preserving relabellings (`crate::tet::EVEN_PERMUTATIONS`, the
/// mesh's own labelling first) as table cells: own | min | median | max (the median of 12 is the mean
/// of the 6th and 7th, rounded down).
pub fn relabel_spread(v: &[u64; 12]) -> String {
    let mut s = *v;
    s.sort_unstable();
    format!("{} | {} | {} | {}", v[0], s[0], (s[5] + s[6]) / 2, s[11])
}
