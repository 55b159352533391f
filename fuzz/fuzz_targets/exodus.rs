//! Exodus II files (from memory, any of the netCDF flavours; needs the
//! `exodus` feature and the netCDF C library: `cargo fuzz run exodus
//! --features exodus`): read, then build every volume and surface the file
//! names, as `seam solve` does. Not in scripts/fuzz's default targets: the
//! netCDF and HDF5 libraries are C, not instrumented, and not seam's.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(msh) = seam_io::read_exodus(data) else { return };
    let _ = msh.volume(None);
    let _ = msh.surface(None);
    for group in msh.physical_groups(3) {
        let _ = msh.volume(Some(&group.tag.to_string()));
    }
    for group in msh.physical_groups(2) {
        let _ = msh.surface_of_volume(&group.tag.to_string(), None);
    }
});
