//! Reports: failure counts per method, as markdown tables and JSON.

pub mod bench;
pub mod count;
pub mod scene_info;
pub mod stress;
pub mod wrong;
