//! Reports: failure counts per method, as markdown tables and JSON.

pub mod stress;
