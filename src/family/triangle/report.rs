//! How the ray–triangle family reads: its stress tables (by aim, place and shape), count table,
//! verdict lines and seed 004 Figure 5's measure (the report layer: formatting only, as `crate::report` calls it).

use super::engine::{PACKETS, SpeedReport};
use super::{HitTally, Hits, Triangle, binned_on};
use crate::choice::Choice;
use crate::engine::count::CountReport;
use crate::engine::stress::{RowReport, StressReport};
use crate::exact::hit::HitTruth;
use crate::family::Said;
use crate::report::count::{CountFormats, audited, relabellings as count_relabellings, transfers};
use crate::report::lines::{Lines, fields};
use crate::report::stress::{per_million, relabellings, rounds, seeds};
use crate::report::{Formats, counted};
use serde_json::{Map, Value, json};

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
            let sum = |f: fn(&HitTally) -> u64| -> u64 {
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

impl CountFormats for Triangle {
    fn count_table(r: &CountReport<Self>) -> String {
        let s = &r.settings.count;
        let mut out = format!(
            "scene {} ({} triangles: its constrained faces, each facing the cameras' side), {} of {}x{}, \
             packets of {}x{} primary rays, backend {}, seed {}, {}, each nearest hit judged against the {} walk's exact first hit{}\n\n",
            r.settings.scene,
            r.scene.triangles,
            counted(r.views_counted as u64, "view", "views"),
            s.views.width,
            s.views.height,
            s.family.packet,
            s.family.packet,
            r.backend,
            s.views.seed,
            if binned_on(&s.family, r.backend.kind) {
                "each tile's candidate triangles tested per ray (src/family/triangle/bins.rs: none a method could hit is left out; on the audited rays every method also tested against every triangle, agreeing)"
            } else {
                "every triangle tested per ray (brute force)"
            },
            s.reference,
            audited(r, "the exact first hit among the triangles"),
        );
        out += "| method | wrong rays per image | wrong triangle | false miss | Mrays/s |\n|---|---|---|---|---|\n";
        for m in &r.methods {
            out += &format!(
                "| {} | {:.3} | {} | {} | {:.3} |\n",
                m.method,
                m.counts.wrong_per_image,
                m.counts.wrong_triangle,
                m.counts.false_miss,
                m.mrays_per_second
            );
        }
        out += &format!("\ntotals over {} rays\n", r.rays);
        out + &count_relabellings(r) + &transfers(r)
    }
}

impl Lines for Triangle {
    /// Judged by the family's one rule ([`HitTruth::judge`]: the triangle and, for a hit, its `t`);
    /// on a closed mesh, every triangle the method reports says whether the ray leaks.
    fn verdict_line(
        case: &crate::cases::HitCase,
        truth: &HitTruth,
        hits: &Hits,
        said: &Said,
    ) -> Map<String, Value> {
        let g = hits.nearest();
        let ok = said.correct == Some(true);
        let first = truth.first();
        let mut o = fields(json!({
            "hit": g.is_some(), "t": g.map(|(_, t)| t), "t_ulps": said.t_ulps,
            "exact_hit": first.is_some(), "exact_t": first.map(|p| ratio(&p.t)),
        }));
        if case.closed {
            o.insert("tri".into(), json!(g.map(|(i, _)| i)));
            let holding = first.map_or(vec![], |p| p.holding.clone());
            let boundary = holding.iter().any(|&i| truth.each[i as usize].on_boundary);
            o.insert("exact_tris".into(), json!(holding));
            o.insert("on_boundary".into(), Value::Bool(boundary));
            o.insert("crosses".into(), json!(first.map(|p| p.crosses)));
            o.insert("leak".into(), Value::Bool(said.leak));
            o.insert(
                "kind".into(),
                json!(said.kind.unwrap_or(if ok { "right" } else { "t" })),
            );
            if crate::exact::hit::inside_out(case.tris()) {
                o.insert("inside_out".into(), Value::Bool(true));
            }
        } else {
            o.insert("on_boundary".into(), Value::Bool(truth.each[0].on_boundary));
        }
        if said.back_face {
            o.insert("back_face".into(), Value::Bool(true));
        }
        o.insert("correct".into(), Value::Bool(ok));
        o
    }
}

/// A rational as `p/q`.
fn ratio(q: &rug::Rational) -> String {
    format!("{}/{}", q.numer(), q.denom())
}

impl SpeedReport {
    /// Seed 004 Figure 5's measure as a table, with what it measured.
    pub(crate) fn markdown(&self) -> String {
        let mut out = format!(
            "seed 004 Figure 5's measure: scene {} ({} triangles), one view of {}x{} ({} primary rays), \
             each ray against its tile's candidate triangles (src/family/triangle/bins.rs, as the triangle count tests \
             them, for the method's error scale; tests per ray in 2x2 packets: {}), one thread, best of {}; \
             speedup = mt-precomputed's time per test (the paper's \"improved Möller\" baseline) in packets \
             of the same size and width over the method's; every method loops over triangles outside and \
             the packet's rays inside, the single-ray methods testing ray by ray; \"4-wide\": the SSE \
             version (four rays of a packet at once, the same answers bit for bit)\n\n",
            self.scene,
            self.triangles,
            self.views.width,
            self.views.height,
            self.rays,
            self.tests
                .iter()
                .map(|(m, n)| format!("{m} {:.1}", *n as f64 / self.rays.max(1) as f64))
                .collect::<Vec<_>>()
                .join(", "),
            self.repeats
        );
        out += "| method |";
        for p in PACKETS {
            out += &format!(" {p}x{p}: ns/test | speedup |");
        }
        out += "\n|---|";
        out += &"---|---|".repeat(PACKETS.len());
        out += "\n";
        let mut names: Vec<(&str, bool)> = Vec::new();
        for r in &self.rows {
            if !names.contains(&(r.method.as_str(), r.wide)) {
                names.push((&r.method, r.wide));
            }
        }
        names.sort_by_key(|n| n.1);
        for (n, wide) in names {
            out += &format!("| {n}{} |", if wide { ", 4-wide" } else { "" });
            for p in PACKETS {
                match self
                    .rows
                    .iter()
                    .find(|r| r.method == n && r.wide == wide && r.packet == p)
                {
                    Some(r) => out += &format!(" {:.2} | {:.2} |", r.ns_per_test, r.speedup),
                    None => out += " - | - |",
                }
            }
            out += "\n";
        }
        let at2 = |n: &str, wide: bool| {
            self.rows
                .iter()
                .find(|r| r.method == n && r.wide == wide && r.packet == 2)
                .map(|r| r.ns_per_test)
        };
        if let (Some(k), Some(m)) = (at2("komatsu-packet", true), at2("mt-precomputed", false)) {
            out += &format!(
                "\nkomatsu-packet 4-wide over scalar mt-precomputed in 2x2 packets: {:.2}x; over 4-wide mt-precomputed: {}; plucker-packet 4-wide over scalar mt-precomputed: {}.\n",
                m / k,
                at2("mt-precomputed", true).map_or("-".into(), |w| format!("{:.2}x", w / k)),
                at2("plucker-packet", true).map_or("-".into(), |p| format!("{:.2}x", m / p)),
            );
        }
        out += "\nseed 004 (Figure 5) reports 1.1x to 1.4x for its packet method over the improved Möller test \
                (2x2 primary-ray packets, 256x256 images, a Pentium 4 with SIMD), the Plücker packet test \
                below it\n";
        out
    }
}
