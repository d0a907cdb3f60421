//! tetwalk finds out, with proof, when ray traversal code gives wrong answers in 32-bit floats: the
//! published methods for walking a ray through a tetrahedral mesh, through an octree, and for
//! intersecting rays with triangles, run in f32 exactly as published, every answer judged by an exact
//! oracle. This page is for using it as a library; the command-line tool has a user guide (`docs/` in
//! the repository) and its own `--help`.
//!
//! # Depending on it
//!
//! ```toml
//! [dev-dependencies]
//! tetwalk = { path = "…", default-features = false }
//! ```
//!
//! Without default features no GPU or command-line crate is built. What the library promises:
//!
//! - [`kit`]: judge your own traversal method from your own `cargo test` — every stress row, property
//!   campaigns through the fuzz generators, walks through lattice-tie meshes, each failure shrunk to
//!   its simplest case ([`kit::exit_faces`], [`kit::triangles`], [`kit::cells`]; a user imports
//!   [`kit::prelude`]).
//! - [`exact`]: the oracle — through which faces a line leaves a tetrahedron ([`exact::classify`]),
//!   exact ray–triangle hits, octree cell exits — with ties broken by Simulation of Simplicity.
//! - [`methods`]: every published method as a plain function over plain data, generic over the
//!   arithmetic model ([`methods::Plain`], and as a GPU may compute it).
//! - [`cases`]: the case format that `tetwalk exit`, `hit` and `judge` read.
//! - [`tet`]: tetrahedra, rays, and the one orientation convention: face `i` is opposite vertex `i`,
//!   and tetrahedra are positively oriented (`orient3d(v0, v1, v2, v3) > 0`).
//!
//! # The oracle and a published method on one case
//!
//! ```
//! use tetwalk::kit::prelude::*;
//! use tetwalk::methods::{Maria17, MomentFirst};
//!
//! // A positively oriented tetrahedron and a ray entering through face 3 (z = 0).
//! let tet: Tet = [Vec3::X, Vec3::ZERO, Vec3::Y, Vec3::Z];
//! let ray = Ray { org: Vec3::new(0.1, 0.1, -1.0), dir: Vec3::Z };
//! let exact = tetwalk::exact::classify(&tet, &ray).unwrap();
//! assert_eq!(exact.entry.to_vec(), vec![3]);
//! assert_eq!(exact.exit.to_vec(), vec![1]); // the face x + y + z = 1, opposite vertex 1
//!
//! // Maria et al. 2017, Algorithm 1, in plain f32, entering through face 3.
//! type M = Maria17<MomentFirst>; // seed 000 §3.4 read by its formula: `maria17`
//! let face = M::exit_face::<Plain>(&tet, &M::prepare::<Plain>(&ray), Some(3));
//! assert!(exact.exit.contains(face.unwrap()));
//! ```
//!
//! # Features
//!
//! `cli` (the default: the command line, its renders and reports; turns on the two below), `gpu` (the
//! GPU backend through wgpu), `internals` (every module public, for tetwalk's own binaries, tests, fuzz
//! targets and benchmarks; nothing beyond the modules above is promised). The modules' layering is in
//! the repository's `docs/architecture.md`.

// Without `cli`, what only the command line calls is unused, and without `internals` what only the
// tool's tests call is unreachable too, so the compiler would call it dead and the re-exports for
// them unused: dead code is looked for in the default build, where every caller is compiled.
#![cfg_attr(not(feature = "cli"), allow(dead_code, unused_imports))]
// Everything the library promises is documented: the crate's public items without `internals`, and
// the public modules' items always (each of `cases`, `exact`, `kit`, `methods`, `tet` warns too).
#![cfg_attr(not(feature = "internals"), warn(missing_docs))]
// With `internals`, the modules' public items are for tetwalk's own binaries and tests, and their
// docs link to the crate-private items beside them: read with `--document-private-items`, as CI
// builds them (a link that names no item is still an error).
#![cfg_attr(feature = "internals", allow(rustdoc::private_intra_doc_links))]

pub mod cases;
pub mod exact;
pub mod kit;
pub mod methods;
pub mod tet;

// Public with the `internals` feature, crate-private without it (written out: a module declared by a
// macro could not export its own macros).
#[cfg(feature = "internals")]
pub mod backend;
#[cfg(not(feature = "internals"))]
pub(crate) mod backend;
#[cfg(feature = "internals")]
pub mod child;
#[cfg(not(feature = "internals"))]
pub(crate) mod child;
#[cfg(feature = "internals")]
pub mod choice;
#[cfg(not(feature = "internals"))]
pub(crate) mod choice;
#[cfg(feature = "internals")]
pub mod engine;
#[cfg(not(feature = "internals"))]
pub(crate) mod engine;
#[cfg(feature = "internals")]
pub mod family;
#[cfg(not(feature = "internals"))]
pub(crate) mod family;
#[cfg(feature = "internals")]
pub mod fpenv;
#[cfg(not(feature = "internals"))]
pub(crate) mod fpenv;
#[cfg(all(feature = "gpu", feature = "internals"))]
pub mod gpu;
#[cfg(all(feature = "gpu", not(feature = "internals")))]
pub(crate) mod gpu;
#[cfg(feature = "internals")]
pub mod mesh;
#[cfg(not(feature = "internals"))]
pub(crate) mod mesh;
#[cfg(feature = "internals")]
pub mod octree;
#[cfg(not(feature = "internals"))]
pub(crate) mod octree;
#[cfg(feature = "internals")]
pub mod registry;
#[cfg(not(feature = "internals"))]
pub(crate) mod registry;
#[cfg(feature = "internals")]
pub mod report;
#[cfg(feature = "internals")]
pub mod scenes;
#[cfg(not(feature = "internals"))]
pub(crate) mod scenes;
#[cfg(feature = "internals")]
pub mod staged;
#[cfg(not(feature = "internals"))]
pub(crate) mod staged;
#[cfg(feature = "internals")]
pub mod walk;
#[cfg(not(feature = "internals"))]
pub(crate) mod walk;

#[cfg(feature = "cli")]
pub mod cli;
#[cfg(feature = "cli")]
pub(crate) mod process;
#[cfg(feature = "cli")]
pub mod render;
