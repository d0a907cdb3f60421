//! The engine: runs that compute, for every family ([`crate::family`]) — stress tables and campaigns,
//! found cases, their checks and replay, the fuzz targets' policy, counts over a scene's views, walk
//! speed and the seeds' tables — returning plain tallies and records of wrong answers. Reports
//! (`crate::report`) only format what these return.

pub mod answerer;
pub mod bench;
pub mod count;
pub mod filters;
pub mod found;
pub mod fuzz;
pub mod info;
pub mod paper;
pub mod shrink;
pub mod standing;
pub mod stress;
pub mod verify;

/// Numbers measured under every labelling, written once for `stress`, `count` and `walk`: `own`
/// (under the cases' or mesh's own labelling, the identity) each beside the same numbers under
/// labellings `1..n`, which `again(k)` measures in the same order.
pub fn under_labellings<E>(
    own: Vec<u64>,
    n: usize,
    mut again: impl FnMut(usize) -> Result<Vec<u64>, E>,
) -> Result<Vec<Vec<u64>>, E> {
    let mut all: Vec<Vec<u64>> = own.into_iter().map(|w| vec![w]).collect();
    for k in 1..n {
        for (a, w) in all.iter_mut().zip(again(k)?) {
            a.push(w);
        }
    }
    Ok(all)
}
