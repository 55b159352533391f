//! The backend's general (nonsymmetric) solve against a manufactured
//! solution, with Dirichlet values, and its refusals.

use seam::CsrMatrix;
use seam_fem::pcg::PcgOptions;
use seam_fem::petsc::PetscSummary;
use seam_fem::{Dirichlet, SolveError, Solver};

/// A x = b of 3·`points` unknowns: 1D convection–diffusion per component,
/// tridiag(−1 − c, 2 + s, −1 + c) (not symmetric for c ≠ 0, regular for
/// |c| ≤ 1), the three components coupled by a small skew term, and b made
/// from the manufactured x (a smooth function with a kink).
fn convection_diffusion(points: usize, c: f64) -> (CsrMatrix, Vec<f64>) {
    let n = 3 * points;
    let mut a = CsrMatrix::zeros(0, n);
    for i in 0..n {
        let (p, k) = (i / 3, i % 3);
        let mut row: Vec<(usize, f64)> = vec![(i, 2.0 + 0.1 * k as f64)];
        if p > 0 {
            row.push((i - 3, -1.0 - c));
        }
        if p + 1 < points {
            row.push((i + 3, -1.0 + c));
        }
        // Component coupling 0.2·(e_{k+1} − e_{k−1}): skew, so not symmetric.
        row.push((3 * p + (k + 1) % 3, 0.2));
        row.push((3 * p + (k + 2) % 3, -0.2));
        row.sort_unstable_by_key(|e| e.0);
        a.indices.extend(row.iter().map(|e| e.0));
        a.values.extend(row.iter().map(|e| e.1));
        a.indptr.push(a.indices.len());
        a.nrows += 1;
    }
    let x = (0..n).map(|i| (i as f64 * 0.37).sin() + (i as f64 / n as f64 - 0.5).abs()).collect();
    (a, x)
}

/// max |x − x*| / max |x*|.
fn error(x: &[f64], exact: &[f64]) -> f64 {
    let scale = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    x.iter().zip(exact).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / scale
}

/// The system with the first and last points' values prescribed (their
/// columns go to the right-hand side) and b = A x* on the free rows.
fn with_ends(points: usize, c: f64) -> (CsrMatrix, Vec<f64>, Dirichlet, Vec<f64>) {
    let (a, exact) = convection_diffusion(points, c);
    let b = a.mul_vec(&exact, 1);
    let mut fixed = Dirichlet::new();
    for dof in (0..3).chain(3 * points - 3..3 * points) {
        fixed.fix_dof(dof, exact[dof]);
    }
    (a, b, fixed, exact)
}

#[test]
fn sparse_lu_recovers_the_manufactured_solution() {
    for c in [0.0, 0.5, 0.99] {
        let (a, b, fixed, exact) = with_ends(400, c);
        let (x, iterations) =
            Solver::Direct.solve_general(&a, &b, &fixed, (None, &[]), &mut PetscSummary::default()).unwrap();
        let e = error(&x, &exact);
        assert!(e <= 1e-12, "c = {c}: error {e:.2e}");
        assert_eq!(iterations, 0);
        for (dof, v) in fixed.iter() {
            assert_eq!(x[dof], v, "prescribed dof {dof}");
        }
    }
}

#[test]
fn symmetric_systems_give_the_cholesky_answer() {
    let (a, b, fixed, _) = with_ends(200, 0.0);
    // c = 0 leaves only the skew coupling: drop it for a symmetric A.
    let mut s = a.clone();
    for i in 0..s.nrows {
        for k in s.indptr[i]..s.indptr[i + 1] {
            if s.indices[k] / 3 == i / 3 && s.indices[k] != i {
                s.values[k] = 0.0;
            }
        }
    }
    let mut summary = PetscSummary::default();
    let (lu, _) = Solver::Direct.solve_general(&s, &b, &fixed, (None, &[]), &mut summary).unwrap();
    let (cholesky, _) = Solver::Direct
        .solve_spd(std::borrow::Cow::Borrowed(&s), &b, &fixed, (None, &[]), &mut summary)
        .unwrap();
    let e = error(&lu, &cholesky);
    assert!(e <= 1e-12, "LU and Cholesky differ by {e:.2e}");
}

#[test]
fn pcg_refuses_a_general_system_and_lu_a_singular_one() {
    let (a, b, fixed, _) = with_ends(20, 0.5);
    let pcg = Solver::Pcg(PcgOptions::default());
    let refused = pcg.solve_general(&a, &b, &fixed, (None, &[]), &mut PetscSummary::default());
    assert_eq!(refused.unwrap_err(), SolveError::NotSymmetric);
    assert!(SolveError::NotSymmetric.to_string().contains("use solver `direct` or `petsc`"));

    // Two equal rows: singular on the free dofs.
    let mut singular = a.clone();
    let (lo, hi) = (singular.indptr[30], singular.indptr[31]);
    let row_30: Vec<(usize, f64)> = (lo..hi).map(|k| (singular.indices[k], singular.values[k])).collect();
    let (lo, hi) = (singular.indptr[33], singular.indptr[34]);
    assert_eq!(hi - lo, row_30.len());
    for (k, (j, v)) in (lo..hi).zip(row_30) {
        singular.indices[k] = j;
        singular.values[k] = v;
    }
    let failed =
        Solver::Direct.solve_general(&singular, &b, &fixed, (None, &[]), &mut PetscSummary::default());
    assert_eq!(failed.unwrap_err(), SolveError::Singular);
}

#[cfg(feature = "petsc")]
#[test]
fn petsc_fgmres_recovers_the_manufactured_solution_from_a_warm_start() {
    use seam_fem::petsc::{initialize_petsc, PetscOptions};
    initialize_petsc("").expect("PETSc starts");
    let petsc = Solver::Petsc(PetscOptions { rtol: 1e-12, ..PetscOptions::default() });
    let (a, b, fixed, exact) = with_ends(400, 0.5);
    let mut summary = PetscSummary::default();
    let (x, cold) = petsc.solve_general(&a, &b, &fixed, (None, &[]), &mut summary).unwrap();
    let e = error(&x, &exact);
    assert!(e <= 1e-9, "error {e:.2e}");
    assert_eq!((&summary.ksp_type[..], &summary.pc_type[..]), ("fgmres", "bjacobi"));
    let (again, warm) = petsc.solve_general(&a, &b, &fixed, (Some(&x), &[]), &mut summary).unwrap();
    assert!(error(&again, &exact) <= 1e-9);
    assert!(warm < cold, "a warm start from the solution: {warm} iterations, cold {cold}");
}
