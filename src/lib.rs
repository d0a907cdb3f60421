//! tetwalk: finds out, with proof, when ray traversal of tetrahedral meshes goes wrong in f32.
//!
//! Data flows one way: scene → mesh → rays → method → walk → outcome → report.

pub mod cases;
pub mod cli;
pub mod exact;
pub mod found;
pub mod gpu;
pub mod mesh;
pub mod methods;
pub mod render;
pub mod report;
pub mod scenes;
pub mod tet;
pub mod walk;
