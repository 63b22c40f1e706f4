//! The subcommands, one module each; what several of them share lives beside this directory
//! (`mesh_files`, `picture_files`, `annotation`, `progress`, `json`).

mod compare;
mod draw;
mod generate;
mod optimize;
mod quality;
mod samples;

pub use compare::compare;
pub use draw::{Drawn, draw};
pub use generate::generate;
pub use optimize::optimize;
pub use quality::quality;
pub use samples::run_data_dir;
