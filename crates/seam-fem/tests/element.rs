//! Element geometry on distorted cells: quadrature volumes against the
//! divergence theorem, orientation, and the zero modes of element stiffnesses.

use crate::common;

use common::{distorted, hybrid, kind_name, KINDS};
use faer::{Mat, Side};
use seam::{triangle_rule, Cell, FaceElement, FaceKind, Point3, VolumeMesh};
use seam_fem::assembly::{element_stiffness, geometry};
use seam_fem::{cell_volumes, CellKind, Material};

/// |e| = ⅓ ∮ x·n dA over the cell's (outward) faces. On a bilinear face
/// x(ξ)·(∂x/∂ξ × ∂x/∂η) has degree 3, so the degree-3 triangle rule is exact.
fn divergence_volume(cell: &Cell, points: &[Point3]) -> f64 {
    let rule = triangle_rule(3).unwrap();
    let mut v = 0.0;
    for face in cell.faces() {
        let x: Vec<Point3> = face.nodes().iter().map(|&p| points[p]).collect();
        let e = match x.len() {
            3 => FaceElement { kind: FaceKind::Tri3, x: [x[0], x[1], x[2], x[2]] },
            _ => FaceElement { kind: FaceKind::Quad4, x: [x[0], x[1], x[2], x[3]] },
        };
        for t in e.reference_triangles() {
            let area = 0.5
                * ((t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[1][1] - t[0][1]) * (t[2][0] - t[0][0]))
                    .abs();
            for (p, w) in rule.points.iter().zip(rule.weights) {
                let xi = [
                    t[0][0] + p[0] * (t[1][0] - t[0][0]) + p[1] * (t[2][0] - t[0][0]),
                    t[0][1] + p[0] * (t[1][1] - t[0][1]) + p[1] * (t[2][1] - t[0][1]),
                ];
                let (a, b) = e.tangents(xi);
                let n = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
                let y = e.map(xi);
                v += w * area * (y[0] * n[0] + y[1] * n[1] + y[2] * n[2]) / 3.0;
            }
        }
    }
    v
}

fn check_volumes(mesh: &VolumeMesh, label: &str) {
    let volumes = cell_volumes(mesh).unwrap();
    for (c, cell) in mesh.cells().iter().enumerate() {
        let reference = divergence_volume(cell, mesh.points());
        assert!(
            (volumes[c] - reference).abs() <= 1e-13 * reference,
            "{label}: {} cell {c}: quadrature {} vs divergence theorem {reference}",
            kind_name(cell),
            volumes[c]
        );
    }
}

#[test]
fn quadrature_volume_equals_divergence_theorem_on_distorted_cells() {
    for kind in KINDS {
        // Non-affine cells: warped map plus random interior moves; hexes and
        // prisms are trilinear with warped faces, pyramids have warped bases.
        let (mesh, _) = distorted(kind, 3, 0.2);
        check_volumes(&mesh, &format!("{kind:?}"));
    }
    check_volumes(&hybrid(), "hybrid_pyramid");
}

#[test]
fn generated_cells_are_positively_oriented() {
    for kind in KINDS {
        let (mesh, _) = distorted(kind, 3, 0.2);
        for cell in mesh.cells() {
            let k = CellKind::of(cell);
            let x: Vec<Point3> = cell.nodes().iter().map(|&p| mesh.points()[p]).collect();
            for &xi in &k.stiffness_rule().points {
                assert!(geometry(k, &x, xi).unwrap().det > 0.0, "{kind:?}");
            }
        }
    }
}

/// Element stiffnesses are symmetric positive semi-definite with exactly the 6
/// rigid-body zero modes: no spurious (hourglass) modes from the quadrature.
#[test]
fn element_stiffness_has_exactly_six_zero_modes() {
    let m = Material::new(1.0, 0.3).unwrap();
    let mut cells: Vec<(CellKind, Vec<Point3>)> = Vec::new();
    for kind in KINDS {
        let (mesh, _) = distorted(kind, 2, 0.25);
        // A cell touching the moved interior point.
        let cell = mesh.cells().iter().find(|c| c.nodes().contains(&13)).unwrap();
        cells.push((CellKind::of(cell), cell.nodes().iter().map(|&p| mesh.points()[p]).collect()));
    }
    for (kind, x) in cells {
        let k = element_stiffness(kind, &x, &m).unwrap();
        let n = 3 * kind.n_nodes();
        for i in 0..n {
            for j in 0..n {
                assert_eq!(k[i * n + j].to_bits(), k[j * n + i].to_bits(), "{kind:?} not symmetric");
            }
        }
        let eig = Mat::from_fn(n, n, |i, j| k[i * n + j]).self_adjoint_eigenvalues(Side::Lower).unwrap();
        let top = eig[n - 1];
        let zero = eig.iter().filter(|&&e| e.abs() < 1e-10 * top).count();
        assert_eq!(zero, 6, "{kind:?}: eigenvalues {eig:?}");
        assert!(eig[6] > 1e-4 * top, "{kind:?}: smallest deformation mode {} vs {top}", eig[6]);
        assert!(eig[0] > -1e-12 * top, "{kind:?}: negative eigenvalue {}", eig[0]);
    }
}
