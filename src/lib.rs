//! tetwalk: finds out, with proof, when ray traversal of tetrahedral meshes goes wrong in f32.
//!
//! Data flows one way, and so do the imports (tests/layering.rs states each module's allowed imports and checks them): files written whole
//! (`staged`) → the floating-point environment (`fpenv`) → geometry (`tet`, with the named value sets of `choice`) → `mesh` → `octree` → oracle
//! (`exact`) → `scenes` (generators, cameras) → `methods` → `walk` (outcomes, judging) → `registry` →
//! the case format (`cases`) → `gpu` → `backend` → `found` → `report` → `conformance` (the kit that
//! judges users' methods) → `render` → `cli`.

pub mod backend;
pub mod cases;
pub mod choice;
pub mod cli;
pub mod engine;
pub mod exact;
pub mod family;
pub mod fpenv;
pub mod gpu;
pub mod kit;
pub mod mesh;
pub mod methods;
pub mod octree;
pub mod registry;
pub mod render;
pub mod report;
pub mod scenes;
pub mod staged;
pub mod tet;
pub mod walk;
