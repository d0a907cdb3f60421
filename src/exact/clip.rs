//! An independent exact formulation: clip the line `o + t·d` against the four face half-spaces with
//! rationals. Slow; it exists to check [`super::classify`] and nothing else depends on it.

use super::rational::{Q3, cross, dot, q3, sub};
use super::{Classification, ExactError, FaceSet};
use crate::tet::{FACE_VERTICES, Ray, Tet, orientation};
use rug::Rational;

/// Exit and entry faces by clipping: the line satisfies `n_f · (x - a_f) ≤ 0` for outward normals
/// `n_f`; exit faces are those with `n_f · d > 0` whose crossing parameter is the smallest of them,
/// provided the clipped interval is non-empty.
pub fn classify_by_clipping(tet: &Tet, ray: &Ray) -> Result<Classification, ExactError> {
    // Reuse the oracle's input checks so both formulations reject the same inputs.
    super::check(tet, ray)?;
    let orient = Rational::from(orientation(tet));
    let p = tet.map(q3);
    let (o, d) = (q3(ray.org), q3(ray.dir));
    let (mut t_in, mut t_out): (Option<Rational>, Option<Rational>) = (None, None);
    let mut crossings = Vec::new();
    let mut empty = false;
    for (f, [a, b, c]) in FACE_VERTICES.iter().enumerate() {
        let n = cross(&sub(&p[*b], &p[*a]), &sub(&p[*c], &p[*a]));
        let n: Q3 = n.map(|x| x * &orient);
        let nd = dot(&n, &d);
        // n · (o + t d - a) ≤ 0  ⇔  t · nd ≤ n · (a - o)
        let rhs = dot(&n, &sub(&p[*a], &o));
        match nd.cmp0() {
            std::cmp::Ordering::Equal => empty |= rhs.cmp0().is_lt(),
            ord => {
                let t = rhs / &nd;
                let bound = if ord.is_gt() { &mut t_out } else { &mut t_in };
                let tighter = match bound {
                    None => true,
                    Some(x) => (ord.is_gt() && t < *x) || (ord.is_lt() && t > *x),
                };
                if tighter {
                    *bound = Some(t.clone());
                }
                crossings.push((f, ord, t));
            }
        }
    }
    let mut c = Classification {
        exit: FaceSet::default(),
        entry: FaceSet::default(),
    };
    let (Some(t_in), Some(t_out)) = (t_in, t_out) else {
        unreachable!("a non-flat tetrahedron bounds every line direction on both sides")
    };
    if empty || t_in > t_out {
        return Ok(c);
    }
    for (f, ord, t) in crossings {
        if ord.is_gt() && t == t_out {
            c.exit.insert(f);
        }
        if ord.is_lt() && t == t_in {
            c.entry.insert(f);
        }
    }
    Ok(c)
}
