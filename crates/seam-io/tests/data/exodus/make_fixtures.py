"""Writes the Exodus II fixtures of crates/seam-io/tests/exodus.rs with real tools.

    apt-get install libexodusii-dev libnetcdf-dev
    python3 -m venv /tmp/hv && /tmp/hv/bin/pip install gmsh meshio netCDF4 numpy
    /tmp/hv/bin/python make_fixtures.py

Every file but the meshio ones is written by the SEACAS Exodus library
(libexodusII 6.02, Debian's libexodusii-dev) through exo_write.c, which also
prints the nodes of each side as the library's ex_get_side_set_node_list
gives them:

- sides.txt: for every element type seam reads, the nodes (1-based) of each side, from a one-element file with
  one side set per side. libexodusII 6.02 counts one node too many for the
  triangular sides of WEDGE15/18 and PYRAMID13/14 (the extra value is
  garbage): the lines keep the 6 nodes of a quadratic triangle. These lists
  place every node of the higher-order types here (an edge node at the
  midpoint of the corners its side lists it between, a face centre at the
  centre of its side (WEDGE18's three, which the library leaves out, as
  FACE_CENTRES says); the one node no side lists, HEX27's 21 and PYRAMID14's
  14, at the cell's centre and at the base's centre).
- cube_TYPE.e / .exo / .ex2 / .g: one element of each type (the unit cube
  for hexahedra; the corner tetrahedron, wedge and pyramid of it), node ids
  100 + 7 i, element id 42, block 5 "body", side sets 1…n ("side1"…) each
  holding one side; flavours classic, 64-bit offset and NetCDF-4 in turn.
- box_NAME.seacas.*: the meshes ../abaqus/box_NAME.msh (Gmsh's) with
  Gmsh's node and element tags as node_num_map / elem_num_map, blocks 1
  "lower" and 2 "upper", side sets 10 "top" and 20 "interface" (each face
  from the first cell by tag that has it); box_hex in all three flavours.
- glue_lower.msh / glue_lower.e (classic) and glue_upper.msh /
  glue_upper.exo (NetCDF-4): two hexahedral blocks, [0,1]²×[0,½] cut 3×3×2
  and [0,1]²×[½,1] cut 4×4×2 (non-matching at z = ½), meshed by Gmsh with
  the surfaces "bottom", "top", "xmin", "ymin" (one block "body", id 1;
  side sets 1…4 in that order), for the CLI's glued case.
- cube_TETRA14.e: one element of a type whose node order seam does not
  know (TETRA14; its nodes on a line) and a side set "side1" on it, for
  the refusal by name.
- huge_counts.ex2: dimensions of 2^40 nodes and elements in a small NetCDF-4 file.
- box_NAME.meshio.exo: the same .msh read and written by meshio's Exodus
  writer (NetCDF-4, blocks numbered from 0 without names, no side sets,
  the Gmsh surface triangles and quadrangles as TRI3 / QUAD blocks) for the
  types whose Exodus order is Gmsh's or VTK's (meshio does not reorder).
"""
import os
import subprocess
import tempfile

import gmsh
import meshio
import netCDF4
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
EXO = os.path.join(tempfile.mkdtemp(), "exo_write")
subprocess.run(["cc", "-O", "-o", EXO, os.path.join(HERE, "exo_write.c"), "-lexoIIv2c", "-lnetcdf"], check=True)
FLAVOURS = [("classic", "e"), ("64bit", "exo"), ("netcdf4", "ex2")]

TYPES = {  # Exodus type -> (node count, side count, corner coordinates)
    "TETRA4": (4, 4, [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]),
    "TETRA10": (10, 4, None),
    "HEX8": (8, 6, [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]),
    "HEX20": (20, 6, None),
    "HEX27": (27, 6, None),
    "WEDGE6": (6, 5, [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (0, 1, 1)]),
    "WEDGE15": (15, 5, None),
    "WEDGE18": (18, 5, None),
    "PYRAMID5": (5, 5, [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 0.5, 1)]),
    "PYRAMID13": (13, 5, None),
    "PYRAMID14": (14, 5, None),
}
LINEAR = {"TETRA": "TETRA4", "HEX": "HEX8", "WEDGE": "WEDGE6", "PYRAMID": "PYRAMID5"}
# Face-centre nodes the library's side lists leave out, node (1-based) ->
# side: WEDGE18's as SEACAS's IOSS places them (Ioss_Wedge18.C,
# face_node_order) and libMesh's Prism18 does.
FACE_CENTRES = {"WEDGE18": {16: 1, 17: 2, 18: 3}}


def family(t):
    return LINEAR[t.rstrip("0123456789")]


def write(path, flavour, nodes, blocks, side_sets):
    """nodes: [(id, (x, y, z))]; blocks: [(id, name, type, [(elem id, [node positions])])];
    side_sets: [(id, name, [(element position, side)])]. Returns the side lines."""
    lines = [str(len(nodes))] + [f"{i} {x!r} {y!r} {z!r}" for i, (x, y, z) in nodes]
    lines.append(str(len(blocks)))
    for bid, name, t, elems in blocks:
        lines.append(f"{bid} {name} {t} {len(elems[0][1])} {len(elems)}")
        lines += [" ".join(str(v) for v in [e] + conn) for e, conn in elems]
    lines.append(str(len(side_sets)))
    for sid, name, sides in side_sets:
        lines.append(f"{sid} {name} {len(sides)}")
        lines += [f"{e} {s}" for e, s in sides]
    out = subprocess.run([EXO, path, flavour], input="\n".join(lines) + "\n", capture_output=True, text=True, check=True)
    return out.stdout.splitlines()


# 1. The library's side node lists.
SIDES = {}
with open(os.path.join(HERE, "sides.txt"), "w") as f:
    f.write("# type side: nodes (1-based), from libexodusII's ex_get_side_set_node_list (make_fixtures.py)\n")
    for t, (n, n_sides, _) in TYPES.items():
        nodes = [(i + 1, (0.0, 0.0, float(i))) for i in range(n)]
        sets = [(s, f"side{s}", [(1, s)]) for s in range(1, n_sides + 1)]
        out = write(os.path.join(tempfile.mkdtemp(), "probe.e"), "classic", nodes, [(1, "b", t, [(1, list(range(1, n + 1)))])], sets)
        SIDES[t] = []
        for line in out:
            values = [int(v) for v in line.split(":")[1].split()]
            corners = 3 if len(set(values[:4])) < 4 or values[3] > TYPES[family(t)][0] else 4
            # A triangle: 3 corners, then 3 edge nodes for a quadratic type.
            keep = {3: 3 if n in (4, 5, 6) else 6, 4: 4 if n in (5, 8, 6) else (9 if len(values) >= 9 else 8)}[corners]
            SIDES[t].append(values[:keep])
            f.write(f"{t} {len(SIDES[t])}: {' '.join(map(str, values[:keep]))}\n")


def positions(t):
    """Each node's place: ('corner', i) | ('edge', a, b) | ('face', side) | ('left',)."""
    n = TYPES[t][0]
    corners = TYPES[family(t)][0]
    place = {i: ("corner", i) for i in range(corners)}
    for k, side in enumerate(SIDES[t]):
        nc = 3 if len(side) in (3, 6) else 4
        c = [v - 1 for v in side[:nc]]
        for j, v in enumerate(side[nc:]):
            place[v - 1] = ("edge", c[j], c[(j + 1) % nc]) if j < nc else ("face", k)
    for v, side in FACE_CENTRES.get(t, {}).items():
        place[v - 1] = ("face", side - 1)
    return [place.get(i, ("left",)) for i in range(n)]


def node_coordinates(t, corners):
    """The nodes of one element of type t with these corners (straight sides)."""
    corners = [np.array(c, float) for c in corners]
    out = []
    for p in positions(t):
        if p[0] == "corner":
            out.append(corners[p[1]])
        elif p[0] == "edge":
            out.append((corners[p[1]] + corners[p[2]]) / 2)
        elif p[0] == "face":
            side = SIDES[t][p[1]]
            nc = 3 if len(side) in (3, 6) else 4
            out.append(sum(corners[v - 1] for v in side[:nc]) / nc)
        elif family(t) == "PYRAMID5":
            out.append(sum(corners[:4]) / 4)  # PYRAMID14: the base's centre
        else:
            out.append(sum(corners) / len(corners))  # HEX27: the centre
    return out


# 2. One element of each type.
for k, (t, (n, n_sides, _)) in enumerate(TYPES.items()):
    flavour, ext = FLAVOURS[k % 3]
    if t == "PYRAMID5":
        ext = "g"
    coords = node_coordinates(t, TYPES[family(t)][2])
    nodes = [(100 + 7 * i, tuple(float(c) for c in x)) for i, x in enumerate(coords)]
    sets = [(s, f"side{s}", [(1, s)]) for s in range(1, n_sides + 1)]
    write(os.path.join(HERE, f"cube_{t}.{ext}"), flavour, nodes, [(5, "body", t, [(42, list(range(1, n + 1)))])], sets)

# 3. Gmsh's meshes.
GMSH_TYPES = {4: "TETRA4", 11: "TETRA10", 5: "HEX8", 17: "HEX20", 12: "HEX27", 6: "WEDGE6", 18: "WEDGE15"}


def exodus_of_gmsh(volumes, surfaces):
    """The current Gmsh model's nodes, blocks (id, physical volume name) and
    side sets (id, physical surface name) for write()."""
    tags, xyz, _ = gmsh.model.mesh.getNodes()
    tags = [int(v) for v in tags]
    point = {tag: np.array(xyz[3 * i:3 * i + 3]) for i, tag in enumerate(tags)}
    index = {tag: i + 1 for i, tag in enumerate(tags)}

    def physical(dim, group):
        return [g for d, g in gmsh.model.getPhysicalGroups(dim) if gmsh.model.getPhysicalName(dim, g) == group][0]

    blocks = []
    for bid, group in volumes:
        elems = []
        for entity in gmsh.model.getEntitiesForPhysicalGroup(3, physical(3, group)):
            for gt, etags, enodes in zip(*gmsh.model.mesh.getElements(3, entity)):
                t = GMSH_TYPES[int(gt)]
                n = TYPES[t][0]
                for i, e in enumerate(etags):
                    cell = [int(v) for v in enodes[i * n:(i + 1) * n]]
                    corners = [point[v] for v in cell[:TYPES[family(t)][0]]]
                    # Each Exodus node is the Gmsh node at its place.
                    conn = []
                    for x in node_coordinates(t, corners):
                        found = [v for v in cell if np.allclose(point[v], x, atol=1e-12)]
                        assert len(found) == 1, (e, x)
                        conn.append(index[found[0]])
                    elems.append((int(e), conn))
        blocks.append((bid, group, t, sorted(elems)))
    order = [(e, b[2], conn) for b in blocks for e, conn in b[3]]
    side_sets = []
    for sid, group in surfaces:
        sides = []
        for entity in gmsh.model.getEntitiesForPhysicalGroup(2, physical(2, group)):
            for gt, etags, enodes in zip(*gmsh.model.mesh.getElements(2, entity)):
                nc = 3 if int(gt) in (2, 9) else 4
                n = len(enodes) // len(etags)
                for i in range(len(etags)):
                    face = {index[int(v)] for v in enodes[i * n:i * n + nc]}
                    hit = None
                    for pos, (e, t, conn) in sorted(enumerate(order), key=lambda p: p[1][0]):
                        for s, side in enumerate(SIDES[t]):
                            snc = 3 if len(side) in (3, 6) else 4
                            if {conn[v - 1] for v in side[:snc]} == face:
                                hit = (pos + 1, s + 1)
                                break
                        if hit:
                            break
                    assert hit, (group, face)
                    sides.append(hit)
        side_sets.append((sid, group, sides))
    nodes = [(tag, tuple(float(c) for c in point[tag])) for tag in tags]
    return nodes, blocks, side_sets


BOXES = ["box_tet", "box_tet_o2", "box_hex", "box_hex20", "box_hex27", "box_prism", "box_prism15"]
for k, name in enumerate(BOXES):
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.open(os.path.join(HERE, "..", "abaqus", name + ".msh"))
    nodes, blocks, side_sets = exodus_of_gmsh([(1, "lower"), (2, "upper")], [(10, "top"), (20, "interface")])
    gmsh.finalize()
    flavours = FLAVOURS if name == "box_hex" else [FLAVOURS[k % 3]]
    for flavour, ext in flavours:
        write(os.path.join(HERE, f"{name}.seacas.{ext}"), flavour, nodes, blocks, side_sets)
    if name in ("box_tet", "box_tet_o2", "box_hex", "box_prism"):
        mesh = meshio.read(os.path.join(HERE, "..", "abaqus", name + ".msh"))
        meshio.write(os.path.join(HERE, name + ".meshio.exo"), mesh, file_format="exodus")

# 4. The glued blocks.
for name, z0, n, (flavour, ext) in [("glue_lower", 0.0, 3, FLAVOURS[0]), ("glue_upper", 0.5, 4, FLAVOURS[2])]:
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add(name)
    gmsh.model.occ.addBox(0, 0, z0, 1, 1, 0.5)
    gmsh.model.occ.synchronize()
    for dim, tag in gmsh.model.getEntities(1):
        lo = gmsh.model.getBoundingBox(dim, tag)
        gmsh.model.mesh.setTransfiniteCurve(tag, 3 if abs(lo[5] - lo[2]) > 1e-6 else n + 1)
    for dim, tag in gmsh.model.getEntities(2):
        gmsh.model.mesh.setTransfiniteSurface(tag)
        gmsh.model.mesh.setRecombine(2, tag)
    gmsh.model.mesh.setTransfiniteVolume(1)
    gmsh.model.addPhysicalGroup(3, [1], 1, name="body")
    planes = {"bottom": (2, z0), "top": (2, z0 + 0.5), "xmin": (0, 0.0), "ymin": (1, 0.0)}
    for i, (group, (axis, value)) in enumerate(planes.items()):
        for dim, tag in gmsh.model.getEntities(2):
            box = gmsh.model.getBoundingBox(dim, tag)
            if abs(box[axis] - value) < 1e-6 and abs(box[axis + 3] - value) < 1e-6:
                gmsh.model.addPhysicalGroup(2, [tag], i + 1, name=group)
    gmsh.model.mesh.generate(3)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.write(os.path.join(HERE, name + ".msh"))
    nodes, blocks, side_sets = exodus_of_gmsh([(1, "body")], [(i + 1, g) for i, g in enumerate(planes)])
    gmsh.finalize()
    write(os.path.join(HERE, f"{name}.{ext}"), flavour, nodes, blocks, side_sets)

# 5. A NetCDF-4 file whose dimensions declare more elements than any file of
# its size holds (netCDF4's writer: no variable needs the space).
with netCDF4.Dataset(os.path.join(HERE, "huge_counts.ex2"), "w", format="NETCDF4") as nc:
    nc.createDimension("num_dim", 3)
    nc.createDimension("num_nodes", 2**40)
    nc.createDimension("num_elem", 2**40)
    nc.createDimension("num_el_blk", 1)
    nc.createDimension("num_el_in_blk1", 2**40)
    nc.createDimension("num_nod_per_el1", 8)

# 6. A type seam refuses by name.
write(os.path.join(HERE, "cube_TETRA14.e"), "classic", [(i + 1, (0.0, 0.0, float(i))) for i in range(14)],
      [(5, "body", "TETRA14", [(42, list(range(1, 15)))])], [(1, "side1", [(1, 1)])])
