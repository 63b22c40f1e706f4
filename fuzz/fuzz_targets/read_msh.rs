//! Arbitrary bytes to the MSH reader: never a panic; a file that parses round-trips and
//! optimizes (see `quadopt_fuzz::check_reader`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use quadopt::io::Format;

fuzz_target!(|data: &[u8]| quadopt_fuzz::check_reader(data, Format::Msh));
