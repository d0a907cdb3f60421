//! The filter checker (after CGAL's `Kernel_checker`): every filtered sign tetwalk decides, beside the
//! exact sign, on inputs drawn from every exponent regime — the oracle's f64 filter
//! ([`crate::exact::sign::filter`], side products and face normals), `robust`'s orient3d behind
//! [`crate::tet::orientation`], and `certified`'s f32 stage under each model's bound
//! ([`crate::methods::certified::f32_stage`]: gradual underflow, flushed to zero, the GPU's). A decided sign
//! that differs from the exact one is a refutation; undecided signs count the exact stage's cost.
//! The box oracle has no filter (rationals throughout), so there is nothing of it to check here.

use crate::exact::rational::{det, q3, sub};
use crate::methods::certified::{self, Bound};
use crate::scenes::Rng;
use crate::scenes::tets::{self, Target, TetShape};
use crate::tet::Ray;
use glam::Vec3;
use rand::RngExt;

/// Where a case's coordinates are drawn from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Regime {
    /// Below f32's normal range (2^-149 to 2^-126).
    Subnormal,
    /// Normal, below the flushing models' gate (2^-126 to 2^-100).
    Tiny,
    /// 2^-100 to 2^-20.
    Small,
    /// 2^-20 to 2^20.
    Unit,
    /// 2^20 to 2^40.
    Huge,
    /// 2^40 to 2^100: products may overflow.
    Vast,
    /// 2^100 to 2^127: products overflow.
    NearOverflow,
    /// Each point from its own regime (one vertex 1e-20 from the origin, another 1e15 away).
    Mixed,
    /// The stress rows' near-edge and near-vertex cases, scaled by an exact power of two 2^-149..2^100.
    Scaled,
}

crate::choice!(Regime {
    Subnormal => "subnormal",
    Tiny => "tiny",
    Small => "small",
    Unit => "unit",
    Huge => "huge",
    Vast => "vast",
    NearOverflow => "near-overflow",
    Mixed => "mixed",
    Scaled => "scaled",
});

impl Regime {
    pub const ALL: [Regime; 9] = [
        Regime::Subnormal,
        Regime::Tiny,
        Regime::Small,
        Regime::Unit,
        Regime::Huge,
        Regime::Vast,
        Regime::NearOverflow,
        Regime::Mixed,
        Regime::Scaled,
    ];

    /// The range of binary exponents of a plain regime.
    fn exponents(self) -> (i32, i32) {
        match self {
            Regime::Subnormal => (-149, -127),
            Regime::Tiny => (-126, -100),
            Regime::Small => (-100, -20),
            Regime::Unit => (-20, 20),
            Regime::Huge => (20, 40),
            Regime::Vast => (40, 100),
            Regime::NearOverflow => (100, 127),
            Regime::Mixed | Regime::Scaled => unreachable!("not a plain regime"),
        }
    }
}

/// The filtered signs checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Filter {
    /// The oracle's f64 filter on a side product `det[a - o, b - o, d]`.
    OracleSide,
    /// The oracle's f64 filter on a face normal's `n · d`.
    OracleNormal,
    /// `robust`'s orient3d (adaptive f64) on `orient3d(a, b, c, o)`.
    Orient3d,
    /// certified's f32 stage, gradual underflow (`cpu`, `cpu-fma`).
    Certified,
    /// certified's f32 stage, subnormals flushed (`cpu-ftz`), inputs gated.
    CertifiedFtz,
    /// certified's GPU bound, gradual underflow.
    CertifiedGpu,
    /// certified's GPU bound, subnormals flushed.
    CertifiedGpuFtz,
}

impl Filter {
    pub const ALL: [Filter; 7] = [
        Filter::OracleSide,
        Filter::OracleNormal,
        Filter::Orient3d,
        Filter::Certified,
        Filter::CertifiedFtz,
        Filter::CertifiedGpu,
        Filter::CertifiedGpuFtz,
    ];

    pub(crate) fn name(self) -> &'static str {
        match self {
            Filter::OracleSide => "oracle side (f64)",
            Filter::OracleNormal => "oracle normal (f64)",
            Filter::Orient3d => "orient3d (robust)",
            Filter::Certified => "certified f32",
            Filter::CertifiedFtz => "certified f32, flushed",
            Filter::CertifiedGpu => "certified GPU bound",
            Filter::CertifiedGpuFtz => "certified GPU bound, flushed",
        }
    }
}

/// One case: a tetrahedron's three points `a, b, c`, a ray.
#[derive(Clone, Copy, Debug)]
pub struct Inputs {
    pub a: Vec3,
    pub b: Vec3,
    pub c: Vec3,
    pub org: Vec3,
    pub dir: Vec3,
}

/// A decided sign that is not the exact one.
#[derive(Clone, Debug)]
pub struct Refuted {
    pub regime: Regime,
    pub filter: Filter,
    pub inputs: Inputs,
    pub decided: i8,
    pub exact: i8,
}

/// Per regime and filter: signs asked, signs the exact stage had to decide, decided signs that were wrong.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct FilterTally {
    pub asked: u64,
    pub exact_stage: u64,
    pub(crate) wrong: u64,
}

impl std::ops::AddAssign for FilterTally {
    fn add_assign(&mut self, o: FilterTally) {
        self.asked += o.asked;
        self.exact_stage += o.exact_stage;
        self.wrong += o.wrong;
    }
}

/// The most refutations a campaign keeps (the first found).
const KEPT: usize = 16;

/// A campaign's tallies, `[regime][filter]`, and the first refutations found (at most `KEPT`).
#[derive(Clone, Debug, Default)]
pub struct Campaign {
    pub tallies: Vec<(Regime, Vec<(Filter, FilterTally)>)>,
    pub refuted: Vec<Refuted>,
}

impl Campaign {
    /// Add another round of the same regimes and filters.
    pub fn add(&mut self, other: Campaign) {
        for ((_, acc), (_, add)) in self.tallies.iter_mut().zip(other.tallies) {
            for ((_, x), (_, y)) in acc.iter_mut().zip(add) {
                *x += y;
            }
        }
        self.refuted.extend(other.refuted);
        self.refuted.truncate(KEPT);
    }

    pub fn wrong(&self) -> u64 {
        self.tallies
            .iter()
            .flat_map(|(_, t)| t.iter().map(|(_, t)| t.wrong))
            .sum()
    }
}

/// Rounds of [`check`] (seeds `first_seed`, `first_seed + 1`, ...) summed: `tetwalk check-filters`.
pub struct Rounds {
    /// The rounds' tallies summed.
    pub campaign: Campaign,
    /// Rounds run.
    pub rounds: u64,
    /// The first round's seed.
    pub(crate) first_seed: u64,
    /// Cases per regime and round.
    pub(crate) cases: usize,
    /// Wall time of all rounds.
    pub(crate) seconds: f64,
}

impl Rounds {
    /// Rounds of `cases` cases per regime from `seed` on, until `seconds` have passed (one at least).
    pub fn run(cases: usize, seed: u64, seconds: u64) -> Rounds {
        let start = std::time::Instant::now();
        let mut campaign = check(cases, seed);
        let mut rounds = 1u64;
        while start.elapsed().as_secs() < seconds {
            campaign.add(check(cases, seed.wrapping_add(rounds)));
            rounds += 1;
        }
        Rounds {
            campaign,
            rounds,
            first_seed: seed,
            cases,
            seconds: start.elapsed().as_secs_f64(),
        }
    }
}

/// An f32 of random sign and mantissa with binary exponent in `lo..=hi` (subnormal below -126),
/// sometimes zero.
fn coordinate(lo: i32, hi: i32, rng: &mut Rng) -> f32 {
    if rng.random_range(0..16) == 0 {
        return 0.0;
    }
    let k = rng.random_range(lo..=hi);
    let mantissa: u32 = rng.random::<u32>() & 0x7f_ffff;
    let bits = if k < -126 {
        // A subnormal of magnitude about 2^k: keep the bits below it.
        let keep = (k + 149) as u32;
        (mantissa & ((1u32 << keep.min(23)) - 1)) | (1 << keep.min(22))
    } else {
        (((k + 127) as u32) << 23) | mantissa
    };
    let x = f32::from_bits(bits);
    if rng.random() { -x } else { x }
}

fn point(regime: Regime, rng: &mut Rng) -> Vec3 {
    let (lo, hi) = regime.exponents();
    Vec3::new(
        coordinate(lo, hi, rng),
        coordinate(lo, hi, rng),
        coordinate(lo, hi, rng),
    )
}

/// The regimes of one magnitude range each: every regime but the two composite ones, which come last.
const PLAIN: &[Regime] = Regime::ALL.split_at(Regime::ALL.len() - 2).0;

/// A case of `regime`: random points, or (one in three) a ray nearly through an edge or along it.
pub fn draw(regime: Regime, rng: &mut Rng) -> Inputs {
    if regime == Regime::Scaled {
        return scaled(rng);
    }
    let p = |rng: &mut Rng| match regime {
        Regime::Mixed => point(PLAIN[rng.random_range(0..PLAIN.len())], rng),
        r => point(r, rng),
    };
    let (a, b, c) = (p(rng), p(rng), p(rng));
    let (org, dir) = match rng.random_range(0..3) {
        // The line nearly through the edge a-b: o on it, rounded.
        0 => (a + (b - a) * rng.random::<f32>(), p(rng)),
        // The direction along the edge, rounded.
        1 => (p(rng), b - a),
        _ => (p(rng), p(rng)),
    };
    let fix = |v: Vec3| if v.is_finite() { v } else { a };
    let dir = fix(dir);
    Inputs {
        a,
        b,
        c,
        org: fix(org),
        dir: if dir == Vec3::ZERO { Vec3::X } else { dir },
    }
}

/// A stress row's near-edge or near-vertex case, scaled by 2^k (exact unless it underflows).
fn scaled(rng: &mut Rng) -> Inputs {
    let family = TetShape::ALL[rng.random_range(0..TetShape::ALL.len())];
    let target = if rng.random() {
        Target::Edge
    } else {
        Target::Vertex
    };
    let flatness = [1.0, 1e-3][rng.random_range(0..2)];
    let k = rng.random_range(0..8);
    let (t, ray) = tets::near(family, flatness, target, k, rng)
        .or_else(|| tets::through(family, flatness, target, rng))
        .unwrap_or_else(|| {
            let t = tets::tet(family, flatness, rng);
            let r = tets::stabbing_ray(&t, rng);
            (t, r)
        });
    let s = 2f32.powi(rng.random_range(-149..=100));
    let scale = |v: Vec3| v * s;
    let dir = scale(ray.dir);
    let i = rng.random_range(0..4);
    Inputs {
        a: scale(t[i]),
        b: scale(t[(i + 1) % 4]),
        c: scale(t[(i + 2) % 4]),
        org: scale(ray.org),
        dir: if dir == Vec3::ZERO { ray.dir } else { dir },
    }
}

/// `det[p - r, s - t, d]`'s sign in rationals (independent of the oracle's integer stage).
fn exact_det(p: Vec3, r: Vec3, s: Vec3, t: Vec3, d: Vec3) -> i8 {
    det(&sub(&q3(p), &q3(r)), &sub(&q3(s), &q3(t)), &q3(d)).cmp0() as i8
}

/// Each filter's decided sign (`None`: undecided) and the exact sign, for one case.
pub(crate) fn signs(x: &Inputs) -> Vec<(Filter, Option<i8>, i8)> {
    let Inputs { a, b, c, org, dir } = *x;
    let ray = Ray { org, dir };
    let side = exact_det(a, org, b, org, dir);
    let stage = |bound: Bound, flush: bool| {
        let run = |()| certified::f32_stage(a, b, &ray, bound, flush);
        if flush {
            crate::fpenv::flushed((), run)
        } else {
            run(())
        }
    };
    let orient = exact_orient(a, b, c, org);
    let o3d = crate::tet::orientation(&[a, b, c, org]);
    vec![
        (
            Filter::OracleSide,
            crate::exact::sign::filter(a, org, b, org, dir),
            side,
        ),
        (
            Filter::OracleNormal,
            crate::exact::sign::filter(b, a, c, a, dir),
            exact_det(b, a, c, a, dir),
        ),
        // orient3d has no undecided outcome: its adaptive stages end exact.
        (Filter::Orient3d, Some(o3d), orient),
        (Filter::Certified, stage(certified::GRADUAL, false), side),
        (Filter::CertifiedFtz, stage(certified::FLUSHING, true), side),
        (Filter::CertifiedGpu, stage(certified::GPU, false), side),
        (Filter::CertifiedGpuFtz, stage(certified::GPU, true), side),
    ]
}

/// `orient3d(a, b, c, d)`'s sign in rationals, with `robust`'s convention: `det[a - d, b - d, c - d]`.
fn exact_orient(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> i8 {
    let d = q3(d);
    let [a, b, c] = [a, b, c].map(|p| sub(&q3(p), &d));
    det(&a, &b, &c).cmp0() as i8
}

/// One regime's tallies per filter, and its first refutations.
type RegimeChecked = (Regime, Vec<(Filter, FilterTally)>, Vec<Refuted>);

/// `cases` cases of every regime from `seed`, each sign of every filter compared with the exact one.
pub fn check(cases: usize, seed: u64) -> Campaign {
    use rayon::prelude::*;
    let per_regime: Vec<RegimeChecked> = Regime::ALL
        .par_iter()
        .enumerate()
        .map(|(i, &regime)| {
            let mut rng = crate::scenes::rng(seed ^ ((i as u64 + 1) << 48));
            let mut t: Vec<(Filter, FilterTally)> = Filter::ALL
                .iter()
                .map(|&f| (f, FilterTally::default()))
                .collect();
            let mut refuted = Vec::new();
            for _ in 0..cases {
                let x = draw(regime, &mut rng);
                for (k, (filter, decided, exact)) in signs(&x).into_iter().enumerate() {
                    let tally = &mut t[k].1;
                    tally.asked += 1;
                    match decided {
                        None => tally.exact_stage += 1,
                        Some(s) if s != exact => {
                            tally.wrong += 1;
                            if refuted.len() < KEPT {
                                refuted.push(Refuted {
                                    regime,
                                    filter,
                                    inputs: x,
                                    decided: s,
                                    exact,
                                });
                            }
                        }
                        Some(_) => {}
                    }
                }
            }
            (regime, t, refuted)
        })
        .collect();
    let mut out = Campaign::default();
    for (regime, t, r) in per_regime {
        out.tallies.push((regime, t));
        out.refuted.extend(r);
    }
    out.refuted.truncate(KEPT);
    out
}
