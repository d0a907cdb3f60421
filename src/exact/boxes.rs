//! The exact oracle for one octree cell: through which faces a line leaves a closed axis-aligned box,
//! and, for each, in which quarter of the face (relative to its centre) the exit point lies.

use super::ExactError;
use super::rational::q3;
use crate::octree::cell::{face_axes, face_of};
use crate::tet::Ray;
use glam::Vec3;
use rug::Rational;
use std::cmp::Ordering;

/// Where a line leaves a closed box, exactly.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BoxExit {
    /// Whether the line crosses the open box (else it misses, touches only an edge or a corner, or
    /// lies in a face plane): only then is an answer judged.
    pub crosses: bool,
    /// Every face (Portalez & Duguet's numbering, [`crate::octree::cell`]) holding the point where
    /// the line leaves the closed box towards `+dir`: one, two at an edge, three at a corner; none when
    /// the line misses the box or runs parallel inside a face plane.
    pub faces: Vec<usize>,
    /// The line's parameter interval `[t_in, t_out]` inside the closed box (`o + t·d`); none when it
    /// misses the box.
    pub interval: Option<(Rational, Rational)>,
    /// For each face of `faces`, every quarter that holds the exit point, as signs `[su, sv]` of the
    /// point relative to the face centre along the face's two axes in x, y, z order (both signs where
    /// it lies on a centre line).
    pub quarters: Vec<Vec<[i8; 2]>>,
}

/// Where the line of `ray` leaves the closed box `[lo, hi]` (`lo < hi` on every axis), exactly.
pub fn box_exit(lo: Vec3, hi: Vec3, ray: &Ray) -> Result<BoxExit, ExactError> {
    super::check_ray(&[lo, hi], ray)?;
    if (0..3).any(|a| lo[a] >= hi[a]) {
        return Err(ExactError::FlatBox);
    }
    let (o, d, l, h) = (q3(ray.org), q3(ray.dir), q3(lo), q3(hi));
    // The parameter interval of the line inside the closed slab of each axis; a line parallel to a
    // slab is inside it (open or closed) or not at all.
    let mut t_in: Option<Rational> = None;
    let mut t_out: Option<Rational> = None;
    let mut open = true;
    let mut exits: Vec<(usize, Rational)> = Vec::new();
    for a in 0..3 {
        match d[a].cmp0() {
            Ordering::Equal => {
                if o[a] < l[a] || o[a] > h[a] {
                    return Ok(miss());
                }
                open &= o[a] > l[a] && o[a] < h[a];
            }
            s => {
                let at = |p: &Rational| Rational::from(p - &o[a]) / &d[a];
                let (enter, exit) = if s.is_gt() {
                    (at(&l[a]), at(&h[a]))
                } else {
                    (at(&h[a]), at(&l[a]))
                };
                if t_in.as_ref().is_none_or(|t| enter > *t) {
                    t_in = Some(enter);
                }
                if t_out.as_ref().is_none_or(|t| exit < *t) {
                    t_out = Some(exit.clone());
                }
                exits.push((face_of(a, s.is_gt()), exit));
            }
        }
    }
    let (Some(t_in), Some(t_out)) = (t_in, t_out) else {
        return Err(ExactError::ZeroDirection);
    };
    if t_in > t_out {
        return Ok(miss());
    }
    let crosses = open && t_in < t_out;
    let interval = Some((t_in.clone(), t_out.clone()));
    let point: [Rational; 3] = std::array::from_fn(|a| Rational::from(&d[a] * &t_out) + &o[a]);
    let mut faces = Vec::new();
    let mut quarters = Vec::new();
    for (f, t) in exits {
        if t != t_out {
            continue;
        }
        let axis = crate::octree::cell::FACE_AXIS[f];
        let signs = face_axes(axis).map(|b| {
            let centre = Rational::from(&l[b] + &h[b]) / 2u32;
            match point[b].cmp(&centre) {
                Ordering::Less => vec![-1i8],
                Ordering::Greater => vec![1],
                Ordering::Equal => vec![-1, 1],
            }
        });
        let mut q = Vec::new();
        for &su in &signs[0] {
            for &sv in &signs[1] {
                q.push([su, sv]);
            }
        }
        faces.push(f);
        quarters.push(q);
    }
    Ok(BoxExit {
        crosses,
        faces,
        interval,
        quarters,
    })
}

fn miss() -> BoxExit {
    BoxExit {
        crosses: false,
        faces: Vec::new(),
        interval: None,
        quarters: Vec::new(),
    }
}

impl BoxExit {
    /// Whether `face` with quarter `quarter` is a right answer (`None` when no answer is judged).
    pub fn right(&self, answer: Option<(usize, [i8; 2])>) -> Option<bool> {
        self.crosses.then(|| {
            answer.is_some_and(|(f, q)| {
                self.faces
                    .iter()
                    .zip(&self.quarters)
                    .any(|(g, qs)| *g == f && qs.contains(&q))
            })
        })
    }
}
