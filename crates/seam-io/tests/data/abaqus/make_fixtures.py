"""Writes the Abaqus fixtures of crates/seam-io/tests/abaqus.rs with real tools.

    python3 -m venv /tmp/hv && /tmp/hv/bin/pip install gmsh meshio numpy
    /tmp/hv/bin/python make_fixtures.py

For each mesh of a unit box cut at z = 0.5 into the physical volumes "lower"
and "upper" (surfaces "top", z = 1, and "interface", z = 0.5): NAME.msh
(MSH 4.1) and NAME.inp, both written by Gmsh (Mesh.SaveGroupsOfElements), and
NAME.meshio.inp, the .msh read and written by meshio's Abaqus writer (not
for Hex27 and Prism15, which meshio 5.3.5 cannot write or read).

Gmsh writes a physical surface as an element set of membrane elements (M3D3,
M3D6, M3D4, M3D8, M3D9), which seam skips; this script appends to NAME.inp a
`*SURFACE, TYPE=ELEMENT` of the same name listing, for each face element, the
volume element with those corners and its face label from the table below
(Abaqus Analysis User's Guide, "three-dimensional solid element library";
corners 1-based, the tables of the reader are written apart from these).
"""
import gmsh
import meshio

FACES = {  # Abaqus face label -> corner nodes (1-based), per corner count
    4: {1: (1, 2, 3), 2: (1, 4, 2), 3: (2, 4, 3), 4: (3, 4, 1)},
    8: {1: (1, 2, 3, 4), 2: (5, 8, 7, 6), 3: (1, 5, 6, 2), 4: (2, 6, 7, 3), 5: (3, 7, 8, 4), 6: (4, 8, 5, 1)},
    6: {1: (1, 2, 3), 2: (4, 6, 5), 3: (1, 4, 5, 2), 4: (2, 5, 6, 3), 5: (3, 6, 4, 1)},
}
CORNERS = {4: 4, 11: 4, 5: 8, 17: 8, 12: 8, 6: 6, 18: 6}  # Gmsh type -> corners (same in both orders)


def make(name, shape, order, complete=True, meshio_too=True):
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add(name)
    occ = gmsh.model.occ
    if shape == "tet":
        occ.addBox(0, 0, 0, 1, 1, 0.5)
        occ.addBox(0, 0, 0.5, 1, 1, 0.5)
    else:
        square = occ.addRectangle(0, 0, 0, 1, 1)
        lower = occ.extrude([(2, square)], 0, 0, 0.5, numElements=[2], recombine=True)
        occ.extrude([lower[0]], 0, 0, 0.5, numElements=[2], recombine=True)
    occ.removeAllDuplicates()
    occ.synchronize()
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.5)
    if shape == "hex":
        for s in gmsh.model.getEntities(2):
            gmsh.model.mesh.setRecombine(2, s[1])
        for c in gmsh.model.getEntities(1):
            gmsh.model.mesh.setTransfiniteCurve(c[1], 3)
        for s in gmsh.model.getEntities(2):
            gmsh.model.mesh.setTransfiniteSurface(s[1])
    volumes = sorted(gmsh.model.getEntities(3), key=lambda v: gmsh.model.occ.getCenterOfMass(*v)[2])
    gmsh.model.addPhysicalGroup(3, [volumes[0][1]], name="lower")
    gmsh.model.addPhysicalGroup(3, [volumes[1][1]], name="upper")
    planes = {}
    for dim, tag in gmsh.model.getEntities(2):
        x, y, z = gmsh.model.occ.getCenterOfMass(dim, tag)
        planes.setdefault(round(z, 6) if abs(x - 0.5) < 1e-6 and abs(y - 0.5) < 1e-6 else None, []).append(tag)
    gmsh.model.addPhysicalGroup(2, planes[1.0], name="top")
    gmsh.model.addPhysicalGroup(2, planes[0.5], name="interface")
    gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 0 if complete else 1)
    gmsh.model.mesh.generate(3)
    if order == 2:
        gmsh.model.mesh.setOrder(2)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.SaveGroupsOfElements", 1)
    gmsh.write(name + ".msh")
    gmsh.write(name + ".inp")
    cells = []  # (tag, gmsh type, node tags in Gmsh order)
    for t, tags, nodes in zip(*gmsh.model.mesh.getElements(3)):
        n = len(nodes) // len(tags)
        cells += [(int(e), int(t), [int(v) for v in nodes[i * n:(i + 1) * n]]) for i, e in enumerate(tags)]
    surfaces = []
    for dim, group in gmsh.model.getPhysicalGroups(2):
        faces = []
        for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, group):
            for t, tags, nodes in zip(*gmsh.model.mesh.getElements(2, entity)):
                n = len(nodes) // len(tags)
                faces += [set(int(v) for v in nodes[i * n:i * n + (3 if t in (2, 9) else 4)]) for i in range(len(tags))]
        surfaces.append((gmsh.model.getPhysicalName(dim, group), faces))
    gmsh.finalize()
    with open(name + ".inp", "a") as f:
        for surface, faces in surfaces:
            f.write(f"*SURFACE, NAME={surface}, TYPE=ELEMENT\n")
            for face in faces:
                # The first cell (by tag) with this face: a face between two
                # cells ("interface") is given from the lower one's side.
                for tag, t, nodes in sorted(cells):
                    corners = nodes[:CORNERS[t]]
                    for label, abaqus in FACES[CORNERS[t]].items():
                        if set(corners[c - 1] for c in abaqus) == face:
                            break
                    else:
                        continue
                    f.write(f"{tag}, S{label}\n")
                    break
                else:
                    raise SystemExit(f"{name}: no cell has face {face}")
    if meshio_too:  # meshio cannot write Hex27 (no Abaqus name) nor read Prism15 (5.3.5)
        mesh = meshio.read(name + ".msh")
        meshio.write(name + ".meshio.inp", mesh, file_format="abaqus")


make("box_tet", "tet", 1)
make("box_tet_o2", "tet", 2)
make("box_hex", "hex", 1)
make("box_hex20", "hex", 2, complete=False)
make("box_hex27", "hex", 2, meshio_too=False)
make("box_prism", "prism", 1)
make("box_prism15", "prism", 2, complete=False, meshio_too=False)
