//! The MSH writers: what they write reads back to the same meshes, bit for bit.

use std::path::PathBuf;

use seam::SurfaceMesh;
use seam_io::{read_msh, read_msh_file, write_msh, write_volume_msh, write_volume_msh_file};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name)
}

/// Writes the volume of the fixture `name` with its physical surface "top" and
/// its boundary, reads the file back: the same points, cells and faces.
fn assert_volume_reads_back_the_same(name: &str) {
    let msh = read_msh_file(fixture(name)).unwrap();
    let volume = msh.volume(None).unwrap();
    let top = msh.surface(Some("top")).unwrap();
    let boundary = msh.surface(None).unwrap();
    let mut bytes = Vec::new();
    write_volume_msh(&mut bytes, &volume, "body", &[("top", &top), ("all sides", &boundary)]).unwrap();
    let back = read_msh(&bytes).unwrap();
    assert_eq!(back.volume(Some("body")).unwrap(), volume, "{name}");
    assert_eq!(back.volume(None).unwrap(), volume, "{name}");
    let same_faces = |a: &SurfaceMesh, b: &SurfaceMesh| {
        let mut fa: Vec<_> = a.faces().to_vec();
        let mut fb: Vec<_> = b.faces().to_vec();
        fa.sort_by_key(|f| f.nodes().to_vec());
        fb.sort_by_key(|f| f.nodes().to_vec());
        assert_eq!(a.points(), b.points(), "{name}");
        assert_eq!(fa, fb, "{name}");
    };
    same_faces(&back.surface(Some("top")).unwrap(), &top);
    same_faces(&back.surface(Some("all sides")).unwrap(), &boundary);
    same_faces(&back.surface(None).unwrap(), &boundary);
    // Groups by number: surfaces 1, 2, the volume 3.
    same_faces(&back.surface(Some("1")).unwrap(), &top);
    assert_eq!(back.volume(Some("3")).unwrap(), volume, "{name}");
}

#[test]
fn a_volume_with_named_surfaces_reads_back_the_same() {
    // Hexahedra, tetrahedra and pyramids, with a physical surface of triangles and quads.
    assert_volume_reads_back_the_same("hybrid_pyramid.v41.bin.msh");
}

/// Every second-order cell and face type (complete and serendipity), mixed
/// within a mesh.
#[test]
fn second_order_volumes_and_surfaces_read_back_the_same() {
    let mut faces = std::collections::BTreeSet::new();
    let mut cells = std::collections::BTreeSet::new();
    for name in ["box_tet_o2", "box_hex_o2", "box_hex_o2s", "slab_prism_o2", "slab_prism_o2s"]
        .into_iter()
        .chain(["hybrid_pyramid_o2", "hybrid_pyramid_o2s"])
    {
        let file = format!("{name}.v22.bin.msh");
        assert_volume_reads_back_the_same(&file);
        let msh = read_msh_file(fixture(&file)).unwrap();
        faces.extend(msh.surface(None).unwrap().faces().iter().map(|f| f.len()));
        cells.extend(msh.volume(None).unwrap().cells().iter().map(|c| c.nodes().len()));
    }
    assert_eq!(faces.into_iter().collect::<Vec<_>>(), [6, 8, 9]);
    assert_eq!(cells.into_iter().collect::<Vec<_>>(), [10, 13, 14, 15, 18, 20, 27]);
    // A surface of second-order triangles, by itself.
    let surface = msh_surface("square_tri6.v41.ascii.msh");
    let mut bytes = Vec::new();
    write_msh(&mut bytes, &surface, "interface").unwrap();
    let back = read_msh(&bytes).unwrap().surface(Some("interface")).unwrap();
    assert_eq!(back, surface);
    // Its enriched version has Tri7 faces, which Gmsh does not have.
    let error = write_msh(&mut Vec::new(), &surface.enriched().0, "interface").unwrap_err();
    assert_eq!(error.kind(), std::io::ErrorKind::InvalidInput);
    assert_eq!(error.to_string(), "Gmsh has no Tri7 faces");
}

#[test]
fn a_surface_reads_back_the_same() {
    let surface = msh_surface("square_mixed.v41.bin.msh");
    let mut bytes = Vec::new();
    write_msh(&mut bytes, &surface, "interface").unwrap();
    let back = read_msh(&bytes).unwrap().surface(Some("interface")).unwrap();
    assert_eq!(back.points(), surface.points());
    assert_eq!(back.n_faces(), surface.n_faces());
}

fn msh_surface(name: &str) -> SurfaceMesh {
    read_msh_file(fixture(name)).unwrap().surface(None).unwrap()
}

#[test]
fn a_surface_of_another_mesh_is_refused() {
    let msh = read_msh_file(fixture("box_hex.v41.ascii.msh")).unwrap();
    let volume = msh.volume(None).unwrap();
    let other = msh_surface("square_tri.v41.ascii.msh");
    let tmp = tempfile::tempdir().unwrap();
    let err = write_volume_msh_file(tmp.path().join("v.msh"), &volume, "v", &[("s", &other)]).unwrap_err();
    assert_eq!(err.kind(), std::io::ErrorKind::InvalidInput);
    assert!(err.to_string().contains("surface \"s\""), "{err}");
}
