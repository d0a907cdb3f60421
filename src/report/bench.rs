//! Speed tables: walk speed per method and backend, and seed 004 Figure 5's packet speed.

use crate::choice::Choice;
use crate::engine::bench::BenchReport;

impl BenchReport {
    pub(crate) fn markdown(&self) -> String {
        let mut out = format!(
            "walk speed on {} ({} tetrahedra{}): {} of {} of {}x{} inside the mesh, {} rays at most per batch\n\n",
            self.scene,
            self.tetrahedra_in_mesh,
            if self.hilbert {
                ", in Hilbert order"
            } else {
                ""
            },
            self.views_timed,
            super::counted(self.views.views as u64, "view", "views"),
            self.views.width,
            self.views.height,
            self.batch
        );
        for b in &self.backends {
            use crate::choice::Instruction::{Avx2, Fma};
            let how = match b.kind.model().map(|m| m.instruction()) {
                Some(Fma) if self.fma_instruction => " (on the FMA instruction)",
                Some(Fma) => {
                    " (through f32::mul_add: no FMA instruction here, or TETWALK_NO_FMA=1)"
                }
                Some(Avx2) if self.avx2 => " (compiled for AVX2)",
                Some(Avx2) => " (compiled for SSE2: no AVX2 here, or TETWALK_NO_AVX2=1)",
                None => "",
            };
            out += &format!("- {b}{how}\n");
        }
        out += "\n";
        let compared = self.rows.iter().any(|r| r.change.is_some());
        out += "| method | layout | backend | rays | Φ (tetrahedra/ray) | end to end Mrays/s | median Mrays/s [min, max] of samples | end to end Mtets/s | kernel Mrays/s | kernel Mtets/s | flagged |";
        out += if compared { " vs baseline |\n" } else { "\n" };
        out += "|---|---|---|---|---|---|---|---|---|---|---|";
        out += if compared { "---|\n" } else { "\n" };
        for r in &self.rows {
            let per = |n: u64, s: f64| format!("{:.1}", n as f64 / s.max(1e-12) / 1e6);
            let kernel = |n: u64| r.kernel_seconds.map_or("-".to_string(), |k| per(n, k));
            let spread = r.spread.map_or("-".to_string(), |s| {
                format!(
                    "{:.1} [{:.1}, {:.1}] of {}",
                    s.median, s.low, s.high, s.samples
                )
            });
            out += &format!(
                "| {} | {} | {} | {} | {:.1} | {} | {spread} | {} | {} | {} | {} |",
                r.method,
                r.layout,
                r.backend.name(),
                r.rays,
                r.tetrahedra as f64 / r.rays.max(1) as f64,
                per(r.rays, r.seconds),
                per(r.tetrahedra, r.seconds),
                kernel(r.rays),
                kernel(r.tetrahedra),
                r.flagged
            );
            if compared {
                out += &match &r.change {
                    Some(c) => format!(
                        " {:.2}× of {:.1} ({:.2}–{:.2}× by batch): {} |",
                        c.ratio, c.baseline_median, c.ratio_range.0, c.ratio_range.1, c.verdict
                    ),
                    None => " - |".to_string(),
                };
            }
            out += "\n";
        }
        out
    }
}
