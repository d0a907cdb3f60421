//! Exact signs of the determinants the oracle needs: an f64 filter with a proven error bound in front,
//! `rug` integers behind it, and per-thread counts of which stage decided.

use glam::Vec3;
use rug::Integer;
use std::cell::Cell;

/// How many signs each stage decided (on the calling thread).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct SignCounts {
    /// Decided by the f64 filter.
    pub filter: u64,
    /// Decided by exact integer arithmetic after the filter could not.
    pub exact: u64,
}

impl SignCounts {
    /// Counts accumulated since `earlier` (a value returned by [`counts`] on the same thread).
    pub fn since(self, earlier: SignCounts) -> SignCounts {
        SignCounts {
            filter: self.filter - earlier.filter,
            exact: self.exact - earlier.exact,
        }
    }
}

impl std::ops::AddAssign for SignCounts {
    fn add_assign(&mut self, o: SignCounts) {
        self.filter += o.filter;
        self.exact += o.exact;
    }
}

thread_local! {
    static COUNTS: Cell<SignCounts> = const { Cell::new(SignCounts { filter: 0, exact: 0 }) };
}

/// The stage counts of the calling thread since it started.
pub fn counts() -> SignCounts {
    COUNTS.with(Cell::get)
}

fn count(exact: bool) {
    COUNTS.with(|c| {
        let mut v = c.get();
        if exact {
            v.exact += 1;
        } else {
            v.filter += 1;
        }
        c.set(v);
    });
}

/// Unit roundoff of f64.
const U: f64 = f64::EPSILON / 2.0;

/// Error bound of the filter, relative to the permanent. Each of the six monomials of
/// `det[a, b, r]` with `a = p1 - q1`, `b = p2 - q2` rounded and `r` exact passes through at most
/// seven roundings (two differences, two products, the minor's difference, two sums), so the
/// computed determinant is within `γ7 · Σ|monomials| ≤ 8u · permanent` of the exact one. f32 inputs
/// never overflow or underflow f64 here: nonzero differences are ≥ 2^-149, products ≥ 2^-447.
const FILTER_BOUND: f64 = 8.0 * U;

/// The f64 filter alone: the sign of `det[p1 - q1, p2 - q2, r]` when `FILTER_BOUND` settles it, for
/// finite f32 inputs (`None`: the exact stage decides).
pub fn filter(p1: Vec3, q1: Vec3, p2: Vec3, q2: Vec3, r: Vec3) -> Option<i8> {
    let (p1, q1, p2, q2, r) = (w64(p1), w64(q1), w64(p2), w64(q2), w64(r));
    let a = [p1[0] - q1[0], p1[1] - q1[1], p1[2] - q1[2]];
    let b = [p2[0] - q2[0], p2[1] - q2[1], p2[2] - q2[2]];
    let (m0, m1, m2) = (
        b[1] * r[2] - b[2] * r[1],
        b[2] * r[0] - b[0] * r[2],
        b[0] * r[1] - b[1] * r[0],
    );
    let det = a[0] * m0 + a[1] * m1 + a[2] * m2;
    let perm = a[0].abs() * ((b[1] * r[2]).abs() + (b[2] * r[1]).abs())
        + a[1].abs() * ((b[2] * r[0]).abs() + (b[0] * r[2]).abs())
        + a[2].abs() * ((b[0] * r[1]).abs() + (b[1] * r[0]).abs());
    (det.abs() > FILTER_BOUND * perm || perm == 0.0).then(|| signum(det))
}

/// Sign of `det[p1 - q1, p2 - q2, r]` (rows), exactly, for finite f32 inputs: [`filter`], then exact
/// integers, in the standard floating-point environment whatever the caller's.
pub fn sign_det(p1: Vec3, q1: Vec3, p2: Vec3, q2: Vec3, r: Vec3) -> i8 {
    crate::fpenv::standard((p1, q1, p2, q2, r), |(p1, q1, p2, q2, r)| {
        if let Some(s) = filter(p1, q1, p2, q2, r) {
            count(false);
            return s;
        }
        count(true);
        big_det(w64(p1), w64(q1), w64(p2), w64(q2), w64(r)).cmp0() as i8
    })
}

/// `det[p1 - q1, p2 - q2, r]` scaled by 2^447, exactly.
fn big_det(p1: [f64; 3], q1: [f64; 3], p2: [f64; 3], q2: [f64; 3], r: [f64; 3]) -> Integer {
    let (p1, q1, p2, q2, r) = (big3(p1), big3(q1), big3(p2), big3(q2), big3(r));
    let a: [Integer; 3] = std::array::from_fn(|i| Integer::from(&p1[i] - &q1[i]));
    let b: [Integer; 3] = std::array::from_fn(|i| Integer::from(&p2[i] - &q2[i]));
    let mut det = Integer::new();
    for (i, ai) in a.iter().enumerate() {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let minor = Integer::from(&b[j] * &r[k]) - Integer::from(&b[k] * &r[j]);
        det += ai * minor;
    }
    det
}

/// `det[p1 - q1, p2 - q2, r]` computed exactly, then rounded to f64 (for measuring, not deciding).
pub fn exact_det(p1: Vec3, q1: Vec3, p2: Vec3, q2: Vec3, r: Vec3) -> f64 {
    let d = big_det(w64(p1), w64(q1), w64(p2), w64(q2), w64(r));
    // Undo the 2^149 scale of each of the three factors (exact: |d| < 2^834 and d is an integer).
    d.to_f64() * 2f64.powi(-447)
}

/// Sign of component `axis` of `(p - q) × r`, exactly; used only by the symbolic perturbation.
pub fn sign_cross(p: Vec3, q: Vec3, r: Vec3, axis: usize) -> i8 {
    let (p, q, r) = (big3(w64(p)), big3(w64(q)), big3(w64(r)));
    let (j, k) = ((axis + 1) % 3, (axis + 2) % 3);
    let e = |i: usize| Integer::from(&p[i] - &q[i]);
    let v = e(j) * &r[k] - e(k) * &r[j];
    v.cmp0() as i8
}

fn w64(v: Vec3) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

fn signum(x: f64) -> i8 {
    (x > 0.0) as i8 - (x < 0.0) as i8
}

/// An f32 value (widened) times 2^149, an integer exactly.
pub(crate) fn big(x: f64) -> Integer {
    Integer::from_f64(x * 2f64.powi(149)).expect("finite f32 values scale to integers")
}

fn big3(v: [f64; 3]) -> [Integer; 3] {
    v.map(big)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filter_and_exact_stage_agree_and_are_counted() {
        let o = Vec3::new(0.1, 0.2, 0.3);
        let before = counts();
        // A clear case the filter decides.
        let s = sign_det(Vec3::X, o, Vec3::Y, o, Vec3::Z);
        assert_eq!(s, 1);
        // Exactly zero with nonzero terms: the filter cannot decide it.
        let (a, b) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.0));
        let z = sign_det(a, Vec3::ZERO, b, Vec3::ZERO, Vec3::new(7.0, 8.0, 9.0));
        assert_eq!(z, 0);
        // An orientation that needs more than f64: tiny offset beside huge coordinates.
        let p = Vec3::new(1.0e20, 1.0, 0.0);
        let q = Vec3::new(-1.0e20, 1.0, 0.0);
        let t = sign_det(p, Vec3::new(0.0, 1.0e-20, 0.0), q, Vec3::ZERO, Vec3::Z);
        assert_ne!(t, 0);
        let c = counts().since(before);
        assert_eq!(c.filter + c.exact, 3);
        assert!(c.exact >= 1 && c.filter >= 1, "{c:?}");
    }
}
