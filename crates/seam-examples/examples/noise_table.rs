//! The noise table (BENCHMARKS.md, the operator under coordinate noise): the covered area 1ᵀD1 (standard multipliers) of
//! surfaces whose coordinates carry Gaussian noise of size ε, worst of three
//! draws, against the noise-free value.
//!
//! ```text
//! cargo run --release -p seam-examples --example noise_table
//! ```
//!
//! Flat unit squares of quads (master | slave cells per side; the error
//! against the exact area 1), quads on a cylinder patch (radius 1, angle 1,
//! height 1) and Quad9 faces on it (the error against the noise-free
//! assembly, relative).

use seam::generate::{cylinder, flat, patch, quadratic_patch, Pattern};
use seam::{assemble, FaceKind, MortarOptions, SurfaceMesh};

/// SplitMix64 with Box–Muller: standard normal numbers.
struct Gauss(u64);

impl Gauss {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform().max(f64::MIN_POSITIVE), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// `mesh` with every coordinate moved by ε times a standard normal number.
fn noisy(mesh: &SurfaceMesh, eps: f64, gauss: &mut Gauss) -> SurfaceMesh {
    let (points, faces) = mesh.clone().into_parts();
    let points = points.into_iter().map(|x| x.map(|c| c + eps * gauss.normal())).collect();
    SurfaceMesh::new(points, faces).expect("a valid mesh")
}

fn covered(master: &SurfaceMesh, slave: &SurfaceMesh) -> f64 {
    assemble(master, slave, &MortarOptions::default()).expect("the surfaces overlap").d.sum()
}

const NOISE: [f64; 5] = [0.0, 1e-15, 1e-13, 1e-12, 1e-10];

fn main() {
    println!("| grids (master \\| slave) | ε = 0 | 1e-15 | 1e-13 | 1e-12 | 1e-10 |");
    println!("|---|---|---|---|---|---|");
    type Make = Box<dyn Fn(usize) -> SurfaceMesh>;
    let flat_quads: Make = Box::new(|n| patch(n, n, Pattern::Quads, flat(1.0, 1.0)));
    let cylinder_quads: Make = Box::new(|n| patch(n, n, Pattern::Quads, cylinder(1.0, 1.0, 1.0)));
    let cylinder_quad9: Make =
        Box::new(|n| quadratic_patch(n, n, FaceKind::Quad9, None, cylinder(1.0, 1.0, 1.0)));
    let rows: [(&str, &Make, usize, usize, bool); 8] = [
        ("flat quads 32 \\| 24", &flat_quads, 32, 24, true),
        ("flat quads 16 \\| 12", &flat_quads, 16, 12, true),
        ("flat quads 20 \\| 20 (matching)", &flat_quads, 20, 20, true),
        ("flat quads 30 \\| 20", &flat_quads, 30, 20, true),
        ("cylinder quads 16 \\| 16", &cylinder_quads, 16, 16, false),
        ("cylinder quads 16 \\| 12", &cylinder_quads, 16, 12, false),
        ("cylinder Quad9 8 \\| 8", &cylinder_quad9, 8, 8, false),
        ("cylinder Quad9 8 \\| 6", &cylinder_quad9, 8, 6, false),
    ];
    let mut gauss = Gauss(31);
    for (name, make, m, s, exact_area) in rows {
        let (master, slave) = (make(m), make(s));
        let reference = if exact_area { 1.0 } else { covered(&master, &slave) };
        let cells: Vec<String> = NOISE
            .iter()
            .map(|&eps| {
                let worst = (0..3)
                    .map(|_| {
                        let (m, s) = (noisy(&master, eps, &mut gauss), noisy(&slave, eps, &mut gauss));
                        ((covered(&m, &s) - reference) / reference).abs()
                    })
                    .fold(0.0f64, f64::max);
                format!("{worst:.1e}")
            })
            .collect();
        println!("| {name} | {} |", cells.join(" | "));
    }
}
