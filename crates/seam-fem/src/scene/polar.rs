//! O-grids for contact around the origin: the plane y ≥ 0 (half model) or
//! x, y ≥ 0 (quarter model) over the square of side `length`, meshed by
//! quadrilaterals on rings about the origin, and extruded through the depth.
//!
//! An axisymmetric contact (Hertz, Cattaneo–Mindlin) has its singular
//! features on circles: the contact rim r = a, where the pressure falls as
//! √(a − r), and the stick–slip boundary r = c inside it. Rings refine the
//! radius across a band of radii without refining the angle (tensor grids
//! refine both, over the whole square).
//!
//! # Layout
//!
//! - The sectors: `sectors` equal angles θ_i = i Δθ over [0, π] (half) or
//!   [0, π/2] (quarter), each along the ray e_i = (cos θ_i, sin θ_i).
//! - The core: the (half or quarter) square of side s = `core` whose
//!   boundary nodes are the rays' points s σ_i e_i, σ_i = 1/max(|cos θ_i|,
//!   sin θ_i); inside, the tensor grid on the lines x, y = s tan(j Δθ) that
//!   those nodes lie on.
//! - Every other node lies on a ray, at the radius r_{k,i} of ring k:
//!   from the core's square to the circle ρ = `circle` linearly in k over
//!   `blend` rings; `circles` + 1 circles `radial` apart from `circle` to
//!   the band's end b; then rings growing geometrically (at most
//!   `grading`×) from the circle b to the square of side `length` (r = ρ (1
//!   + (σ_i − 1) (ρ − b)/(length − b)), monotone in ρ).
//!
//! Points on y = 0 have y exactly 0 (and x exactly 0 on x = 0 for the
//! quarter).

use super::hertz::{graded, raise_mapped, Hertz};
use crate::material::Material;
use crate::problem::ProblemBody;
use seam::{Cell, Face, MeshError, Point3, SurfaceMesh, VolumeMesh};

/// The rings of an O-grid (module doc); lengths absolute.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Rings {
    /// Equal angles over the half (a multiple of 4) or the quarter (a
    /// multiple of 2).
    pub sectors: usize,
    /// The core's side s (less than `circle`/√2).
    pub core: f64,
    /// Rings from the core's square to the first circle.
    pub blend: usize,
    /// The first circle's radius.
    pub circle: f64,
    /// The spacing h of the circles.
    pub radial: f64,
    /// Cells between the circles: the band ends at the circle `circle` +
    /// `circles` h.
    pub circles: usize,
    /// The largest ratio of neighbouring radial spacings beyond the band.
    pub grading: f64,
}

/// A plane quadrilateral mesh: points (x, y) and counter-clockwise quads.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Plane {
    pub points: Vec<[f64; 2]>,
    pub quads: Vec<[usize; 4]>,
}

impl Rings {
    /// The O-grid of the half (`half`) or quarter plane over the square of
    /// side `length` (module doc).
    ///
    /// # Panics
    /// If the parameters cannot make a valid grid (a programming error of
    /// the scene: the sectors not a multiple of 4 or 2, s ≥ circle/√2,
    /// radii out of order).
    pub fn plane(&self, length: f64, half: bool) -> Plane {
        let per_side = self.sectors / if half { 4 } else { 2 };
        assert!(
            per_side > 0 && per_side * if half { 4 } else { 2 } == self.sectors,
            "sectors {}",
            self.sectors
        );
        assert!(
            self.core * std::f64::consts::SQRT_2 < self.circle
                && self.band() < length
                && self.blend > 0
                && self.radial > 0.0
                && self.grading > 1.0,
            "{self:?} over {length}"
        );
        let step = std::f64::consts::FRAC_PI_4 / per_side as f64;
        // The core's grid lines s tan(j Δθ), exactly 0 and ±s at the ends.
        let line = |j: isize| match j.unsigned_abs() {
            0 => 0.0,
            a if a == per_side => self.core * j.signum() as f64,
            _ => self.core * (j as f64 * step).tan(),
        };
        let (nx, ny) = if half { (2 * per_side, per_side) } else { (per_side, per_side) };
        let x0 = if half { -(per_side as isize) } else { 0 };
        let mut plane = Plane::default();
        for l in 0..=ny {
            for j in 0..=nx {
                plane.points.push([line(x0 + j as isize), line(l as isize)]);
            }
        }
        let core = |j: usize, l: usize| j + (nx + 1) * l;
        for l in 0..ny {
            for j in 0..nx {
                plane.quads.push([core(j, l), core(j + 1, l), core(j + 1, l + 1), core(j, l + 1)]);
            }
        }
        // Ring 0: the core's boundary, counter-clockwise from (s, 0).
        let ring0: Vec<usize> = (0..=self.sectors)
            .map(|i| match i {
                i if i <= per_side => core(nx, i),
                i if i <= per_side + nx => core(nx - (i - per_side), ny),
                i => core(0, ny - (i - per_side - nx)),
            })
            .collect();
        let rays: Vec<([f64; 2], f64)> = (0..=self.sectors)
            .map(|i| {
                let (sin, cos) = (i as f64 * step).sin_cos();
                // Exact axes: y = 0 at θ = 0 (and π), x = 0 at π/2.
                let e = match i {
                    0 => [1.0, 0.0],
                    i if half && i == self.sectors => [-1.0, 0.0],
                    i if i == 2 * per_side => [0.0, 1.0],
                    _ => [cos, sin],
                };
                (e, 1.0 / e[0].abs().max(e[1].abs()))
            })
            .collect();
        let mut previous = ring0;
        for (a, b) in self.radii(length) {
            let ring: Vec<usize> = rays
                .iter()
                .map(|&(e, sigma)| {
                    let r = a + b * sigma;
                    plane.points.push([r * e[0], r * e[1]]);
                    plane.points.len() - 1
                })
                .collect();
            for i in 0..self.sectors {
                plane.quads.push([previous[i], ring[i], ring[i + 1], previous[i + 1]]);
            }
            previous = ring;
        }
        plane
    }

    /// The last circle's radius, `circle` + `circles` h.
    pub fn band(&self) -> f64 {
        self.circle + self.circles as f64 * self.radial
    }

    /// Rings 1, 2, … as (α, β): r_{k,i} = α + β σ_i (module doc).
    fn radii(&self, length: f64) -> Vec<(f64, f64)> {
        let (s, rc, band) = (self.core, self.circle, self.band());
        let blend = (1..=self.blend).map(|k| k as f64 / self.blend as f64).map(|t| (rc * t, s * (1.0 - t)));
        let circles = (1..=self.circles).map(|j| (rc + j as f64 * self.radial, 0.0));
        let outer = graded(length - band, (self.radial, 1), self.grading);
        let squares = outer[1..].iter().map(|&d| {
            let (rho, w) = (band + d, d / (length - band));
            (rho * (1.0 - w), rho * w)
        });
        blend.chain(circles).chain(squares).collect()
    }
}

/// The bodies "indenter" and "block" of [`super::hertz`] on O-grids
/// ([`super::Layout::Rings`]): the surfaces "bottom", "top" and "y0" (and
/// "x0" for the quarter model, `half` false).
///
/// The block's rings, for n = `fine_cells` and z = `fine_zone`: 3n sectors
/// over the half (rounded up to a multiple of 4, 2 for the quarter);
/// circles h = z a/(2n) apart from about a/2 to z a, placed so that Hertz's
/// contact radius a lies midway between two of them (circles at a + (j −
/// ½) h: a circle just outside a would be in contact where the analytic
/// pressure is zero, and carry most of the traction's error); the core's
/// side half the first circle's radius, blended to it over rings about h
/// apart; the depth uniform at h to z a/4, then growing at most `grading`×.
/// The indenter's the same with `master_ratio` n for n (so the meshes do not
/// match).
///
/// # Errors
/// [`MeshError`] only for degenerate parameters.
///
/// # Panics
/// For cells other than hexahedra (first or second order).
pub(super) fn ring_bodies(p: &Hertz, half: bool) -> Result<Vec<ProblemBody>, MeshError> {
    assert!(p.cells == crate::generate::BlockKind::Hex, "O-grids are meshed with hexahedra only");
    let quadrant = if half { 4 } else { 2 };
    let (a, zone) = (p.contact_radius, p.fine_zone * p.contact_radius);
    let rings = |cells: f64| {
        let radial = 0.5 * zone / cells;
        // Circles a + (j − ½) h for j from ⌈½ − a/(2h)⌉ (≥ a/2) to ⌊½ + (z a − a)/h⌋ (≤ z a).
        let first = (0.5 - 0.5 * a / radial).ceil();
        let last = (0.5 + (zone - a) / radial).floor().max(first + 1.0);
        let circle = a + (first - 0.5) * radial;
        let core = 0.5 * circle;
        Rings {
            sectors: quadrant * (3.0 * cells / quadrant as f64).ceil() as usize,
            core,
            blend: ((circle - core) / radial).ceil() as usize,
            circle,
            radial,
            circles: (last - first) as usize,
            grading: p.grading,
        }
    };
    let n = p.fine_cells as f64;
    let (slave, master) = (rings(n), rings(n * p.master_ratio));
    // The depth: uniform at the radial spacing over the first quarter of the fine zone.
    let depth = |rings: &Rings, length: f64| {
        let fine = 0.25 * zone;
        let cells = (fine / rings.radial).ceil() as usize;
        graded(length, (fine, cells), p.grading)
    };
    let w = p.block_size();
    let down: Vec<f64> = depth(&slave, w).iter().rev().map(|z| 1.0 - z / w).collect();
    let (l, h) = p.indenter_size();
    let up: Vec<f64> = depth(&master, h).iter().map(|z| z / h).collect();
    let sphere = |x: f64, y: f64| p.sphere(x, y);
    Ok(vec![
        ring_body(
            ("indenter", p.indenter),
            (&master.plane(l, half), &up, half),
            p.second_order,
            |x, y, t| {
                let z = sphere(x, y);
                [x, y, z + (h - z) * t]
            },
            |x| {
                let z = sphere(x[0], x[1]);
                [x[0], x[1], (x[2] - z) / (h - z)]
            },
        )?,
        ring_body(
            ("block", p.block),
            (&slave.plane(w, half), &down, half),
            p.second_order,
            |x, y, t| [x, y, -w * (1.0 - t)],
            |x| [x[0], x[1], 1.0 + x[2] / w],
        )?,
    ])
}

/// One body: `plane` (of the half plane, or with `half` false the quarter)
/// extruded through `ws` by `map` (of second order when `second_order`, the
/// new nodes placed through `unmap`), with the surfaces "bottom" (w = 0),
/// "top" (w = 1), "x0" for the quarter and "y0".
fn ring_body(
    (name, material): (&str, Material),
    (plane, ws, half): (&Plane, &[f64], bool),
    second_order: bool,
    map: impl Fn(f64, f64, f64) -> Point3,
    unmap: impl Fn(Point3) -> Point3,
) -> Result<ProblemBody, MeshError> {
    let (np, top) = (plane.points.len(), ws.len() - 1);
    let mesh = extrude(plane, ws, &map);
    let mesh = if second_order { raise_mapped(&mesh, |x| map(x[0], x[1], x[2]), unmap)? } else { mesh };
    let on_axis = |axis: usize| move |q: usize| plane.points[q % np][axis] == 0.0;
    let mut surfaces = vec![
        ("bottom".to_string(), faces_on(&mesh, |q| q < np)?),
        ("top".to_string(), faces_on(&mesh, |q| q / np == top)?),
    ];
    if !half {
        surfaces.push(("x0".to_string(), faces_on(&mesh, on_axis(0))?));
    }
    surfaces.push(("y0".to_string(), faces_on(&mesh, on_axis(1))?));
    Ok(ProblemBody::new(name, mesh, material, surfaces))
}

/// The hexahedra of `plane` extruded through the layers `ws` (increasing
/// from 0 to 1), point (p, k) at `map(x_p, y_p, w_k)`, index p + |plane| k.
fn extrude(plane: &Plane, ws: &[f64], map: impl Fn(f64, f64, f64) -> Point3) -> VolumeMesh {
    let n = plane.points.len();
    let points = ws
        .iter()
        .flat_map(|&w| plane.points.iter().map(|&[x, y]| map(x, y, w)).collect::<Vec<_>>())
        .collect();
    let cells = (0..ws.len() - 1)
        .flat_map(|k| {
            plane.quads.iter().map(move |q| {
                let [a, b, c, d] = q.map(|i| i + n * k);
                Cell::Hex8([a, b, c, d, a + n, b + n, c + n, d + n])
            })
        })
        .collect();
    VolumeMesh::new(points, cells).expect("extruded O-grids are valid by construction")
}

/// The boundary faces of `mesh` whose corners all satisfy `on` (indices of
/// the first-order points), outward.
fn faces_on(mesh: &VolumeMesh, on: impl Fn(usize) -> bool) -> Result<SurfaceMesh, MeshError> {
    let faces: Vec<Face> = mesh
        .boundary()?
        .faces()
        .iter()
        .filter(|f| f.corner_nodes().iter().all(|&p| on(p)))
        .copied()
        .collect();
    SurfaceMesh::new(mesh.points().to_vec(), faces)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Hertz, Layout};
    use seam::area_vector;
    use std::collections::HashMap;

    fn rings(sectors: usize) -> Rings {
        Rings { sectors, core: 0.3, blend: 3, circle: 0.625, radial: 0.05, circles: 9, grading: 1.3 }
    }

    /// Shoelace area of a plane quad.
    fn area(plane: &Plane, q: &[usize; 4]) -> f64 {
        let x = q.map(|i| plane.points[i]);
        0.5 * (0..4).map(|i| x[i][0] * x[(i + 1) % 4][1] - x[(i + 1) % 4][0] * x[i][1]).sum::<f64>()
    }

    /// Every corner of every quad turns left (convex, counter-clockwise),
    /// the quads tile the (half or quarter) square exactly, every interior
    /// edge is shared by two quads in opposite directions, and only the
    /// square's sides are boundary edges.
    #[test]
    fn the_rings_tile_the_square_with_convex_quads() {
        for (half, sectors, length) in [(true, 24, 12.5), (false, 14, 10.0), (true, 4, 3.0)] {
            let plane = rings(sectors).plane(length, half);
            for q in &plane.quads {
                for i in 0..4 {
                    let [a, b, c] = [q[i], q[(i + 1) % 4], q[(i + 2) % 4]].map(|k| plane.points[k]);
                    let turn = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
                    assert!(turn > 0.0, "{half} {sectors}: quad {q:?} turns right at {b:?}");
                }
            }
            let total: f64 = plane.quads.iter().map(|q| area(&plane, q)).sum();
            let square = if half { 2.0 } else { 1.0 } * length * length;
            assert!((total - square).abs() < 1e-12 * square, "{total} against {square}");
            // Per edge: the quads that use it, and its directions summed (+1 a → b, −1 b → a).
            let mut edges: HashMap<(usize, usize), (usize, i32)> = HashMap::new();
            for q in &plane.quads {
                for i in 0..4 {
                    let (a, b) = (q[i], q[(i + 1) % 4]);
                    let e = edges.entry((a.min(b), a.max(b))).or_default();
                    *e = (e.0 + 1, e.1 + if a < b { 1 } else { -1 });
                }
            }
            for (&(a, b), &(n, direction)) in &edges {
                let [x, y] = [plane.points[a], plane.points[b]];
                let on_side = |k: usize, v: f64| (x[k] - v).abs() < 1e-12 && (y[k] - v).abs() < 1e-12;
                let side = on_side(1, 0.0) || on_side(1, length) || on_side(0, length) || on_side(0, -length);
                let side = side || (!half && on_side(0, 0.0));
                match n {
                    2 => assert_eq!(direction, 0, "edge {x:?}–{y:?} used twice the same way"),
                    1 => assert!(side, "boundary edge {x:?}–{y:?} inside the square"),
                    _ => panic!("edge {x:?}–{y:?} in {n} quads"),
                }
            }
        }
    }

    /// The band's rings are circles, and the axes' points lie exactly on
    /// the axes.
    #[test]
    fn band_nodes_lie_on_circles_and_axis_nodes_on_the_axes() {
        let r = rings(24);
        let plane = r.plane(12.5, true);
        let radii: Vec<f64> = plane.points.iter().map(|x| x[0].hypot(x[1])).collect();
        let circles: Vec<f64> =
            radii.iter().copied().filter(|&s| s > r.circle - 1e-9 && s < r.band() + 1e-9).collect();
        assert_eq!(circles.len(), 25 * (r.circles + 1));
        for s in &circles {
            let same = circles.iter().filter(|&&t| (t - s).abs() < 1e-14 * s).count();
            assert_eq!(same, 25, "a ring of 25 nodes at r = {s}");
        }
        let on_axis = plane.points.iter().filter(|x| x[1] == 0.0).count();
        let near_axis = plane.points.iter().filter(|x| x[1].abs() < 1e-9).count();
        assert_eq!(on_axis, near_axis);
        let quarter = rings(14).plane(10.0, false);
        assert_eq!(
            quarter.points.iter().filter(|x| x[0] == 0.0).count(),
            quarter.points.iter().filter(|x| x[0].abs() < 1e-9).count()
        );
    }

    /// The extruded bodies are conforming (their boundary is the box's),
    /// fill the box, and their named surfaces are its sides.
    #[test]
    fn ring_bodies_fill_the_boxes_with_their_named_sides() {
        for (half, second_order) in [(true, false), (false, false), (true, true)] {
            let p = Hertz { fine_cells: 3, layout: Layout::Rings, second_order, ..Hertz::default() };
            let bodies = ring_bodies(&p, half).unwrap();
            let w = p.block_size();
            let block = &bodies[1];
            let width = if half { 2.0 * w } else { w };
            let surface_area = |name: &str| -> [f64; 3] {
                let s = &block.surfaces.iter().find(|(n, _)| n == name).unwrap().1;
                let mut a = [0.0; 3];
                for f in 0..s.n_faces() {
                    let v = area_vector(&s.corners(f));
                    (0..3).for_each(|k| a[k] += v[k]);
                }
                a
            };
            let close = |a: [f64; 3], b: [f64; 3]| (0..3).all(|k| (a[k] - b[k]).abs() < 1e-12 * w * w);
            assert!(close(surface_area("top"), [0.0, 0.0, width * w]), "{:?}", surface_area("top"));
            assert!(close(surface_area("bottom"), [0.0, 0.0, -width * w]));
            assert!(close(surface_area("y0"), [0.0, -width * w, 0.0]), "{:?}", surface_area("y0"));
            if !half {
                assert!(close(surface_area("x0"), [-w * w, 0.0, 0.0]));
            }
            // Conforming: every boundary face lies on a side of the box.
            let boundary = block.mesh.boundary().unwrap();
            for f in 0..boundary.n_faces() {
                let c = boundary.corners(f);
                let on = |k: usize, v: f64| c.iter().all(|x| (x[k] - v).abs() < 1e-9 * w);
                let outer =
                    on(0, w) || on(1, w) || on(0, -w) || on(0, 0.0) || on(1, 0.0) || on(2, 0.0) || on(2, -w);
                assert!(outer, "an inner boundary face {c:?}");
            }
            // The indenter's bottom lies on the sphere.
            let ball = &bodies[0];
            let bottom = &ball.surfaces[0].1;
            for &q in bottom.faces().iter().flat_map(|f| f.nodes()) {
                let x = ball.mesh.points()[q];
                assert!((x[2] - p.sphere(x[0], x[1])).abs() < 1e-15, "{x:?}");
            }
        }
    }
}
