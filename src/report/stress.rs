//! Stress tables: per row and method, each family's failures per million judged cases; the backends'
//! disagreements; the labellings' spread.

use super::{Formats, relabel_spread};
use crate::engine::stress::{Disagreements, RowReport, StressReport};
use crate::family::{ExitFace, Family, OctreeCells, Triangle, Walks};
use crate::walk::OutcomeKind;

/// Failures per million of `of` judged, rounded, or "—" where nothing was judged (a row whose every
/// case left f32's range at its scale): not a rate of zero.
pub fn per_million(n: u64, of: u64) -> String {
    match of {
        0 => "—".into(),
        _ => format!("{:.0}", n as f64 * 1e6 / of as f64),
    }
}

/// `" in each of R rounds"` for a campaign's summed report, else nothing.
fn rounds<F: Family>(r: &StressReport<F>) -> String {
    match r.rounds {
        1 => String::new(),
        n => format!(" in each of {n} rounds"),
    }
}

/// `seed S`, or over a campaign's rounds `seeds S to T`; and the scale the cases were taken at,
/// unless 1.
fn seeds<F: Family>(r: &StressReport<F>) -> String {
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
fn table<F: Family>(r: &StressReport<F>, cell: impl Fn(&F::Tally) -> String) -> String {
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
            F::row_name(&row.row),
            judged,
            cells.join(" | ")
        );
    }
    out
}

/// `what` under every labelling, per row and method where any is wrong.
fn relabellings<F: Family>(r: &StressReport<F>, what: &str) -> String {
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

impl Formats for ExitFace {
    /// Per row and method, wrong exit faces / "no exit face", per million judged cases.
    fn stress_table(r: &StressReport<Self>) -> String {
        let s = &r.settings;
        let offset = match s.rows.offset {
            0.0 => String::new(),
            d => format!(", every case moved {d} along (1, 1, 1)"),
        };
        let contract = match s.contract.is_default() {
            true => String::new(),
            false => format!(", within the contract: {}", s.contract.describe()),
        };
        let mut out = format!(
            "{} cases per row{}, {}, {}, flatness {}, near-* within {} ulps of each case's largest coordinate{offset}{contract}; cells: wrong face / no exit face per million judged cases\n\n",
            s.cases,
            rounds(r),
            seeds(r),
            s.backend,
            s.rows.flatness,
            s.rows.ulps
        );
        out += &table(r, |t| {
            format!(
                "{} / {}",
                per_million(t.wrong_face, t.judged),
                per_million(t.no_exit_face, t.judged)
            )
        });
        out += &format!(
            "\noracle: {} signs decided by the f64 filter, {} exactly\n",
            r.oracle.filter, r.oracle.exact
        );
        out + &relabellings(r, "wrong answers (wrong face or no exit face)")
    }
}

impl Formats for Walks {
    /// Per scene and method, wrong walks per million (of which endless: cycles and step limits).
    fn stress_table(r: &StressReport<Self>) -> String {
        let mut out = format!(
            "{} rays per row{}, {}, {}; each walk judged against the exact walk (itself checked against the brute-force first hit); cells: wrong walks (endless: cycle or step limit) per million walks\n\n",
            r.settings.cases,
            rounds(r),
            seeds(r),
            r.settings.backend
        );
        out += &table(r, |t| {
            let endless = [OutcomeKind::Cycle, OutcomeKind::StepLimit]
                .map(|k| t.wrong.0[k.code() as usize])
                .iter()
                .sum();
            format!(
                "{} ({})",
                per_million(Self::wrong(t), t.judged),
                per_million(endless, t.judged)
            )
        });
        out + &relabellings(r, "wrong answers")
    }
}

impl Formats for OctreeCells {
    /// Per row and method, wrong answers (of which wrong quarter / no exit face) per million.
    fn stress_table(r: &StressReport<Self>) -> String {
        let s = &r.settings;
        let mut out = format!(
            "{} cells and rays per row{}, {}, {}, near-* within {} ulps of each case's largest coordinate; cells: wrong (of which wrong quarter / no exit face) per million judged cases\n\n",
            s.cases,
            rounds(r),
            seeds(r),
            s.backend,
            s.rows.ulps
        );
        out += &table(r, |t| {
            format!(
                "{} ({} / {})",
                per_million(t.wrong, t.judged),
                per_million(t.wrong_quarter, t.judged),
                per_million(t.no_exit_face, t.judged)
            )
        });
        out + &relabellings(r, "wrong answers")
    }
}

impl Formats for Triangle {
    /// Per method, leaks, misses beside, double hits, wrong first hits and wrong `t`s per million rays,
    /// by aim, by place and by shape.
    fn stress_table(r: &StressReport<Self>) -> String {
        let s = &r.settings;
        let mut out = format!(
            "Ray-triangle stress: {} rays per row{}, {} rows, {}, backend {}, flatness {}, near rows within {} ulps of each case's largest coordinate.\n\
             Where the ray crosses the closed surface (every triangle holding the point faces one way along \
             it) and no triangle around the first crossing (sharing a vertex with one holding it) that faces \
             that way reports a hit: a leak when the crossing is at a shared edge or vertex, or when the \
             method sees the surface elsewhere along the ray (it passed through); a miss beside when \
             rounding may have carried the ray off the object (a silhouette within ulps, a chord inside \
             shorter than 2^-10 of the way, or, inside a triangle, no hit on the mesh at all). A double hit: a \
             triangle holding it and one the exact ray misses both report hits. A wrong first hit: the \
             nearest reported hit is on no triangle holding the first crossing point (or a point before \
             it the ray only touches), or a miss where the ray crosses. A wrong t: the right triangle at a \
             t beyond {} ulps of the exact one (the rule hit and judge apply). Per million rays.\n",
            s.cases,
            rounds(r),
            r.rows.len(),
            seeds(r),
            s.backend,
            s.rows.flatness,
            s.rows.ulps,
            crate::exact::hit::T_ULPS
        );
        out += &by(r, |x| x.row.aim.name(), "rays aimed");
        out += &by(r, |x| x.row.place.name(), "place");
        out += &by(r, |x| x.row.shape.name(), "shape");
        out + &relabellings(r, "wrong answers")
    }
}

use crate::choice::Choice;

/// Per method, a ray–triangle report's counts per million rays summed over the rows that `key` puts
/// together.
fn by(
    r: &StressReport<Triangle>,
    key: impl Fn(&RowReport<Triangle>) -> &'static str,
    what: &str,
) -> String {
    let mut keys: Vec<&str> = Vec::new();
    for row in &r.rows {
        if !keys.contains(&key(row)) {
            keys.push(key(row));
        }
    }
    let mut s = format!(
        "\n| method | {what} | rays | crossing | leaks /M | misses beside /M | double hits /M | wrong first hits /M | wrong t /M |\n|---|---|---|---|---|---|---|---|---|\n"
    );
    for (mi, m) in r.methods.iter().enumerate() {
        for &k in &keys {
            let rows: Vec<&RowReport<Triangle>> = r.rows.iter().filter(|x| key(x) == k).collect();
            let rays: u64 = rows.iter().map(|x| x.facts.rays).sum();
            let crossing: u64 = rows.iter().map(|x| x.facts.crossing).sum();
            let sum = |f: fn(&crate::family::triangle::HitTally) -> u64| -> u64 {
                rows.iter().map(|x| f(&x.tallies[mi].counts)).sum()
            };
            let pm = |n: u64| per_million(n, rays);
            s += &format!(
                "| {m} | {k} | {rays} | {crossing} | {} | {} | {} | {} | {} |\n",
                pm(sum(|t| t.leaks)),
                pm(sum(|t| t.misses_beside)),
                pm(sum(|t| t.double_hits)),
                pm(sum(|t| t.wrong_first_hits)),
                pm(sum(|t| t.wrong_t)),
            );
        }
    }
    s
}

/// The comparison's table: per row and method, cases cpu ≠ cpu-fma / cpu ≠ gpu / cpu-fma ≠ gpu.
pub fn disagreements<F: Family>(d: &Disagreements<F>) -> String {
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
