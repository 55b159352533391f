//! Frictionless contact with second-order slave faces (Tri6, Quad8, Quad9):
//! the contact patch test on second-order bodies, glued and in contact, and
//! the refusal of a prescribed component that does not carry over to the
//! transformed unknowns of Popp, Wohlmuth, Gee and Wall (2012).
//!
//! Blocks stacked along z over [1, 2] × [½, 3/2] (so that the prescribed
//! roller values u_x = ν p x/E and u_y = ν p y/E are not zero), meshed
//! independently and raised to second order (`raise_order`: mid-edge, face
//! and cell nodes at the linear positions): rollers on x = 1 and y = ½ (every
//! node of those planes, mid-edge nodes included, prescribed to the exact
//! value), the bottom of the lowest block on u_z = 0, the top of the highest
//! one loaded by −p e₃ (or held). Every such problem has the homogeneous
//! uniaxial solution σ = −p e₃⊗e₃, which second-order elements reproduce
//! exactly: the contact pressure is p at every slave point (for dual
//! multipliers the coefficient of the dual basis ψ_p, biorthogonal to the
//! transformed λ̃_p, whose sum is one), and u = (ν x, ν y, −z) p/E per body
//! plus the rigid shift of each upper body.
//!
//! Measured (`cargo test -p seam-fem --test main contact_second_order:: -- --nocapture`):
//! every case prints its pressure, displacement and resultant errors: pressure
//! ≤ 2.2e-12, displacement ≤ 7.7e-13, resultant ≤ 1.2e-14, KKT residuals
//! ≤ 4.9e-15 (PCG; ≤ 3.6e-16 direct); asserted to 1e-8.
use seam::{Facing, MortarOptions, Multiplier, Point3, SurfaceMesh, VolumeMesh};
use seam_fem::generate::{block, raise_order, BlockKind, Grid, Side};
use seam_fem::pcg::PcgOptions;
use seam_fem::{solve_coupled, traction, Dirichlet, Material, ProblemError, Solution, SolveOptions};
use seam_fem::{Body, Coupling, Interface, Solver};

const RTOL: f64 = 1e-8;

/// The lower corner of the stack in x and y.
const ORIGIN: [f64; 2] = [1.0, 0.5];

/// One block of the stack: [1, 2] × [½, 3/2] × [bottom, bottom + height].
struct Layer {
    mesh: VolumeMesh,
    grid: Grid,
    material: Material,
    bottom: f64,
    height: f64,
}

impl Layer {
    /// `n` cells of `kind`, raised to second order (complete cells when
    /// `complete`).
    fn new(
        n: [usize; 3],
        kind: BlockKind,
        complete: bool,
        bottom: f64,
        height: f64,
        material: Material,
    ) -> Layer {
        let mut layer = Layer::first_order(n, kind, bottom, height, material);
        layer.mesh = raise_order(&layer.mesh, complete).unwrap();
        layer
    }

    /// The same block of first-order cells.
    fn first_order(n: [usize; 3], kind: BlockKind, bottom: f64, height: f64, material: Material) -> Layer {
        let mesh =
            block(n[0], n[1], n[2], |u, v, w| [ORIGIN[0] + u, ORIGIN[1] + v, bottom + height * w], kind);
        Layer { mesh, grid: Grid::new(n[0], n[1], n[2]), material, bottom, height }
    }

    fn side(&self, side: Side) -> SurfaceMesh {
        self.grid.side_faces(&self.mesh, side).unwrap()
    }
}

/// How the layers are joined, bottom to top: one entry per pair of
/// consecutive layers (the lower one master, the upper one slave), with the
/// initial gap δ between them (negative: an overlap).
struct Join {
    kind: Coupling,
    multiplier: Multiplier,
    gap: f64,
}

/// Pressure p on top (or the top held at u_z = `top`), every node of the
/// planes x = 1 and y = ½ prescribed to the exact roller values for
/// pressure `p_exact`.
struct Load {
    p: f64,
    top: Option<f64>,
    p_exact: f64,
}

fn stack(layers: &[Layer], joins: &[Join], load: &Load, solver: Solver) -> Result<Solution, ProblemError> {
    let surfaces: Vec<(SurfaceMesh, SurfaceMesh)> =
        layers.windows(2).map(|w| (w[0].side(Side::ZMax), w[1].side(Side::ZMin))).collect();
    let last = layers.len() - 1;
    let bodies: Vec<Body> = layers
        .iter()
        .enumerate()
        .map(|(i, layer)| {
            let mut d = Dirichlet::new();
            let m = layer.material;
            let roller = load.p_exact * m.poisson() / m.young();
            for (q, x) in layer.mesh.points().iter().enumerate() {
                let at = |c: usize, v: f64| (x[c] == v).then_some(roller * v);
                let uz = if i == 0 && x[2] == layer.bottom { Some(0.0) } else { None };
                let uz = match (i == last && x[2] == layer.bottom + layer.height, load.top) {
                    (true, Some(v)) => Some(v),
                    _ => uz,
                };
                d.fix(q, [at(0, ORIGIN[0]), at(1, ORIGIN[1]), uz]);
            }
            let load = match (i == last, load.top) {
                (true, None) => traction(&layer.side(Side::ZMax), |_, _| [0.0, 0.0, -load.p]),
                _ => vec![0.0; 3 * layer.mesh.points().len()],
            };
            Body { mesh: &layer.mesh, material: layer.material, load, dirichlet: d, ties: Vec::new() }
        })
        .collect();
    let interfaces: Vec<Interface> = joins
        .iter()
        .zip(&surfaces)
        .enumerate()
        .map(|(i, (j, (master, slave)))| Interface {
            master: i,
            master_surface: master,
            slave: i + 1,
            slave_surface: slave,
            options: MortarOptions {
                multiplier: j.multiplier,
                facing: Facing::Opposite,
                ..Default::default()
            },
            kind: j.kind,
            friction: 0.0,
        })
        .collect();
    solve_coupled(&bodies, &interfaces, &SolveOptions { solver, ..Default::default() })
}

/// max |u − u_exact| / max |u_exact| for the uniaxial solution with pressure
/// p: each body compressed by p/E, shifted by the compression of those below
/// it and by the initial gaps that closed.
fn displacement_error(layers: &[Layer], joins: &[Join], s: &Solution, p: f64) -> f64 {
    let (mut err, mut size, mut offset) = (0.0f64, 0.0f64, 0.0);
    for (b, layer) in layers.iter().enumerate() {
        if b > 0 {
            offset -= joins[b - 1].gap;
        }
        let (e, nu) = (layer.material.young(), layer.material.poisson());
        for (q, x) in layer.mesh.points().iter().enumerate() {
            let exact = [nu * p / e * x[0], nu * p / e * x[1], -p / e * (x[2] - layer.bottom) + offset];
            for c in 0..3 {
                err = err.max((s.displacement[b][3 * q + c] - exact[c]).abs());
                size = size.max(exact[c].abs());
            }
        }
        offset -= p / e * layer.height;
    }
    err / size
}

/// Every contact point active with pressure p and its gap closed, the
/// resultant p × area, the KKT conditions and the displacement; prints the
/// errors.
fn check(label: &str, layers: &[Layer], joins: &[Join], s: &Solution, p: f64) {
    let report = s.report.contact.as_ref().expect("a contact report");
    assert!(report.kkt.max() <= RTOL, "{label}: KKT {:?}", report.kkt);
    let mut pressure = 0.0f64;
    let mut force = 0.0f64;
    for ((interface, join), j) in s.interfaces.iter().zip(joins).zip(0..) {
        if join.kind != Coupling::Contact {
            continue;
        }
        let i = interface.contact.as_ref().expect("contact fields");
        let points: Vec<usize> = (0..i.contact.len()).filter(|&q| i.contact[q]).collect();
        let covered = interface.mortar.covered.iter().filter(|&&c| c).count();
        assert_eq!(
            points.len(),
            covered,
            "{label}: interface {j}: one contact point per covered slave point"
        );
        assert!(points.iter().all(|&q| i.active[q]), "{label}: interface {j}: every point in contact");
        assert!(
            points.iter().all(|&q| i.gap[q].abs() <= 1e-12 && (i.initial_gap[q] - join.gap).abs() <= 1e-12),
            "{label}: interface {j}: gaps"
        );
        pressure = points.iter().fold(pressure, |m, &q| m.max((i.pressure[q] - p).abs() / p));
        // The slave faces cover the unit square.
        force = force.max((interface.force[2] - p).abs() / p).max(interface.force[0].abs() / p);
    }
    let u = displacement_error(layers, joins, s, p);
    println!(
        "{label}: pressure {pressure:.1e}, displacement {u:.1e}, resultant {force:.1e}, KKT {:.1e}, steps {}",
        report.kkt.max(),
        report.steps.len()
    );
    assert!(pressure <= RTOL, "{label}: pressure error {pressure:e}");
    assert!(u <= RTOL, "{label}: displacement error {u:e}");
    assert!(force <= RTOL, "{label}: resultant error {force:e}");
}

fn materials() -> [Material; 2] {
    [Material::new(1000.0, 0.3).unwrap(), Material::new(300.0, 0.2).unwrap()]
}

/// A block's mesh: (cells across, kind, complete second-order cells).
type Mesh = (usize, BlockKind, bool);

/// Master (lower, [½ − h, ½]) and slave (upper, [½ + δ, 1 + δ]) of the given
/// kinds, (cells across, kind, complete).
fn pair(master: Mesh, slave: Mesh, delta: f64) -> Vec<Layer> {
    let [m1, m2] = materials();
    vec![
        Layer::new([master.0, master.0, 2], master.1, master.2, 0.0, 0.5, m1),
        Layer::new([slave.0, slave.0, 2], slave.1, slave.2, 0.5 + delta, 0.5, m2),
    ]
}

fn contact(multiplier: Multiplier, gap: f64) -> Join {
    Join { kind: Coupling::Contact, multiplier, gap }
}

/// (label, master, slave): Quad9, Tri6 and Quad8 slave faces on non-matching
/// second-order masters.
fn kinds() -> Vec<(&'static str, Mesh, Mesh)> {
    use BlockKind::*;
    vec![
        ("Tet10 | Hex27 (Quad9 slave)", (3, Tet, true), (2, Hex, true)),
        ("Hex20 | Tet10 (Tri6 slave)", (3, Hex, false), (2, Tet, true)),
        ("Prism18 | Hex20 (Quad8 slave)", (2, Prism, true), (3, Hex, false)),
    ]
}

#[test]
fn contact_patch_test_on_second_order_bodies() {
    let p = 2.0;
    for (label, master, slave) in kinds() {
        let layers = pair(master, slave, 0.0);
        let joins = [contact(Multiplier::Dual, 0.0)];
        let load = Load { p, top: None, p_exact: p };
        let s = stack(&layers, &joins, &load, Solver::Direct).unwrap();
        assert!(s.interfaces[0].mortar.basis.is_some(), "{label}: the transformed dual basis");
        check(&format!("{label} dual"), &layers, &joins, &s, p);
    }
    // Quad9 faces also take lumped multipliers (positive row sums): no transformation.
    let layers = pair((3, BlockKind::Tet, true), (2, BlockKind::Hex, true), 0.0);
    let joins = [contact(Multiplier::Lumped, 0.0)];
    let s = stack(&layers, &joins, &Load { p, top: None, p_exact: p }, Solver::Direct).unwrap();
    assert!(s.interfaces[0].mortar.basis.is_none());
    check("Tet10 | Hex27 (Quad9 slave) lumped", &layers, &joins, &s, p);
}

#[test]
fn contact_patch_test_on_second_order_bodies_with_pcg() {
    let p = 2.0;
    let pcg = Solver::Pcg(PcgOptions { rtol: 1e-13, ..Default::default() });
    let layers = pair((3, BlockKind::Hex, false), (2, BlockKind::Tet, true), 0.0);
    let joins = [contact(Multiplier::Dual, 0.0)];
    let s = stack(&layers, &joins, &Load { p, top: None, p_exact: p }, pcg).unwrap();
    check("Hex20 | Tet10 (Tri6 slave) dual, PCG", &layers, &joins, &s, p);
}

/// First-order bodies with the same non-zero roller values: at the slave
/// point on both roller planes the frame is (n, e_x, n × e_x = −e_y), so the
/// prescribed u_y enters the rotated unknowns with a minus sign (once lost).
#[test]
fn non_zero_rollers_at_first_order_contact_points() {
    let p = 2.0;
    let [m1, m2] = materials();
    for multiplier in [Multiplier::Lumped, Multiplier::Dual] {
        let layers = [
            Layer::first_order([4, 4, 2], BlockKind::Tet, 0.0, 0.5, m1),
            Layer::first_order([3, 3, 2], BlockKind::Hex, 0.5, 0.5, m2),
        ];
        let joins = [contact(multiplier, 0.0)];
        let s = stack(&layers, &joins, &Load { p, top: None, p_exact: p }, Solver::Direct).unwrap();
        check(&format!("Tet4 | Hex8 {multiplier:?}"), &layers, &joins, &s, p);
    }
}

/// An initial overlap −δ pushed out with the top held: p = δ / Σ h/E
/// (springs in series), and a gap +δ closed by pressing beyond it: the
/// transformed slave positions x̃ = Q⁻ᵀ x give the weighted gaps.
#[test]
fn second_order_overlaps_are_pushed_out_and_gaps_closed() {
    let [e1, e2] = [materials()[0].young(), materials()[1].young()];
    for (label, master, slave) in kinds() {
        for (delta, push) in [(-0.01, 0.0), (0.01, -0.03)] {
            let layers = pair(master, slave, delta);
            let p = (-push - delta) / (0.5 / e1 + 0.5 / e2);
            let joins = [contact(Multiplier::Dual, delta)];
            let s = stack(&layers, &joins, &Load { p: 0.0, top: Some(push), p_exact: p }, Solver::Direct)
                .unwrap();
            check(&format!("{label}, δ = {delta}, top u_z = {push}"), &layers, &joins, &s, p);
        }
    }
}

/// A third body glued on top of the slave body (dual multipliers: eliminated;
/// standard: saddle points per active-set step), the contact slave side of
/// second order: the transformation composes with the glued constraints.
/// The glued bodies share a material, so that the uniaxial fields agree on
/// their interface.
#[test]
fn second_order_contact_with_a_glued_body() {
    let p = 2.0;
    let [m1, m2] = materials();
    let layers = [
        Layer::new([3, 3, 2], BlockKind::Tet, true, 0.0, 0.5, m1),
        Layer::new([2, 2, 2], BlockKind::Hex, true, 0.5, 0.5, m2),
        Layer::new([3, 3, 1], BlockKind::Tet, true, 1.0, 0.25, m2),
    ];
    for glue in [Multiplier::Dual, Multiplier::Standard] {
        let joins =
            [contact(Multiplier::Dual, 0.0), Join { kind: Coupling::Glue, multiplier: glue, gap: 0.0 }];
        let s = stack(&layers, &joins, &Load { p, top: None, p_exact: p }, Solver::Direct).unwrap();
        check(&format!("Tet10 | Hex27 contact, Tet10 glued on top ({glue:?})"), &layers, &joins, &s, p);
        let glued = &s.interfaces[1];
        let t = glued.traction.iter().zip(&glued.constrained).filter(|(_, &c)| c).map(|(t, _)| t);
        let worst = t.fold(0.0f64, |m, t| m.max((t[2] - p).abs()).max(t[0].abs()).max(t[1].abs()));
        assert!(worst <= RTOL * p, "glued traction error {worst:e} ({glue:?})");
    }
}

/// A prescribed component at a mid-edge slave node whose edge has a free
/// corner cannot be written in the transformed unknowns: refused, naming the
/// point.
#[test]
fn a_prescribed_edge_node_with_a_free_corner_is_refused() {
    let layers = pair((3, BlockKind::Tet, true), (2, BlockKind::Hex, true), 0.0);
    // The mid-edge node of the slave face edge from (1, 1, ½) to (1.5, 1, ½):
    // its corner at x = 1 is on the roller, the one at x = 1.5 is free in x.
    let slave = &layers[1];
    let target: Point3 = [1.25, 1.0, 0.5];
    let node = slave.mesh.points().iter().position(|&x| x == target).expect("a mid-edge node");
    let surfaces = (layers[0].side(Side::ZMax), slave.side(Side::ZMin));
    let mut d = Dirichlet::new();
    d.fix(node, [Some(0.0), None, None]);
    let mut lower = Dirichlet::new();
    for (q, x) in layers[0].mesh.points().iter().enumerate() {
        d_fix_rollers(&mut lower, q, *x, x[2] == 0.0);
    }
    for (q, x) in slave.mesh.points().iter().enumerate() {
        d_fix_rollers(&mut d, q, *x, x[2] == 1.0);
    }
    let bodies = [
        Body {
            mesh: &layers[0].mesh,
            material: layers[0].material,
            load: vec![0.0; 3 * layers[0].mesh.points().len()],
            dirichlet: lower,
            ties: Vec::new(),
        },
        Body {
            mesh: &slave.mesh,
            material: slave.material,
            load: vec![0.0; 3 * slave.mesh.points().len()],
            dirichlet: d,
            ties: Vec::new(),
        },
    ];
    let interfaces = [Interface {
        master: 0,
        master_surface: &surfaces.0,
        slave: 1,
        slave_surface: &surfaces.1,
        options: MortarOptions {
            multiplier: Multiplier::Dual,
            facing: Facing::Opposite,
            ..Default::default()
        },
        kind: Coupling::Contact,
        friction: 0.0,
    }];
    let error = solve_coupled(&bodies, &interfaces, &SolveOptions::default()).unwrap_err().to_string();
    println!("{error}");
    assert!(
        error.contains(&format!("slave point {node} at (1.25, 1, 0.5) has component 0 prescribed"))
            && error.contains("corner of its edge")
            && error.starts_with("interface 0:"),
        "{error}"
    );
}

/// Rollers at zero on x = 1 and y = ½, and u_z = 0 where `base`.
fn d_fix_rollers(d: &mut Dirichlet, q: usize, x: Point3, base: bool) {
    let at = |c: usize| (x[c] == ORIGIN[c]).then_some(0.0);
    d.fix(q, [at(0), at(1), base.then_some(0.0)]);
}
