//! Speed tables: walk speed per method and backend, and seed 004 Figure 5's packet speed.

use crate::choice::Choice;
use crate::engine::bench::{BenchReport, PACKETS, SpeedReport};

impl BenchReport {
    pub fn markdown(&self) -> String {
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

impl SpeedReport {
    pub fn markdown(&self) -> String {
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
