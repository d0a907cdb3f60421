//! How the octree family reads: its stress table, count table and verdict lines (the report layer:
//! formatting only, as `crate::report` calls it).

use super::{CellExit, OctreeCells};
use crate::engine::count::CountReport;
use crate::engine::stress::StressReport;
use crate::exact::boxes::BoxExit;
use crate::family::Said;
use crate::octree::cell::FACE_NAMES;
use crate::report::count::{CountFormats, relabellings as count_relabellings, totals, transfers};
use crate::report::lines::{Lines, fields};
use crate::report::stress::{per_million, relabellings, rounds, seeds, table};
use crate::report::{Formats, counted};
use crate::walk::OutcomeKind;
use serde_json::{Map, Value, json};

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

impl CountFormats for OctreeCells {
    fn count_table(r: &CountReport<Self>) -> String {
        let s = &r.settings.count;
        let mut out = format!(
            "scene {} ({} triangles: its constrained faces, each facing the cameras' side), octree of depth {} and leaf capacity {} ({} leaves; {} without the regularity constraint), {} of {}x{}, seed {}, backend {}, each leaf's triangles tested with {}; each walk judged against the {} walk's exact first hit (the exact octree walk audited against it on {} rays, all agreeing)\n\n",
            r.settings.scene,
            r.scene.triangles,
            s.family.octree.depth,
            s.family.octree.capacity,
            r.scene.leaves,
            r.scene.unconstrained_leaves,
            counted(r.views_counted as u64, "view", "views"),
            s.views.width,
            s.views.height,
            s.views.seed,
            r.backend,
            s.family.triangle_method,
            s.reference,
            r.audited
        );
        out += &format!(
            "| method | wrong rays per image | {} | cells per ray | Mrays/s |\n|---|---|---|---|---|---|---|---|---|\n",
            OutcomeKind::ALL.map(|k| k.wrong()).join(" | ")
        );
        for m in &r.methods {
            out += &format!(
                "| {} | {:.3} | {} | {:.2} | {:.3} |\n",
                m.method,
                m.counts.wrong_per_image,
                m.counts.wrong.map(|n| n.to_string()).join(" | "),
                m.counts.cells as f64 / r.rays.max(1) as f64,
                m.mrays_per_second
            );
        }
        out + &totals(r) + &count_relabellings(r) + &transfers(r)
    }
}

impl Lines for OctreeCells {
    fn verdict_line(
        _: &crate::cases::BoxCase,
        x: &BoxExit,
        a: &CellExit,
        said: &Said,
    ) -> Map<String, Value> {
        let mut quarters = Map::new();
        for (f, q) in x.faces.iter().zip(&x.quarters) {
            quarters.insert(FACE_NAMES[*f].into(), json!(q));
        }
        fields(json!({
            "face": a.map(|(f, _)| FACE_NAMES[f as usize]),
            "quarter": a.map(|(_, q)| q),
            "exact_faces": x.faces.iter().map(|&f| FACE_NAMES[f]).collect::<Vec<_>>(),
            "exact_quarters": quarters,
            "correct": said.correct,
        }))
    }
}
