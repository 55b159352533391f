//! Case files of `seam solve`: TOML, schema and every check that needs no file.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = seam_case::Case::from_toml(text, std::path::Path::new(""));
    }
});
