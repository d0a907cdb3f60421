//! The engine: runs that compute, for every family ([`crate::family`]) — stress tables and campaigns,
//! found cases, their checks and replay, the fuzz targets' policy, counts over a scene's views, walk
//! speed and the seeds' tables — returning plain tallies and records of wrong answers. Reports
//! (`crate::report`) only format what these return.

pub mod answerer;
pub mod answering;
pub mod bench;
pub mod count;
pub mod filing;
pub mod filters;
pub mod found;
pub mod fuzz;
pub mod info;
pub mod paper;
pub mod replay;
pub mod shrink;
pub mod standing;
pub mod stress;
pub mod verify;
pub mod view;

/// Most memory a run may plan to hold at once; larger runs are refused with the figure they need.
pub const MEMORY_BUDGET: u64 = 8 << 30;

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

/// Sorted numbers as runs of consecutive ones: `0, 1, 2, 4` as `0..=2` and `4..=4`.
pub fn runs(sorted: &[usize]) -> Vec<std::ops::RangeInclusive<usize>> {
    let mut out: Vec<std::ops::RangeInclusive<usize>> = Vec::new();
    for &n in sorted {
        match out.last_mut() {
            Some(r) if *r.end() + 1 == n => *r = *r.start()..=n,
            _ => out.push(n..=n),
        }
    }
    out
}

/// A run written `a-b`, or `a` alone.
pub fn run_text(r: &std::ops::RangeInclusive<usize>) -> String {
    if r.start() == r.end() {
        r.start().to_string()
    } else {
        format!("{}-{}", r.start(), r.end())
    }
}

#[cfg(test)]
mod tests {
    /// Each number keeps its place: the own labelling's first, then labelling 1, 2, … in order; the
    /// first error stops the runs.
    #[test]
    fn under_labellings_puts_each_number_beside_its_own() {
        let all = super::under_labellings(vec![7, 9], 3, |k| Ok::<_, ()>(vec![10 * k as u64, 100]))
            .unwrap();
        assert_eq!(all, vec![vec![7, 10, 20], vec![9, 100, 100]]);
        let mut ran = Vec::new();
        let e = super::under_labellings(vec![1], 4, |k| {
            ran.push(k);
            if k == 2 { Err("at 2") } else { Ok(vec![0]) }
        });
        assert_eq!((e, ran), (Err("at 2"), vec![1, 2]));
    }
}
