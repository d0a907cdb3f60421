//! `tetwalk stress`: wrong exit faces and "no exit face" per million cases, per method and family.

use crate::backend::{Backend, BackendError};
use crate::cases::{Case, Judged, classify, judged};
use crate::choice::Choice;
use crate::exact::Classification;
use crate::registry::Method;
use crate::scenes::rng;
use crate::scenes::tets::{self, Family, Target};
use crate::tet::{Ray, Tet};
use glam::Vec3;
use rand::RngExt;
use rayon::prelude::*;

/// The rows of the stress table: a tetrahedron family with stabbing rays, or a way of aiming rays.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Row {
    Well,
    Sliver,
    Cap,
    Needle,
    Wedge,
    /// Well-shaped, moved 1e4 to 1e6 from the origin.
    FarOffset,
    /// Within k ulps of an edge (every shape family in turn).
    NearEdge,
    /// Within k ulps of a vertex.
    NearVertex,
    /// Exactly through an edge.
    ThroughEdge,
    /// Exactly through a vertex.
    ThroughVertex,
}

crate::choice!(Row {
    Well => "well",
    Sliver => "sliver",
    Cap => "cap",
    Needle => "needle",
    Wedge => "wedge",
    FarOffset => "far-offset",
    NearEdge => "near-edge",
    NearVertex => "near-vertex",
    ThroughEdge => "through-edge",
    ThroughVertex => "through-vertex",
});

/// Settings of a stress run.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Settings {
    pub cases: usize,
    pub rows: Vec<Row>,
    pub seed: u64,
    /// `cpu`, `cpu-fma` or the GPU's description.
    pub backend: String,
    /// Flatness of the degenerate families (well-shaped ones use 1).
    pub flatness: f32,
    /// Largest ulp offset of the near-* rows.
    pub ulps: i32,
    /// How every case's tetrahedron is relabelled before the methods see it (new vertex `i` is old
    /// vertex `relabel[i]`; answers are mapped back): one of `crate::tet::EVEN_PERMUTATIONS`.
    pub relabel: [usize; 4],
}

/// Counts for one method on one row.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct Tally {
    pub method: String,
    /// Cases whose line meets the tetrahedron (the others are not judged).
    pub judged: u64,
    pub wrong_face: u64,
    pub no_exit_face: u64,
}

impl Tally {
    /// Count one judged answer: a line that misses the tetrahedron is not judged; a wrong answer is a
    /// wrong face, or "no exit face" when the method gave none.
    pub fn add(&mut self, j: &Judged) {
        self.judged += j.correct.is_some() as u64;
        self.wrong_face += (j.correct == Some(false) && j.face.is_some()) as u64;
        self.no_exit_face += (j.correct == Some(false) && j.face.is_none()) as u64;
    }

    pub fn per_million(n: u64, of: u64) -> f64 {
        if of == 0 {
            0.0
        } else {
            n as f64 * 1e6 / of as f64
        }
    }
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct RowReport {
    pub row: Row,
    /// Per method, in the order of `StressReport::methods`.
    pub tallies: Vec<Tally>,
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct StressReport {
    pub settings: Settings,
    /// Rounds of `settings.cases` cases per row, seeds `seed`, `seed + 1`, … (one unless a campaign).
    pub rounds: u64,
    pub methods: Vec<String>,
    pub rows: Vec<RowReport>,
    /// Signs the oracle decided in its f64 filter and exactly.
    pub oracle: crate::exact::Counts,
    /// With `stress --relabel all`: per row and method, wrong answers under each of the 12
    /// orientation-preserving relabellings (`crate::tet::EVEN_PERMUTATIONS`, the identity first).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub relabelled: Option<Vec<Relabelled>>,
}

/// One row and method under the 12 relabellings.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Relabelled {
    pub row: Row,
    pub method: String,
    /// Wrong faces plus "no exit face" answers.
    pub wrong: [u64; 12],
}

impl StressReport {
    /// Run `s` again under every other relabelling (the identity is this report) and keep each row's
    /// and method's wrong answers under all 12.
    pub fn relabel_all(
        &mut self,
        methods: &[&Method],
        backend: &Backend,
    ) -> Result<(), BackendError> {
        let wrong = |r: &StressReport| -> Vec<u64> {
            r.rows
                .iter()
                .flat_map(|row| row.tallies.iter().map(|t| t.wrong_face + t.no_exit_face))
                .collect()
        };
        let mut all: Vec<[u64; 12]> = wrong(self).into_iter().map(|w| [w; 12]).collect();
        for (k, p) in crate::tet::EVEN_PERMUTATIONS.iter().enumerate().skip(1) {
            let s = Settings {
                relabel: *p,
                ..self.settings.clone()
            };
            let r = run(&s, methods, backend, &|_| {}, &mut |_, _, _, _| {})?;
            for (a, w) in all.iter_mut().zip(wrong(&r)) {
                a[k] = w;
            }
        }
        let mut all = all.into_iter();
        self.relabelled = Some(
            self.rows
                .iter()
                .flat_map(|row| row.tallies.iter().map(move |t| (row.row, t.method.clone())))
                .map(|(row, method)| Relabelled {
                    row,
                    method,
                    wrong: all.next().unwrap_or([0; 12]),
                })
                .collect(),
        );
        Ok(())
    }
}

/// Case `i` of `row`: a pure function of `(seed, row, i)`, so results do not depend on threads.
fn case(row: Row, s: &Settings, i: usize) -> Option<(Tet, Ray)> {
    let key = s.seed
        ^ (row as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15)
        ^ (i as u64).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    let mut r = rng(key);
    let shape = Family::ALL[i % Family::ALL.len()];
    let flat = |f: Family| if f == Family::Well { 1.0 } else { s.flatness };
    let stab = |f: Family, r: &mut crate::scenes::Rng| {
        let t = tets::tet(f, flat(f), r);
        let ray = tets::stabbing_ray(&t, r);
        Some((t, ray))
    };
    match row {
        Row::Well => stab(Family::Well, &mut r),
        Row::Sliver => stab(Family::Sliver, &mut r),
        Row::Cap => stab(Family::Cap, &mut r),
        Row::Needle => stab(Family::Needle, &mut r),
        Row::Wedge => stab(Family::Wedge, &mut r),
        Row::FarOffset => {
            let (t, ray) = stab(Family::Well, &mut r)?;
            let d = 10f32.powf(r.random_range(4.0..6.0));
            let dir = Vec3::new(
                r.random_range(-1.0..1.0),
                r.random_range(-1.0..1.0),
                r.random_range(-1.0..1.0),
            );
            tets::translated(&t, &ray, dir.normalize_or(Vec3::X) * d)
        }
        Row::NearEdge => tets::near(shape, flat(shape), Target::Edge, s.ulps, &mut r),
        Row::NearVertex => tets::near(shape, flat(shape), Target::Vertex, s.ulps, &mut r),
        Row::ThroughEdge => tets::through(shape, flat(shape), Target::Edge, &mut r),
        Row::ThroughVertex => tets::through(shape, flat(shape), Target::Vertex, &mut r),
    }
}

/// Generated cases of a row with their exact classification (lines that miss included). Even-numbered
/// cases carry the exact entry face (as a walk would have it), odd ones none (a starting tetrahedron).
fn row_cases(row: Row, s: &Settings) -> (Vec<(Case, Classification)>, crate::exact::Counts) {
    (0..s.cases)
        .into_par_iter()
        .map(|i| {
            let before = crate::exact::counts();
            let out = case(row, s, i).and_then(|(tet, ray)| {
                let mut c = Case {
                    tet,
                    org: ray.org,
                    dir: ray.dir,
                    entry: None,
                };
                let x = classify(&c).ok()?;
                if i % 2 == 0 {
                    c.entry = x.entry.first().map(|f| f as u8);
                }
                Some((c, x))
            });
            (out, crate::exact::counts().since(before))
        })
        .fold(
            || (Vec::new(), crate::exact::Counts::default()),
            |(mut v, mut n), (c, k)| {
                v.extend(c);
                n += k;
                (v, n)
            },
        )
        .reduce(
            || (Vec::new(), crate::exact::Counts::default()),
            |(mut a, mut na), (b, nb)| {
                a.extend(b);
                na += nb;
                (a, na)
            },
        )
}

/// What [`run`] shows of each wrong answer: the row, the method, the case and the face it answered.
pub type OnWrong<'a> = dyn FnMut(Row, &Method, &Case, Option<usize>) + 'a;

/// Run every method on `cases` cases of every row on `backend`, judging each answer exactly; `tick`
/// is told how many cases each row held, and `wrong` sees every wrong answer.
pub fn run(
    s: &Settings,
    methods: &[&Method],
    backend: &Backend,
    tick: &(dyn Fn(u64) + Sync),
    wrong: &mut OnWrong,
) -> Result<StressReport, BackendError> {
    let mut rows = Vec::new();
    let mut oracle = crate::exact::Counts::default();
    for &row in &s.rows {
        let (cases, counts) = row_cases(row, s);
        oracle += counts;
        let plain: Vec<Case> = cases.iter().map(|(c, _)| c.relabelled(s.relabel)).collect();
        let mut tallies = Vec::new();
        for m in methods {
            let faces = backend.exit_faces(m, &plain)?;
            let faces = faces.into_iter().map(|f| f.map(|f| s.relabel[f]));
            let mut t = Tally {
                method: m.name.to_string(),
                ..Tally::default()
            };
            for ((c, x), f) in cases.iter().zip(faces) {
                let j = judged(x, f);
                if j.correct == Some(false) {
                    wrong(row, m, c, f);
                }
                t.add(&j);
            }
            tallies.push(t);
        }
        tick(s.cases as u64);
        rows.push(RowReport { row, tallies });
    }
    Ok(StressReport {
        settings: s.clone(),
        rounds: 1,
        methods: methods.iter().map(|m| m.name.to_string()).collect(),
        rows,
        oracle,
        relabelled: None,
    })
}

/// A differential campaign: rounds of [`run`], round `k` with seed `seed + k`, until `seconds` have
/// passed (one round at least); the tallies summed over rounds.
pub fn campaign(
    s: &Settings,
    methods: &[&Method],
    backend: &Backend,
    seconds: f64,
    tick: &(dyn Fn(u64) + Sync),
    wrong: &mut OnWrong,
) -> Result<StressReport, BackendError> {
    let t0 = std::time::Instant::now();
    let mut total = run(s, methods, backend, tick, wrong)?;
    while t0.elapsed().as_secs_f64() < seconds {
        let round = Settings {
            seed: s.seed.wrapping_add(total.rounds),
            ..s.clone()
        };
        let more = run(&round, methods, backend, tick, wrong)?;
        for (a, b) in total.rows.iter_mut().zip(&more.rows) {
            for (x, y) in a.tallies.iter_mut().zip(&b.tallies) {
                x.judged += y.judged;
                x.wrong_face += y.wrong_face;
                x.no_exit_face += y.no_exit_face;
            }
        }
        total.oracle += more.oracle;
        total.rounds += 1;
    }
    Ok(total)
}

/// One row of the comparison: per method, how many of the row's cases each pair of backends answers
/// differently.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CompareRow {
    pub row: Row,
    pub cases: usize,
    pub methods: Vec<Pairs>,
}

/// Cases one method answers differently on each pair of backends.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Pairs {
    pub method: String,
    pub cpu_vs_cpu_fma: u64,
    pub cpu_vs_gpu: u64,
    pub cpu_fma_vs_gpu: u64,
}

/// How often two backends answer differently, per row and method: cpu vs cpu-fma, cpu vs gpu, cpu-fma
/// vs gpu (the comparison mode).
#[derive(Clone, Debug, serde::Serialize)]
pub struct Disagreements {
    pub methods: Vec<String>,
    pub rows: Vec<CompareRow>,
    pub gpu: String,
}

/// The same generated cases on the CPU, the CPU as a GPU compiles it, and `gpu`.
pub fn compare(
    s: &Settings,
    methods: &[&Method],
    gpu: &Backend,
) -> Result<Disagreements, BackendError> {
    let mut rows = Vec::new();
    for &row in &s.rows {
        let plain: Vec<Case> = row_cases(row, s).0.into_iter().map(|(c, _)| c).collect();
        let mut per = Vec::new();
        for m in methods.iter().filter(|m| !m.reference) {
            let a = crate::backend::CPU.exit_faces(m, &plain)?;
            let b = crate::backend::CPU_FMA.exit_faces(m, &plain)?;
            let c = gpu.exit_faces(m, &plain)?;
            let diff = |x: &[Option<usize>], y: &[Option<usize>]| {
                x.iter().zip(y).filter(|(p, q)| p != q).count() as u64
            };
            per.push(Pairs {
                method: m.name.to_string(),
                cpu_vs_cpu_fma: diff(&a, &b),
                cpu_vs_gpu: diff(&a, &c),
                cpu_fma_vs_gpu: diff(&b, &c),
            });
        }
        rows.push(CompareRow {
            row,
            cases: plain.len(),
            methods: per,
        });
    }
    Ok(Disagreements {
        methods: methods
            .iter()
            .filter(|m| !m.reference)
            .map(|m| m.name.to_string())
            .collect(),
        rows,
        gpu: gpu.describe(),
    })
}

impl Disagreements {
    pub fn markdown(&self) -> String {
        let mut out = format!(
            "GPU {}; cells: cpu≠cpu-fma / cpu≠gpu / cpu-fma≠gpu, cases out of the row's\n\n",
            self.gpu
        );
        out += &format!(
            "| row | cases | {} |\n|---|---|{}\n",
            self.methods.join(" | "),
            "---|".repeat(self.methods.len())
        );
        for r in &self.rows {
            let (row, n) = (r.row, r.cases);
            let cells: Vec<String> = r
                .methods
                .iter()
                .map(|p| {
                    format!(
                        "{} / {} / {}",
                        p.cpu_vs_cpu_fma, p.cpu_vs_gpu, p.cpu_fma_vs_gpu
                    )
                })
                .collect();
            out += &format!("| {} | {n} | {} |\n", row.name(), cells.join(" | "));
        }
        out
    }
}

impl StressReport {
    /// The table: per row and method, wrong exit faces / "no exit face", per million judged cases.
    pub fn markdown(&self) -> String {
        let s = &self.settings;
        let cases = if self.rounds > 1 {
            format!(
                "{} cases per row in each of {} rounds, seeds {} to {}",
                s.cases,
                self.rounds,
                s.seed,
                s.seed.wrapping_add(self.rounds - 1)
            )
        } else {
            format!("{} cases per row, seed {}", s.cases, s.seed)
        };
        let mut out = format!(
            "{cases}, {}, flatness {}, near-* within {} ulps; cells: wrong face / no exit face per million judged cases\n\n",
            s.backend, s.flatness, s.ulps
        );
        out += &format!("| row | judged | {} |\n", self.methods.join(" | "));
        out += &format!("|---|---|{}\n", "---|".repeat(self.methods.len()));
        for r in &self.rows {
            let judged = r.tallies.first().map_or(0, |t| t.judged);
            let cells: Vec<String> = r
                .tallies
                .iter()
                .map(|t| {
                    format!(
                        "{:.0} / {:.0}",
                        Tally::per_million(t.wrong_face, t.judged),
                        Tally::per_million(t.no_exit_face, t.judged)
                    )
                })
                .collect();
            out += &format!(
                "| {} | {} | {} |\n",
                r.row.name(),
                judged,
                cells.join(" | ")
            );
        }
        out += &format!(
            "\noracle: {} signs decided by the f64 filter, {} exactly\n",
            self.oracle.filter, self.oracle.exact
        );
        if let Some(r) = &self.relabelled {
            out += "\nwrong answers (wrong face or no exit face) under the 12 orientation-preserving relabellings\n\n";
            out += "| row | method | own labelling | min | median | max |\n|---|---|---|---|---|---|\n";
            for x in r.iter().filter(|x| x.wrong.iter().any(|&w| w > 0)) {
                out += &format!(
                    "| {} | {} | {} |\n",
                    x.row.name(),
                    x.method,
                    super::relabel_spread(&x.wrong)
                );
            }
        }
        out
    }
}
