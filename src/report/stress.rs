//! Stress tables: per row and method, each family's failures per million judged cases; the backends'
//! disagreements; the labellings' spread.

use super::{counted, relabel_spread};
use crate::choice::Choice;
use crate::engine::filing::Filing;
use crate::engine::stress::{Disagreements, StressReport};
use crate::family::Family;

/// Failures per million of `of` judged, rounded, or "—" where nothing was judged (a row whose every
/// case left f32's range at its scale): not a rate of zero.
pub(crate) fn per_million(n: u64, of: u64) -> String {
    match of {
        0 => "—".into(),
        _ => format!("{:.0}", n as f64 * 1e6 / of as f64),
    }
}

/// `" in each of R rounds"` for a campaign's summed report, else nothing.
pub(crate) fn rounds<F: Family>(r: &StressReport<F>) -> String {
    match r.rounds {
        1 => String::new(),
        n => format!(" in each of {n} rounds"),
    }
}

/// `seed S`, or over a campaign's rounds `seeds S to T`; and the scale the cases were taken at,
/// unless 1.
pub(crate) fn seeds<F: Family>(r: &StressReport<F>) -> String {
    let seed = r.settings.seed;
    let seeds = match r.rounds {
        1 => format!("seed {seed}"),
        n => format!("seeds {seed} to {}", seed.wrapping_add(n - 1)),
    };
    match r.settings.scale {
        s if s.is_one() => seeds,
        s => format!("{seeds}, every case scaled by {s}"),
    }
}

/// A table with a row per stress row and a column per method, each cell `cell(tally)`.
pub(crate) fn table<F: Family>(r: &StressReport<F>, cell: impl Fn(&F::Tally) -> String) -> String {
    let mut out = format!("| row | judged | {} |\n", r.methods.join(" | "));
    out += &format!("|---|---|{}\n", "---|".repeat(r.methods.len()));
    for row in &r.rows {
        let judged = row
            .tallies
            .first()
            .map_or(0, |t| F::judged(&row.facts, &t.counts));
        let cells: Vec<String> = row.tallies.iter().map(|t| cell(&t.counts)).collect();
        out += &format!(
            "| {} | {} | {} |\n",
            F::row_label(&row.row, &r.settings.contract),
            judged,
            cells.join(" | ")
        );
    }
    let unjudged: Vec<String> = r
        .rows
        .iter()
        .filter(|row| {
            row.tallies
                .first()
                .is_some_and(|t| F::judged(&row.facts, &t.counts) == 0)
        })
        .map(|row| F::row_name(&row.row))
        .collect();
    if !unjudged.is_empty() {
        out += &format!(
            "\nnot judged: {} (no case of the row could be made {}at this scale)\n",
            unjudged.join(", "),
            if r.settings.contract.is_default() {
                String::new()
            } else {
                format!("within the contract ({}) ", r.settings.contract.describe())
            }
        );
    }
    out
}

/// `what` under every labelling, per row and method where any is wrong.
pub(crate) fn relabellings<F: Family>(r: &StressReport<F>, what: &str) -> String {
    let Some(all) = &r.relabelled else {
        return String::new();
    };
    let mut out = format!(
        "\n{what} under the {} orientation-preserving relabellings\n\n",
        F::LABELLINGS
    );
    out += "| row | method | own labelling | min | median | max |\n|---|---|---|---|---|---|\n";
    for x in all.iter().filter(|x| x.wrong.iter().any(|&w| w > 0)) {
        out += &format!(
            "| {} | {} | {} |\n",
            F::row_name(&x.row),
            x.method,
            relabel_spread(&x.wrong)
        );
    }
    out
}

/// The comparison's table: per row and method, cases cpu ≠ cpu-fma / cpu ≠ gpu / cpu-fma ≠ gpu.
pub(crate) fn disagreements<F: Family>(d: &Disagreements<F>) -> String {
    let models: Vec<&str> = d
        .rows
        .first()
        .and_then(|r| r.methods.first())
        .map(|p| p.gpu_vs.iter().map(|(k, _)| k.name()).collect())
        .unwrap_or_default();
    let mut out = format!(
        "GPU {}; cells: the cases it answers otherwise than {}, out of the row's\n\n",
        d.gpu,
        models.join(" / ")
    );
    out += &format!(
        "| row | cases | {} |\n|---|---|{}\n",
        d.methods.join(" | "),
        "---|".repeat(d.methods.len())
    );
    for r in &d.rows {
        let cells: Vec<String> = r
            .methods
            .iter()
            .map(|p| {
                let n: Vec<String> = p.gpu_vs.iter().map(|(_, n)| n.to_string()).collect();
                n.join(" / ")
            })
            .collect();
        out += &format!(
            "| {} | {} | {} |\n",
            F::row_name(&r.row),
            r.cases,
            cells.join(" | ")
        );
    }
    out
}

/// What a campaign filed, after its table: wrong answers seen in its rounds, the new found cases and
/// where.
pub(crate) fn filed(f: &Filing, rounds: u64) -> String {
    let mut out = format!(
        "\n{} in {}; {} filed under {} (at most {} per method, row and kind):\n",
        counted(f.seen, "wrong answer", "wrong answers"),
        counted(rounds, "round", "rounds"),
        counted(f.filed.len() as u64, "new found case", "new found cases"),
        f.dir.display(),
        f.keep
    );
    for p in &f.filed {
        out += &format!("  {}\n", p.display());
    }
    out
}
