//! The operator in parts (`seam::parts`, for MPI ranks): split, handed over
//! as bytes, assembled part by part and put back together, it is the whole
//! assembly's B, D and totals bit for bit, for any number of parts.

use seam::generate::{cylinder, flat, hyperbolic_paraboloid, patch, quadratic_patch, Pattern};
use seam::parts::{assemble_here, assemble_parts, bisect, split, PartBlocks, PartJob};
use seam::{assemble, CsrMatrix, FaceKind, FaceTree, MaxGap, Mortar, MortarOptions, Multiplier, SurfaceMesh};

fn same_bits(a: &CsrMatrix, b: &CsrMatrix, what: &str) {
    assert_eq!((a.nrows, a.ncols), (b.nrows, b.ncols), "{what}: shape");
    assert_eq!(a.indptr, b.indptr, "{what}: row pointers");
    assert_eq!(a.indices, b.indices, "{what}: columns");
    let bits = |m: &CsrMatrix| m.values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert!(bits(a) == bits(b), "{what}: values differ");
}

/// Split into `n` parts, through bytes both ways, and back together.
fn in_parts(master: &SurfaceMesh, slave: &SurfaceMesh, options: &MortarOptions, n: usize) -> Mortar {
    let tree = FaceTree::new(master);
    let parts = split(&tree, slave, options, n);
    assert_eq!(parts.len(), n);
    let blocks: Vec<PartBlocks> = parts
        .iter()
        .enumerate()
        .map(|(p, part)| {
            if p == n - 1 {
                // As rank 0 does its own: from the whole surfaces.
                return assemble_here(master, &tree, slave, options, part);
            }
            let job = PartJob::from_bytes(&PartJob::new(master, slave, options, part).to_bytes()).unwrap();
            assert_eq!(job.slave_faces(), part.slave_faces.len());
            PartBlocks::from_bytes(&job.assemble().to_bytes()).unwrap()
        })
        .collect();
    assemble_parts(master, &tree, slave, options, blocks).unwrap()
}

fn check(name: &str, master: &SurfaceMesh, slave: &SurfaceMesh, options: &MortarOptions) {
    let whole = assemble(master, slave, options).unwrap();
    for n in [1, 2, 3, 4, 7] {
        let what = format!("{name}, {n} parts");
        let parted = in_parts(master, slave, options, n);
        same_bits(&parted.b, &whole.b, &format!("{what}: B"));
        same_bits(&parted.d, &whole.d, &format!("{what}: D"));
        assert_eq!(parted.summary, whole.summary, "{what}: totals");
        assert_eq!(parted.faces, whole.faces, "{what}: face statistics");
        assert_eq!(parted.segments, whole.segments, "{what}: segments");
        assert_eq!(parted.covered, whole.covered, "{what}: covered nodes");
        match (&parted.basis, &whole.basis) {
            (Some(a), Some(b)) => same_bits(a, b, &format!("{what}: Q")),
            (a, b) => assert_eq!(a.is_some(), b.is_some(), "{what}: Q"),
        }
    }
}

fn options(multiplier: Multiplier) -> MortarOptions {
    MortarOptions { multiplier, record_segments: true, ..Default::default() }
}

#[test]
fn flat_surfaces_in_parts_are_the_whole() {
    let slave = patch(13, 11, Pattern::Quads, flat(1.0, 1.0));
    let master = patch(9, 10, Pattern::JitteredTriangles { amplitude: 0.25, seed: 7 }, flat(1.0, 1.0));
    for m in [Multiplier::Standard, Multiplier::Dual, Multiplier::Lumped] {
        check("flat", &master, &slave, &options(m));
    }
}

#[test]
fn curved_and_warped_surfaces_in_parts_are_the_whole() {
    // A quarter cylinder, the master 1 % farther out (gaps), and warped quads.
    let slave = patch(12, 9, Pattern::Quads, cylinder(1.0, std::f64::consts::FRAC_PI_2, 1.0));
    let master = patch(10, 7, Pattern::Triangles, cylinder(1.01, std::f64::consts::FRAC_PI_2, 1.0));
    check("cylinder", &master, &slave, &options(Multiplier::Dual));
    let slave = patch(10, 10, Pattern::Quads, hyperbolic_paraboloid(0.4));
    let master = patch(7, 8, Pattern::Quads, hyperbolic_paraboloid(0.4));
    check("warped", &master, &slave, &options(Multiplier::Standard));
}

#[test]
fn partly_overlapping_surfaces_in_parts_are_the_whole() {
    // The master covers part of the slave, so parts have uncovered faces and
    // partition boundaries run through the end of the coverage.
    let slave = patch(12, 12, Pattern::Quads, flat(1.0, 1.0));
    let master = patch(7, 9, Pattern::Triangles, |u, v| [0.3 + 0.5 * u, -0.2 + 0.9 * v, 0.001 * u]);
    check("partly", &master, &slave, &options(Multiplier::Dual));
    // Regions that no master face meets.
    let corner = patch(3, 3, Pattern::Triangles, |u, v| [0.8 + 0.2 * u, 0.8 + 0.2 * v, 0.0]);
    check("a corner", &corner, &slave, &options(Multiplier::Dual));
    let absolute = MortarOptions { max_gap: MaxGap::Absolute(0.2), ..options(Multiplier::Standard) };
    check("partly, absolute gap", &master, &slave, &absolute);
}

#[test]
fn second_order_surfaces_in_parts_are_the_whole() {
    let surface = cylinder(1.0, 1.2, 1.0);
    let slave = quadratic_patch(5, 4, FaceKind::Tri6, None, &surface);
    let master = quadratic_patch(4, 4, FaceKind::Quad9, Some((0.2, 3)), cylinder(1.0, 1.2, 1.0));
    // Dual multipliers on Tri6: the basis transformation, decided for the whole surface.
    check("second order", &master, &slave, &options(Multiplier::Dual));
    check("second order, reversed", &slave, &master, &options(Multiplier::Standard));
}

#[test]
fn bisection_balances_the_parts() {
    let slave = patch(30, 17, Pattern::Triangles, cylinder(1.0, 1.0, 2.0));
    let centres: Vec<_> = (0..slave.n_faces()).map(|f| slave.corners(f)[0]).collect();
    for parts in [1, 2, 3, 5, 8, 13] {
        let owner = bisect(&centres, parts);
        let mut sizes = vec![0usize; parts];
        owner.iter().for_each(|&p| sizes[p] += 1);
        let (min, max) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
        assert!(max - min <= 4, "{parts} parts: sizes {sizes:?}");
        assert_eq!(bisect(&centres, parts), owner, "deterministic");
    }
    // More parts than faces: some are empty, and the operator is still the whole.
    let slave = patch(2, 1, Pattern::Quads, flat(1.0, 1.0));
    let master = patch(3, 2, Pattern::Triangles, flat(1.0, 1.0));
    let o = options(Multiplier::Dual);
    let whole = assemble(&master, &slave, &o).unwrap();
    same_bits(&in_parts(&master, &slave, &o, 4).b, &whole.b, "4 parts of 2 faces: B");
}

#[test]
fn parts_that_do_not_fit_are_refused() {
    let slave = patch(6, 6, Pattern::Quads, flat(1.0, 1.0));
    let master = patch(5, 5, Pattern::Triangles, flat(1.0, 1.0));
    let o = options(Multiplier::Dual);
    let tree = FaceTree::new(&master);
    let parts = split(&tree, &slave, &o, 3);
    let blocks: Vec<PartBlocks> =
        parts.iter().map(|p| PartJob::new(&master, &slave, &o, p).assemble()).collect();
    // A missing part, a part given twice.
    assert!(assemble_parts(
        &master,
        &tree,
        &slave,
        &o,
        blocks[..2].iter().map(|b| PartBlocks::from_bytes(&b.to_bytes()).unwrap()).collect()
    )
    .is_err());
    let twice: Vec<PartBlocks> =
        [0, 1, 2, 2].map(|p| PartBlocks::from_bytes(&blocks[p].to_bytes()).unwrap()).into();
    assert!(assemble_parts(&master, &tree, &slave, &o, twice).is_err());
    // Every truncation of the bytes is an error, never a panic.
    let job = PartJob::new(&master, &slave, &o, &parts[1]).to_bytes();
    let bytes = blocks[1].to_bytes();
    for cut in (0..job.len()).step_by(7) {
        assert!(PartJob::from_bytes(&job[..cut]).is_err());
    }
    for cut in (0..bytes.len()).step_by(7) {
        assert!(PartBlocks::from_bytes(&bytes[..cut]).is_err());
    }
    let mut corrupt = bytes.clone();
    corrupt[..8].copy_from_slice(&u64::MAX.to_le_bytes());
    assert!(PartBlocks::from_bytes(&corrupt).is_err(), "an array longer than the bytes");
    // A face beyond the slave surface.
    let mut beyond = bytes.clone();
    beyond[8..16].copy_from_slice(&u64::MAX.to_le_bytes());
    let beyond: Vec<PartBlocks> = [blocks[0].to_bytes(), beyond, blocks[2].to_bytes()]
        .iter()
        .map(|b| PartBlocks::from_bytes(b).unwrap())
        .collect();
    assert!(assemble_parts(&master, &tree, &slave, &o, beyond).is_err());
}
