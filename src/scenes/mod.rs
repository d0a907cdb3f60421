//! Generated scenes, seeded and deterministic: single tetrahedra of each shape family with rays that stab
//! them, and small meshes that trap walks.

pub mod build;
pub mod camera;
pub mod cells;
pub mod closed;
pub mod from_bytes;
pub mod meshes;
pub mod model;
pub mod subdivide;
pub mod tets;

/// The generators' random source: PCG, the same stream for a seed on every platform.
pub type Rng = rand_pcg::Pcg64;

/// A generator seeded with `seed`.
pub fn rng(seed: u64) -> Rng {
    rand::SeedableRng::seed_from_u64(seed)
}

use crate::choice::Choice;
use crate::mesh::{Mesh, MeshError};
use crate::tet::Ray;
use glam::Vec3;
use rand::RngExt;

/// Why a scene cannot be read, built or loaded; each says where.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// A model file that cannot be read or parsed: `place` is the file, and the line where known.
    #[error("{place}: {why}")]
    Model { place: String, why: String },
    #[error("the model is not closed: edge ({a}, {b}) {what}")]
    NotClosed { a: u32, b: u32, what: &'static str },
    #[error("tetgen is not installed (Debian: apt-get install tetgen)")]
    NoTetgen,
    #[error("the model intersects itself: tetgen -d says \"{0}\"")]
    SelfIntersecting(String),
    #[error("the scene cannot be represented: {0}")]
    Unrepresentable(String),
    #[error("tetgen {args} ran past its time limit of {seconds} s and was stopped")]
    TetgenTimeout { args: String, seconds: f64 },
    #[error(
        "points TetGen added ({inexact}) are still not f32 values after {rounds} rounds of rounding them and running it again with them; nothing was written"
    )]
    InexactPoints { inexact: usize, rounds: usize },
    #[error("tetgen {args} failed ({status}):\n{output}")]
    Tetgen {
        args: String,
        status: String,
        output: String,
    },
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

impl SceneError {
    /// An I/O error at `path`.
    pub(crate) fn io(path: &std::path::Path) -> impl FnOnce(std::io::Error) -> SceneError + '_ {
        move |source| SceneError::Io {
            path: path.display().to_string(),
            source,
        }
    }
}

/// The generated meshes, by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Generated {
    /// Kuhn-subdivided `n³` cube grid; the inner box's faces constrained.
    Kuhn,
    /// The same with interior points jittered.
    Jitter,
    /// `16·n` thin tetrahedra around one edge; the lower hull constrained.
    Fan,
}

crate::choice!(Generated { Kuhn => "kuhn", Jitter => "jitter", Fan => "fan" });

mod built_in;
pub use built_in::{BUILT_IN, BUILT_IN_FILES};

include!(concat!(env!("OUT_DIR"), "/built_in_scenes.rs"));

/// Scenes too large to ship, built on the user's machine by a script of the repository (byte for byte
/// the same wherever it runs) into the folder [`built_here_dir`] names: name and script.
pub(crate) const BUILT_HERE: [(&str, &str); 1] = [("bunny-paper", "corpora/scenes/bunny-paper.sh")];

/// The environment variable naming the folder of the scenes built on this machine ([`BUILT_HERE`]).
pub(crate) const SCENES_VAR: &str = "TETWALK_SCENES";

/// Where the scenes built on this machine are looked for: the folder `TETWALK_SCENES` names, else
/// `corpora/scenes` under the current directory (a checkout's root, where the script writes them).
pub(crate) fn built_here_dir() -> std::path::PathBuf {
    std::env::var_os(SCENES_VAR)
        .filter(|v| !v.is_empty())
        .map_or_else(|| "corpora/scenes".into(), Into::into)
}

/// Most bytes a built-in scene's file inflates to (the largest is under 1 MB).
const MAX_BUILT_IN_FILE: usize = 64 << 20;

/// A built-in scene's mesh, from the copy embedded in the binary (`build.rs`); `None` for another name.
fn built_in(name: &str) -> Option<Result<Mesh, MeshError>> {
    let (_, files) = EMBEDDED.iter().find(|(n, _)| *n == name)?;
    let texts: Result<Vec<String>, MeshError> = files
        .iter()
        .zip(BUILT_IN_FILES)
        .map(|(packed, ext)| {
            let bad = |what: String| MeshError {
                place: format!("built-in scene {name} ({name}.{ext})"),
                what,
            };
            let bytes =
                miniz_oxide::inflate::decompress_to_vec_zlib_with_limit(packed, MAX_BUILT_IN_FILE)
                    .map_err(|e| bad(format!("the embedded copy does not inflate: {e:?}")))?;
            String::from_utf8(bytes).map_err(|e| bad(format!("not UTF-8: {e}")))
        })
        .collect();
    Some(texts.and_then(|t| {
        let [node, ele, neigh, face] = [&t[0], &t[1], &t[2], &t[3]];
        crate::mesh::parse_tetgen(
            std::path::Path::new(name),
            &crate::mesh::TetgenTexts {
                node,
                ele,
                neigh: Some(neigh),
                face: Some(face),
            },
        )
    }))
}

/// The scene names a user may give besides files: the built-in, built-here and generated ones.
pub(crate) fn names() -> String {
    let mut all: Vec<String> = BUILT_IN.iter().map(|s| s.to_string()).collect();
    all.extend(BUILT_HERE.iter().map(|(n, _)| format!("{n} (once built)")));
    for g in Generated::ALL {
        all.push(format!("{0}, {0}-far", g.name()));
    }
    all.join(", ")
}

/// Where a scene named by the user comes from.
enum Source {
    /// Made in code: the kind, moved by the offset.
    Generated(Generated, Vec3),
    /// Embedded in the binary.
    BuiltIn,
    /// A file: a Gmsh, VTK or MEDIT mesh, a TetGen stem or one of its files, or something else.
    File(std::path::PathBuf),
}

/// Where the scene `name` comes from; a scene built here that is not built yet is an error saying how
/// to build it.
fn source(name: &str) -> Result<Source, MeshError> {
    let kind = Generated::from_name;
    let generated = match name.strip_suffix("-far").and_then(kind) {
        Some(k) => Some((k, Vec3::splat(65536.0))),
        None => kind(name).map(|k| (k, Vec3::ZERO)),
    };
    if let Some((k, offset)) = generated {
        return Ok(Source::Generated(k, offset));
    }
    if BUILT_IN.contains(&name) {
        return Ok(Source::BuiltIn);
    }
    let Some((_, script)) = BUILT_HERE.iter().find(|(n, _)| *n == name) else {
        return Ok(Source::File(name.into()));
    };
    let stem = built_here_dir().join(name);
    let [_, ele, ..] = crate::mesh::tetgen_files(&stem);
    if !ele.exists() {
        return Err(MeshError {
            place: format!("scene {name}"),
            what: format!(
                "not built on this machine (too large to ship): no {} here; in a tetwalk checkout run `bash {script}` (about 20 s; it writes corpora/scenes/{name}.*), then run tetwalk from the checkout's root or set {SCENES_VAR} to the folder holding {name}.node",
                ele.display()
            ),
        });
    }
    Ok(Source::File(stem))
}

/// The files the scene `name` is read from: none for a built-in or generated scene, the mesh file, or
/// a TetGen mesh's four.
pub(crate) fn files_of(name: &str) -> Vec<std::path::PathBuf> {
    match source(name) {
        Ok(Source::File(path)) => {
            #[cfg(feature = "formats")]
            if crate::mesh::formats::Format::of(&path).is_some() {
                return vec![path];
            }
            crate::mesh::tetgen_files(&path).into()
        }
        _ => Vec::new(),
    }
}

/// A scene as loaded: the name it was asked for by, and its mesh, which travel together from
/// [`load`] to every report that names the scene.
#[derive(Clone, Debug)]
pub struct Loaded {
    pub name: String,
    pub mesh: Mesh,
}

/// A scene by name: a built-in one (embedded in the binary: [`BUILT_IN`]), one built on this machine
/// ([`BUILT_HERE`], in [`built_here_dir`]), a generated one (`kuhn`, `jitter`, `fan`, each with a
/// `-far` variant moved by 2^16), a Gmsh, VTK or MEDIT file (`.msh`, `.vtk`, `.vtu`, `.mesh`), or the
/// stem or any file of TetGen output.
pub fn load(name: &str, faces: crate::mesh::Faces) -> Result<Loaded, MeshError> {
    Ok(Loaded {
        name: name.to_string(),
        mesh: mesh_of(name, faces)?,
    })
}

/// The mesh of the scene `name` ([`load`]).
fn mesh_of(name: &str, faces: crate::mesh::Faces) -> Result<Mesh, MeshError> {
    let path = match source(name)? {
        Source::Generated(k, offset) => return generated_mesh(k, 8, offset, 1),
        Source::BuiltIn => return built_in(name).expect("a built-in scene is embedded"),
        Source::File(path) => path,
    };
    found(name, &path)?;
    #[cfg(feature = "formats")]
    if let Some(format) = crate::mesh::formats::Format::of(&path) {
        return crate::mesh::formats::load(&path, format, faces);
    }
    crate::mesh::load_tetgen_with(&path, faces)
}

/// An error unless the scene `name` is one tetwalk can read: built in, generated, or files that are
/// there (a mesh file, or TetGen's `.node` and `.ele` of a stem), not folders. What is in them is
/// the loader's to judge; this says only whether there is something to judge (`scene check` exits
/// 2 where there is not).
pub fn readable(name: &str) -> Result<(), MeshError> {
    match source(name)? {
        Source::File(path) => found(name, &path),
        _ => Ok(()),
    }
}

/// [`readable`] for a file scene at `path`.
fn found(name: &str, path: &std::path::Path) -> Result<(), MeshError> {
    let fail = |what: String| {
        Err(MeshError {
            place: path.display().to_string(),
            what,
        })
    };
    if path.is_dir() {
        return fail("is a folder, not a mesh file or a TetGen stem".into());
    }
    #[cfg(feature = "formats")]
    if crate::mesh::formats::Format::of(path).is_some() {
        return match std::fs::metadata(path) {
            Ok(_) => Ok(()),
            Err(e) => fail(format!("cannot read: {e}")),
        };
    }
    if let Some(ext @ ("off" | "obj" | "ply")) = path.extension().and_then(|e| e.to_str()) {
        return Err(MeshError {
            place: path.display().to_string(),
            what: format!(
                "a surface model (.{ext}), not a tetrahedral mesh: tetrahedralize it first with `tetwalk scene build {} --out STEM`, then name STEM",
                path.display()
            ),
        });
    }
    let [node, ele, ..] = crate::mesh::tetgen_files(path);
    if path.is_file() && !(node.is_file() && ele.is_file()) {
        return fail(format!(
            "a file whose extension ({}) is not one tetwalk reads: a mesh is a .msh, .vtk, .vtu or .mesh file, or TetGen's .node and .ele",
            path.extension()
                .map_or("none".into(), |e| format!(".{}", e.to_string_lossy()))
        ));
    }
    if !node.is_file() || !ele.is_file() {
        return Err(MeshError {
            place: format!("scene {name}"),
            what: format!(
                "no such scene: not one of {}, nor a mesh file (.msh, .vtk, .vtu, .mesh) or TetGen stem ({} or {} missing)",
                names(),
                node.display(),
                ele.display()
            ),
        });
    }
    Ok(())
}

/// Most tetrahedra a generated mesh may have (about 3 GiB while it is built).
pub(crate) const MAX_GENERATED_TETS: u64 = 1 << 25;
/// Bytes a tetrahedron takes while a mesh is built and walked, roughly (its cell included).
const BYTES_PER_TET: u64 = 176;

/// A generated mesh of `size`, moved by `offset` (exactly, for offsets up to 2^20).
pub fn generated_mesh(
    kind: Generated,
    size: u32,
    offset: Vec3,
    seed: u64,
) -> Result<Mesh, MeshError> {
    let tets = match kind {
        Generated::Kuhn | Generated::Jitter => 6 * (size as u64).pow(3),
        Generated::Fan => 16 * size as u64,
    };
    let least = match kind {
        Generated::Kuhn | Generated::Jitter => 3,
        Generated::Fan => 1,
    };
    if size < least || tets > MAX_GENERATED_TETS {
        return Err(MeshError {
            place: format!("{} mesh of size {size}", kind.name()),
            what: if size < least {
                format!("the size must be {least} or more")
            } else {
                format!(
                    "{tets} tetrahedra would need about {:.1} GiB; at most {MAX_GENERATED_TETS} are made",
                    (tets * BYTES_PER_TET) as f64 / (1u64 << 30) as f64
                )
            },
        });
    }
    let raw = match kind {
        Generated::Kuhn => meshes::kuhn_grid(size),
        Generated::Jitter => meshes::jittered_grid(size, 0.15, &mut rng(seed)),
        Generated::Fan => meshes::edge_fan(16 * size, 8.0),
    };
    let mesh = Mesh::build(raw)?;
    if offset == Vec3::ZERO {
        return Ok(mesh);
    }
    mesh.translated(offset).map_err(|e| MeshError {
        place: format!("{} mesh of size {size} moved by {offset}", kind.name()),
        what: format!("{e}: f32 cannot hold the mesh there (exact up to offsets of 2^20)"),
    })
}

/// Rays for a generated mesh: origins inside it, half with random directions and half aimed exactly
/// through vertices and edges (lattice directions in the grids, through the axis edge in the fan).
/// Coordinates are multiples of 1/16, so the rays move exactly with the mesh's `offset`.
pub fn rays(kind: Generated, mesh: &Mesh, offset: Vec3, n: usize, seed: u64) -> Vec<Ray> {
    let mut r = rng(seed ^ 0x005e_ed0f_4a75);
    let bounds = crate::mesh::bounds(&mesh.points);
    (0..n)
        .map(|i| ray(kind, bounds, offset, i % 2 == 1, &mut r))
        .collect()
}

/// One ray of [`rays`] for a mesh within `(lo, hi)`: aimed exactly through vertices and edges when
/// `tie`, else in a random direction.
pub(crate) fn ray(
    kind: Generated,
    (lo, hi): (Vec3, Vec3),
    offset: Vec3,
    tie: bool,
    r: &mut Rng,
) -> Ray {
    let (lo, hi) = (lo - offset, hi - offset);
    let q = |x: f32| (x * 16.0).round() / 16.0;
    let (org, dir) = match kind {
        Generated::Fan => {
            let a = r.random_range(0.0..std::f32::consts::TAU);
            let rad = r.random_range(0.5..3.0);
            let org = Vec3::new(
                q(rad * a.cos()),
                q(rad * a.sin()),
                q(r.random_range(-0.5..0.5)),
            );
            let dz = q(r.random_range(-0.5..0.5));
            let dir = if tie {
                Vec3::new(-org.x, -org.y, dz)
            } else {
                Vec3::new(r.random_range(-1.0..1.0), r.random_range(-1.0..1.0), dz)
            };
            (org, dir)
        }
        Generated::Kuhn | Generated::Jitter => {
            let span = hi - lo;
            let org = Vec3::from_array(std::array::from_fn(|a| {
                q(lo[a] + span[a] * r.random_range(0.1..0.9))
            }));
            if tie {
                let d = Vec3::from_array(std::array::from_fn(|_| r.random_range(-2..=2) as f32));
                (org.round(), d)
            } else {
                (
                    org,
                    Vec3::from_array(std::array::from_fn(|_| r.random_range(-1.0..1.0))),
                )
            }
        }
    };
    Ray {
        org: org + offset,
        dir: if dir == Vec3::ZERO { Vec3::Z } else { dir },
    }
}

/// The random source of case `i` of the stress row keyed `row` (a value fixed per row, whichever rows
/// run beside it) under `seed`.
pub(crate) fn row_rng(seed: u64, row: u64, i: usize) -> Rng {
    rng(seed
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(row << 32 | i as u64))
}
