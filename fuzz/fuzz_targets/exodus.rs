//! Exodus II files (from memory, any of the netCDF flavours): read, then
//! build every volume and surface the file names, as `seam solve` does. The
//! netCDF side is the pure-Rust netcdf-reader and hdf5-reader, instrumented
//! with seam.
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "select_all.rs"]
mod select_all;

fuzz_target!(|data: &[u8]| {
    if let Ok(msh) = seam_io::read_exodus(data) {
        select_all::select_all(&msh);
    }
});
