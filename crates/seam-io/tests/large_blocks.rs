//! Long ASCII blocks (over 4096 records) are read at once, in parallel: the
//! same mesh, and the same first error, as record by record.

use seam::generate::{flat, patch, Pattern};
use seam::SurfaceMesh;
use seam_io::{read_msh, write_msh};

/// A 70 × 70 quad patch (5041 nodes, 4900 quads) as MSH 4.1 ASCII.
fn v41() -> (SurfaceMesh, String) {
    let mesh = patch(70, 70, Pattern::Quads, flat(1.0, 2.0));
    let mut bytes = Vec::new();
    write_msh(&mut bytes, &mesh, "s").unwrap();
    (mesh, String::from_utf8(bytes).unwrap())
}

/// The same patch as MSH 2.2 ASCII.
fn v22(mesh: &SurfaceMesh) -> String {
    let mut text = String::from("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n");
    text += &format!("{}\n", mesh.n_points());
    for (i, p) in mesh.points().iter().enumerate() {
        text += &format!("{} {} {} {}\n", i + 1, p[0], p[1], p[2]);
    }
    text += &format!("$EndNodes\n$Elements\n{}\n", mesh.n_faces());
    for (i, f) in mesh.faces().iter().enumerate() {
        let nodes: Vec<String> = f.nodes().iter().map(|n| (n + 1).to_string()).collect();
        text += &format!("{} 3 2 1 1 {}\n", i + 1, nodes.join(" "));
    }
    text + "$EndElements\n"
}

/// `text` with the whole line starting with `old` (after a line break)
/// replaced by `new`, and the 1-based number of that line.
fn edit(text: &str, old: &str, new: &str) -> (String, usize) {
    let at = text.find(&format!("\n{old}\n")).unwrap_or_else(|| panic!("{old:?} not found")) + 1;
    let line = text[..at].matches('\n').count() + 1;
    (format!("{}{new}{}", &text[..at], &text[at + old.len()..]), line)
}

fn error(text: &str) -> String {
    read_msh(text.as_bytes()).unwrap_err().to_string()
}

#[test]
fn long_ascii_blocks_read_the_mesh() {
    let (mesh, text) = v41();
    for text in [text, v22(&mesh)] {
        let surface = read_msh(text.as_bytes()).unwrap().surface(None).unwrap();
        assert_eq!(surface.points(), mesh.points());
        assert_eq!(surface.faces(), mesh.faces());
    }
}

#[test]
fn long_ascii_blocks_report_the_first_error_on_its_line() {
    let (mesh, text) = v41();
    let p = |i: usize| mesh.points()[i];
    let coords = |i: usize| format!("{} {} {}", p(i)[0], p(i)[1], p(i)[2]);
    let element = |i: usize| {
        let nodes: Vec<String> = mesh.faces()[i].nodes().iter().map(|n| (n + 1).to_string()).collect();
        format!("{} {}", i + 1, nodes.join(" "))
    };

    let (bad, line) = edit(&text, &coords(2999), "0.5 abc");
    assert_eq!(error(&bad), format!("line {line}: expected 3 coordinates for node 3000, found \"0.5 abc\""));
    let (bad, line) = edit(&text, &coords(3999), "1 nan 0");
    assert_eq!(error(&bad), format!("line {line}: node 4000 has a non-finite coordinate"));
    let (bad, line) = edit(&text, "2500", "2499");
    assert_eq!(error(&bad), format!("line {line}: node 2499 is defined twice"));
    let (bad, line) = edit(&text, "2500", "2500 7");
    assert_eq!(
        error(&bad),
        format!("line {line}: expected the end of the line after a node tag, found \"7\"")
    );

    let (bad, line) = edit(&text, &element(3999), "4000 1 2 3 99999");
    assert_eq!(
        error(&bad),
        format!("line {line}: element 4000 refers to node 99999, which the $Nodes section does not define")
    );
    let (bad, line) = edit(&text, &element(3999), &format!("{} 7", element(3999)));
    assert_eq!(
        error(&bad),
        format!("line {line}: expected the end of the line after element 4000, found \"7\"")
    );
    // An unknown node before a malformed line: the unknown node is the error.
    let (bad, line) = edit(&text, &element(99), "100 1 2 3 99999");
    let (bad, _) = edit(&bad, &element(4499), "4500 1 2 x 4");
    assert_eq!(
        error(&bad),
        format!("line {line}: element 100 refers to node 99999, which the $Nodes section does not define")
    );

    let text = v22(&mesh);
    let (bad, line) = edit(&text, &format!("3000 {}", coords(2999)), "3000 0.5 abc 0");
    assert_eq!(
        error(&bad),
        format!("line {line}: expected 3 coordinates for node 3000, found \"0.5 abc 0\"")
    );
    let (bad, line) = edit(&text, &format!("3001 {}", coords(3000)), &format!("3000 {}", coords(3000)));
    assert_eq!(error(&bad), format!("line {line}: node 3000 is defined twice"));
}
