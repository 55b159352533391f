//! Reading speed of the MSH and VTU readers on a large surface.
//!
//! ```text
//! cargo run --release -p seam-io --example read_speed [-- QUAD_SIDE TRI_SIDE]
//! RAYON_NUM_THREADS=1 cargo run --release -p seam-io --example read_speed
//! READ_SPEED_RUNS=7 READ_SPEED_ONLY="MSH 4.1" cargo run --release -p seam-io --example read_speed
//! ```
//!
//! Generates a `QUAD_SIDE²`-quad flat patch (default 448: 200 704 quads) and a
//! `2·TRI_SIDE²`-triangle jittered one (default 345: 238 050 triangles), each
//! with a scalar point field, writes each in every form below to a temporary
//! directory, then times reading it (best of 3, or of `READ_SPEED_RUNS`; only the
//! forms whose name contains `READ_SPEED_ONLY`) and prints a Markdown table.
//! With `READ_SPEED_DIR` set, the files are written there and kept.
//! The `check` column is a hash of what was read (points, faces, field values),
//! the same for every form of a mesh and unchanged by the reader's speed-ups.
//!
//! | form | written by |
//! |---|---|
//! | VTU inline base64 | `write_vtu_file` (what seam writes) |
//! | VTU appended raw, VTU ASCII | this example (as ParaView writes them) |
//! | MSH 4.1 ASCII | `write_msh_file` |
//! | MSH 4.1 binary, MSH 2.2 binary, MSH 2.2 ASCII | this example (as Gmsh writes them), with `$NodeData` |

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use seam::generate::{flat, patch, Pattern};
use seam::{Face, SurfaceMesh};
use seam_io::{read_msh_file, read_surface_file, read_vtu_file, write_msh_file, write_vtu_file, Field};

fn main() {
    let args: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let runs = std::env::var("READ_SPEED_RUNS").ok().and_then(|r| r.parse().ok()).unwrap_or(3);
    let only = std::env::var("READ_SPEED_ONLY").unwrap_or_default();
    let quad_side = args.first().copied().unwrap_or(448);
    let tri_side = args.get(1).copied().unwrap_or(345);
    let temp = tempfile::tempdir().expect("a temporary directory");
    let keep = std::env::var_os("READ_SPEED_DIR").map(PathBuf::from);
    let dir = keep.as_deref().unwrap_or(temp.path());
    let threads = rayon::current_num_threads();
    println!("rayon threads: {threads}\n");
    println!("| mesh | form | size MB | read s | MB/s | surface s | check |");
    println!("|---|---|---:|---:|---:|---:|---|");
    let quads = patch(quad_side, quad_side, Pattern::Quads, flat(1.0, 1.0));
    run(dir, &format!("{} quads", quads.n_faces()), &quads, runs, &only);
    let tris =
        patch(tri_side, tri_side, Pattern::JitteredTriangles { amplitude: 0.2, seed: 42 }, flat(1.0, 1.0));
    run(dir, &format!("{} triangles", tris.n_faces()), &tris, runs, &only);
}

/// A point field with varied, non-round values.
fn field(mesh: &SurfaceMesh) -> Vec<f64> {
    mesh.points().iter().map(|p| (3.0 * p[0]).sin() * (2.0 * p[1]).cos() + 0.1 * p[0]).collect()
}

fn run(dir: &Path, label: &str, mesh: &SurfaceMesh, runs: usize, only: &str) {
    let u = field(mesh);
    let dir = dir.join(label.replace(' ', "_"));
    std::fs::create_dir_all(&dir).expect("a directory");
    let files: Vec<(&str, PathBuf)> = vec![
        ("VTU inline base64", dir.join("b64.vtu")),
        ("VTU appended raw", dir.join("raw.vtu")),
        ("VTU ASCII", dir.join("ascii.vtu")),
        ("MSH 4.1 binary", dir.join("v41.bin.msh")),
        ("MSH 4.1 ASCII", dir.join("v41.ascii.msh")),
        ("MSH 2.2 binary", dir.join("v22.bin.msh")),
        ("MSH 2.2 ASCII", dir.join("v22.ascii.msh")),
    ];
    write_vtu_file(&files[0].1, mesh, &[Field::scalars("u", u.clone())], &[]).expect("VTU written");
    std::fs::write(&files[1].1, vtu_appended_raw(mesh, &u)).expect("written");
    std::fs::write(&files[2].1, vtu_ascii(mesh, &u)).expect("written");
    std::fs::write(&files[3].1, msh41_binary(mesh, &u)).expect("written");
    write_msh_file(&files[4].1, mesh, "surface").expect("MSH written");
    let mut v41 = std::fs::read(&files[4].1).expect("read back");
    node_data(&mut v41, &u, false);
    std::fs::write(&files[4].1, v41).expect("written");
    std::fs::write(&files[5].1, msh22(mesh, &u, true)).expect("written");
    std::fs::write(&files[6].1, msh22(mesh, &u, false)).expect("written");
    for (form, path) in files.iter().filter(|(form, _)| form.contains(only)) {
        let mb = std::fs::metadata(path).expect("a file").len() as f64 / 1e6;
        let (read, surface, check) = if form.starts_with("VTU") {
            let (t, read) = best_of(runs, || read_vtu_file(path).expect("VTU read"));
            let field = read.point_field("u").map(|f| f.values.as_slice()).unwrap_or_default();
            (t, None, check(&read.mesh, field))
        } else {
            let (t, msh) = best_of(runs, || read_msh_file(path).expect("MSH read"));
            let (ts, surface) = best_of(runs, || read_surface_file(path, None).expect("surface read"));
            let field = msh.node_data("u").map(|f| f.values.as_slice()).unwrap_or_default();
            (t, Some(ts), check(&surface, field))
        };
        let surface = surface.map_or("".into(), |t| format!("{t:.4}"));
        println!("| {label} | {form} | {mb:.1} | {read:.4} | {:.0} | {surface} | {check:016x} |", mb / read);
    }
}

/// The best time of `runs` runs of `f`, and its result.
fn best_of<T>(runs: usize, f: impl Fn() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        let value = f();
        best = best.min(start.elapsed().as_secs_f64());
        out = Some(value);
    }
    (best, out.expect("ran"))
}

/// FNV-1a over the bits of the points, the face nodes and the field.
fn check(mesh: &SurfaceMesh, field: &[f64]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let mut eat = |v: u64| {
        for b in v.to_le_bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    };
    for p in mesh.points() {
        p.iter().for_each(|x| eat(x.to_bits()));
    }
    for f in mesh.faces() {
        eat(f.nodes().len() as u64);
        f.nodes().iter().for_each(|&n| eat(n as u64));
    }
    field.iter().for_each(|x| eat(x.to_bits()));
    h
}

fn vtk_type(face: &Face) -> u8 {
    face.kind().info().vtk_type
}

/// A VTU file with `<AppendedData encoding="raw">`, UInt64 headers, as ParaView
/// writes uncompressed files.
fn vtu_appended_raw(mesh: &SurfaceMesh, u: &[f64]) -> Vec<u8> {
    let points: Vec<u8> = mesh.points().iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
    let conn: Vec<u8> =
        mesh.faces().iter().flat_map(Face::nodes).flat_map(|&n| (n as i64).to_le_bytes()).collect();
    let mut end = 0i64;
    let offsets: Vec<u8> = mesh
        .faces()
        .iter()
        .flat_map(|f| {
            end += f.nodes().len() as i64;
            end.to_le_bytes()
        })
        .collect();
    let types: Vec<u8> = mesh.faces().iter().map(vtk_type).collect();
    let field: Vec<u8> = u.iter().flat_map(|x| x.to_le_bytes()).collect();
    let arrays = [&points, &conn, &offsets, &types, &field];
    let mut at = Vec::new();
    let mut offset = 0;
    for a in arrays {
        at.push(offset);
        offset += 8 + a.len();
    }
    let (np, nc) = (mesh.n_points(), mesh.n_faces());
    let mut head = String::new();
    write!(
        head,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n\
         <Piece NumberOfPoints=\"{np}\" NumberOfCells=\"{nc}\">\n<PointData Scalars=\"u\">\n\
         <DataArray type=\"Float64\" Name=\"u\" format=\"appended\" offset=\"{}\"/>\n</PointData>\n\
         <Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"appended\" offset=\"{}\"/>\n\
         </Points>\n<Cells>\n\
         <DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\" offset=\"{}\"/>\n\
         <DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\" offset=\"{}\"/>\n\
         <DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"{}\"/>\n\
         </Cells>\n</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_",
        at[4], at[0], at[1], at[2], at[3]
    )
    .expect("formatted");
    let mut out = head.into_bytes();
    for a in arrays {
        out.extend_from_slice(&(a.len() as u64).to_le_bytes());
        out.extend_from_slice(a);
    }
    out.extend_from_slice(b"\n</AppendedData>\n</VTKFile>\n");
    out
}

/// A VTU file with ASCII data arrays, 6 values a line.
fn vtu_ascii(mesh: &SurfaceMesh, u: &[f64]) -> Vec<u8> {
    fn array<T: std::fmt::Display>(out: &mut String, head: &str, values: impl Iterator<Item = T>) {
        writeln!(out, "<DataArray {head} format=\"ascii\">").expect("formatted");
        for (i, v) in values.enumerate() {
            let sep = if i % 6 == 5 { '\n' } else { ' ' };
            write!(out, "{v}{sep}").expect("formatted");
        }
        out.push_str("\n</DataArray>\n");
    }
    let (np, nc) = (mesh.n_points(), mesh.n_faces());
    let mut out = String::new();
    writeln!(
        out,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n\
         <UnstructuredGrid>\n<Piece NumberOfPoints=\"{np}\" NumberOfCells=\"{nc}\">\n<PointData>"
    )
    .expect("formatted");
    array(&mut out, "type=\"Float64\" Name=\"u\"", u.iter());
    out.push_str("</PointData>\n<Points>\n");
    array(&mut out, "type=\"Float64\" NumberOfComponents=\"3\"", mesh.points().iter().flatten());
    out.push_str("</Points>\n<Cells>\n");
    array(&mut out, "type=\"Int64\" Name=\"connectivity\"", mesh.faces().iter().flat_map(Face::nodes));
    let mut end = 0;
    let offsets = mesh.faces().iter().map(|f| {
        end += f.nodes().len();
        end
    });
    array(&mut out, "type=\"Int64\" Name=\"offsets\"", offsets);
    array(&mut out, "type=\"UInt8\" Name=\"types\"", mesh.faces().iter().map(vtk_type));
    out.push_str("</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    out.into_bytes()
}

fn gmsh_type(face: &Face) -> i32 {
    seam_io::msh::face_type(face).unwrap_or(0) as i32
}

/// `$NodeData` with the field `u`: text header, then `tag value` records.
fn node_data(out: &mut Vec<u8>, u: &[f64], binary: bool) {
    let n = u.len();
    write!(out, "$NodeData\n1\n\"u\"\n1\n0\n3\n0\n1\n{n}\n").expect("written");
    for (i, x) in u.iter().enumerate() {
        if binary {
            out.extend_from_slice(&(i as i32 + 1).to_le_bytes());
            out.extend_from_slice(&x.to_le_bytes());
        } else {
            writeln!(out, "{} {x}", i + 1).expect("written");
        }
    }
    out.extend_from_slice(if binary { b"\n$EndNodeData\n" } else { b"$EndNodeData\n" });
}

/// MSH 4.1 binary as Gmsh writes it: one surface entity in physical group 1,
/// one node block, one element block per run of one type.
fn msh41_binary(mesh: &SurfaceMesh, u: &[f64]) -> Vec<u8> {
    let mut out = Vec::new();
    let size = |out: &mut Vec<u8>, v: usize| out.extend_from_slice(&(v as u64).to_le_bytes());
    let int = |out: &mut Vec<u8>, v: i32| out.extend_from_slice(&v.to_le_bytes());
    out.extend_from_slice(b"$MeshFormat\n4.1 1 8\n");
    int(&mut out, 1);
    out.extend_from_slice(b"\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"surface\"\n$EndPhysicalNames\n");
    out.extend_from_slice(b"$Entities\n");
    for count in [0, 0, 1, 0] {
        size(&mut out, count);
    }
    int(&mut out, 1);
    for x in [0.0f64, 0.0, 0.0, 1.0, 1.0, 0.0] {
        out.extend_from_slice(&x.to_le_bytes());
    }
    size(&mut out, 1);
    int(&mut out, 1);
    size(&mut out, 0);
    out.extend_from_slice(b"\n$EndEntities\n$Nodes\n");
    let n = mesh.n_points();
    for v in [1, n, 1, n] {
        size(&mut out, v);
    }
    for v in [2, 1, 0] {
        int(&mut out, v);
    }
    size(&mut out, n);
    for i in 1..=n {
        size(&mut out, i);
    }
    for x in mesh.points().iter().flatten() {
        out.extend_from_slice(&x.to_le_bytes());
    }
    out.extend_from_slice(b"\n$EndNodes\n$Elements\n");
    let faces = mesh.faces();
    let runs: Vec<&[Face]> = faces.chunk_by(|a, b| gmsh_type(a) == gmsh_type(b)).collect();
    for v in [runs.len(), faces.len(), 1, faces.len()] {
        size(&mut out, v);
    }
    let mut tag = 0;
    for run in runs {
        for v in [2, 1, gmsh_type(&run[0])] {
            int(&mut out, v);
        }
        size(&mut out, run.len());
        for face in run {
            tag += 1;
            size(&mut out, tag);
            face.nodes().iter().for_each(|&node| size(&mut out, node + 1));
        }
    }
    out.extend_from_slice(b"\n$EndElements\n");
    node_data(&mut out, u, true);
    out
}

/// MSH 2.2, binary or ASCII, as Gmsh writes it (physical 1, entity 1).
fn msh22(mesh: &SurfaceMesh, u: &[f64], binary: bool) -> Vec<u8> {
    let mut out = Vec::new();
    let int = |out: &mut Vec<u8>, v: i32| out.extend_from_slice(&v.to_le_bytes());
    if binary {
        out.extend_from_slice(b"$MeshFormat\n2.2 1 8\n");
        int(&mut out, 1);
        out.extend_from_slice(b"\n$EndMeshFormat\n");
    } else {
        out.extend_from_slice(b"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
    }
    out.extend_from_slice(b"$PhysicalNames\n1\n2 1 \"surface\"\n$EndPhysicalNames\n");
    let n = mesh.n_points();
    write!(out, "$Nodes\n{n}\n").expect("written");
    for (i, p) in mesh.points().iter().enumerate() {
        if binary {
            int(&mut out, i as i32 + 1);
            p.iter().for_each(|x| out.extend_from_slice(&x.to_le_bytes()));
        } else {
            writeln!(out, "{} {} {} {}", i + 1, p[0], p[1], p[2]).expect("written");
        }
    }
    out.extend_from_slice(if binary { b"\n$EndNodes\n" } else { b"$EndNodes\n" });
    let faces = mesh.faces();
    write!(out, "$Elements\n{}\n", faces.len()).expect("written");
    let mut tag = 0;
    for run in faces.chunk_by(|a, b| gmsh_type(a) == gmsh_type(b)) {
        let ty = gmsh_type(&run[0]);
        if binary {
            for v in [ty, run.len() as i32, 2] {
                int(&mut out, v);
            }
        }
        for face in run {
            tag += 1;
            if binary {
                for v in [tag, 1, 1] {
                    int(&mut out, v);
                }
                face.nodes().iter().for_each(|&node| int(&mut out, node as i32 + 1));
            } else {
                write!(out, "{tag} {ty} 2 1 1").expect("written");
                face.nodes().iter().for_each(|&node| write!(out, " {}", node + 1).expect("written"));
                out.push(b'\n');
            }
        }
    }
    out.extend_from_slice(if binary { b"\n$EndElements\n" } else { b"$EndElements\n" });
    node_data(&mut out, u, binary);
    out
}
