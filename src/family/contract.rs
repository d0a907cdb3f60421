//! Contracts: what a kernel assumes of the cases it is given — where the ray's origin lies, a unit
//! direction, an entry face given or not, the tetrahedron's orientation, a tolerance it is allowed.
//! Stress rows, campaigns, `gen-cases` and the shrinker keep every case inside the contract
//! ([`Family::contracted`], [`Family::holds`]): a case outside it is never blamed on the kernel.

use super::Family;
use crate::tet::{FACE_VERTICES, Tet, orientation};
use glam::{DVec3, Vec3};

/// Where a case's ray starts, relative to its tetrahedron.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Origin {
    /// Anywhere the rows place it: inside the closed tetrahedron half the time, before it on the line
    /// the rest, never past its exit.
    #[default]
    Anywhere,
    /// Strictly before the entry face: outside the closed tetrahedron, the line entering ahead.
    Before,
    /// On an entry face, exactly, where f32 has a point there next to the exact entry point; else
    /// the nearest point strictly inside, one f32 step from outside (docs/answerers.md, "Contracts";
    /// photon-transport step functions).
    Entry,
    /// Strictly inside the tetrahedron (exactly so).
    Inside,
}

crate::choice!(Origin { Anywhere => "anywhere", Before => "before", Entry => "entry", Inside => "inside" });

/// The placements a contract allows a case's origin: one or more of before, entry and inside
/// (`--origin inside,entry`: a step function that starts inside its element or on the face it
/// entered by), or anywhere on the line (the rows' own). Each case is made for one of them in turn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Origins(u8);

impl Origins {
    /// No placement asked: the rows' own (inside the closed tetrahedron or before it on the line).
    pub const ANYWHERE: Origins = Origins(0);

    /// The set of `placements` (`anywhere` among them asks nothing).
    pub fn of(placements: &[Origin]) -> Origins {
        Origins(placements.iter().fold(0, |s, &o| match o {
            Origin::Anywhere => s,
            o => s | 1 << o as u8,
        }))
    }

    /// Whether no placement is asked.
    pub fn is_anywhere(self) -> bool {
        self.0 == 0
    }

    /// Whether `o` is one of the placements (every placement is, where none is asked).
    pub fn allows(self, o: Origin) -> bool {
        self.is_anywhere() || self.0 & (1 << o as u8) != 0
    }

    /// The placements, in the order `before`, `entry`, `inside` (`anywhere` alone where none).
    pub fn placements(self) -> Vec<Origin> {
        use crate::choice::Choice;
        let asked: Vec<Origin> = Origin::ALL
            .iter()
            .copied()
            .filter(|&o| o != Origin::Anywhere && self.0 & (1 << o as u8) != 0)
            .collect();
        if asked.is_empty() {
            vec![Origin::Anywhere]
        } else {
            asked
        }
    }

    /// The placement the case of key `key` is made for: each in turn.
    pub(crate) fn for_key(self, key: u64) -> Origin {
        let p = self.placements();
        p[(key % p.len() as u64) as usize]
    }

    /// As `--origin` writes it: `anywhere`, `inside`, `inside,entry`.
    pub fn name(self) -> String {
        use crate::choice::Choice;
        let names: Vec<&str> = self.placements().into_iter().map(Origin::name).collect();
        names.join(",")
    }
}

impl From<Origin> for Origins {
    fn from(o: Origin) -> Origins {
        Origins::of(&[o])
    }
}

impl serde::Serialize for Origins {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.name())
    }
}

/// Whether a case carries the face its ray entered through.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum EntryGiven {
    /// As the rows make them: even-numbered cases carry it, odd ones not.
    #[default]
    Any,
    /// Every case carries an exact entry face.
    Given,
    /// No case carries one.
    None,
}

crate::choice!(EntryGiven { Any => "any", Given => "given", None => "none" });

/// Which orientations of tetrahedra a kernel takes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Orientation {
    /// Positively oriented only ([`crate::tet::orientation`]): the rows' own.
    #[default]
    Positive,
    /// Negatively oriented only (TetGen's `.ele` order): every case has vertices 0 and 1 swapped.
    Negative,
    /// Either: half the cases have vertices 0 and 1 swapped (negatively oriented).
    Any,
}

crate::choice!(Orientation { Positive => "positive", Negative => "negative", Any => "any" });

/// What a kernel assumes (module docs); the default is what the rows make.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Contract {
    /// Where each ray's origin may lie.
    pub origin: Origins,
    /// Directions of length 1 (each rounded to f32 from the exact unit vector, the case judged as it
    /// then is).
    pub unit_direction: bool,
    /// Whether cases carry their entry face.
    pub entry: EntryGiven,
    /// Which orientations of tetrahedra the method takes: the cases an answerer is sent are made so.
    /// A Rust method of the kit ([`crate::methods::ExitMethod`]) is handed every tetrahedron
    /// positively oriented whatever this says (its faces renumbered to match); the kit's convention
    /// check says where its answers fit the mirrored ones instead.
    pub orientation: Orientation,
    /// Lines passing within this distance of an edge, relative to the longest edge, are outside the
    /// contract (a kernel with an epsilon is allowed its epsilon); 0: none.
    pub tolerance: f64,
}

impl Contract {
    /// Whether it asks nothing beyond what the rows make.
    pub(crate) fn is_default(&self) -> bool {
        *self == Contract::default()
    }

    /// Whether it asks only what every family's cases can give (a unit direction).
    pub(crate) fn is_general(&self) -> bool {
        Contract {
            unit_direction: false,
            ..*self
        }
        .is_default()
    }

    /// The same contract with the tetrahedra of the other orientation (`None` for either).
    pub(crate) fn mirrored(&self) -> Option<Contract> {
        let orientation = match self.orientation {
            Orientation::Positive => Orientation::Negative,
            Orientation::Negative => Orientation::Positive,
            Orientation::Any => return None,
        };
        Some(Contract {
            orientation,
            ..*self
        })
    }

    /// An error naming what is not a contract (a tolerance out of range).
    pub(crate) fn check(&self) -> Result<(), String> {
        if !(self.tolerance.is_finite() && (0.0..1.0).contains(&self.tolerance)) {
            return Err(format!(
                "--tolerance {} is not a relative distance in [0, 1)",
                self.tolerance
            ));
        }
        Ok(())
    }

    /// An error naming what is not a contract, or what family `F`'s cases cannot hold (only exit
    /// faces hold more than a unit direction).
    pub(crate) fn check_for<F: super::Family>(&self) -> Result<(), String> {
        self.check()?;
        if !F::CONTRACTS && !self.is_general() {
            return Err(format!(
                "--origin, --entry, --orientation and --tolerance state what an exit-face kernel assumes; {} cases take --unit-direction only",
                F::NAME
            ));
        }
        Ok(())
    }

    /// The contract in words, for reports.
    pub fn describe(&self) -> String {
        use crate::choice::Choice;
        let mut s = vec![
            format!("origin {}", self.origin.name()),
            format!("entry face {}", self.entry.name()),
            format!("orientation {}", self.orientation.name()),
        ];
        if self.unit_direction {
            s.push("unit direction".into());
        }
        if self.tolerance > 0.0 {
            s.push(format!("tolerance {}", self.tolerance));
        }
        s.join(", ")
    }
}

/// A direction of length 1: the unit vector of `d` rounded to f32, where that is the f32 rounding of a
/// unit vector ([`is_unit`]; `None` for a zero direction, or where f64's normalising rounded it off).
pub(crate) fn unit(d: Vec3) -> Option<Vec3> {
    let u = d.as_dvec3().normalize_or_zero().as_vec3();
    (u != Vec3::ZERO && is_unit(u)).then_some(u)
}

/// The reals that round to the f32 `x` (round to nearest): `[x - h, x + h]` with `h` half the gap to
/// the neighbour on each side, as exact f64 values (closed: a tie's side is taken either way).
fn rounding_interval(x: f32) -> (f64, f64) {
    let v = x as f64;
    (
        v - (v - x.next_down() as f64) / 2.0,
        v + (x.next_up() as f64 - v) / 2.0,
    )
}

/// Whether `d` is the f32 rounding of a unit vector, exactly: the box of the reals rounding to it
/// meets the unit sphere (its nearest point to the origin within length 1, its farthest beyond).
/// The box's corners are exact in f64, their squares too; the sums are compared in rationals.
pub(crate) fn is_unit(d: Vec3) -> bool {
    use rug::Rational;
    if !d.is_finite() {
        return false;
    }
    let (mut near, mut far) = (Rational::new(), Rational::new());
    for x in d.to_array() {
        let (lo, hi) = rounding_interval(x);
        let q = |v: f64| Rational::from_f64(v).expect("finite");
        let n = if lo <= 0.0 && hi >= 0.0 {
            0.0
        } else {
            lo.abs().min(hi.abs())
        };
        near += q(n) * q(n);
        far += q(lo.abs().max(hi.abs())) * q(lo.abs().max(hi.abs()));
    }
    near <= 1 && far >= 1
}

/// The side of face `f`'s plane `p` lies on, as vertex `f` does (+1), the other side (-1) or on it
/// (0): exactly.
pub(crate) fn face_side(tet: &Tet, f: usize, p: Vec3) -> i8 {
    let [a, b, c] = FACE_VERTICES[f].map(|i| tet[i]);
    orientation(&[a, b, c, p]) * orientation(&[a, b, c, tet[f]])
}

/// Whether `p` lies strictly inside the tetrahedron.
pub(crate) fn strictly_inside(tet: &Tet, p: Vec3) -> bool {
    (0..4).all(|f| face_side(tet, f, p) > 0)
}

/// Whether `p` lies in the closed tetrahedron (inside or on its boundary), exactly.
pub(crate) fn in_closed(tet: &Tet, p: Vec3) -> bool {
    (0..4).all(|f| face_side(tet, f, p) >= 0)
}

/// The sign of `n_f · d`, `n_f` face `f`'s outward normal, exactly: negative where a line along `d`
/// enters through face `f`'s plane, positive where it leaves through it.
pub(crate) fn facing(tet: &Tet, f: usize, d: Vec3) -> i8 {
    let [a, b, c] = FACE_VERTICES[f].map(|i| tet[i]);
    orientation(tet) * crate::exact::normal_dot(a, b, c, d)
}

/// Whether `p` lies on an entry face of the line through it along `d`, exactly: in the closed
/// tetrahedron, on the plane of a face the line enters through.
pub(crate) fn on_entry_face(tet: &Tet, p: Vec3, d: Vec3) -> bool {
    in_closed(tet, p) && (0..4).any(|f| face_side(tet, f, p) == 0 && facing(tet, f, d) < 0)
}

/// Whether `p` lies past the exit of the line through it along `d`: beyond the plane of a face the
/// line leaves through (then the ray from `p` never meets the tetrahedron), exactly.
pub(crate) fn past_exit(tet: &Tet, p: Vec3, d: Vec3) -> bool {
    (0..4).any(|f| facing(tet, f, d) > 0 && face_side(tet, f, p) < 0)
}

/// The 26 f32 points next to `p`: each coordinate one step down, kept or one step up.
pub(crate) fn neighbours(p: Vec3) -> impl Iterator<Item = Vec3> {
    (0..27).filter(|&k| k != 13).map(move |k| {
        let step = |x: f32, s: i32| match s {
            0 => x.next_down(),
            2 => x.next_up(),
            _ => x,
        };
        Vec3::new(step(p.x, k % 3), step(p.y, k / 3 % 3), step(p.z, k / 9))
    })
}

/// An origin on the entry face of the line `o + t·d` that enters the tetrahedron at the exact point
/// `at` (f64), through face `e`, exactly so: of the f32 points nearest `at` (its rounding and their
/// 26 neighbours), the nearest one that lies on an entry face of its own line (in the closed
/// tetrahedron, on the plane of a face its line enters through); where none does, as f32 allows:
/// the one strictly inside nearest face `e`'s plane. `None` where none of them is in the
/// tetrahedron (a cell thinner than the f32 grid there).
pub(crate) fn entry_origin(tet: &Tet, at: DVec3, e: usize, d: Vec3) -> Option<Vec3> {
    let r = at.as_vec3();
    let near = |p: &Vec3| (p.as_dvec3() - at).length();
    let [a, b, c] = FACE_VERTICES[e].map(|i| tet[i].as_dvec3());
    let n = (b - a).cross(c - a).normalize_or_zero();
    let plane = |p: &Vec3| n.dot(p.as_dvec3() - a).abs();
    let candidates: Vec<Vec3> = std::iter::once(r).chain(neighbours(r)).collect();
    let least = |keep: &dyn Fn(Vec3) -> bool, key: &dyn Fn(&Vec3) -> (f64, f64)| {
        candidates
            .iter()
            .copied()
            .filter(|&p| keep(p))
            .min_by(|p, q| {
                let (a, b) = (key(p), key(q));
                a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1))
            })
    };
    least(&|p| on_entry_face(tet, p, d), &|p| (near(p), 0.0))
        .or_else(|| least(&|p| strictly_inside(tet, p), &|p| (plane(p), near(p))))
}

/// Whether `o` is an origin [`entry_origin`] could place for the line along `d`: on an entry face of
/// its line, or, where no f32 point next to it is, strictly inside and next to a point outside the
/// plane of a face its line enters through (as near that face as f32 allows).
pub(crate) fn holds_entry(tet: &Tet, o: Vec3, d: Vec3) -> bool {
    if on_entry_face(tet, o, d) {
        return true;
    }
    let entering: Vec<usize> = (0..4).filter(|&f| facing(tet, f, d) < 0).collect();
    strictly_inside(tet, o)
        && !neighbours(o).any(|p| on_entry_face(tet, p, d))
        && neighbours(o).any(|p| entering.iter().any(|&f| face_side(tet, f, p) < 0))
}

/// The distance from the line `o + s·d` to the segment `a b`, in f64.
fn line_segment_distance(o: DVec3, d: DVec3, a: DVec3, b: DVec3) -> f64 {
    let e = b - a;
    let n = d.cross(e);
    let w = a - o;
    if n.length_squared() > 0.0 {
        // The segment's point nearest the line: where it crosses the plane through the line with
        // normal d × n, clamped to the segment.
        let m = d.cross(n);
        let s = (-(w.dot(m)) / e.dot(m)).clamp(0.0, 1.0);
        let p = a + e * s - o;
        return (p - d * (p.dot(d) / d.length_squared())).length();
    }
    (w - d * (w.dot(d) / d.length_squared())).length()
}

/// The distance from the case's line to the nearest edge, relative to the longest edge (f64: a
/// contract's border, never a verdict).
pub(crate) fn edge_distance(tet: &Tet, org: Vec3, dir: Vec3) -> f64 {
    let longest = crate::tet::EDGES
        .iter()
        .map(|&[a, b]| (tet[b] - tet[a]).as_dvec3().length())
        .fold(0.0, f64::max);
    crate::tet::EDGES
        .iter()
        .map(|&[a, b]| {
            line_segment_distance(
                org.as_dvec3(),
                dir.as_dvec3(),
                tet[a].as_dvec3(),
                tet[b].as_dvec3(),
            ) / longest
        })
        .fold(f64::INFINITY, f64::min)
}

/// `case` made to hold a contract other than the default one ([`Family::contracted`], with `key`),
/// judged again as it then is, and kept where it holds: the case and its truth.
pub(crate) fn within<F: Family>(
    contract: &Contract,
    case: &F::Case,
    key: u64,
) -> Option<(F::Case, F::Truth)> {
    let c = F::contracted(contract, case, key)?;
    let x = F::truth(&c).ok()?;
    F::holds(contract, &c, &x).then_some((c, x))
}

/// The cases of `F`'s stress row made until `count` of them hold `contract`, with their truths: case
/// `i` of the row is tried, made to hold it ([`Family::contracted`], with key `i`), judged again as it
/// then is, and kept where it holds — the default contract too, which is what the rows promise
/// (for tetrahedra: positively oriented, the line crossing, the origin inside or before), so that a
/// case a scale's rounding flips or moves is replaced, not judged as the row's; at most eight times
/// `count` are tried. The first `count` kept, in order of `i`; a pure function of
/// the row, the seed and the contract.
pub(crate) fn cases_within<F: Family>(
    contract: &Contract,
    count: usize,
    make: impl Fn(usize) -> Option<(F::Case, F::Truth)> + Sync,
) -> Vec<(F::Case, F::Truth)> {
    use rayon::prelude::*;
    let mut kept = Vec::with_capacity(count);
    let mut from = 0;
    while kept.len() < count && from < count.saturating_mul(8) {
        let to = if from == 0 {
            count
        } else {
            from + (count - kept.len()).max(64)
        };
        let more: Vec<_> = (from..to)
            .into_par_iter()
            .map(|i| {
                let (c, _) = make(i)?;
                within::<F>(contract, &c, i as u64)
            })
            .collect();
        kept.extend(more.into_iter().flatten().take(count - kept.len()));
        from = to;
    }
    kept
}
