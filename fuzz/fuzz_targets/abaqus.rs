//! Abaqus / CalculiX input (`.inp`, from memory: no `*INCLUDE`): parse,
//! then build every volume and surface the file names, as `seam solve` does.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(msh) = seam_io::read_inp(data) else { return };
    let _ = msh.volume(None);
    let _ = msh.surface(None);
    for group in msh.physical_groups(3) {
        let _ = msh.volume(Some(&group.tag.to_string()));
    }
    for group in msh.physical_groups(2) {
        let _ = msh.surface_of_volume(&group.tag.to_string(), None);
    }
});
