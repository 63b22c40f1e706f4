//! Arbitrary bytes to the OBJ reader: never a panic; a file that parses round-trips and
//! optimizes (see `quadopt_fuzz::check_reader`); a leading UTF-8 byte-order mark changes
//! nothing.
#![no_main]

use libfuzzer_sys::fuzz_target;
use quadopt::io::Format;

fuzz_target!(|data: &[u8]| {
    quadopt_fuzz::check_reader(data, Format::Obj);
    quadopt_fuzz::check_bom(data, Format::Obj);
});
