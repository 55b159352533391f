"""Glue and contact in one case, meshed by Gmsh and solved by seam.

A base [0,1]² × [0,1] carries a block [0,1]² × [1,1.5] through frictionless
contact (slave: the block's bottom), and a cap [0,1]² × [1.5,2] is glued on
top of the block (slave: the cap's bottom). Each box is meshed on its own by
Gmsh with unstructured tetrahedra of a different size, so neither interface
matches. Every body sits on rollers u_x = 0 at x = 0 and u_y = 0 at y = 0
(they touch both interfaces' slave sides), the base on u_z = 0 at z = 0, and
the cap is pressed by p on its top: the exact solution is the uniaxial stress
σ_zz = −p in every body, so the contact pressure is p at every contact point.

    python glue_and_contact.py [DIR]        (default: out/glue-and-contact)

writes DIR/<body>.msh, DIR/case.toml (rerun it with `seam solve
DIR/case.toml --force`) and the results in DIR/out. Needs `pip install gmsh`.
"""

import sys
from pathlib import Path

import gmsh
import numpy as np

import seam

P = 2.0
# name: (z0, z1, mesh size, Young's modulus)
BOXES = {"base": (0.0, 1.0, 0.3, 2000.0), "block": (1.0, 1.5, 0.22, 1000.0), "cap": (1.5, 2.0, 0.35, 1000.0)}


def mesh_box(path, z0, z1, size):
    """The box [0,1]² × [z0,z1] as unstructured tetrahedra, with the physical
    surfaces xmin, ymin, bottom and top, written as MSH 4.1."""
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        volume = gmsh.model.occ.addBox(0.0, 0.0, z0, 1.0, 1.0, z1 - z0)
        gmsh.model.occ.synchronize()
        eps = 1e-6
        planes = {"xmin": (0, 0.0), "ymin": (1, 0.0), "bottom": (2, z0), "top": (2, z1)}
        for name, (axis, at) in planes.items():
            lo, hi = np.array([-eps, -eps, z0 - eps]), np.array([1 + eps, 1 + eps, z1 + eps])
            lo[axis], hi[axis] = at - eps, at + eps
            (surface,) = gmsh.model.getEntitiesInBoundingBox(*lo, *hi, dim=2)
            gmsh.model.addPhysicalGroup(2, [surface[1]], name=name)
        gmsh.model.addPhysicalGroup(3, [volume], name="body")
        gmsh.option.setNumber("Mesh.MeshSizeMin", size)
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.model.mesh.generate(3)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


def case_toml():
    """The case: bodies, a contact and a glued interface, rollers, the press."""
    text = ""
    for name, (_, _, _, young) in BOXES.items():
        text += f'[[body]]\nname = "{name}"\nmesh = "{name}.msh"\nyoung = {young}\npoisson = 0.3\n\n'
    text += '[[interface]]\nmaster = "base:top"\nslave = "block:bottom"\nkind = "contact"\n\n'
    text += '[[interface]]\nmaster = "block:top"\nslave = "cap:bottom"\nkind = "glue"\nmultiplier = "dual"\n\n'
    for name in BOXES:
        text += f'[[dirichlet]]\nboundary = "{name}:xmin"\nux = 0.0\n\n'
        text += f'[[dirichlet]]\nboundary = "{name}:ymin"\nuy = 0.0\n\n'
    text += '[[dirichlet]]\nboundary = "base:bottom"\nuz = 0.0\n\n'
    text += f'[[traction]]\nboundary = "cap:top"\nt = [0.0, 0.0, {-P}]\n\n[output]\ndir = "out"\n'
    return text


def main(directory):
    directory.mkdir(parents=True, exist_ok=True)
    for name, (z0, z1, size, _) in BOXES.items():
        mesh_box(directory / f"{name}.msh", z0, z1, size)
    (directory / "case.toml").write_text(case_toml())

    solution = seam.solve(directory / "case.toml")
    contact, glue = solution.interfaces
    at = contact.active == 1
    print(f"{solution.summary['dofs']} unknowns, {solution.summary['method']}")
    print(f"contact: {at.sum()} of {len(at)} slave nodes active, pressure "
          f"{contact.contact_pressure[at].min():.12f} … {contact.contact_pressure[at].max():.12f} (p = {P})")
    print(f"glue: normal traction {glue.normal_traction.min():.12f} … {glue.normal_traction.max():.12f}")
    for name, body in solution.bodies.items():
        print(f"{name}: σ_zz {body.stress[:, 2].min():.12f} … {body.stress[:, 2].max():.12f}")
    solution.write(directory / "out", force=True)
    return solution


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "out/glue-and-contact"))
