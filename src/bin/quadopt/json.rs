//! Pieces of the `--json` outputs that several commands share: the library's (`quadopt::json`,
//! which the Python package reports with too).

pub use quadopt::json::{by_kind_json, stats_json};
