//! The engine: runs that compute, for every family ([`crate::family`]) — stress tables and campaigns,
//! found cases, their checks and replay, the fuzz targets' policy, counts over a scene's views, walk
//! speed and the seeds' tables — returning plain tallies and records of wrong answers. Reports
//! (`crate::report`) only format what these return.

pub mod answerer;
pub mod bench;
pub mod count;
pub mod filters;
pub mod found;
pub mod fuzz;
pub mod info;
pub mod paper;
pub mod shrink;
pub mod standing;
pub mod stress;
pub mod verify;
