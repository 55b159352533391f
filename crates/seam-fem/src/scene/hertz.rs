//! Hertz contact: an elastic indenter with a spherical face pressed on an
//! elastic block, force-controlled, against the analytic solution.

use super::block_body;
use crate::generate::{block, node_supports, raise_order, BlockKind, Grid, RaiseError, Side};
use crate::material::Material;
use crate::multibody::Coupling;
use crate::problem::{Load, Problem, ProblemBody, ProblemInterface, Support, SurfaceId};
use seam::CellKind;
use seam::{Facing, MaxGap, MeshError, MortarOptions, Multiplier, Point3, VolumeMesh};

/// Parameters of [`hertz`]. Lengths in units of the sphere radius R.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hertz {
    /// R.
    pub radius: f64,
    /// The analytic contact radius a; the force is F = 4E*a³/(3R).
    pub contact_radius: f64,
    /// Slave (block) cells across the fine zone [0, `fine_zone` a] of each
    /// symmetry axis: the slave element size near the contact is
    /// `fine_zone` a / `fine_cells`.
    pub fine_cells: usize,
    /// The fine zone's extent in units of a (both meshes, and the depth).
    pub fine_zone: f64,
    /// The largest ratio (> 1) of neighbouring cell sizes outside the fine
    /// zone, where the cells grow geometrically to the bodies' sides.
    pub grading: f64,
    /// Contact pairs are kept up to the gap `max_gap` a (the approach is
    /// a²/R: every point that can close is a contact point while this
    /// exceeds a/R).
    pub max_gap: f64,
    /// Master (indenter) cells across its fine zone, relative to the slave's
    /// (non-matching meshes).
    pub master_ratio: f64,
    /// The indenter's material.
    pub indenter: Material,
    /// The block's material.
    pub block: Material,
    /// The multiplier (lumped or dual; lumped is refused on the Tri6 faces
    /// of second-order tetrahedra).
    pub multiplier: Multiplier,
    /// The cells of both bodies: [`BlockKind::Hex`] or [`BlockKind::Tet`]
    /// (six per grid cell).
    pub cells: BlockKind,
    /// Second-order cells: Hex27 or Tet10, every new node of the indenter
    /// placed by its map (so the nodes of its spherical face lie on the
    /// sphere).
    pub second_order: bool,
    /// How both bodies are meshed about the pole: tensor grids or rings.
    pub layout: Layout,
    /// The indenter's spherical face is the slave side (the pressure lives on
    /// the curved face, whose nodal normals approximate the sphere's) instead
    /// of the block's flat top; `fine_cells` still counts the block's cells.
    pub curved_slave: bool,
}

impl Default for Hertz {
    /// R = 1, a = 0.08 R, 8 slave cells across 1.5a, the master 1.3× finer,
    /// cells growing by at most 1.25× outside, pairs kept up to the gap a;
    /// indenter E = 2000, ν = 0.3 on a block E = 1000, ν = 0.25; lumped D;
    /// first-order hexahedra.
    fn default() -> Self {
        Hertz {
            radius: 1.0,
            contact_radius: 0.08,
            fine_cells: 8,
            fine_zone: 1.5,
            grading: 1.25,
            max_gap: 1.0,
            master_ratio: 1.3,
            indenter: Material::new(2000.0, 0.3).expect("valid constants"),
            block: Material::new(1000.0, 0.25).expect("valid constants"),
            multiplier: Multiplier::Lumped,
            cells: BlockKind::Hex,
            second_order: false,
            layout: Layout::Tensor,
            curved_slave: false,
        }
    }
}

/// How [`hertz`]'s bodies are meshed about the pole.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// Tensor grids: `fine_cells` equal cells across the fine zone
    /// [0, `fine_zone` a] in x, y and the depth, growing beyond.
    Tensor,
    /// O-grids of hexahedra: rings about the pole, `fine_cells` radial cells
    /// across the band [`fine_zone` a/2, `fine_zone` a], where the contact's
    /// rim and stick–slip circle lie, and about 3 `fine_cells` sectors over
    /// the half plane, the contact radius a midway between two rings. They
    /// refine the radius without the angle. First- or second-order
    /// hexahedra only.
    Rings,
}

impl Hertz {
    /// 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂.
    pub fn effective_modulus(&self) -> f64 {
        let compliance = |m: &Material| (1.0 - m.poisson().powi(2)) / m.young();
        1.0 / (compliance(&self.indenter) + compliance(&self.block))
    }

    /// The total force F = 4E*a³/(3R) (a³ = 3FR/(4E*)); the quarter model
    /// carries F/4.
    pub fn force(&self) -> f64 {
        4.0 * self.effective_modulus() * self.contact_radius.powi(3) / (3.0 * self.radius)
    }

    /// The peak pressure p₀ = 3F/(2πa²).
    pub fn peak_pressure(&self) -> f64 {
        3.0 * self.force() / (2.0 * std::f64::consts::PI * self.contact_radius.powi(2))
    }

    /// Hertz's pressure p(r) = p₀ √(1 − r²/a²) (zero beyond a).
    pub fn pressure(&self, r: f64) -> f64 {
        let s = 1.0 - (r / self.contact_radius).powi(2);
        if s > 0.0 {
            self.peak_pressure() * s.sqrt()
        } else {
            0.0
        }
    }

    /// The block's half-width and depth, W = H = 12.5a (≥ 10a).
    pub fn block_size(&self) -> f64 {
        12.5 * self.contact_radius
    }

    /// The indenter's half-width L = R/2 and height 0.6R above the pole.
    pub(super) fn indenter_size(&self) -> (f64, f64) {
        (0.5 * self.radius, 0.6 * self.radius)
    }

    /// The slave element size in the fine zone: `fine_zone` a /
    /// `fine_cells` for tensor grids, the radial spacing `fine_zone` a /
    /// (2 `fine_cells`) in the band of rings.
    pub fn slave_size(&self) -> f64 {
        let across = match self.layout {
            Layout::Tensor => 1.0,
            Layout::Rings => 0.5,
        };
        across * self.fine_zone * self.contact_radius / self.fine_cells as f64
    }

    /// The extent of the fine zone, `fine_zone` a.
    fn fine_length(&self) -> f64 {
        self.fine_zone * self.contact_radius
    }

    /// The indenter's spherical face, z = R − √(R² − x² − y²).
    pub fn sphere(&self, x: f64, y: f64) -> f64 {
        self.radius - (self.radius.powi(2) - x * x - y * y).sqrt()
    }
}

/// Grid coordinates on [0, length]: `fine` equal cells of size h on
/// [0, fine_len], then cells growing geometrically from h to fill the rest
/// (the ratio chosen so the sizes never shrink and grow at most `ratio`×).
pub(super) fn graded(length: f64, (fine_len, fine): (f64, usize), ratio: f64) -> Vec<f64> {
    let h = fine_len / fine as f64;
    let mut x: Vec<f64> = (0..=fine).map(|i| i as f64 * h).collect();
    let rest = length - fine_len;
    // The fewest cells k with ratio q ≤ `ratio`: h (q^k − 1)/(q − 1) = rest.
    let k = ((1.0 + rest * (ratio - 1.0) / h).ln() / ratio.ln()).ceil().max(1.0) as usize;
    let sum = |q: f64| h * (1..=k).map(|i| q.powi(i as i32)).sum::<f64>();
    let (mut lo, mut hi) = (1.0, ratio);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if sum(mid) < rest {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let q = 0.5 * (lo + hi);
    let mut step = h;
    for _ in 0..k {
        step *= q;
        x.push(x.last().unwrap() + step);
    }
    *x.last_mut().unwrap() = length;
    x
}

/// A structured block of `kind` cells on the tensor grid `xs × ys × ws`
/// (ws on [0, 1]), each grid point mapped by `map(x, y, w)`; of second order
/// when `second_order`, every new node mapped from the mean of its supporting
/// corners' (x, y, w) (`unmap` gives a corner's), so that it lies on the
/// mapped block (on the sphere, for the indenter's face).
fn tensor_block(
    [xs, ys, ws]: [&[f64]; 3],
    (kind, second_order): (BlockKind, bool),
    map: impl Fn(f64, f64, f64) -> Point3,
    unmap: impl Fn(Point3) -> Point3,
) -> Result<(VolumeMesh, Grid), MeshError> {
    let (nx, ny, nz) = (xs.len() - 1, ys.len() - 1, ws.len() - 1);
    let at = |coords: &[f64], t: f64, cells: usize| coords[(t * cells as f64).round() as usize];
    let mesh = block(nx, ny, nz, |u, v, w| map(at(xs, u, nx), at(ys, v, ny), at(ws, w, nz)), kind);
    let mesh = if second_order { raise_mapped(&mesh, |x| map(x[0], x[1], x[2]), unmap)? } else { mesh };
    Ok((mesh, Grid::new(nx, ny, nz)))
}

/// `mesh` raised to second order (complete cells) with each new node at
/// `map` of the mean of `unmap` over its supporting corners.
pub(super) fn raise_mapped(
    mesh: &VolumeMesh,
    map: impl Fn(Point3) -> Point3,
    unmap: impl Fn(Point3) -> Point3,
) -> Result<VolumeMesh, MeshError> {
    let raised = match raise_order(mesh, true) {
        Ok(raised) => raised,
        Err(RaiseError::Mesh(e)) => return Err(e),
        Err(e @ RaiseError::SecondOrder { .. }) => unreachable!("blocks are of first order: {e}"),
    };
    let first = mesh.points().len();
    let corners: Vec<Point3> = mesh.points().iter().map(|&x| unmap(x)).collect();
    let mut points = raised.points().to_vec();
    let mut placed = vec![false; points.len()];
    for cell in raised.cells() {
        let kind = CellKind::of(cell);
        let nodes = cell.nodes();
        for (i, support) in node_supports(kind).iter().enumerate().filter(|&(i, _)| nodes[i] >= first) {
            if !std::mem::replace(&mut placed[nodes[i]], true) {
                let mean = std::array::from_fn(|k| {
                    support.iter().map(|&c| corners[nodes[c]][k]).sum::<f64>() / support.len() as f64
                });
                points[nodes[i]] = map(mean);
            }
        }
    }
    VolumeMesh::new(points, raised.cells().to_vec())
}

/// The named sides of a quarter-model body: bottom, top, and the symmetry
/// planes x0 (x = 0) and y0 (y = 0).
const SIDES: [(&str, Side); 4] =
    [("bottom", Side::ZMin), ("top", Side::ZMax), ("x0", Side::XMin), ("y0", Side::YMin)];

/// The named sides of a half-model body: bottom, top and the symmetry plane
/// y0 (y = 0).
const HALF_SIDES: [(&str, Side); 3] = [("bottom", Side::ZMin), ("top", Side::ZMax), ("y0", Side::YMin)];

/// The Hertz problem, a quarter model (symmetry planes x = 0 and y = 0):
///
/// - body "indenter" (master, surfaces "bottom" = the sphere
///   z = R − √(R² − x² − y²), "top" at z = 0.6R, "x0", "y0") over
///   [0, R/2]², loaded on top by the uniform traction −F/(4 (R/2)²) e₃ and held
///   only by the contact (and the symmetry planes);
/// - body "block" (slave, "top" at z = 0, "bottom" at z = −W, "x0", "y0") over
///   [0, W]² × [−W, 0], W = 12.5a, clamped at the bottom;
/// - both meshed with hexahedra or tetrahedra (`cells`), of first or second
///   order, uniform on [0, 1.5a] in x, y and z near the pole and
///   geometrically coarser beyond; the meshes do not match.
///
/// The block's top is the slave side: its normals are exact, and the contact
/// pressure lives on it (the indenter's face with [`Hertz::curved_slave`]).
///
/// # Errors
/// [`MeshError`] only for degenerate parameters.
pub fn hertz(p: &Hertz) -> Result<Problem, MeshError> {
    let bodies = bodies(p, false)?;
    let (bottom, x0, y0) = (0, 2, 3);
    let (indenter, slab) = (0, 1);
    let mut supports = vec![Support::new(id(slab, bottom), [Some(0.0); 3])];
    for body in [indenter, slab] {
        supports.push(Support::new(id(body, x0), [Some(0.0), None, None]));
        supports.push(Support::new(id(body, y0), [None, Some(0.0), None]));
    }
    let (l, _) = p.indenter_size();
    let pressure = p.force() / (4.0 * l * l);
    Ok(Problem {
        bodies,
        interfaces: vec![contact(p)],
        supports,
        loads: vec![Load::new(id(indenter, TOP), [0.0, 0.0, -pressure])],
        ..Problem::default()
    })
}

/// The surface `surface` of body `body`.
pub(super) fn id(body: usize, surface: usize) -> SurfaceId {
    SurfaceId { body, surface }
}

/// The index of the surface "top" in [`SIDES`].
pub(super) const TOP: usize = 1;

/// The bodies "indenter" and "block" of [`hertz`] with the surfaces of
/// [`SIDES`] over the quarter [0, ·]², or with `half` those of
/// [`HALF_SIDES`] over the half [−·, ·] × [0, ·] (the grid mirrored at
/// x = 0).
pub(super) fn bodies(p: &Hertz, half: bool) -> Result<Vec<ProblemBody>, MeshError> {
    if p.layout == Layout::Rings {
        return super::polar::ring_bodies(p, half);
    }
    let w = p.block_size();
    let mirrored = |y: Vec<f64>| -> Vec<f64> {
        if half {
            y.iter().rev().map(|v| -v).chain(y[1..].iter().copied()).collect()
        } else {
            y
        }
    };
    let fine = p.fine_length();
    let ys = graded(w, (fine, p.fine_cells), p.grading);
    let xs = mirrored(ys.clone());
    let depth: Vec<f64> = ys.iter().rev().map(|z| 1.0 - z / w).collect();
    let cells = (p.cells, p.second_order);
    let (slab, slab_grid) = tensor_block(
        [&xs, &ys, &depth],
        cells,
        |x, y, t| [x, y, -w * (1.0 - t)],
        |x| [x[0], x[1], 1.0 + x[2] / w],
    )?;

    let (l, h) = p.indenter_size();
    let master = (fine, ((p.fine_cells as f64) * p.master_ratio).round() as usize);
    let ym = graded(l, master, p.grading);
    let xm = mirrored(ym.clone());
    let up: Vec<f64> = graded(h, master, p.grading).iter().map(|z| z / h).collect();
    let (ball, ball_grid) = tensor_block(
        [&xm, &ym, &up],
        cells,
        |x, y, t| {
            let z = p.sphere(x, y);
            [x, y, z + (h - z) * t]
        },
        |x| {
            let z = p.sphere(x[0], x[1]);
            [x[0], x[1], (x[2] - z) / (h - z)]
        },
    )?;
    let sides: &[(&str, Side)] = if half { &HALF_SIDES } else { &SIDES };
    Ok(vec![
        block_body("indenter", ball, &ball_grid, p.indenter, sides)?,
        block_body("block", slab, &slab_grid, p.block, sides)?,
    ])
}

/// The frictionless contact interface of [`hertz`] between the bodies of
/// [`bodies`].
pub(super) fn contact(p: &Hertz) -> ProblemInterface {
    let (indenter, slab, bottom) = (0, 1, 0);
    let options = MortarOptions {
        multiplier: p.multiplier,
        facing: Facing::Opposite,
        max_gap: MaxGap::Absolute(p.max_gap * p.contact_radius),
        ..MortarOptions::default()
    };
    ProblemInterface {
        master: if p.curved_slave { id(slab, TOP) } else { id(indenter, bottom) },
        slave: if p.curved_slave { id(indenter, bottom) } else { id(slab, TOP) },
        options,
        kind: Coupling::Contact,
        friction: 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn graded_coordinates_are_uniform_then_growing() {
        let x = graded(1.0, (0.12, 8), 1.25);
        assert_eq!(x[0], 0.0);
        assert_eq!(*x.last().unwrap(), 1.0);
        let h: Vec<f64> = x.windows(2).map(|s| s[1] - s[0]).collect();
        assert!(h[..8].iter().all(|&d| (d - 0.015).abs() < 1e-15));
        assert!(h.windows(2).all(|s| s[1] >= s[0] * (1.0 - 1e-12) && s[1] <= 1.25 * s[0] * (1.0 + 1e-12)));
    }

    #[test]
    fn analytic_values_satisfy_hertz() {
        let p = Hertz::default();
        let a = (3.0 * p.force() * p.radius / (4.0 * p.effective_modulus())).cbrt();
        assert!((a - p.contact_radius).abs() < 1e-15);
        // ∫ p dA = F.
        let n = 20000;
        let dr = p.contact_radius / n as f64;
        let total: f64 = (0..n)
            .map(|i| (i as f64 + 0.5) * dr)
            .map(|r| p.pressure(r) * 2.0 * std::f64::consts::PI * r * dr)
            .sum();
        assert!((total / p.force() - 1.0).abs() < 1e-6);
    }
}
