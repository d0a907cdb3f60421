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
    /// Anywhere on the line (the rows' own: inside half the time, before the entry face the rest).
    #[default]
    Anywhere,
    /// Strictly before the entry face: outside the closed tetrahedron, the line entering ahead.
    Before,
    /// On the entry face: the exact entry point rounded to f32 (photon-transport step functions).
    Entry,
    /// Strictly inside the tetrahedron (exactly so).
    Inside,
}

crate::choice!(Origin { Anywhere => "anywhere", Before => "before", Entry => "entry", Inside => "inside" });

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
    /// Either: half the cases have vertices 0 and 1 swapped (negatively oriented).
    Any,
}

crate::choice!(Orientation { Positive => "positive", Any => "any" });

/// What a kernel assumes (module docs); the default is what the rows make.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Contract {
    /// Where each ray's origin lies.
    pub origin: Origin,
    /// Directions of length 1 (each rounded to f32 from the exact unit vector, the case judged as it
    /// then is).
    pub unit_direction: bool,
    /// Whether cases carry their entry face.
    pub entry: EntryGiven,
    /// Which orientations of tetrahedra the method takes.
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
    pub(crate) fn describe(&self) -> String {
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

/// A direction of length 1: the exact unit vector rounded to f32 (`None` for a zero direction).
pub(crate) fn unit(d: Vec3) -> Option<Vec3> {
    let u = d.as_dvec3().normalize_or_zero().as_vec3();
    (u != Vec3::ZERO).then_some(u)
}

/// Whether `d` has length 1 to f32 rounding: within 4 ulps of 1 (a unit vector rounded per
/// coordinate is within about 2).
pub(crate) fn is_unit(d: Vec3) -> bool {
    (d.as_dvec3().length() - 1.0).abs() <= 4.0 * f32::EPSILON as f64
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
/// then is, and kept where it holds; at most eight times `count` are tried. The first `count` kept,
/// in order of `i`; a pure function of the row, the seed and the contract.
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
                let (c, x) = make(i)?;
                if contract.is_default() {
                    return Some((c, x));
                }
                within::<F>(contract, &c, i as u64)
            })
            .collect();
        kept.extend(more.into_iter().flatten().take(count - kept.len()));
        from = to;
        if contract.is_default() {
            break;
        }
    }
    kept
}
