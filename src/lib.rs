//! tetwalk: finds out, with proof, when ray traversal of tetrahedral meshes, octrees and triangle sets
//! goes wrong in f32.
//!
//! Data flows one way, and so do the imports (`tests/layering.rs` states each module's allowed imports
//! and checks them): files written whole (`staged`), the floating-point environment (`fpenv`) and
//! geometry (`tet`, with the named value sets of `choice`) → `mesh`, `octree` → the oracle (`exact`) →
//! `scenes` (generators, cameras) → `methods` → `walk` (outcomes, judging) → `registry` (every method
//! once) → the case format (`cases`) → `gpu` → `backend` (the one seam where answers are computed) →
//! `family` (what a family of methods is: cases, answers, truths, verdicts, stress rows, counts) →
//! `engine` (stress, campaigns, counts, found cases, fuzz policy, standings: runs that return tallies)
//! → `kit` (users' methods judged from their `cargo test`) → `report` and `render` (formatting only)
//! → `cli`.
//!
//! A user's crate depends on it with `default-features = false` and imports [`kit::prelude`]; the
//! oracle ([`exact`]), the methods ([`methods`]) and the case format ([`cases`]) are public too.
//! Everything else is the tool's own: public with the `internals` feature (the default `cli` turns it
//! on, for the binaries, tests, fuzz targets and benchmarks), crate-private without it.

// Without `internals`, what only the tool's binaries and tests call is unreachable from outside the
// crate, so the compiler would call it dead, and the re-exports for them unused.
#![cfg_attr(not(feature = "internals"), allow(dead_code, unused_imports))]

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
pub mod render;
