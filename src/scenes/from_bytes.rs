//! Decoding fuzzer bytes into cases that favour near-degenerate geometry: coordinates on a shared
//! power-of-two lattice (so ties are exact), rays aimed at vertices, edge points and face points and
//! moved by a few ulps, and everything optionally far from the origin.

use super::tets::ulps;
use crate::tet::{Case, EDGES, Ray, orientation};
use arbitrary::{Result, Unstructured};
use glam::Vec3;

/// A point on the lattice `m · 2^e` (m a small integer), moved by `offset`.
fn lattice(u: &mut Unstructured, e: i32, offset: f32) -> Result<Vec3> {
    let mut c = || -> Result<f32> {
        Ok(offset + f32::from(u.int_in_range::<i16>(-64..=64)?) * 2f32.powi(e))
    };
    Ok(Vec3::new(c()?, c()?, c()?))
}

/// `p` with each coordinate moved by -k..=k ulps.
fn nudge(u: &mut Unstructured, p: Vec3, k: i32) -> Result<Vec3> {
    let mut out = p;
    for a in 0..3 {
        out[a] = ulps(out[a], u.int_in_range(-k..=k)?);
    }
    Ok(out)
}

/// An offset from the origin: none, or 1e4 to 1e6.
fn offset(u: &mut Unstructured) -> Result<f32> {
    Ok(*u.choose(&[0.0, 0.0, 0.0, 1.0e4, 65536.0, 1.0e5, -1.0e6])?)
}

/// A (tetrahedron, ray) case; `None` when the bytes make a flat tetrahedron or a zero direction.
pub(crate) fn exit_case(u: &mut Unstructured) -> Result<Option<Case>> {
    let e = u.int_in_range(-12..=8)?;
    let off = offset(u)?;
    let mut tet = [Vec3::ZERO; 4];
    for v in &mut tet {
        *v = lattice(u, e, off)?;
    }
    // Optionally squash one vertex towards the opposite face's centroid: slivers, caps, needles.
    if u.ratio(1, 2)? {
        let i = u.int_in_range(0..=3)?;
        let c = (0..4).filter(|&j| j != i).map(|j| tet[j]).sum::<Vec3>() / 3.0;
        let s = 2f32.powi(-u.int_in_range(1..=20)?);
        tet[i] = c + (tet[i] - c) * s;
    }
    let k = u.int_in_range(0..=8)?;
    let aim = match u.int_in_range(0..=3)? {
        0 => tet[u.int_in_range(0..=3)?],
        1 => {
            let [a, b] = EDGES[u.int_in_range(0..=5)?];
            (tet[a] + tet[b]) * 0.5
        }
        2 => (tet[0] + tet[1] + tet[2] + tet[3]) * 0.25,
        _ => lattice(u, e, off)?,
    };
    let aim = nudge(u, aim, k)?;
    let org = lattice(u, e + 2, off)?;
    let org = nudge(u, org, k)?;
    let dir = aim - org;
    if orientation(&tet) == 0
        || dir == Vec3::ZERO
        || !dir.is_finite()
        || !tet.iter().all(|v| v.is_finite())
    {
        return Ok(None);
    }
    let mut case = Case {
        tet,
        org,
        dir,
        entry: None,
    };
    if u.ratio(1, 2)? {
        case.entry = crate::exact::classify(&case.tet, &case.ray())
            .ok()
            .and_then(|c| c.entry.first())
            .map(|f| f as u8);
    }
    Ok(Some(case))
}

/// A small generated mesh and a ray through it, as a found walk failure records them.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WalkCase {
    /// Which generated mesh.
    pub(crate) mesh: super::Generated,
    /// Its size (grid cells per side, or 16·size tetrahedra in the fan).
    pub(crate) size: u32,
    /// How far it is moved along (1, 1, 1).
    pub(crate) offset: f32,
    /// The mesh's points (after the offset) times 2^`scale`, exactly; 0 (left out): as generated.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub(crate) scale: i32,
    /// The ray's origin, inside the mesh.
    pub(crate) org: [f32; 3],
    /// The ray's direction.
    pub(crate) dir: [f32; 3],
}

fn is_zero(e: &i32) -> bool {
    *e == 0
}

impl WalkCase {
    /// The case's ray.
    pub(crate) fn ray(&self) -> Ray {
        Ray {
            org: Vec3::from(self.org),
            dir: Vec3::from(self.dir),
        }
    }
}

/// A walk case: a fan, Kuhn grid or jittered grid, small, near or far, and a ray from a dyadic point
/// inside it aimed at a mesh vertex or lattice point, moved by a few ulps.
pub(crate) fn walk_case(u: &mut Unstructured) -> Result<WalkCase> {
    let mesh = *u.choose(&[
        super::Generated::Fan,
        super::Generated::Kuhn,
        super::Generated::Jitter,
    ])?;
    let size = u.int_in_range(1..=4)?;
    // The grids need three cells a side (a constrained inner box); smaller sizes meant three.
    let size = if mesh == super::Generated::Fan {
        size
    } else {
        size.max(3)
    };
    let off = *u.choose(&[0.0, 0.0, 65536.0, 1.0e6])?;
    let extent = if mesh == super::Generated::Fan {
        2.0
    } else {
        size as f32
    };
    let mut d = |lo: f32, hi: f32| -> Result<f32> {
        Ok(lo + (hi - lo) * f32::from(u.int_in_range::<u8>(1..=255)?) / 256.0)
    };
    let org = if mesh == super::Generated::Fan {
        Vec3::new(d(-2.0, 2.0)?, d(-2.0, 2.0)?, d(-0.5, 0.5)?)
    } else {
        Vec3::new(d(0.0, extent)?, d(0.0, extent)?, d(0.0, extent)?)
    };
    let aim = if mesh == super::Generated::Fan {
        Vec3::new(0.0, 0.0, d(-1.0, 1.0)?)
    } else {
        Vec3::new(d(0.0, extent)?, d(0.0, extent)?, d(0.0, extent)?).round()
    };
    let k = u.int_in_range(0..=4)?;
    let org = nudge(u, org + Vec3::splat(off), k)?;
    let dir = aim + Vec3::splat(off) - org;
    let dir = if dir == Vec3::ZERO { Vec3::Z } else { dir };
    Ok(WalkCase {
        mesh,
        size,
        offset: off,
        scale: 0,
        org: org.to_array(),
        dir: dir.to_array(),
    })
}

/// A closed triangle mesh and a ray from outside it ([`super::closed::case`]: shape, aim and place from
/// the bytes, the rest from a seed they give), the origin and direction then moved by a few ulps.
pub(crate) fn hit_case(u: &mut Unstructured) -> Result<(Vec<crate::tet::Tri>, Ray)> {
    use super::closed::{MeshShape, TriAim, TriPlace, case};
    use crate::choice::Choice;
    let shape = *u.choose(MeshShape::ALL)?;
    let aim = *u.choose(TriAim::ALL)?;
    let place = *u.choose(TriPlace::ALL)?;
    let flatness = *u.choose(&[1.0, 1e-2, 1e-3, 1e-4])?;
    let mut rng = super::rng(u.arbitrary()?);
    let (mesh, ray) = case(shape, aim, place, flatness, 4, &mut rng);
    let k = u.int_in_range(0..=2)?;
    let org = nudge(u, ray.org, k)?;
    let dir = nudge(u, ray.dir, k)?;
    let dir = if dir == Vec3::ZERO { ray.dir } else { dir };
    Ok((mesh, Ray { org, dir }))
}

/// An octree cell and a ray ([`super::cells::case`]: aim and place from the bytes, the rest from a seed
/// they give), the origin and direction then moved by a few ulps.
pub(crate) fn cell_case(u: &mut Unstructured) -> Result<(Vec3, Vec3, Ray)> {
    use super::cells::{CellAim, CellPlace, case};
    use crate::choice::Choice;
    let aim = *u.choose(CellAim::ALL)?;
    let place = *u.choose(CellPlace::ALL)?;
    let mut rng = super::rng(u.arbitrary()?);
    let (lo, hi, ray) = case(aim, place, 4, &mut rng);
    let k = u.int_in_range(0..=2)?;
    let org = nudge(u, ray.org, k)?;
    let dir = nudge(u, ray.dir, k)?;
    let dir = if dir == Vec3::ZERO { ray.dir } else { dir };
    Ok((lo, hi, Ray { org, dir }))
}
