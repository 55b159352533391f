//! The tables checked against Gmsh's reference elements and against each
//! other, and the shape functions against their defining properties.

use super::*;
use crate::catalogue::faces::MONOMIALS;

/// Points of a face's reference cell (and a little outside) to test at.
pub(crate) fn samples(kind: FaceKind) -> Vec<Xi> {
    let mut out = Vec::new();
    for i in 0..=6 {
        for j in 0..=6 {
            let xi = [-0.1 + 1.2 * i as f64 / 6.0, -0.1 + 1.2 * j as f64 / 6.0];
            if kind.contains(xi, 0.1) {
                out.push(xi);
            }
        }
    }
    out
}

/// Points strictly inside each reference cell.
fn cell_samples(kind: CellKind) -> Vec<Xi3> {
    match kind.reference_shape() {
        Shape::Tetrahedron => vec![[0.1, 0.2, 0.3], [0.25, 0.25, 0.25], [0.6, 0.1, 0.05]],
        Shape::Hexahedron => vec![[0.1, -0.7, 0.3], [0.0; 3], [0.9, 0.8, -0.95]],
        Shape::Prism => vec![[0.1, 0.2, 0.3], [0.5, 0.3, -0.9], [0.2, 0.7, 0.6]],
        _ => vec![[0.1, -0.2, 0.3], [0.5, 0.3, 0.1], [-0.05, 0.02, 0.9]],
    }
}

/// Gmsh's reference nodes of the second-order types, as Gmsh reports them
/// (`gmsh.model.mesh.getElementProperties`, recorded by seam-io's fixture
/// script): (type number, nodes).
fn gmsh_reference_nodes() -> Vec<(u32, Vec<Vec<f64>>)> {
    let text = include_str!("../../../seam-io/tests/data/second_order.txt");
    text.lines()
        .filter_map(|l| l.strip_prefix("ref "))
        .map(|l| {
            let fields: Vec<&str> = l.split_whitespace().collect();
            let nodes =
                fields[2].split(';').map(|p| p.split(',').map(|c| c.parse().unwrap()).collect()).collect();
            (fields[0].parse().unwrap(), nodes)
        })
        .collect()
}

#[test]
fn nodes_are_gmsh_reference_nodes() {
    let recorded = gmsh_reference_nodes();
    assert_eq!(recorded.len(), 10, "the second-order types");
    for (gmsh_type, nodes) in recorded {
        if let Some(kind) = FaceKind::from_gmsh(gmsh_type) {
            // Gmsh's quads live on [−1,1]², seam's on [0,1]².
            let gmsh: Vec<Xi> =
                nodes
                    .iter()
                    .map(|c| {
                        if kind.is_triangle() {
                            [c[0], c[1]]
                        } else {
                            [(c[0] + 1.0) / 2.0, (c[1] + 1.0) / 2.0]
                        }
                    })
                    .collect();
            assert_eq!(gmsh, kind.nodes(), "{kind:?}");
        } else {
            let kind = CellKind::from_gmsh(gmsh_type).unwrap();
            let gmsh: Vec<Xi3> = nodes.iter().map(|c| [c[0], c[1], c[2]]).collect();
            assert_eq!(gmsh, kind.reference_nodes(), "{kind:?}");
        }
    }
}

#[test]
fn first_order_kinds_are_the_corners_of_their_second_order_ones() {
    for kind in FaceKind::ALL {
        let linear = kind.linear();
        assert_eq!(linear.order(), 1);
        assert_eq!(&kind.nodes()[..kind.n_corners()], linear.nodes(), "{kind:?}");
        assert_eq!(kind.info().edges, linear.info().edges);
        assert_eq!(kind.info().shape, linear.info().shape);
    }
    for kind in CellKind::ALL {
        let family = kind.family();
        assert_eq!(family.order(), 1);
        assert_eq!(&kind.reference_nodes()[..kind.n_corners()], family.reference_nodes(), "{kind:?}");
        assert_eq!(kind.info().edges, family.info().edges);
        for (face, linear) in kind.info().faces.iter().zip(family.info().faces) {
            assert_eq!(face.corners(), linear.nodes(), "{kind:?}");
            assert_eq!(face.kind.linear(), linear.kind);
        }
    }
}

fn mean<const D: usize>(points: impl Iterator<Item = [f64; D]>) -> [f64; D] {
    let (mut sum, mut n) = ([0.0; D], 0.0);
    for p in points {
        for k in 0..D {
            sum[k] += p[k];
        }
        n += 1.0;
    }
    sum.map(|s| s / n)
}

/// Mid-edge nodes are at the middle of their edges, face centres at the mean
/// of the face's corners, and every node is a corner, a mid-edge node, a face
/// centre or (Hex27) the cell centre: the supports say which.
#[test]
fn higher_order_nodes_sit_at_edge_midpoints_and_face_centres() {
    for kind in FaceKind::ALL.into_iter().filter(|k| k.order() == 2) {
        let (x, c) = (kind.nodes(), kind.n_corners());
        for (e, &[a, b]) in kind.info().edges.iter().enumerate() {
            assert_eq!(x[c + e], mean([x[a], x[b]].into_iter()), "{kind:?} edge {e}");
        }
        if kind.n_nodes() > 2 * c {
            assert_eq!(x[2 * c], mean(x[..c].iter().copied()), "{kind:?} centre");
        }
    }
    for kind in CellKind::ALL {
        let x = kind.reference_nodes();
        let supports = kind.node_supports();
        assert_eq!(supports.len(), kind.n_nodes());
        for (i, support) in supports.iter().enumerate() {
            assert_eq!(x[i], mean(support.iter().map(|&c| x[c])), "{kind:?} node {i}");
        }
        for face in kind.info().faces {
            let n = face.nodes();
            for (e, &[a, b]) in face.kind.info().edges.iter().enumerate().filter(|_| kind.order() == 2) {
                assert_eq!(x[n[face.kind.n_corners() + e]], mean([x[n[a]], x[n[b]]].into_iter()), "{kind:?}");
            }
        }
        let edges = kind.info().edges;
        assert!(
            edges.iter().all(|e| e[0] < e[1] && e[1] < kind.n_corners()),
            "{kind:?}: sorted corner pairs"
        );
    }
}

/// Every local face is outward: its normal (from its first three corners)
/// points away from the reference cell's centroid, and the faces of a
/// cell close up (their area vectors sum to zero).
#[test]
fn local_faces_are_outward_and_close_the_cell() {
    for kind in CellKind::ALL {
        let x = kind.reference_nodes();
        let centre = kind.centroid();
        let mut total = [0.0; 3];
        for face in kind.info().faces {
            let c: Vec<Xi3> = face.corners().iter().map(|&i| x[i]).collect();
            let a = crate::mesh::area_vector(&c);
            let out = crate::vec3::sub(mean(c.iter().copied()), centre);
            assert!(crate::vec3::dot(a, out) > 0.0, "{kind:?}: face {:?} points inward", face.nodes());
            total = [total[0] + a[0], total[1] + a[1], total[2] + a[2]];
        }
        assert!(total.iter().all(|t| t.abs() < 1e-14), "{kind:?}: {total:?}");
    }
}

#[test]
fn kinds_are_found_by_their_numbers() {
    for kind in FaceKind::ALL {
        let info = kind.info();
        if let Some(number) = info.gmsh_type {
            assert_eq!(FaceKind::from_gmsh(number), Some(kind));
        }
        assert_eq!(FaceKind::from_vtk(info.vtk_type), Some(kind));
        assert_eq!(FaceKind::with_nodes(kind.n_nodes()), Some(kind));
        assert_eq!(info.shape.dim(), 2);
        assert_eq!(format!("{kind:?}"), info.name);
    }
    for kind in CellKind::ALL {
        if let Some(number) = kind.info().gmsh_type {
            assert_eq!(CellKind::from_gmsh(number), Some(kind));
        }
        assert_eq!(kind.reference_shape().dim(), 3);
        assert_eq!(format!("{kind:?}"), kind.name());
    }
    assert_eq!(FaceKind::from_gmsh(4), None);
    assert_eq!(FaceKind::Tri7.info().gmsh_type, None, "Gmsh has no seven-node triangle");
    assert_eq!(CellKind::Tet14.info().gmsh_type, None, "nor a fourteen-node tetrahedron");
    assert_eq!(CellKind::from_gmsh(2), None);
    assert_eq!(CellKind::Hex8.second_order(true), Some(CellKind::Hex27));
    assert_eq!(CellKind::Pyramid5.second_order(false), Some(CellKind::Pyramid13));
    assert_eq!(CellKind::Tet4.second_order(false), Some(CellKind::Tet10));
    assert_eq!(CellKind::Tet10.second_order(true), None);
}

/// VTK's node orders are permutations (of all nodes but a Pyramid14's base
/// centre), with the corners first and in place; reversal is an involution.
#[test]
fn permutations_are_permutations() {
    let is_permutation = |p: &[usize], n: usize| {
        let mut sorted = p.to_vec();
        sorted.sort_unstable();
        sorted == (0..n).collect::<Vec<_>>()
    };
    for kind in FaceKind::ALL {
        let info = kind.info();
        assert!(is_permutation(info.vtk_order, kind.n_nodes()), "{kind:?}");
        assert!(is_permutation(info.reversed, kind.n_nodes()), "{kind:?}");
        let face = Face::new(kind, &(10..10 + kind.n_nodes()).collect::<Vec<_>>()).unwrap();
        assert_eq!(face.reversed().reversed(), face);
        let pieces: Vec<usize> = info.pieces.iter().flat_map(|p| p.iter().copied()).collect();
        assert!((0..kind.n_nodes()).all(|i| pieces.contains(&i)), "{kind:?}: every node drawn");
    }
    for kind in CellKind::ALL {
        let order = kind.info().vtk_order;
        // VTK has no 14-node pyramid or tetrahedron: they are written with 13 and 10 nodes.
        let n = match kind {
            CellKind::Pyramid14 => 13,
            CellKind::Tet14 => 10,
            _ => kind.n_nodes(),
        };
        assert!(is_permutation(order, n), "{kind:?}");
        assert_eq!(&order[..kind.n_corners()], (0..kind.n_corners()).collect::<Vec<_>>());
    }
}

#[test]
fn elements_carry_their_kind() {
    for kind in FaceKind::ALL {
        let nodes: Vec<usize> = (0..kind.n_nodes()).collect();
        let face = Face::from_nodes(&nodes);
        assert_eq!((face.kind(), face.nodes(), face.len()), (kind, &nodes[..], kind.n_nodes()));
        assert_eq!(Face::new(kind, &nodes[1..]), None);
        assert_eq!(face.to_string(), format!("{}{nodes:?}", kind.name()));
    }
    for kind in CellKind::ALL {
        let nodes: Vec<usize> = (0..kind.n_nodes()).collect();
        let cell = kind.cell(&nodes).unwrap();
        assert_eq!((cell.kind(), cell.nodes()), (kind, &nodes[..]));
        assert_eq!(cell.is_second_order(), kind.order() == 2);
        assert_eq!(cell.faces().count(), kind.info().faces.len());
    }
}

#[test]
fn face_shape_functions_are_a_partition_of_unity_and_nodal() {
    for kind in FaceKind::ALL {
        for xi in samples(kind) {
            let (n, g) = shape_and_gradients(kind, xi);
            assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14, "{kind:?} {xi:?}");
            for k in 0..2 {
                assert!(g.iter().map(|g| g[k]).sum::<f64>().abs() < 1e-13, "{kind:?} {xi:?}");
            }
        }
        for (i, &node) in kind.nodes().iter().enumerate() {
            let (n, _) = shape_and_gradients(kind, node);
            for (j, &v) in n.iter().enumerate().take(kind.n_nodes()) {
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!((v - expected).abs() < 1e-15, "{kind:?}: N_{j}(node {i}) = {v}");
            }
        }
    }
}

#[test]
fn face_gradients_match_finite_differences() {
    let h = 1e-6;
    for kind in FaceKind::ALL {
        for xi in samples(kind) {
            let (_, g) = shape_and_gradients(kind, xi);
            for k in 0..2 {
                let (mut a, mut b) = (xi, xi);
                a[k] += h;
                b[k] -= h;
                let (na, nb) = (shape_and_gradients(kind, a).0, shape_and_gradients(kind, b).0);
                for i in 0..MAX_FACE_NODES {
                    let fd = (na[i] - nb[i]) / (2.0 * h);
                    assert!(
                        (g[i][k] - fd).abs() < 1e-8,
                        "{kind:?} {xi:?} ∂N_{i}/∂ξ_{k}: {} vs {fd}",
                        g[i][k]
                    );
                }
            }
        }
    }
}

#[test]
fn quadratic_fields_are_reproduced_on_faces() {
    // Every quadratic monomial (and, for the quads, ξ²η and ξη²; Quad9 also ξ²η²).
    type Field = fn(f64, f64) -> f64;
    let kinds = [FaceKind::Tri6, FaceKind::Quad8, FaceKind::Quad9];
    let fields: [(Field, [bool; 3]); 9] = [
        (|_, _| 1.0, [true; 3]),
        (|s, _| s, [true; 3]),
        (|_, t| t, [true; 3]),
        (|s, _| s * s, [true; 3]),
        (|s, t| s * t, [true; 3]),
        (|_, t| t * t, [true; 3]),
        (|s, t| s * s * t, [false, true, true]),
        (|s, t| s * t * t, [false, true, true]),
        (|s, t| s * s * t * t, [false, false, true]),
    ];
    for (f, exact_for) in fields {
        for (k, kind) in kinds.into_iter().enumerate().filter(|&(k, _)| exact_for[k]) {
            let values: Vec<f64> = kind.nodes().iter().map(|x| f(x[0], x[1])).collect();
            for xi in samples(kind) {
                let (n, _) = shape_and_gradients(kind, xi);
                let interpolated: f64 = values.iter().zip(&n).map(|(v, n)| v * n).sum();
                assert!((interpolated - f(xi[0], xi[1])).abs() < 1e-14, "{kind:?} field {k} at {xi:?}");
            }
        }
    }
}

/// The monomial tables are the shape functions, and use only the first
/// `n_monomials` monomials; `shape_values` agrees with `shape_and_gradients`.
#[test]
fn monomial_tables_and_sized_values_are_the_shape_functions() {
    for kind in FaceKind::ALL {
        let info = kind.info();
        for xi in samples(kind) {
            let [s, t] = xi;
            let m = [1.0, s, t, s * s, s * t, t * t, s * s * t, s * t * t, s * s * t * t];
            let n = shape_and_gradients(kind, xi).0;
            for (i, row) in info.monomials.iter().enumerate() {
                let v: f64 = row.iter().zip(m).map(|(c, m)| c * m).sum();
                assert!((v - n[i]).abs() < 1e-14, "{kind:?} N_{i} at {xi:?}");
                assert!(row[info.n_monomials..MONOMIALS].iter().all(|&c| c == 0.0), "{kind:?}");
            }
            let sized: Vec<f64> = match kind.n_nodes() {
                3 => shape_values::<3>(xi).to_vec(),
                4 => shape_values::<4>(xi).to_vec(),
                6 => shape_values::<6>(xi).to_vec(),
                7 => shape_values::<7>(xi).to_vec(),
                8 => shape_values::<8>(xi).to_vec(),
                _ => shape_values::<9>(xi).to_vec(),
            };
            assert_eq!(sized, n[..kind.n_nodes()], "{kind:?}");
        }
    }
}

/// ∫ N_i over the reference cell by a degree-4 rule, against
/// [`FaceType::positive_integrals`].
#[test]
fn positive_integrals_are_what_the_tables_say() {
    let rule = crate::triangle_rule(4).unwrap();
    for kind in FaceKind::ALL {
        let mut integral = [0.0; MAX_FACE_NODES];
        for t in kind.reference_triangles() {
            for (p, w) in rule.points.iter().zip(rule.weights) {
                let xi = [0, 1].map(|k| t[0][k] + p[0] * (t[1][k] - t[0][k]) + p[1] * (t[2][k] - t[0][k]));
                let n = shape_and_gradients(kind, xi).0;
                for i in 0..kind.n_nodes() {
                    integral[i] += w * n[i];
                }
            }
        }
        let positive = integral[..kind.n_nodes()].iter().all(|&v| v > 1e-12);
        assert_eq!(positive, kind.info().positive_integrals, "{kind:?}: {integral:?}");
    }
}

#[test]
fn cell_shape_functions_are_a_partition_of_unity_and_linearly_complete() {
    for kind in CellKind::ALL {
        // First order: closed forms, exact to 1e-14. Second order: bases
        // from an inverted 10–27-term interpolation matrix, whose round-off
        // is larger (values 1e-13, gradients 1e-12).
        let (tol, gtol) = if kind.order() == 1 { (1e-14, 1e-14) } else { (1e-13, 1e-12) };
        for xi in cell_samples(kind) {
            let n = kind.shape(xi);
            assert!((n.iter().sum::<f64>() - 1.0).abs() < tol, "{kind:?} at {xi:?}");
            let g = kind.gradients(xi);
            for k in 0..3 {
                let s: f64 = g.iter().map(|gi| gi[k]).sum();
                assert!(s.abs() < gtol, "{kind:?} at {xi:?}: Σ ∂N/∂ξ_{k} = {s}");
            }
            // Linear completeness: Σ N_i ξ_i = ξ, Σ ξ_i ⊗ ∇N_i = I.
            let nodes = kind.reference_nodes();
            for k in 0..3 {
                let s: f64 = nodes.iter().zip(&n).map(|(p, n)| p[k] * n).sum();
                assert!((s - xi[k]).abs() < tol, "{kind:?}: Σ N_i ξ_i ≠ ξ");
                for l in 0..3 {
                    let s: f64 = nodes.iter().zip(&g).map(|(p, g)| p[k] * g[l]).sum();
                    assert!((s - (k == l) as u8 as f64).abs() < gtol, "{kind:?}: Σ ξ_i ∇N_i ≠ I");
                }
            }
        }
    }
}

#[test]
fn cell_shape_functions_interpolate_at_the_nodes() {
    for kind in CellKind::ALL {
        for (j, &p) in kind.reference_nodes().iter().enumerate() {
            let n = kind.shape(p);
            for (i, &v) in n[..kind.n_nodes()].iter().enumerate() {
                let expected = if i == j { 1.0 } else { 0.0 };
                // First-order kinds are closed forms; second-order ones go through V⁻¹.
                let tol = if kind.order() == 1 { 1e-15 } else { 1e-13 };
                assert!((v - expected).abs() < tol, "{kind:?}: N_{i}(node {j}) = {v}");
            }
        }
    }
}

#[test]
fn cell_gradients_match_finite_differences() {
    let h = 1e-6;
    for kind in CellKind::ALL {
        for xi in cell_samples(kind) {
            let g = kind.gradients(xi);
            for k in 0..3 {
                let (mut a, mut b) = (xi, xi);
                a[k] += h;
                b[k] -= h;
                let (na, nb) = (kind.shape(a), kind.shape(b));
                for i in 0..kind.n_nodes() {
                    let fd = (na[i] - nb[i]) / (2.0 * h);
                    assert!(
                        (fd - g[i][k]).abs() < 1e-8,
                        "{kind:?} N_{i} ∂_{k} at {xi:?}: {fd} vs {}",
                        g[i][k]
                    );
                }
            }
        }
    }
}

/// Conformity: on each local face, a cell's shape functions are the face
/// kind's functions of the face's nodes and the others vanish (the face's
/// reference cell mapped onto the cell's through its nodes' positions).
#[test]
fn cell_functions_on_a_face_are_the_face_functions() {
    for kind in CellKind::ALL {
        let nodes = kind.reference_nodes();
        for face in kind.info().faces {
            let on_face = face.nodes();
            for xi in samples(face.kind).into_iter().filter(|&xi| face.kind.contains(xi, 0.0)) {
                let phi = face.kind.shape_and_gradients(xi).0;
                let x: Xi3 =
                    std::array::from_fn(|k| on_face.iter().zip(&phi).map(|(&i, p)| p * nodes[i][k]).sum());
                let n = kind.shape(x);
                for j in 0..kind.n_nodes() {
                    let expected = on_face.iter().position(|&i| i == j).map_or(0.0, |p| phi[p]);
                    assert!((n[j] - expected).abs() < 1e-12, "{kind:?} face {on_face:?} at {xi:?}: N_{j}");
                }
            }
        }
    }
}
