//! Count tables: per method, wrong rays per image by kind, the work per image and speed, then the
//! totals (seed 000 Table 4's measure, for every family that counts a scene).

use super::relabel_spread;
use crate::engine::count::CountReport;
use crate::family::count::{Counted, Counts};
use crate::family::{OctreeCells, Triangle, Walks};
use crate::walk::OutcomeKind;

/// How a counted family's count reads.
pub trait CountFormats: Counted {
    fn count_table(r: &CountReport<Self>) -> String;
}

/// A count's last line: each method's wrong rays over all the rays counted.
pub fn totals<F: Counted>(r: &CountReport<F>) -> String {
    let each: Vec<String> = r
        .methods
        .iter()
        .map(|m| format!("{} {}", m.method, m.counts.wrong_total()))
        .collect();
    format!("\ntotals over {} rays: {}\n", r.rays, each.join(", "))
}

/// The wrong rays under the 12 relabellings, per method that has them.
fn relabellings<F: Counted>(r: &CountReport<F>) -> String {
    let mut out = String::new();
    for m in &r.methods {
        if let Some(w) = &m.relabelled {
            out += &format!("| {} | {} |\n", m.method, relabel_spread(w));
        }
    }
    if out.is_empty() {
        return out;
    }
    "\nwrong rays under the 12 orientation-preserving relabellings of the tetrahedra\n\n| method | own labelling | min | median | max |\n|---|---|---|---|---|\n".to_string() + &out
}

/// On a GPU, what each row's answers moved between the CPU and the GPU, per ray, and the kernels'
/// share of its wall time.
fn transfers<F: Counted>(r: &CountReport<F>) -> String {
    let mut out = String::new();
    for m in &r.methods {
        if let Some(t) = &m.transfer {
            let share = t
                .kernel_share
                .map_or("-".into(), |k| format!("{:.1}%", 100.0 * k));
            out += &format!(
                "| {} | {:.1} | {:.1} | {} | {share} |\n",
                m.method, t.bytes_written_per_ray, t.bytes_read_per_ray, t.total.dispatches
            );
        }
    }
    if out.is_empty() {
        return out;
    }
    "\nbetween the CPU and the GPU, per ray counted\n\n| method | bytes written | bytes read back | dispatches | kernels' share of the wall time |\n|---|---|---|---|---|\n".to_string() + &out
}

/// `(audited against … on N rays, all agreeing)`, or nothing when no ray was audited.
fn audited<F: Counted>(r: &CountReport<F>, against: &str) -> String {
    if r.audited > 0 {
        format!(
            " (audited against {against} on {} rays, all agreeing)",
            r.audited
        )
    } else {
        String::new()
    }
}

impl CountFormats for Walks {
    /// Per method, wrong rays per image by kind (wrong faces also split into adjacent and
    /// elsewhere), Φ per image, and speed; then the totals.
    fn count_table(r: &CountReport<Self>) -> String {
        let s = &r.settings.views;
        let mut out = format!(
            "scene {} ({} tetrahedra), {} of {}x{}, backend {}, seed {}, reference {}{}; per image, averaged over views\n\n",
            r.settings.scene,
            r.scene.tetrahedra,
            super::counted(r.views_counted as u64, "view", "views"),
            s.width,
            s.height,
            r.backend,
            s.seed,
            r.settings.reference,
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
        out + &totals(r) + &relabellings(r) + &transfers(r)
    }
}

impl CountFormats for Triangle {
    fn count_table(r: &CountReport<Self>) -> String {
        let s = &r.settings;
        let mut out = format!(
            "scene {} ({} triangles: its constrained faces, each facing the cameras' side), {} of {}x{}, \
             packets of {}x{} primary rays, backend {}, seed {}, {}, each nearest hit judged against the {} walk's exact first hit{}\n\n",
            s.scene,
            r.scene.triangles,
            super::counted(r.views_counted as u64, "view", "views"),
            s.views.width,
            s.views.height,
            s.family.packet,
            s.family.packet,
            r.backend,
            s.views.seed,
            if crate::family::triangle::binned_on(&s.family, r.backend.kind) {
                "each tile's candidate triangles tested per ray (src/family/bins.rs: none a method could hit is left out; on the audited rays every method also tested against every triangle, agreeing)"
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
        out + &relabellings(r) + &transfers(r)
    }
}

impl CountFormats for OctreeCells {
    fn count_table(r: &CountReport<Self>) -> String {
        let s = &r.settings;
        let mut out = format!(
            "scene {} ({} triangles: its constrained faces, each facing the cameras' side), octree of depth {} and leaf capacity {} ({} leaves; {} without the regularity constraint), {} of {}x{}, seed {}, backend {}, each leaf's triangles tested with {}; each walk judged against the {} walk's exact first hit (the exact octree walk audited against it on {} rays, all agreeing)\n\n",
            s.scene,
            r.scene.triangles,
            s.family.octree.depth,
            s.family.octree.capacity,
            r.scene.leaves,
            r.scene.unconstrained_leaves,
            super::counted(r.views_counted as u64, "view", "views"),
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
        out + &totals(r) + &relabellings(r) + &transfers(r)
    }
}
