//! `tetwalk shrink`'s lines: each case shrunk (what it took, the case, the line that reproduces it),
//! and the run summed up.

use super::counted;
use crate::engine::shrink::{CaseShrunk, ShrinkReport};

/// A case shrunk, `at` naming where it was: what it took, the shrunk case, and the line that
/// reproduces it, each line ending in a newline.
pub(crate) fn case_lines(at: &str, done: &CaseShrunk) -> String {
    let mut out = format!(
        "{at}: {} on {}: {} -> {} significant bits in {} numbers (at most {} -> {} in one), clearance {:.3} -> {:.3}, {} checks{}{}\n  {}\n",
        done.method,
        done.backend,
        done.bits_before,
        done.bits_after,
        done.numbers,
        done.largest_before,
        done.largest_after,
        done.clearance_before,
        done.clearance_after,
        done.checks,
        if done.exhausted { ", budget spent" } else { "" },
        if done.simpler() {
            ""
        } else {
            ": already as simple as the search finds"
        },
        done.shrunk
    );
    if let Some(r) = &done.reproduce {
        out += &format!("  reproduce: {r}\n");
    }
    out
}

/// The run summed up: cases shrunk (and written back, `in_place`), already simple, left; the mean
/// significant bits per number before and after, where a case was shrunk.
pub(crate) fn summary(r: &ShrinkReport, in_place: bool) -> String {
    let simpler = r.cases.iter().filter(|d| d.simpler()).count();
    let bits = match r.mean_bits() {
        None => String::new(),
        Some((before, after)) => {
            format!("; significant bits per number, mean {before:.1} -> {after:.1}")
        }
    };
    format!(
        "tetwalk shrink: {} shrunk{}, {} already as simple as the search finds, {} left as they were (each with its reason above){bits}",
        counted(simpler as u64, "case", "cases"),
        if in_place { " and written back" } else { "" },
        r.cases.len() - simpler,
        r.left.len(),
    )
}
