//! Abaqus / CalculiX input (`.inp`, from memory: no `*INCLUDE`): parse,
//! then build every volume and surface the file names, as `seam solve` does.
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "select_all.rs"]
mod select_all;

fuzz_target!(|data: &[u8]| {
    if let Ok(msh) = seam_io::read_inp(data) {
        select_all::select_all(&msh);
    }
});
