"""Patch tests through seam.solve: supports and other interfaces touching the
slave sides, glue next to contact (the Python versions of seam-cli's
tests/supports.rs).

Each case has an affine exact solution that the discretisation reproduces:
``Solution.bodies[name].displacement`` and ``.stress`` must equal it to 1e-10
relative, and the interfaces' ``traction`` (the force per area the master
exerts on the slave) must be σ n_s, n_s the slave's outward normal; for
contact, ``contact_pressure`` is the applied pressure at every active point.
Case dicts use only constant Dirichlet values, so supports are rollers and
the stress is diagonal, σ = diag(S), u = ε x. Meshes: structured hexahedra or
Kuhn tetrahedra written as MSH 2.2 by patch_meshes.py; all interfaces are
non-matching.

Direct and PCG (``rtol=1e-13``: PCG's default 1e-10 on the residual leaves
errors up to 5e-10 relative in these tractions).
"""

import numpy as np
import pytest

import seam
from patch_meshes import write_block

RTOL = 1e-10
E, NU = 1000.0, 0.3
S = np.array([2.0, -1.0, -3.0])  # σ_xx, σ_yy, σ_zz of the glue patch tests


def strain(stress=S, young=E):
    return np.array([(stress[i] - NU * (stress[(i + 1) % 3] + stress[(i + 2) % 3])) / young for i in range(3)])


def voigt(diagonal):
    return np.array([*diagonal, 0.0, 0.0, 0.0])


def tensor(v):
    return np.array([[v[0], v[5], v[4]], [v[5], v[1], v[3]], [v[4], v[3], v[2]]])


def body(name, young=E):
    return {"name": name, "mesh": f"{name}.msh", "young": young, "poisson": NU}


def glue(master, slave, multiplier, kind="glue"):
    return {"master": master, "slave": slave, "kind": kind, "multiplier": multiplier}


def roller(boundary, component):
    return {"boundary": boundary, component: 0.0}


def load(boundary, t):
    return {"boundary": boundary, "t": [float(x) for x in t]}


def body_errors(solution, exact, stress):
    """Largest relative errors of displacement and cell stress over all bodies:
    ``exact(name, points)`` (n, 3), ``stress(name)`` (6,)."""
    u_scale = max(np.abs(exact(n, b.points)).max() for n, b in solution.bodies.items())
    s_scale = max(np.abs(stress(n)).max() for n in solution.bodies)
    u_error = s_error = 0.0
    for name, b in solution.bodies.items():
        assert b.displacement.shape == b.points.shape
        assert b.stress.shape[1] == 6 and len(b.stress) > 0
        u_error = max(u_error, np.abs(b.displacement - exact(name, b.points)).max() / u_scale)
        s_error = max(s_error, np.abs(b.stress - stress(name)).max() / s_scale)
    return u_error, s_error


def traction_error(interface, sigma, normal, scale, elsewhere=None):
    """Largest relative error of ``traction`` against σ n (n the slave's exact
    outward normal, also checked against ``normal``) at every point: where the
    interface constrains the point and where another interface does (the
    points ``elsewhere(points)`` selects; there ``constrained`` is 0 and the
    traction is the modified multiplier's value, still σ n)."""
    n = np.broadcast_to(np.asarray(normal, dtype=float), interface.points.shape)
    assert np.abs(interface.normal - n).max() <= 1e-12
    other = np.zeros(len(n), bool) if elsewhere is None else elsewhere(interface.points)
    np.testing.assert_array_equal(interface.constrained, np.where(other, 0.0, 1.0))
    exact = n @ tensor(sigma).T
    return np.abs(interface.traction - exact).max() / scale


SOLVERS = ["direct", "pcg"]


def solve(case, solver):
    s = seam.solve(case, solver=solver, rtol=1e-13)
    assert s.summary["residual"] <= 1e-10
    return s


def rollers_case(multiplier, stress=S, lower="lower.msh", upper="upper.msh"):
    """The bodies lower (master) and upper (slave) of these meshes glued at
    lower:top / upper:bottom; rollers at x = 0 and y = 0 on both and at
    z = 0 under lower; σ n, σ = diag(stress), on their other outer faces."""
    case = {
        "body": [{**body("lower"), "mesh": str(lower)}, {**body("upper"), "mesh": str(upper)}],
        "interface": [glue("lower:top", "upper:bottom", multiplier)],
        "dirichlet": [roller("lower:bottom", "uz")],
        "traction": [load("upper:top", [0, 0, stress[2]])],
    }
    for b in ("lower", "upper"):
        case["dirichlet"] += [roller(f"{b}:xmin", "ux"), roller(f"{b}:ymin", "uy")]
        case["traction"] += [load(f"{b}:xmax", [stress[0], 0, 0]), load(f"{b}:ymax", [0, stress[1], 0])]
    return case


USUAL = ((3, 4, 2), (4, 3, 2))
# A fine slave over a coarse master: dual multipliers are eliminated (reduced
# Cholesky); on the usual small meshes the elimination would fill in and the
# saddle point is solved.
FINE_OVER_COARSE = ((2, 2, 1), (6, 6, 6))
MESHES = [(("hex", "hex"), USUAL), (("tet", "tet"), USUAL), (("hex", "tet"), USUAL), (("tet", "hex"), USUAL),
          (("hex", "hex"), FINE_OVER_COARSE)]


@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize("multiplier", ["standard", "dual"])
@pytest.mark.parametrize("kinds,sizes", MESHES, ids=lambda v: "|".join(map(str, v)))
@pytest.mark.parametrize("slope", [0.0, 0.2])
def test_rollers_on_both_bodies_touching_a_glued_interface(tmp_path, monkeypatch, slope, kinds, sizes, multiplier,
                                                           solver):
    """A lower block (master, 3×4×2, or 2×2×1) under an upper one (slave,
    4×3×2, or 6×6×6, up to z = 1.2), meeting on z = 1/2 + slope (x − 1/2); both on rollers at x = 0
    and y = 0 (both touch the interface), the lower one at z = 0; σ n on the
    other outer faces. The tilted interface carries normal and shear traction."""
    monkeypatch.chdir(tmp_path)

    def interface(x):
        return 0.5 + slope * (x - 0.5)

    write_block(tmp_path / "lower.msh", sizes[0], kinds[0], lambda u, v, w: (u, v, w * interface(u)))
    write_block(tmp_path / "upper.msh", sizes[1], kinds[1],
                lambda u, v, w: (u, v, interface(u) + w * (1.2 - interface(u))))
    s = solve(rollers_case(multiplier), solver)
    eps = strain()
    u, sigma = body_errors(s, lambda _, x: x * eps, lambda _: voigt(S))
    (f,) = s.interfaces
    assert len(f.points) == (sizes[1][0] + 1) * (sizes[1][1] + 1)
    eliminated = multiplier == "dual" and sizes == FINE_OVER_COARSE
    direct = "reduced Cholesky (u_s = T u_m)" if eliminated else "saddle-point LDLᵀ"
    pcg = "reduced PCG, matrix-free (u_s = T u_m)"
    assert s.summary["method"] == (direct if solver == "direct" else pcg)
    norm = np.hypot(1.0, slope)
    t = traction_error(f, voigt(S), [slope / norm, 0.0, -1.0 / norm], np.abs(S).max())
    print(f"u {u:.1e} σ {sigma:.1e} t {t:.1e} ({s.summary['method']})")
    assert u <= RTOL and sigma <= RTOL and t <= RTOL, (u, sigma, t)


@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize("multiplier", ["standard", "dual"])
@pytest.mark.parametrize("kinds", [("hex",) * 3, ("tet",) * 3, ("hex", "tet", "hex"), ("tet", "hex", "tet")],
                         ids="|".join)
def test_three_blocks_meeting_along_a_crossline(tmp_path, monkeypatch, kinds, multiplier, solver):
    """a = [0,1]³, b = [1,2]×[0,1]², c = [0,2]×[0,1]×[1,1.6] glued a|b (x = 1),
    a|c and b|c (z = 1; c's bottom split at x = 1): c's points on the line
    x = 1, z = 1 are slave of two interfaces, b's slave of a|b and master of
    b|c. Rollers on b and c touch their slave sides."""
    monkeypatch.chdir(tmp_path)
    write_block(tmp_path / "a.msh", (3, 3, 3), kinds[0], lambda u, v, w: (u, v, w))
    write_block(tmp_path / "b.msh", (2, 4, 3), kinds[1], lambda u, v, w: (1.0 + u, v, w))
    write_block(tmp_path / "c.msh", (4, 5, 2), kinds[2], lambda u, v, w: (2.0 * u, v, 1.0 + 0.6 * w),
                split={"bottom_a": ("bottom", lambda c: c[0] < 1.0), "bottom_b": ("bottom", lambda c: c[0] > 1.0)})
    case = {
        "body": [body("a"), body("b"), body("c")],
        "interface": [glue("a:xmax", "b:xmin", multiplier), glue("a:top", "c:bottom_a", multiplier),
                      glue("b:top", "c:bottom_b", multiplier)],
        "dirichlet": [roller("a:xmin", "ux"), roller("a:ymin", "uy"), roller("a:bottom", "uz"),
                      roller("b:ymin", "uy"), roller("b:bottom", "uz"), roller("c:xmin", "ux"),
                      roller("c:ymin", "uy")],
        "traction": [load(f"{b}:ymax", [0, S[1], 0]) for b in "abc"]
        + [load("b:xmax", [S[0], 0, 0]), load("c:xmax", [S[0], 0, 0]), load("c:top", [0, 0, S[2]])],
    }
    s = solve(case, solver)
    eps = strain()
    u, sigma = body_errors(s, lambda _, x: x * eps, lambda _: voigt(S))
    t = 0.0
    # c's points on the crossline (x = 1) are slave points of a|c first: b|c does not constrain them.
    on_crossline = (None, None, lambda x: x[:, 0] == 1.0)
    for f, normal, points, elsewhere in zip(s.interfaces, ([-1, 0, 0], [0, 0, -1], [0, 0, -1]), (20, 18, 18),
                                            on_crossline):
        assert len(f.points) == points
        t = max(t, traction_error(f, voigt(S), normal, np.abs(S).max(), elsewhere))
    print(f"u {u:.1e} σ {sigma:.1e} t {t:.1e} ({s.summary['method']})")
    assert u <= RTOL and sigma <= RTOL and t <= RTOL, (u, sigma, t)


P = 3.0
YOUNG = {"base": 2000.0, "block": 1000.0, "cap": 1000.0}


def stack_exact(name, x):
    """Uniaxial σ_zz = −P, u_z continuous at z = 1 and z = 1.5."""
    e = {b: P / y for b, y in YOUNG.items()}
    z = x[:, 2]
    uz = {"base": -e["base"] * z, "block": -e["base"] - e["block"] * (z - 1.0),
          "cap": -e["base"] - 0.5 * e["block"] - e["cap"] * (z - 1.5)}[name]
    return np.column_stack([NU * e[name] * x[:, 0], NU * e[name] * x[:, 1], uz])


def stack_case(tmp_path, kinds, contact, glue_multiplier):
    """base [0,1]² × [0,1] | contact | block [0,1]² × [1,1.5] | glue | cap
    [0,1]² × [1.5,2.2], pressed by P on top, rollers at x = 0 and y = 0 on
    every body, u_z = 0 under the base."""
    write_block(tmp_path / "base.msh", (3, 4, 2), kinds[0], lambda u, v, w: (u, v, w))
    write_block(tmp_path / "block.msh", (4, 3, 2), kinds[1], lambda u, v, w: (u, v, 1.0 + 0.5 * w))
    write_block(tmp_path / "cap.msh", (5, 2, 2), kinds[2], lambda u, v, w: (u, v, 1.5 + 0.7 * w))
    return {
        "body": [body(b, YOUNG[b]) for b in YOUNG],
        "interface": [glue("base:top", "block:bottom", contact, kind="contact"),
                      glue("block:top", "cap:bottom", glue_multiplier)],
        "dirichlet": [roller(f"{b}:{side}", c) for b in YOUNG for side, c in (("xmin", "ux"), ("ymin", "uy"))]
        + [roller("base:bottom", "uz")],
        "traction": [load("cap:top", [0, 0, -P])],
    }


@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize("glue_multiplier", ["dual", "standard"])
@pytest.mark.parametrize("contact", ["dual", "lumped"])
@pytest.mark.parametrize("kinds", [("hex", "tet", "hex"), ("tet", "hex", "tet")], ids="|".join)
def test_glue_and_contact_carry_a_uniform_pressure(tmp_path, monkeypatch, kinds, contact, glue_multiplier, solver):
    monkeypatch.chdir(tmp_path)
    s = solve(stack_case(tmp_path, kinds, contact, glue_multiplier), solver)
    stress = voigt([0.0, 0.0, -P])
    u, sigma = body_errors(s, stack_exact, lambda _: stress)
    c, g = s.interfaces
    assert (c.kind, g.kind) == ("contact", "glue")
    assert len(c.points) == 20 and np.all(c.active == 1.0)
    assert np.abs(c.gap).max() <= 1e-12
    p = np.abs(c.contact_pressure[c.active == 1.0] - P).max() / P
    t = traction_error(g, stress, [0, 0, -1], P)
    kkt = s.summary["contact"]["kkt"]["max"]
    print(f"u {u:.1e} σ {sigma:.1e} pressure {p:.1e} t {t:.1e} KKT {kkt:.1e} ({s.summary['method']})")
    assert u <= RTOL and sigma <= RTOL and p <= RTOL and t <= RTOL and kkt <= RTOL, (u, sigma, p, t, kkt)
