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
pub mod numbering;
pub mod paper;
pub mod replay;
pub mod shrink;
pub mod standing;
pub mod stress;
pub mod verify;
pub mod view;

/// Backends opened once each, or why one cannot be here: for runs that meet the same backend many
/// times (found cases, a dump's lines, the register's checks).
#[derive(Default)]
pub(crate) struct Backends(
    std::collections::HashMap<crate::choice::BackendKind, Result<crate::backend::Backend, String>>,
);

impl Backends {
    /// `kind`, opened the first time it is asked for, or why it cannot be.
    pub(crate) fn open(
        &mut self,
        kind: crate::choice::BackendKind,
    ) -> Result<&crate::backend::Backend, String> {
        self.0
            .entry(kind)
            .or_insert_with(|| crate::backend::Backend::open(kind).map_err(|e| e.to_string()))
            .as_ref()
            .map_err(Clone::clone)
    }
}

/// Most memory a run may plan to hold at once; larger runs are refused with the figure they need.
pub(crate) const MEMORY_BUDGET: u64 = 8 << 30;

/// Numbers measured under every labelling, written once for `stress`, `count` and `walk`: `own`
/// (under the cases' or mesh's own labelling, the identity) each beside the same numbers under
/// labellings `1..n`, which `again(k)` measures in the same order.
pub(crate) fn under_labellings<E>(
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
pub(crate) fn runs(sorted: &[usize]) -> Vec<std::ops::RangeInclusive<usize>> {
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
pub(crate) fn run_text(r: &std::ops::RangeInclusive<usize>) -> String {
    if r.start() == r.end() {
        r.start().to_string()
    } else {
        format!("{}-{}", r.start(), r.end())
    }
}

/// Line numbers (sorted) in runs, `line 7` or `lines 3, 7-9 and 12`: the first 8 runs, then how many
/// lines are left.
pub(crate) fn line_runs(lines: &[usize]) -> String {
    const RUNS: usize = 8;
    let runs = runs(lines);
    let shown: Vec<String> = runs.iter().take(RUNS).map(run_text).collect();
    let left: usize = runs.iter().skip(RUNS).map(|r| r.clone().count()).sum();
    match (shown.as_slice(), left) {
        ([one], 0) if lines.len() == 1 => format!("line {one}"),
        ([one], 0) => format!("lines {one}"),
        ([init @ .., last], 0) => format!("lines {} and {last}", init.join(", ")),
        _ => format!("lines {} and {left} more", shown.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    /// Line numbers read as a person writes them: one line, one run, several runs joined by `and`,
    /// and past 8 runs how many lines are left.
    #[test]
    fn line_runs_read_as_written() {
        assert_eq!(super::line_runs(&[7]), "line 7");
        assert_eq!(super::line_runs(&[3, 4]), "lines 3-4");
        assert_eq!(super::line_runs(&[3, 7, 8, 9, 12]), "lines 3, 7-9 and 12");
        let many: Vec<usize> = (0..12).map(|i| 3 * i).chain([40, 41]).collect();
        assert_eq!(
            super::line_runs(&many),
            "lines 0, 3, 6, 9, 12, 15, 18, 21 and 6 more"
        );
    }

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
