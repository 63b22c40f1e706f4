//! A mesh from arbitrary arrays, optimized with arbitrary options through the Rust API:
//! validation errors are typed, invalid options are refused, and a run keeps every guarantee
//! (see `quadopt_fuzz::check_optimize`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use quadopt_fuzz::{RawMesh, RawOptions};

fuzz_target!(|input: (RawMesh, RawOptions)| quadopt_fuzz::check_optimize(&input.0, &input.1));
