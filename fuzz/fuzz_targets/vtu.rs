//! VTU (VTK XML UnstructuredGrid): every encoding and compressor seam reads.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = seam_io::read_vtu(data);
});
