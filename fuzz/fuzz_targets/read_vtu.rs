//! Arbitrary bytes to the VTU reader: never a panic; a file that parses round-trips and
//! optimizes (see `quadopt_fuzz::check_reader`); a leading UTF-8 byte-order mark changes
//! nothing.
#![no_main]

use libfuzzer_sys::fuzz_target;
use quadopt::io::{self, Format};

fuzz_target!(|data: &[u8]| {
    quadopt_fuzz::check_reader(data, Format::Vtu);
    const BOM: &[u8] = b"\xef\xbb\xbf";
    if !data.starts_with(BOM) {
        let with_bom = [BOM, data].concat();
        assert_eq!(
            io::read_mesh_bytes(data, Format::Vtu).ok(),
            io::read_mesh_bytes(&with_bom, Format::Vtu).ok()
        );
    }
});
