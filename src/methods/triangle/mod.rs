//! Ray–triangle intersection methods (seed 004 and the tests it names): plain functions over plain data
//! behind one small trait, generic over [`Arith`] like the exit-face methods, each in a file of its own.
//!
//! A method tests a *packet* of rays sharing an origin against one triangle; a single ray is a packet of
//! one. Methods that share work across a packet (Komatsu et al.'s and Benthin's) do it once per packet
//! and triangle; the others test ray by ray. What every ray tracer adds around a test lives here, once:
//! a reported hit counts when its f32 `t` lies in `0 < t < ∞` ([`accepts`]), and the nearest hit over
//! many triangles is the first with the smallest `t` ([`nearest`]).

mod komatsu;
mod mt;
mod mt_precomputed;
mod plucker_packet;
mod woop;

pub use komatsu::KomatsuPacket;
pub use mt::{Mt, MtTwoSided};
pub use mt_precomputed::MtPrecomputed;
pub use plucker_packet::PluckerPacket;
pub use woop::WoopWatertight;

use super::Arith;
use crate::tet::Ray;
use glam::Vec3;

pub use crate::tet::Tri;

/// Which triangles each run of rays is tested against: runs of consecutive rays (`groups`' first
/// ranges, in order, covering every ray), each with a range of `ids` (ascending triangle indices).
#[derive(Clone, Debug, Default)]
pub struct Among {
    /// Triangle indices, each group's ascending.
    pub ids: Vec<u32>,
    /// Per group: its rays, and its range of `ids`.
    pub groups: Vec<(std::ops::Range<usize>, std::ops::Range<usize>)>,
}

impl Among {
    /// Every one of `tris` triangles for each of `rays` rays (brute force), the rays in runs of `run`.
    pub fn all(tris: usize, rays: usize, run: usize) -> Among {
        let run = run.max(1);
        Among {
            ids: (0..tris as u32).collect(),
            groups: (0..rays)
                .step_by(run)
                .map(|r| (r..(r + run).min(rays), 0..tris))
                .collect(),
        }
    }

    /// The ray–triangle tests it asks for: each group's rays times its triangles.
    pub fn tests(&self) -> u64 {
        self.groups
            .iter()
            .map(|(r, ids)| (r.len() * ids.len()) as u64)
            .sum()
    }
}

/// Most rays in one packet (8×8).
pub const MAX_PACKET: usize = 64;

/// A ray–triangle method: what it computes once per triangle and once per ray, then one call per packet
/// of rays sharing an origin and one triangle.
pub trait HitMethod {
    /// Precomputed per triangle (seed 004 eq. 2's `N`, `E1`, `E2`), or the vertices.
    type TriData: Copy + Send + Sync;
    /// Precomputed per ray (Woop et al.'s axes and shear), or the ray.
    type RayData: Copy + Send + Sync;
    /// The per-triangle data, computed once in arithmetic model `A`.
    fn tri<A: Arith>(tri: &Tri) -> Self::TriData;
    /// The per-ray data, computed once in arithmetic model `A`.
    fn ray<A: Arith>(ray: &Ray) -> Self::RayData;
    /// For each ray of a packet whose rays all start at `org`: `Some(t)` where the method reports a hit
    /// at parameter `t`, else `None` (`out` is as long as `rays`).
    fn packet<A: Arith>(
        tri: &Self::TriData,
        org: Vec3,
        rays: &[Self::RayData],
        out: &mut [Option<f32>],
    );
}

/// What a method's rounding error in its side products scales with (`family::triangle::bins` derives both):
/// its terms are edges from a vertex and the vertex seen from the origin (`|d|·R·L`: Möller–Trumbore
/// and its packet forms), or every vertex seen from the origin (`|d|·R²`: the Plücker packet test and
/// Woop's sheared edge functions), `R` the farthest vertex from the origin and `L` the longest edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SideError {
    /// Errors grow with `|d|·R·L` (Möller–Trumbore and its packet forms).
    EdgeScaled,
    /// Errors grow with `|d|·R²` (the Plücker packet test, Woop's edge functions).
    OriginScaled,
}

/// A method with a 4-wide version (seed 004's SIMD packets, [`crate::methods::lanes`]): four rays of a packet at once
/// in the plain model, answering bit for bit as [`HitMethod::packet`] does there (`tests/triangle.rs`).
pub trait Wide: HitMethod {
    /// Four rays' data as the 4-wide test reads them (made once per packet).
    type Lanes: Copy + Send + Sync;
    /// What the test computes once per packet and triangle.
    type Shared: Copy;
    /// Four rays' data in lanes.
    fn lanes(rays: [&Self::RayData; 4]) -> Self::Lanes;
    /// What a packet sharing origin `org` computes once for a triangle.
    fn shared(tri: &Self::TriData, org: Vec3) -> Self::Shared;
    /// `out` (one to four answers) for four rays (the last repeated where a packet has fewer).
    fn packet4(
        tri: &Self::TriData,
        shared: &Self::Shared,
        lanes: &Self::Lanes,
        out: &mut [Option<f32>],
    );
}

/// How a packet of rays is tested against one triangle: a method's [`HitMethod::packet`] in a model
/// ([`Scalar`]), or its 4-wide one ([`Four`]).
pub trait Tester<M: HitMethod> {
    /// A packet's rays as the test reads them.
    type Rays: Default;
    /// Lay a packet's rays out as the test reads them.
    fn rays(rays: &[M::RayData], into: &mut Self::Rays);
    /// Each ray's hit `t`, or `None`, for one triangle.
    fn test(tri: &M::TriData, org: Vec3, rays: &Self::Rays, out: &mut [Option<f32>]);
}

/// [`HitMethod::packet`] in the model `A`.
pub struct Scalar<A>(std::marker::PhantomData<A>);
/// [`Wide::packet4`], four rays at a time.
pub struct Four;

impl<M: HitMethod, A: Arith> Tester<M> for Scalar<A> {
    type Rays = Vec<M::RayData>;
    fn rays(rays: &[M::RayData], into: &mut Vec<M::RayData>) {
        into.clear();
        into.extend_from_slice(rays);
    }
    #[inline(always)]
    fn test(tri: &M::TriData, org: Vec3, rays: &Vec<M::RayData>, out: &mut [Option<f32>]) {
        M::packet::<A>(tri, org, rays, out);
    }
}

impl<M: Wide> Tester<M> for Four {
    type Rays = Vec<M::Lanes>;
    fn rays(rays: &[M::RayData], into: &mut Vec<M::Lanes>) {
        into.clear();
        into.extend(rays.chunks(4).map(|c| {
            let lane = |i: usize| &c[i.min(c.len() - 1)];
            M::lanes([lane(0), lane(1), lane(2), lane(3)])
        }));
    }
    #[inline(always)]
    fn test(tri: &M::TriData, org: Vec3, rays: &Vec<M::Lanes>, out: &mut [Option<f32>]) {
        let shared = M::shared(tri, org);
        for (lanes, o) in rays.iter().zip(out.chunks_mut(4)) {
            M::packet4(tri, &shared, lanes, o);
        }
    }
}

/// A method that tests ray by ray from the vertices, precomputing nothing.
pub trait SingleRay {
    /// `Some(t)` where the method reports a hit at parameter `t`.
    fn test<A: Arith>(tri: &Tri, ray: &Ray) -> Option<f32>;
}

impl<M: SingleRay> HitMethod for M {
    type TriData = Tri;
    type RayData = Ray;
    fn tri<A: Arith>(tri: &Tri) -> Tri {
        *tri
    }
    fn ray<A: Arith>(ray: &Ray) -> Ray {
        *ray
    }
    #[inline(always)]
    fn packet<A: Arith>(tri: &Tri, _org: Vec3, rays: &[Ray], out: &mut [Option<f32>]) {
        for (ray, o) in rays.iter().zip(out) {
            *o = M::test::<A>(tri, ray);
        }
    }
}

/// Whether a hit the method reports at `t` counts: on the ray's interval `0 < t < ∞` (a NaN does not).
#[inline(always)]
pub fn accepts(t: f32) -> bool {
    t > 0.0 && t < f32::INFINITY
}

/// `M`'s answer for one ray and one triangle: the `t` of a hit that counts.
pub fn hit<M: HitMethod, A: Arith>(tri: &Tri, ray: &Ray) -> Option<f32> {
    A::run(
        (tri, ray),
        #[inline(always)]
        |(tri, ray)| {
            let mut out = [None];
            M::packet::<A>(&M::tri::<A>(tri), ray.org, &[M::ray::<A>(ray)], &mut out);
            out[0].filter(|&t| accepts(t))
        },
    )
}

/// Calls `f(triangle, ray, t)` for every hit that counts of each of a packet's `n` rays (sharing
/// `org`, prepared by `T`) with each of `tris` (prepared, with their indices), triangle by triangle.
#[inline(always)]
pub fn each_hit<'a, M: HitMethod, T: Tester<M>>(
    tris: impl Iterator<Item = (u32, &'a M::TriData)>,
    org: Vec3,
    rays: &T::Rays,
    n: usize,
    mut f: impl FnMut(u32, usize, f32),
) where
    M::TriData: 'a,
{
    let n = n.min(MAX_PACKET);
    let mut out = [None; MAX_PACKET];
    for (i, tri) in tris {
        T::test(tri, org, rays, &mut out[..n]);
        for (r, o) in out[..n].iter().enumerate() {
            if let Some(t) = *o
                && accepts(t)
            {
                f(i, r, t);
            }
        }
    }
}

/// A ray's nearest hit: the triangle and its `t`, or none.
pub type Nearest = Option<(u32, f32)>;

/// Whether a hit at `t` replaces `best` as the nearest: the first with the smallest `t` is kept.
#[inline(always)]
fn nearer(best: Nearest, t: f32) -> bool {
    best.is_none_or(|(_, bt)| t < bt)
}

/// The nearest of a method's hits (triangle, `t`) in triangle order, as [`nearest`] keeps it.
pub fn nearest_of(hits: &[(u32, f32)]) -> Option<(u32, f32)> {
    hits.iter().fold(
        None,
        |best, &(i, t)| if nearer(best, t) { Some((i, t)) } else { best },
    )
}

/// The nearest hit of each ray of a packet among `tris` (prepared, with their indices in ascending
/// order): the first triangle with the smallest `t`.
#[inline(always)]
pub fn nearest<'a, M: HitMethod, T: Tester<M>>(
    tris: impl Iterator<Item = (u32, &'a M::TriData)>,
    org: Vec3,
    rays: &T::Rays,
    best: &mut [Option<(u32, f32)>],
) where
    M::TriData: 'a,
{
    each_hit::<M, T>(tris, org, rays, best.len(), |i, r, t| {
        if nearer(best[r], t) {
            best[r] = Some((i, t));
        }
    });
}

/// Runs of consecutive rays, each with the range of `ids` naming its triangles ([`Among::groups`]).
pub type Groups = [(std::ops::Range<usize>, std::ops::Range<usize>)];

/// The nearest hit of each ray of `groups` (in order; each group's rays against the triangles its ids
/// name, ascending, prepared once per group), the rays taken `packet` at a time; a packet ends early
/// where the origin changes, so each shares one origin. With every triangle named this is the
/// brute-force answer; with fewer it is the same wherever no triangle left out could be hit
/// (`family::triangle::bins` derives when).
pub fn trace<M: HitMethod, A: Arith>(
    tris: &[Tri],
    ids: &[u32],
    groups: &Groups,
    rays: &[Ray],
    packet: usize,
) -> Vec<Option<(u32, f32)>> {
    A::run(
        (tris, ids, groups, rays),
        #[inline(always)]
        |(tris, ids, groups, rays)| trace_by::<M, A, Scalar<A>>(tris, ids, groups, rays, packet),
    )
}

/// [`trace`] in the plain model with the method's 4-wide test: the same answers, bit for bit.
pub fn trace_wide<M: Wide>(
    tris: &[Tri],
    ids: &[u32],
    groups: &Groups,
    rays: &[Ray],
    packet: usize,
) -> Vec<Option<(u32, f32)>> {
    trace_by::<M, super::Plain, Four>(tris, ids, groups, rays, packet)
}

/// [`trace`] with the packet test `T` (run in `A`'s environment); buffers reused across groups.
#[inline(always)]
fn trace_by<M: HitMethod, A: Arith, T: Tester<M>>(
    tris: &[Tri],
    ids: &[u32],
    groups: &Groups,
    rays: &[Ray],
    packet: usize,
) -> Vec<Option<(u32, f32)>> {
    let mut best = Vec::with_capacity(groups.iter().map(|g| g.0.len()).sum());
    let (mut prepared, mut data, mut packed) = (Vec::new(), Vec::new(), T::Rays::default());
    let size = packet.clamp(1, MAX_PACKET);
    for (range, named) in groups {
        let among = &ids[named.clone()];
        prepared.clear();
        prepared.extend(among.iter().map(|&i| M::tri::<A>(&tris[i as usize])));
        let rays = &rays[range.clone()];
        let first = best.len();
        best.resize(first + rays.len(), None);
        let mut start = 0;
        while start < rays.len() {
            let org = rays[start].org;
            let len = rays[start..]
                .iter()
                .take(size)
                .take_while(|r| r.org == org)
                .count();
            data.clear();
            data.extend(rays[start..start + len].iter().map(M::ray::<A>));
            T::rays(&data, &mut packed);
            let named = among.iter().copied().zip(&prepared);
            let at = first + start;
            nearest::<M, T>(named, org, &packed, &mut best[at..at + len]);
            start += len;
        }
    }
    best
}

/// Every hit of one ray among `tris`, in triangle order.
pub fn hits<M: HitMethod, A: Arith>(tris: &[Tri], ray: &Ray) -> Vec<(u32, f32)> {
    A::run(
        (tris, ray),
        #[inline(always)]
        |(tris, ray)| hits_by::<M, A, Scalar<A>>(tris, ray),
    )
}

/// [`hits`] in the plain model with the method's 4-wide test (the ray in every lane).
pub fn hits_wide<M: Wide>(tris: &[Tri], ray: &Ray) -> Vec<(u32, f32)> {
    hits_by::<M, super::Plain, Four>(tris, ray)
}

/// [`hits`] with the packet test `T`.
#[inline(always)]
fn hits_by<M: HitMethod, A: Arith, T: Tester<M>>(tris: &[Tri], ray: &Ray) -> Vec<(u32, f32)> {
    let prepared: Vec<M::TriData> = tris.iter().map(M::tri::<A>).collect();
    let mut out = Vec::new();
    let named = (0..tris.len() as u32).zip(&prepared);
    let mut one = T::Rays::default();
    T::rays(&[M::ray::<A>(ray)], &mut one);
    each_hit::<M, T>(named, ray.org, &one, 1, |i, _, t| out.push((i, t)));
    out
}
