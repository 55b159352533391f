//! Sparse solve benchmark: a Hex8 block n × n × n (3(n+1)³ dofs) clamped at
//! x = 0 and pulled at x = 1, solved by the direct solver with each ordering and
//! by preconditioned conjugate gradients.
//!
//! ```text
//! cargo run --release -p seam-fem --example solve_bench                       # default table
//! cargo run --release -p seam-fem --example solve_bench -- --sizes 21,30 --methods nd,pcg-block
//! ```
//!
//! Methods: `dof-amd`, `point-amd`, `nd` (direct), `pcg-jacobi`, `pcg-block`
//! (PCG, rtol 1e-8). Every row runs in a fresh process (`--row n method`), so
//! the peak memory (VmHWM) is its own.

mod common;

use common::{fresh_row, peak_mb};
use seam_fem::generate::{block, BlockKind, Grid, Side};
use seam_fem::pcg::{solve_pcg, PcgOptions, Preconditioner};
use seam_fem::solve::{solve_direct, DirectOptions, FillOrdering};
use seam_fem::{stiffness, traction, Dirichlet, Material};
use std::time::Instant;

/// User + system CPU seconds of this process so far.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let after = stat.rsplit(')').next().unwrap_or("");
    let fields: Vec<&str> = after.split_whitespace().collect();
    let ticks = |i: usize| fields.get(i).and_then(|t| t.parse::<f64>().ok()).unwrap_or(f64::NAN);
    // utime and stime are fields 14 and 15 of stat, 12 and 13 after the name.
    (ticks(11) + ticks(12)) / 100.0
}

fn row(n: usize, method: &str) {
    let material = Material::new(1000.0, 0.3).expect("valid material");
    let mesh = block(n, n, n, |u, v, w| [u, v, w], BlockKind::Hex);
    let grid = Grid::new(n, n, n);
    let k = stiffness(&mesh, &material).expect("valid mesh");
    let f = traction(&grid.side_faces(&mesh, Side::XMax).expect("side"), |_, _| [1.0, 0.2, 0.0]);
    let mut bc = Dirichlet::new();
    bc.clamp(grid.side_points(Side::XMin));
    let clock = Instant::now();
    let cpu = cpu_seconds();
    let (u, cols) = if let Some(pc) = method.strip_prefix("pcg-") {
        let preconditioner = match pc {
            "jacobi" => Preconditioner::Jacobi,
            "block" => Preconditioner::BlockJacobi,
            other => panic!("unknown preconditioner {other}"),
        };
        let options = PcgOptions { rtol: 1e-8, max_iter: 100_000, preconditioner };
        let (u, rep) = solve_pcg(&k, &f, &bc, &options).expect("pcg converges");
        (u, format!("| - | - | - | - | - | - | - | {} | {:.1e} |", rep.iterations, rep.relative_residual))
    } else {
        let ordering = match method {
            "dof-amd" => FillOrdering::DofAmd,
            "point-amd" => FillOrdering::PointAmd,
            "nd" => FillOrdering::NestedDissection,
            other => panic!("unknown method {other}"),
        };
        let (u, rep) = solve_direct(&k, &f, &bc, &DirectOptions { ordering }).expect("solvable");
        let cols = format!(
            "| {:.2} | {:.2} | {:.2} | {:.1} | {:.1} | {:.1} | {} | - | - |",
            rep.ordering_seconds + rep.symbolic_seconds,
            rep.numeric_seconds,
            rep.solve_seconds,
            rep.nnz_l as f64 / 1e6,
            rep.flops / 1e9,
            rep.flops / 1e9 / rep.numeric_seconds,
            rep.largest_supernode,
        );
        (u, cols)
    };
    let total = clock.elapsed().as_secs_f64();
    let cpu = cpu_seconds() - cpu;
    // The true residual on the free dofs, relative to ‖f‖.
    let ku = k.mul_vec(&u, 1);
    let fixed: std::collections::BTreeSet<usize> = bc.iter().map(|(d, _)| d).collect();
    let (mut r2, mut f2) = (0.0, 0.0);
    for i in 0..k.nrows {
        if !fixed.contains(&i) {
            r2 += (ku[i] - f[i]).powi(2);
            f2 += f[i] * f[i];
        }
    }
    let tip = u[3 * grid.point(n, n / 2, n / 2)];
    println!(
        "| {n} | {} | {method} {} {:.2} | {:.1} | {:.0} | {:.1e} | {tip:.9e} |",
        k.nrows - bc.len(),
        cols,
        total,
        cpu,
        peak_mb(),
        (r2 / f2).sqrt()
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let get = |name: &str| args.iter().position(|a| a == name).and_then(|i| args.get(i + 1)).cloned();
    if let Some(n) = get("--row") {
        let method = args.last().expect("method").clone();
        row(n.parse().expect("size"), &method);
        return;
    }
    let sizes: Vec<usize> = get("--sizes")
        .unwrap_or_else(|| "21,30,46".into())
        .split(',')
        .map(|s| s.parse().expect("size"))
        .collect();
    let methods = get("--methods").unwrap_or_else(|| "point-amd,nd,pcg-jacobi,pcg-block".into());
    println!(
        "| n | free dofs | method | order+symbolic s | numeric s | solve s | nnz(L) M | GFlop | GFlop/s | widest supernode | PCG its | PCG rel res | total s | CPU s | peak MB | rel residual | u_x tip |"
    );
    println!("|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for &n in &sizes {
        for method in methods.split(',') {
            match fresh_row(&[&n.to_string(), method]) {
                Ok(line) => println!("{line}"),
                Err(why) => println!("| {n} | - | {method} | failed: {why} |"),
            }
        }
    }
}
