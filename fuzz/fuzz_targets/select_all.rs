//! What `seam solve` builds of a model, for the targets of model readers:
//! every volume and surface the file names (a module of those targets).

/// Builds all cells and faces, and every named volume and surface.
pub fn select_all(msh: &seam_io::Msh) {
    let _ = msh.volume(None);
    let _ = msh.surface(None);
    for group in msh.physical_groups(3) {
        let _ = msh.volume(Some(&group.tag.to_string()));
    }
    for group in msh.physical_groups(2) {
        let _ = msh.surface_of_volume(&group.tag.to_string(), None);
    }
}
