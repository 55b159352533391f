//! Gmsh MSH (2.2 and 4.1, ASCII and binary): parse, then build every surface
//! and volume the file selects, as `seam assemble` and `seam solve` do.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(msh) = seam_io::read_msh(data) else { return };
    let _ = msh.surface(None);
    let _ = msh.volume(None);
    for dim in [2, 3] {
        for group in msh.physical_groups(dim) {
            let name = group.tag.to_string();
            match dim {
                2 => drop(msh.surface(Some(&name))),
                _ => drop(msh.volume(Some(&name))),
            }
        }
    }
});
