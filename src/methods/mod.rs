//! Exit-face methods: plain functions over plain data behind one small trait, and a registry by name.
//!
//! Every method is written once, generic over [`Arith`]: [`Plain`] rounds every product and sum as
//! written (what a CPU compiler emits), [`Fused`] contracts each `a·b + c` into one fused multiply-add
//! (what a GPU shader compiler may emit). Contractions applied by [`Fused`]: in [`Arith::dot`] the second
//! and third products are fused into the running sum; in [`Arith::cross`] the first product of each
//! component is fused with the negated second one; in [`Arith::axpy`] each product with its sum; and
//! wherever a method calls [`Arith::mad`]. Nothing else is contracted.

pub mod aman20;
mod exact;
mod halfspace;
mod maria17;
mod ms06;
mod plucker;
mod ray_plane;
mod stp;

pub use aman20::{Aman20, Aman20Scaled};
pub use exact::Exact;
pub use halfspace::HalfSpace;
pub use maria17::Maria17;
pub use ms06::Ms06;
pub use plucker::Plucker;
pub use ray_plane::RayPlane;
pub use stp::Stp;

use crate::tet::{Ray, Tet};
use crate::walk::layouts::{self, LayoutWalkFn};
use crate::walk::{self, CheckedWalkFn, WalkFn};
use glam::Vec3;

/// Rounding of a method's arithmetic: as written, or contracted to fused multiply-add.
pub trait Arith {
    /// `a·b + c`.
    fn mad(a: f32, b: f32, c: f32) -> f32;
    /// `a.x·b.x + a.y·b.y + a.z·b.z`, summed left to right.
    fn dot(a: Vec3, b: Vec3) -> f32 {
        Self::mad(a.z, b.z, Self::mad(a.y, b.y, a.x * b.x))
    }
    /// `s·a + b`, per component.
    fn axpy(s: f32, a: Vec3, b: Vec3) -> Vec3 {
        Vec3::new(
            Self::mad(a.x, s, b.x),
            Self::mad(a.y, s, b.y),
            Self::mad(a.z, s, b.z),
        )
    }
    /// `a × b`, each component `a_j·b_k - a_k·b_j`.
    fn cross(a: Vec3, b: Vec3) -> Vec3 {
        Vec3::new(
            Self::mad(a.y, b.z, -(a.z * b.y)),
            Self::mad(a.z, b.x, -(a.x * b.z)),
            Self::mad(a.x, b.y, -(a.y * b.x)),
        )
    }
}

/// Every product and sum rounded separately.
pub struct Plain;
/// Products contracted into fused multiply-adds, as a GPU compiler may.
pub struct Fused;

impl Arith for Plain {
    #[inline(always)]
    fn mad(a: f32, b: f32, c: f32) -> f32 {
        a * b + c
    }
}

impl Arith for Fused {
    #[inline(always)]
    fn mad(a: f32, b: f32, c: f32) -> f32 {
        a.mul_add(b, c)
    }
}

/// An exit-face method: per-ray data computed once, then one call per tetrahedron.
pub trait ExitMethod {
    /// What the method precomputes once per ray (e.g. the Plücker moment).
    type RayData: Copy + Send + Sync;
    fn prepare<A: Arith>(ray: &Ray) -> Self::RayData;
    /// The face (0..4, opposite that vertex) through which the ray leaves the positively oriented
    /// tetrahedron, knowing the face it entered through (`None` in the starting tetrahedron); `None`
    /// when the method finds no exit face.
    fn exit_face<A: Arith>(tet: &Tet, ray: &Self::RayData, entry: Option<usize>) -> Option<usize>;
}

/// Whether a face is left, from the signs along its outward cycle (side products or projected
/// determinants): all `≥ 0` and not all zero (Platis & Theoharis' test).
#[inline(always)]
pub(crate) fn leaves(s: &[f32; 3]) -> bool {
    s.iter().all(|&x| x >= 0.0) && s.iter().any(|&x| x != 0.0)
}

/// A method's exit function with its arithmetic fixed, for callers that pick methods at run time.
pub type ExitFn = fn(&Tet, &Ray, Option<usize>) -> Option<usize>;

fn exit_fn<M: ExitMethod, A: Arith>(tet: &Tet, ray: &Ray, entry: Option<usize>) -> Option<usize> {
    M::exit_face::<A>(tet, &M::prepare::<A>(ray), entry)
}

/// A registered method.
pub struct Method {
    pub name: &'static str,
    /// Paper and algorithm it implements.
    pub source: &'static str,
    /// Whether its paper claims it never fails in f32 (fuzzing and the replay hold it to that).
    pub claims_robust: bool,
    exit: [ExitFn; 2],
    walk: [WalkFn; 2],
    checked: [CheckedWalkFn; 2],
    layout_walk: Option<[LayoutWalkFn; 2]>,
}

impl Method {
    const fn of<M: ExitMethod>(
        name: &'static str,
        source: &'static str,
        claims_robust: bool,
    ) -> Self {
        Method {
            name,
            source,
            claims_robust,
            exit: [exit_fn::<M, Plain>, exit_fn::<M, Fused>],
            walk: [walk::walk::<M, Plain>, walk::walk::<M, Fused>],
            checked: [
                walk::walk_checked::<M, Plain>,
                walk::walk_checked::<M, Fused>,
            ],
            layout_walk: None,
        }
    }

    /// A method of the 2-D frame family, which can also walk the compact layouts.
    const fn planar<M: ExitMethod>(name: &'static str, source: &'static str) -> Self
    where
        M::RayData: aman20::Frame,
    {
        Method {
            layout_walk: Some([
                layouts::walk_layout_unobserved::<M, Plain>,
                layouts::walk_layout_unobserved::<M, Fused>,
            ]),
            ..Self::of::<M>(name, source, false)
        }
    }

    /// The exit function, plain or as a GPU compiles it (`fma`).
    pub fn exit(&self, fma: bool) -> ExitFn {
        self.exit[fma as usize]
    }

    /// The walk specialised to this method, plain or with `fma`.
    pub fn walk(&self, fma: bool) -> WalkFn {
        self.walk[fma as usize]
    }

    /// The walk over Tet32/Tet20/Tet16, for the methods that have one (seed 003 Algorithms 2-7).
    pub fn layout_walk(&self, fma: bool) -> Option<LayoutWalkFn> {
        self.layout_walk.map(|w| w[fma as usize])
    }

    /// The walk that judges every step with the oracle ([`walk::walk_checked`]).
    pub fn walk_checked(&self, fma: bool) -> CheckedWalkFn {
        self.checked[fma as usize]
    }
}

/// Every method, in the order reports list them.
pub static METHODS: &[Method] = &[
    Method::of::<Exact>(
        "exact",
        "exact oracle with Simulation of Simplicity tie-breaking (reference)",
        true,
    ),
    Method::of::<RayPlane>(
        "ray-plane",
        "Lagae & Dutré 2008 after Garrity 1990: four ray/plane intersections, smallest t (reconstructed)",
        false,
    ),
    Method::of::<HalfSpace>(
        "halfspace",
        "Lagae & Dutré 2008: half-space classification (reconstructed)",
        false,
    ),
    Method::of::<Plucker>(
        "plucker",
        "Lagae & Dutré 2008 after Platis & Theoharis 2003: six Plücker side products (reconstructed)",
        false,
    ),
    Method::of::<Stp>(
        "stp",
        "Lagae & Dutré 2008: three to six scalar triple products with early outs (reconstructed)",
        false,
    ),
    Method::of::<Ms06>(
        "ms06",
        "Marmitt & Slusallek 2006: Plücker tests from the entry face, 2.67 on average (reconstructed)",
        false,
    ),
    Method::of::<Maria17>(
        "maria17",
        "Maria, Horna, Aveneau 2017, Algorithms 1-2, Tables 1-2, translated frame of §3.4",
        true,
    ),
    Method::planar::<Aman20>(
        "aman20",
        "Aman, Demirci, Güdükbay §4: Duff et al. 2017 2-D frame, Algorithm 1; walks Tet32/20/16",
    ),
    Method::planar::<Aman20Scaled>(
        "aman20-scaled",
        "Aman, Demirci, Güdükbay §4.1: specialised scaled basis (eqs. 1-3), Algorithm 1; walks Tet32/20/16",
    ),
];

/// The method called `name`.
pub fn by_name(name: &str) -> Option<&'static Method> {
    METHODS.iter().find(|m| m.name == name)
}

/// Methods from a comma-separated list, or all of them for `all`.
pub fn parse_list(list: &str) -> Result<Vec<&'static Method>, String> {
    if list == "all" {
        return Ok(METHODS.iter().collect());
    }
    list.split(',')
        .map(|n| {
            by_name(n.trim()).ok_or_else(|| {
                let known: Vec<_> = METHODS.iter().map(|m| m.name).collect();
                format!("unknown method '{n}' (known: {}, or all)", known.join(", "))
            })
        })
        .collect()
}
