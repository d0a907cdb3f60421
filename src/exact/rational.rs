//! Vectors of rationals for the slow exact formulations (clipping, ray–triangle parameters).

use glam::Vec3;
use rug::Rational;

pub type Q3 = [Rational; 3];

/// An f32 vector, exactly.
pub fn q3(v: Vec3) -> Q3 {
    [v.x, v.y, v.z].map(|x| Rational::try_from(x).expect("finite"))
}

pub fn sub(a: &Q3, b: &Q3) -> Q3 {
    std::array::from_fn(|i| Rational::from(&a[i] - &b[i]))
}

pub fn neg(a: &Q3) -> Q3 {
    std::array::from_fn(|i| Rational::from(-&a[i]))
}

pub fn cross(a: &Q3, b: &Q3) -> Q3 {
    std::array::from_fn(|i| {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        Rational::from(&a[j] * &b[k]) - Rational::from(&a[k] * &b[j])
    })
}

pub fn dot(a: &Q3, b: &Q3) -> Rational {
    a.iter()
        .zip(b)
        .fold(Rational::new(), |s, (x, y)| s + Rational::from(x * y))
}

/// `det[a, b, c]` (rows).
pub fn det(a: &Q3, b: &Q3, c: &Q3) -> Rational {
    dot(a, &cross(b, c))
}
