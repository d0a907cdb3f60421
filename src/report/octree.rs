//! Octree reports (seed 001): wrong exit faces and quarters per million cells and rays, per method
//! and row ([`stress`]), every answer judged exactly.

use crate::backend::{Backend, BackendError};
use crate::cases::{BoxCase, Subject};
use crate::choice::Choice;
use crate::exact::boxes::{BoxExit, box_exit};
use crate::found::{Answer, Failure, Record};
use crate::octree::cell::quarter_signs;
use crate::registry::OctreeMethod;
use crate::scenes::cells::{Aim, Place, case};
use rayon::prelude::*;

/// Settings of an octree stress run.
#[derive(Clone, Debug, serde::Serialize)]
pub struct StressSettings {
    /// Cases per row.
    pub cases: usize,
    pub aims: Vec<Aim>,
    pub places: Vec<Place>,
    pub seed: u64,
    pub backend: String,
    pub ulps: i32,
}

/// One method's counts on one row.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct CellTally {
    pub method: String,
    /// Cases whose line crosses the open cell (the others are not judged).
    pub judged: u64,
    /// A face through which the line does not leave, or the wrong quarter of one it does.
    pub wrong: u64,
    /// Of those, the right face but a wrong quarter (a wrong neighbour among four).
    pub wrong_quarter: u64,
    /// No exit face (eq. 8's 7).
    pub no_exit_face: u64,
}

/// One row: an aim and a place.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CellRow {
    pub aim: Aim,
    pub place: Place,
    pub tallies: Vec<CellTally>,
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct CellStressReport {
    pub settings: StressSettings,
    pub methods: Vec<String>,
    pub rows: Vec<CellRow>,
}

/// A row's cases with their exact answers; case `i` a pure function of the seed, the row and `i`.
fn row_cases(s: &StressSettings, aim: Aim, place: Place, row: u64) -> Vec<(BoxCase, BoxExit)> {
    (0..s.cases)
        .into_par_iter()
        .filter_map(|i| {
            let mut rng = crate::scenes::rng(
                s.seed
                    .wrapping_mul(0x9E37_79B9_7F4A_7C15)
                    .wrapping_add(row << 32 | i as u64),
            );
            let (lo, hi, ray) = case(aim, place, s.ulps, &mut rng);
            let c = BoxCase {
                lo,
                hi,
                org: ray.org,
                dir: ray.dir,
            };
            let x = box_exit(lo, hi, &ray).ok()?;
            Some((c, x))
        })
        .collect()
}

/// Every row of `s` (aims × places) with each method on the CPU backend `backend`; `wrong` sees each
/// wrong answer as a found case, with its row's name.
pub fn stress(
    s: &StressSettings,
    methods: &[&OctreeMethod],
    backend: &Backend,
    wrong: &mut dyn FnMut(&str, Record),
) -> Result<CellStressReport, BackendError> {
    let Backend::Cpu { fma } = backend else {
        return Err(BackendError::CpuOnly("the octree methods"));
    };
    let mut rows = Vec::new();
    for &aim in &s.aims {
        for &place in &s.places {
            let cases = row_cases(s, aim, place, rows.len() as u64);
            let name = format!("{}-{}", aim.name(), place.name());
            let mut tallies = Vec::new();
            for m in methods {
                let exit = m.exit(*fma);
                let mut t = CellTally {
                    method: m.name.into(),
                    ..CellTally::default()
                };
                let answers: Vec<_> = cases
                    .par_iter()
                    .map(|(c, _)| exit(c.lo, c.hi, &c.ray()).map(|(f, q)| (f, quarter_signs(q))))
                    .collect();
                for ((c, x), a) in cases.iter().zip(answers) {
                    let Some(right) = x.right(a) else { continue };
                    t.judged += 1;
                    if right {
                        continue;
                    }
                    t.wrong += 1;
                    t.no_exit_face += a.is_none() as u64;
                    t.wrong_quarter += a.is_some_and(|(f, _)| x.faces.contains(&f)) as u64;
                    wrong(
                        &name,
                        Record {
                            subject: Subject::Box(*c),
                            failure: Some(Failure {
                                method: m.name.into(),
                                backend: backend.kind(),
                                adapter: None,
                                answer: Answer::Box(a.map(|(f, q)| (f as u8, q))),
                            }),
                        },
                    );
                }
                tallies.push(t);
            }
            rows.push(CellRow {
                aim,
                place,
                tallies,
            });
        }
    }
    Ok(CellStressReport {
        settings: s.clone(),
        methods: methods.iter().map(|m| m.name.to_string()).collect(),
        rows,
    })
}

impl CellStressReport {
    pub fn markdown(&self) -> String {
        let s = &self.settings;
        let mut out = format!(
            "{} cells and rays per row, seed {}, {}, near-* within {} ulps; cells: wrong (of which wrong quarter / no exit face) per million judged cases\n\n| row | judged |",
            s.cases, s.seed, s.backend, s.ulps
        );
        for m in &self.methods {
            out += &format!(" {m} |");
        }
        out += "\n|---|---|";
        out += &"---|".repeat(self.methods.len());
        out += "\n";
        let pm = |n: u64, of: u64| super::stress::Tally::per_million(n, of);
        for r in &self.rows {
            let judged = r.tallies.first().map_or(0, |t| t.judged);
            out += &format!("| {}-{} | {judged} |", r.aim.name(), r.place.name());
            for t in &r.tallies {
                out += &format!(
                    " {:.0} ({:.0} / {:.0}) |",
                    pm(t.wrong, t.judged),
                    pm(t.wrong_quarter, t.judged),
                    pm(t.no_exit_face, t.judged)
                );
            }
            out += "\n";
        }
        out
    }
}
