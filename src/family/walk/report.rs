//! How the walk family reads: its stress table, count table and verdict lines (the report layer:
//! formatting only, as `crate::report` calls it).

use super::engine::{RelabelledWalks, WalkReport};
use super::{WalkTruth, Walks};
use crate::engine::count::CountReport;
use crate::engine::stress::StressReport;
use crate::family::{Family, Said};
use crate::report::count::{
    CountFormats, audited, relabellings as count_relabellings, totals, transfers,
};
use crate::report::lines::{Lines, fields};
use crate::report::stress::{per_million, relabellings, rounds, seeds, table};
use crate::report::{Formats, counted, relabel_spread};
use crate::walk::{OutcomeKind, Walk};
use serde_json::{Map, Value, json};

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

impl CountFormats for Walks {
    /// Per method, wrong rays per image by kind (wrong faces also split into adjacent and
    /// elsewhere), Φ per image, and speed; then the totals.
    fn count_table(r: &CountReport<Self>) -> String {
        let s = &r.settings.count.views;
        let mut out = format!(
            "scene {} ({} tetrahedra), {} of {}x{}, backend {}, seed {}, reference {}{}; per image, averaged over views\n\n",
            r.settings.scene,
            r.scene.tetrahedra,
            counted(r.views_counted as u64, "view", "views"),
            s.width,
            s.height,
            r.backend,
            s.seed,
            r.settings.count.reference,
            audited(r, "exact"),
        );
        out += &format!(
            "| method | wrong rays | {} | wrong face adjacent | wrong face elsewhere | Φ (tetrahedra) | Mrays/s |\n",
            OutcomeKind::ALL.map(|k| k.wrong()).join(" | ")
        );
        out += &format!(
            "|---|---|{}---|---|---|---|\n",
            "---|".repeat(OutcomeKind::ALL.len())
        );
        for m in &r.methods {
            let p = &m.counts.per_image;
            let kinds: Vec<String> = p.by_kind.0.iter().map(|w| format!("{w:.3}")).collect();
            let speed = if m.seconds > 0.0 {
                format!("{:.2}", m.mrays_per_second)
            } else {
                "-".into()
            };
            out += &format!(
                "| {} | {:.3} | {} | {:.3} | {:.3} | {:.0} | {speed} |\n",
                m.method,
                p.wrong,
                kinds.join(" | "),
                p.wrong_face_adjacent,
                p.wrong_face_elsewhere,
                p.tetrahedra,
            );
        }
        out + &totals(r) + &count_relabellings(r) + &transfers(r)
    }
}

impl Lines for Walks {
    fn verdict_line(
        _: &crate::cases::WalkCase,
        t: &WalkTruth,
        got: &Walk,
        said: &Said,
    ) -> Map<String, Value> {
        fields(json!({
            "walk": got.outcome, "steps": got.steps, "exact_walk": t.exact.outcome, "correct": said.correct,
        }))
    }
}

/// `tetwalk walk`'s heading: the mesh, the rays and what walked them (`walked_by`).
pub(super) fn walk_heading(r: &WalkReport, walked_by: &str) -> String {
    format!(
        "mesh {:?} size {} offset {} ({} tetrahedra), {} rays, seed {}, {walked_by}{}\n",
        r.mesh,
        r.size,
        r.offset,
        r.tetrahedra,
        r.rays,
        r.seed,
        if r.outside > 0 {
            format!(
                ", {} starting outside skipped",
                counted(r.outside as u64, "ray", "rays")
            )
        } else {
            String::new()
        },
    )
}

/// `tetwalk walk`'s table: per method how its walks ended, its wrong results, its diverged walks
/// ("-" where not measured: over a layout, or unless `checked`) and its mean steps.
pub(super) fn walk_table(r: &WalkReport, checked: bool) -> String {
    let mut out = "| method | hit | left mesh | no exit face | cycle | step limit | wrong result | diverged | mean steps |\n|---|---|---|---|---|---|---|---|---|\n".to_string();
    for row in &r.methods {
        let (s, k) = (&row.tally, row.tally.kinds);
        let name = row
            .layout
            .map_or(row.method.clone(), |k| format!("{} ({k:?})", row.method));
        let diverged = if row.layout.is_some() || !checked {
            "-".to_string()
        } else {
            s.diverged.to_string()
        };
        out += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {:.2} |\n",
            name,
            k[0],
            k[1],
            k[2],
            k[3],
            k[4],
            s.wrong,
            diverged,
            s.steps as f64 / s.rays.max(1) as f64
        );
    }
    out
}

/// `tetwalk walk --relabel all`'s table: per method its wrong results and cycles under its own
/// labelling beside their min / median / max over the 12.
pub(super) fn relabelled_table(r: &[RelabelledWalks]) -> String {
    let mut out = "\nunder the 12 orientation-preserving relabellings of the tetrahedra\n\n| method | wrong, own | min | median | max | cycles, own | min | median | max |\n|---|---|---|---|---|---|---|---|---|\n".to_string();
    for r in r {
        out += &format!(
            "| {} | {} | {} |\n",
            r.method,
            relabel_spread(&r.wrong),
            relabel_spread(&r.cycles)
        );
    }
    out
}
