//! The register of claims ("What the papers claim and what we found"), held in one place and checked
//! as Embree's `verify` checks its kernels: each paper's robustness claim and tetwalk's own, on each
//! backend, backed by the counterexample that refutes it (replayed) or by the stress rows of its family
//! at every scale of the domain where it was found to hold, the found corpus beside them, and the
//! scales where it stops holding. `tetwalk verify` runs the checks; the register's table in docs/results.md is generated
//! from [`REGISTER`] (`tetwalk verify --register`) and a test holds the two together.

use crate::backend::{Backend, BackendKind};
use crate::engine::found::{Found, FoundError, Hold, check};
use crate::engine::stress::{StressSettings, Who, run};
use crate::family::{self, Family, Kind, Scale};
use std::path::Path;

/// What the register says of a claim on a backend.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Expect {
    Stands,
    Refuted,
}

/// What backs the register's word.
#[derive(Clone, Copy, Debug)]
pub enum Evidence {
    /// A found case (its path under the found corpus, `corpora/found/`) the method fails, as it is
    /// held to its claim, on the check's backend.
    Counterexample(&'static str),
    /// Every stress row of the family at each scale of `holds` (the domain where the claim was found to
    /// hold, its ends among them) and every found case of the family: none refutes the claim. At each
    /// scale of `stops` (just outside the domain) the rows do refute it.
    Domain {
        holds: &'static [Scale],
        stops: &'static [Scale],
    },
}

/// One check of the register: a method's claim on a backend.
#[derive(Clone, Copy, Debug)]
pub struct Check {
    /// Its name for `--run` and `--skip`.
    pub name: &'static str,
    pub family: Kind,
    pub method: &'static str,
    pub backend: BackendKind,
    /// On a GPU, the adapter the register speaks of: a word of its description (`llvmpipe`,
    /// `NVIDIA`), matched without regard to case.
    pub adapter: Option<&'static str>,
    pub expect: Expect,
    pub evidence: Evidence,
}

/// A row of the register: the methods, the claim quoted, the verdict and the counterexample (as the
/// docs/results.md writes them), and the checks behind the verdict.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Entry {
    pub(crate) methods: &'static str,
    pub(crate) claim: &'static str,
    pub(crate) verdict: &'static str,
    pub(crate) counterexample: &'static str,
    pub(crate) checks: &'static [Check],
}

/// Scales spanning f32's range, tiny, huge and mixed within a case (the direction at its own scale):
/// where a claim made for every finite input is checked.
const EVERY_SCALE: &[Scale] = &[
    Scale::uniform(-140),
    Scale::uniform(-100),
    Scale::uniform(-60),
    Scale::uniform(0),
    Scale::uniform(60),
    Scale::uniform(100),
    Scale::uniform(110),
    Scale {
        points: 0,
        direction: -120,
    },
    Scale {
        points: 0,
        direction: 100,
    },
    Scale {
        points: -60,
        direction: 60,
    },
];

/// `woop-watertight`'s domain as written and unfused: the triangle rows scaled by 2^-62 to 2^44.
const WOOP_HOLDS: &[Scale] = &[
    Scale::uniform(-62),
    Scale::uniform(-40),
    Scale::uniform(-20),
    Scale::uniform(0),
    Scale::uniform(20),
    Scale::uniform(44),
];

/// Where it stops: its edge functions' products underflow (2^-70) or overflow (2^47).
const WOOP_STOPS: &[Scale] = &[Scale::uniform(-70), Scale::uniform(47)];

const MARIA17_A: &str = "maria17/exit_face-wrong_face-50e741ec2f3d.json";

/// The adapter word a check names, if any.
const fn first(words: &[&'static str]) -> Option<&'static str> {
    match words {
        [w, ..] => Some(*w),
        [] => None,
    }
}

macro_rules! checks {
    ($($name:literal: $family:ident $method:literal @ $backend:ident $(($adapter:literal))? $expect:ident
        $evidence:expr;)*) => {
        &[$(Check {
            name: $name,
            family: Kind::$family,
            method: $method,
            backend: BackendKind::$backend,
            adapter: first(&[$($adapter)?]),
            expect: Expect::$expect,
            evidence: $evidence,
        }),*]
    };
}

use Evidence::{Counterexample, Domain};

/// The register.
pub(crate) const REGISTER: &[Entry] = &[
    Entry {
        methods: "`maria17`, `maria17-translated` (both readings of §3.4)",
        claim: "seed 000, abstract: \"it is robust with 32-bits floats\"; §1: \"It is robust, since it does not cause any error due to numerical instability, either on CPU or on GPU\"; §4.3: \"we did not obtain wrong results using our method\"",
        verdict: "**does not hold**, on the CPU and on the GPU (lavapipe, and an NVIDIA H200)",
        counterexample: "(a) the tetrahedron below: entering through face 1, leaving through face 3 only, both readings answer face 2; (b) the 8³ Kuhn grid of `tetwalk walk --mesh kuhn`, the ray from (4.875, 5.75, 6.25) along (1, 2, −2): through the vertex (5, 6, 6), then a cycle of period 6 (`maria17`; `tests/walk.rs`); (c) the default count: 12 (`maria17`, each 0.07–6 ulps from an edge) and 8 (`maria17-translated`) wrong rays; (d) on an H100, 6,659 wrong faces per million far-offset cases (`corpora/results/h100-fuzz.md`)",
        checks: checks! {
            "maria17@cpu": ExitFace "maria17" @ Cpu Refuted Counterexample(MARIA17_A);
            "maria17@gpu": ExitFace "maria17" @ Gpu("llvmpipe") Refuted Counterexample(MARIA17_A);
            "maria17@gpu-nvidia": ExitFace "maria17" @ Gpu("NVIDIA") Refuted Counterexample(MARIA17_A);
            "maria17-translated@cpu": ExitFace "maria17-translated" @ Cpu Refuted
                Counterexample("maria17-translated/aman20-scaled-exit_face-wrong_face-50e741ec2f3d-wrong_face.json");
        },
    },
    Entry {
        methods: "`aman20-scaled`",
        claim: "seed 003, §4.1: \"Since the basis vectors are only scaled, the exit face determination still works correctly\"",
        verdict: "true in exact arithmetic; **does not hold** in f32: the scaled and unscaled bases answer differently",
        counterexample: "the same tetrahedron: `aman20` answers face 3 (right), `aman20-scaled` face 0",
        checks: checks! {
            "aman20-scaled@cpu": ExitFace "aman20-scaled" @ Cpu Refuted
                Counterexample("aman20-scaled/exit_face-wrong_face-50e741ec2f3d.json");
        },
    },
    Entry {
        methods: "`woop-watertight`",
        claim: "Woop, Benthin, Wald 2013, \"Watertight Ray/Triangle Intersection\": no ray passes through the edges and vertices a closed mesh's triangles share",
        verdict: "**stands** in f32 as written (`cpu`, `cpu-ftz`, and its WGSL on lavapipe) on the stress rows scaled by 2^-62 to 2^44; **stops** beyond, where its products underflow (2^-70) or overflow (2^47); **does not hold** with its 2×2 determinants fused, as a GPU compiler may (`cpu-fma`, and `cpu-gpu`, fused and flushed as the H200 computes): 46,033 per million (`cpu-fma`) rays through exact edges leak; **does not hold** on an NVIDIA H200 (Vulkan, driver 580.159.04, which fuses and flushes; `woop-watertight@gpu-nvidia`): 1,333 of 90,000 stress answers from 2^-62 to 2^44 leak (`corpora/results/h200/verify-gpu.txt`)",
        counterexample: "the closed tetrahedron of `corpora/found/woop-watertight/stress-tetrahedron-edge-origin-wrong_face-15054ba8dc6ab2ef.json` as found: the ray crosses exactly through the edge between triangles 0 and 2 at `t = 1`; fused, Woop's test hits neither and first reports triangle 3, where the ray leaves, at `t = 1.589068`",
        checks: checks! {
            "woop-watertight@cpu": Triangle "woop-watertight" @ Cpu Stands
                Domain { holds: WOOP_HOLDS, stops: WOOP_STOPS };
            "woop-watertight@cpu-ftz": Triangle "woop-watertight" @ CpuFtz Stands
                Domain { holds: WOOP_HOLDS, stops: WOOP_STOPS };
            "woop-watertight@gpu": Triangle "woop-watertight" @ Gpu("llvmpipe") Stands
                Domain { holds: WOOP_HOLDS, stops: WOOP_STOPS };
            "woop-watertight@gpu-nvidia": Triangle "woop-watertight" @ Gpu("NVIDIA") Refuted
                Domain { holds: WOOP_HOLDS, stops: WOOP_STOPS };
            "woop-watertight@cpu-fma": Triangle "woop-watertight" @ CpuFma Refuted
                Counterexample("woop-watertight/stress-tetrahedron-edge-origin-wrong_face-15054ba8dc6ab2ef.json");
            "woop-watertight@cpu-gpu": Triangle "woop-watertight" @ CpuGpu Refuted
                Counterexample("woop-watertight/stress-tetrahedron-edge-origin-wrong_face-15054ba8dc6ab2ef.json");
        },
    },
    Entry {
        methods: "`komatsu-packet`",
        claim: "seed 004 §4: \"our proposed method achieves about 1.1x to 1.4x speedup for all the test scenes\" over the improved Möller test",
        verdict: "**not reproduced** in 2×2 packets (one thread, per test over the count's candidates): its SSE 4-wide version runs at 0.95–1.03× scalar `mt-precomputed`'s speed (the scalar one 0.48–0.89×); 1.08–1.13× in 8×8 packets, on the shipped bunny and the paper-scale one (`corpora/results/paper-scale.md`); a speed claim, which `verify` does not check (`bench --family triangle`)",
        counterexample: "-",
        checks: &[],
    },
    Entry {
        methods: "`mt` (seed 004 eq. 1)",
        claim: "eq. 1 as printed, with its leading minus sign",
        verdict: "a misprint: literally, `t`, `u`, `v` are negated and nothing in front is hit; `mt` implements Möller & Trumbore's own signs",
        counterexample: "-",
        checks: &[],
    },
    Entry {
        methods: "`certified` (ours)",
        claim: "never wrong: every walk ends where the `exact` walk ends",
        verdict: "**did not hold** where f32 products underflow (issue 24: 166 wrong of 2,970 adversarial cases, on `cpu`, `cpu-fma` and the GPU): the bound's absolute term ignored that `(V_f − o) × d`'s underflow is multiplied by `|V_k − V_f|`. **Stands** again with the bound derived for every finite f32 input (`src/methods/certified.md`, lemmas and constants checked by z3), on every backend (the four CPU models, lavapipe, and an NVIDIA H200: 193,898 stress answers, `corpora/results/h200/verify-gpu.txt`) and at every scale: the exit-face rows from 2^-140 to 2^110 and with the direction at its own scale, the walks, the found corpus, the filter checker's ten-minute campaign (`corpora/results/filters.md`), and the adversarial underflow cases",
        counterexample: "every coordinate a power of two (1.5·2^-90 once): the tetrahedron below, entering through face 0, leaving through face 3 only; the old bound settled its first sign wrong and answered face 1 (`tests/certified.rs` replays it on every backend)",
        checks: checks! {
            "certified@cpu": ExitFace "certified" @ Cpu Stands Domain { holds: EVERY_SCALE, stops: &[] };
            "certified@cpu-fma": ExitFace "certified" @ CpuFma Stands Domain { holds: EVERY_SCALE, stops: &[] };
            "certified@cpu-ftz": ExitFace "certified" @ CpuFtz Stands Domain { holds: EVERY_SCALE, stops: &[] };
            "certified@cpu-gpu": ExitFace "certified" @ CpuGpu Stands Domain { holds: EVERY_SCALE, stops: &[] };
            "certified@gpu": ExitFace "certified" @ Gpu("llvmpipe") Stands Domain { holds: EVERY_SCALE, stops: &[] };
            "certified@gpu-nvidia": ExitFace "certified" @ Gpu("NVIDIA") Stands Domain { holds: EVERY_SCALE, stops: &[] };
            "certified-walks@cpu": Walk "certified" @ Cpu Stands Domain { holds: EVERY_SCALE, stops: &[] };
            "certified-walks@gpu": Walk "certified" @ Gpu("llvmpipe") Stands Domain { holds: EVERY_SCALE, stops: &[] };
            "certified-walks@gpu-nvidia": Walk "certified" @ Gpu("NVIDIA") Stands Domain { holds: EVERY_SCALE, stops: &[] };
        },
    },
    Entry {
        methods: "`portalez16`, `portalez16-direction`",
        claim: "seed 001 §4.2.1, eq. 7: \"7 étant une valeur par défaut pour les cas inaccessibles\" (7 for the cases no ray reaches)",
        verdict: "**does not hold**, even in exact arithmetic",
        counterexample: "box [0, 2]³, origin (1, 1, 1), direction (−1, −1, −1) (`corpora/found/portalez16*/eq7-corner-no_exit_face.json`): exactly through the exit corner 0 all three orientations vanish and eq. 8 gives 7, no exit face",
        checks: checks! {
            "portalez16@cpu": Octree "portalez16" @ Cpu Refuted
                Counterexample("portalez16/eq7-corner-no_exit_face.json");
            "portalez16-direction@cpu": Octree "portalez16-direction" @ Cpu Refuted
                Counterexample("portalez16-direction/eq7-corner-no_exit_face.json");
        },
    },
    Entry {
        methods: "`exact` (ours, exit faces, walks and octree cells)",
        claim: "the reference: the exact exit face (and cell exit), ties broken by Simulation of Simplicity",
        verdict: "**stands**, at every scale",
        counterexample: "none: it agrees with an independent rational clipping of every case (`tests/oracle.rs`) and with brute-force first hits (`tests/walk.rs`)",
        checks: checks! {
            "exact@cpu": ExitFace "exact" @ Cpu Stands Domain { holds: EVERY_SCALE, stops: &[] };
            "exact-walks@cpu": Walk "exact" @ Cpu Stands Domain { holds: EVERY_SCALE, stops: &[] };
            "exact-cells@cpu": Octree "exact" @ Cpu Stands Domain { holds: EVERY_SCALE, stops: &[] };
        },
    },
];

/// Every check of the register, in its order.
pub fn checks() -> impl Iterator<Item = &'static Check> {
    REGISTER.iter().flat_map(|e| e.checks.iter())
}

/// What one stress run at one scale showed: answers judged, and how many refuted the claim.
#[derive(Clone, Debug, serde::Serialize)]
pub struct AtScale {
    pub(crate) scale: Scale,
    pub(crate) judged: u64,
    pub(crate) refuted: u64,
}

/// What a check found.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CheckResult {
    pub(crate) name: &'static str,
    pub(crate) backend: String,
    pub(crate) expect: Expect,
    /// On a GPU, the adapter the register speaks of ([`Check::adapter`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) registered_for: Option<&'static str>,
    /// Whether the claim held in every part of the check.
    pub holds: bool,
    /// Whether that is what the register says; `None` where the register speaks of another adapter
    /// than the GPU checked.
    pub as_registered: Option<bool>,
    /// What was seen, in words.
    pub seen: String,
    /// The domain's scales and where it stops, each run.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(crate) domain: Vec<AtScale>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(crate) stops: Vec<AtScale>,
}

/// Why a check could not run.
#[derive(Debug, thiserror::Error)]
pub enum VerifyError {
    #[error("{name}: {why}")]
    Check { name: &'static str, why: String },
}

/// Run `check` with `cases` cases per stress row (the family's share of it, as the kit takes it), on
/// `backend` (opened for its kind), the found corpus in `found`: what it found.
pub fn verify(
    check: &Check,
    backend: &Backend,
    cases: usize,
    found: &Path,
) -> Result<CheckResult, VerifyError> {
    let fail = |why: String| VerifyError::Check {
        name: check.name,
        why,
    };
    crate::with_family!(check.family, F => verify_in::<F>(check, backend, cases, found))
        .map_err(fail)
}

fn verify_in<F: Family>(
    c: &Check,
    backend: &Backend,
    cases: usize,
    found: &Path,
) -> Result<CheckResult, String> {
    let m = family::by_name::<F>(c.method).map_err(|e| e.to_string())?;
    let held = [(m, Hold::Claim)];
    let on = backend.ran();
    let (holds, seen, domain, stops) = match c.evidence {
        Counterexample(file) => {
            let path = found.join(file);
            let path = path.display();
            let text =
                std::fs::read_to_string(found.join(file)).map_err(|e| format!("{path}: {e}"))?;
            let found = Found::<F>::parse(text.trim()).map_err(|e| format!("{path}: {e}"))?;
            // The case as found (the register's words are about it) and as shrunk.
            let cases: Vec<(&str, F::Case)> = found
                .original
                .map(|o| ("as found", o))
                .into_iter()
                .chain([("shrunk", found.case)])
                .collect();
            // Refuted only when the case fails as found and as shrunk (the register's words are about
            // both), and, where this check runs the method and backend the file records, with the
            // answer it records: an edited counterexample does not pass.
            let recorded = found
                .failure
                .as_ref()
                .filter(|f| f.method == c.method && f.backend == on.kind);
            let mut refuted = true;
            let mut seen = format!("{path}:");
            for (what, case) in &cases {
                let now = check::<F>(std::slice::from_ref(case), &held, &[backend])
                    .map_err(|e: FoundError| format!("{path}: {e}"))?;
                let right =
                    F::truth(case).map_or_else(|e| e.to_string(), |t| F::right_answers(case, &t));
                seen += &match &now {
                    Some((_, f)) => format!(
                        " {what}, answers {}, right: {right};",
                        F::describe(&f.answer)
                    ),
                    None => format!(" {what}, right now;"),
                };
                refuted &= now.is_some();
                if let (Some(r), Some((_, f)), "shrunk") = (recorded, &now, *what)
                    && F::answer_json(&f.answer) != F::answer_json(&r.answer)
                {
                    refuted = false;
                    seen += &format!(
                        " the file records the answer {}, not this one;",
                        F::describe(&r.answer)
                    );
                }
            }
            seen.pop();
            let now = refuted.then_some(());
            (now.is_none(), seen, Vec::new(), Vec::new())
        }
        Domain { holds, stops } => {
            let at = |scale: Scale| -> Result<AtScale, String> {
                let s = StressSettings::<F> {
                    contract: Default::default(),
                    cases: F::kit_row_cases(cases),
                    rows: F::Rows::default(),
                    seed: 1,
                    backend: on.clone(),
                    scale,
                };
                let r = run(&s, &[Who::Method(m)], backend, &|_| {}, &mut |_| {})
                    .map_err(|e| e.to_string())?;
                Ok(AtScale {
                    scale,
                    judged: r
                        .rows
                        .iter()
                        .map(|row| F::judged(&row.facts, &row.tallies[0].counts))
                        .sum(),
                    refuted: r
                        .rows
                        .iter()
                        .map(|row| F::refuted(&row.tallies[0].counts))
                        .sum(),
                })
            };
            let domain: Vec<AtScale> = holds.iter().map(|&s| at(s)).collect::<Result<_, _>>()?;
            let stops: Vec<AtScale> = stops.iter().map(|&s| at(s)).collect::<Result<_, _>>()?;
            let corpus = super::found::corpus::<F>(found).map_err(|e| e.to_string())?;
            let in_corpus = check::<F>(&corpus, &held, &[backend]).map_err(|e| e.to_string())?;
            let judged: u64 = domain.iter().map(|a| a.judged).sum();
            let refuted: u64 = domain.iter().map(|a| a.refuted).sum();
            let mut seen = format!(
                "{refuted} refuting of {judged} stress answers at {}",
                scales(holds)
            );
            seen += &match &in_corpus {
                Some((i, f)) => format!("; found case {i} refutes it ({})", F::describe(&f.answer)),
                None => format!("; none of {} found cases refutes it", corpus.len()),
            };
            for s in &stops {
                seen += &format!("; at {} {} of {} refute it", s.scale, s.refuted, s.judged);
            }
            // The claim holds in its domain, and stops where the register says it stops.
            let holds = refuted == 0 && in_corpus.is_none();
            let stops_ok = stops.iter().all(|s| s.refuted > 0);
            if holds && !stops_ok {
                seen += "; the domain is wider than the register says";
            }
            (holds && stops_ok, seen, domain, stops)
        }
    };
    let expected = match c.expect {
        Expect::Stands => holds,
        Expect::Refuted => !holds,
    };
    // On a GPU the register speaks of one adapter: another compiles and rounds differently.
    let registered = c.registered_for(on.adapter.as_deref());
    Ok(CheckResult {
        name: c.name,
        backend: on.to_string(),
        expect: c.expect,
        holds,
        registered_for: c.adapter,
        as_registered: registered.then_some(expected),
        seen,
        domain,
        stops,
    })
}

/// The scales of a domain in words: `N scales from 2^a to 2^b` (or `the scale 2^a`), the directions' range beside where
/// any has its own.
fn scales(s: &[Scale]) -> String {
    let range = |f: fn(&Scale) -> i32| {
        let lo = s.iter().map(f).min().unwrap_or(0);
        let hi = s.iter().map(f).max().unwrap_or(0);
        format!("from 2^{lo} to 2^{hi}")
    };
    let mut out = match s.len() {
        1 => format!("the scale 2^{}", s[0].points),
        n => format!("{n} scales {}", range(|x| x.points)),
    };
    if s.iter().any(|x| x.points != x.direction) {
        out += &format!(", directions {}", range(|x| x.direction));
    }
    out
}

/// One picked check: what it found, or why it was not run here.
pub(crate) enum Verified {
    /// It ran: what it found.
    Checked(CheckResult),
    /// It did not run here: the check, and why.
    Skipped { name: &'static str, why: String },
}

impl Verified {
    /// What it found, where it ran.
    pub(crate) fn checked(&self) -> Option<&CheckResult> {
        match self {
            Verified::Checked(c) => Some(c),
            Verified::Skipped { .. } => None,
        }
    }

    /// Its name, where it was skipped.
    pub(crate) fn skipped(&self) -> Option<&'static str> {
        match self {
            Verified::Skipped { name, .. } => Some(name),
            Verified::Checked(_) => None,
        }
    }
}

/// Run `checks` in order (as [`verify`]), each backend opened once; a check whose backend cannot be
/// opened, or registered for another adapter than this one where the same claim has a check of its
/// own here, is skipped. `each` sees every one as it ends.
pub(crate) fn verify_all(
    checks: &[&'static Check],
    cases: usize,
    found: &Path,
    mut each: impl FnMut(&Verified),
) -> Result<Vec<Verified>, VerifyError> {
    let mut backends = super::Backends::default();
    let mut all = Vec::new();
    for &c in checks {
        let v = match backends.open(c.backend) {
            Err(why) => Verified::Skipped { name: c.name, why },
            Ok(b) => {
                let adapter = b.ran().adapter;
                if c.elsewhere(adapter.as_deref()) {
                    let word = c.adapter.unwrap_or_default();
                    Verified::Skipped {
                        name: c.name,
                        why: format!(
                            "registered for {word}; {} has its own check",
                            adapter.unwrap_or_default()
                        ),
                    }
                } else {
                    Verified::Checked(verify(c, b, cases, found)?)
                }
            }
        };
        each(&v);
        all.push(v);
    }
    Ok(all)
}

/// Checks picked by `--run` (names or their start before `@`, none for all) less `--skip`'s; an
/// unknown name is an error listing the names.
pub fn pick(run: &[String], skip: &[String]) -> Result<Vec<&'static Check>, String> {
    let matches = |c: &Check, n: &str| c.name == n || c.name.split('@').next() == Some(n);
    for n in run.iter().chain(skip) {
        if !checks().any(|c| matches(c, n)) {
            let names: Vec<&str> = checks().map(|c| c.name).collect();
            return Err(format!(
                "no claim '{n}' in the register: {}",
                names.join(", ")
            ));
        }
    }
    Ok(checks()
        .filter(|c| run.is_empty() || run.iter().any(|n| matches(c, n)))
        .filter(|c| !skip.iter().any(|n| matches(c, n)))
        .collect())
}

impl Check {
    /// Whether the register's word is for the adapter described so (every CPU check is; a GPU
    /// check is for the adapters whose description holds its word).
    pub fn registered_for(&self, adapter: Option<&str>) -> bool {
        match (self.backend, self.adapter) {
            (BackendKind::Gpu, Some(word)) => {
                adapter.is_some_and(|a| a.to_lowercase().contains(&word.to_lowercase()))
            }
            _ => true,
        }
    }

    /// Whether the same claim has another check registered for this adapter (`verify` runs that
    /// one there and leaves this one out).
    pub fn elsewhere(&self, adapter: Option<&str>) -> bool {
        !self.registered_for(adapter)
            && checks().any(|o| {
                o.name != self.name
                    && (o.family, o.method, o.backend) == (self.family, self.method, self.backend)
                    && o.registered_for(adapter)
            })
    }

    /// The method, looked up in its family (a check of a method the registry lacks is a bug of the
    /// register, which a test catches).
    pub fn known(&self) -> bool {
        crate::with_family!(self.family, F => family::by_name::<F>(self.method).is_ok())
    }
}
