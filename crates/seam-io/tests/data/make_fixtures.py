#!/usr/bin/env python3
"""Writes the Gmsh MSH fixtures of seam-io's tests (run from anywhere).

Every mesh is written in four flavours, `<name>.v22.ascii.msh`, `<name>.v22.bin.msh`,
`<name>.v41.ascii.msh` and `<name>.v41.bin.msh`, and `expected.txt` records what
the tests should find in them (counted with the Gmsh API, areas from the geometry).
The tet, hex, prism and hybrid meshes are also raised to order 2 (`<name>_o2`,
and the incomplete variants `<name>_o2s`); `second_order.txt` records their
element counts and Gmsh's reference nodes of every second-order type.

Needs `pip install gmsh` (tested with Gmsh 4.15). Meshing is single-threaded and
the algorithms are fixed, so re-running gives the same files.
"""

import os

import gmsh

HERE = os.path.dirname(os.path.abspath(__file__))
FLAVOURS = [(2.2, 0, "v22.ascii"), (2.2, 1, "v22.bin"), (4.1, 0, "v41.ascii"), (4.1, 1, "v41.bin")]
TYPE_NAMES = {2: "tri3", 3: "quad4", 4: "tet4", 5: "hex8", 6: "prism6", 7: "pyramid5"}

manifest = []


def new_model(name):
    gmsh.clear()
    gmsh.model.add(name)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)  # Delaunay
    gmsh.option.setNumber("Mesh.RandomSeed", 1)


def set_size(h):
    """Mesh size at every geometry point (Mesh.MeshSizeMax alone does not coarsen
    below Gmsh's default point sizes)."""
    gmsh.model.mesh.setSize(gmsh.model.getEntities(0), h)


def write_flavours(name, with_views=()):
    for version, binary, suffix in FLAVOURS:
        gmsh.option.setNumber("Mesh.MshFileVersion", version)
        gmsh.option.setNumber("Mesh.Binary", binary)
        gmsh.option.setNumber("PostProcessing.SaveMesh", 0)
        path = os.path.join(HERE, f"{name}.{suffix}.msh")
        gmsh.write(path)
        for view in with_views:
            gmsh.view.write(view, path, append=True)


def count_types(dim, entities):
    counts = {}
    for tag in entities:
        types, elements, _ = gmsh.model.mesh.getElements(dim, tag)
        for t, e in zip(types, elements):
            key = TYPE_NAMES.get(t, f"type{t}")
            counts[key] = counts.get(key, 0) + len(e)
    return counts


def group_entities(dim, name):
    for d, tag in gmsh.model.getPhysicalGroups(dim):
        if gmsh.model.getPhysicalName(d, tag) == name:
            return list(gmsh.model.getEntitiesForPhysicalGroup(d, tag))
    raise KeyError(name)


def record_surface(fixture, group, area, centre=None):
    """One `surface` line: counts of the group (or of the volume boundary if None)."""
    if group is None and gmsh.model.getEntities(3):
        volumes = gmsh.model.getEntities(3)
        entities = [t for _, t in gmsh.model.getBoundary(volumes, combined=True, oriented=False)]
    elif group is None:
        entities = [t for _, t in gmsh.model.getEntities(2)]
    else:
        entities = group_entities(2, group)
    counts = count_types(2, entities)
    nodes = len(gmsh.model.mesh.getNodes()[0])
    fields = [f"nodes={nodes}", f"tri3={counts.get('tri3', 0)}", f"quad4={counts.get('quad4', 0)}", f"area={area!r}"]
    if centre is not None:
        fields.append("centre=" + ",".join(repr(float(c)) for c in centre))
    manifest.append(" ".join(["surface", fixture, group or "-"] + fields))


def record_volume(fixture, group):
    entities = [t for _, t in gmsh.model.getEntities(3)] if group is None else group_entities(3, group)
    counts = count_types(3, entities)
    fields = [f"{k}={counts.get(k, 0)}" for k in ("tet4", "hex8", "prism6", "pyramid5")]
    manifest.append(" ".join(["volume", fixture, group or "-"] + fields))


def box_faces(volume):
    """Physical groups "bottom" (z min) and "top" (z max) of a box volume's faces."""
    faces = [t for _, t in gmsh.model.getBoundary([(3, volume)], oriented=False)]
    z = {f: gmsh.model.occ.getCenterOfMass(2, f)[2] for f in faces}
    return min(faces, key=z.get), max(faces, key=z.get)


def square_tri():
    """Unstructured triangles on the unit square; "interface" (7) and the rim lines."""
    new_model("square_tri")
    s = gmsh.model.occ.addRectangle(0, 0, 0, 1, 1)
    gmsh.model.occ.synchronize()
    gmsh.model.addPhysicalGroup(2, [s], tag=7, name="interface")
    gmsh.model.addPhysicalGroup(1, [c for _, c in gmsh.model.getBoundary([(2, s)])], tag=8, name="rim")
    set_size(0.25)
    gmsh.model.mesh.generate(2)
    write_flavours("square_tri")
    record_surface("square_tri", "interface", 1.0)
    record_surface("square_tri", None, 1.0)


def square_mixed():
    """Unit square: left half recombined transfinite quads, right half triangles."""
    new_model("square_mixed")
    occ = gmsh.model.occ
    left = occ.addRectangle(0, 0, 0, 0.5, 1)
    right = occ.addRectangle(0.5, 0, 0, 0.5, 1)
    occ.fragment([(2, left)], [(2, right)])
    occ.synchronize()
    for _, c in gmsh.model.getBoundary([(2, left)], oriented=False):
        gmsh.model.mesh.setTransfiniteCurve(c, 5)
    gmsh.model.mesh.setTransfiniteSurface(left)
    gmsh.model.mesh.setRecombine(2, left)
    gmsh.model.addPhysicalGroup(2, [left, right], tag=3, name="interface")
    set_size(0.25)
    gmsh.model.mesh.generate(2)
    write_flavours("square_mixed")
    record_surface("square_mixed", "interface", 1.0)


def box_tet():
    """Unit box of tetrahedra; "bottom" (1), "top" (2), volume "body" (3)."""
    new_model("box_tet")
    v = gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
    gmsh.model.occ.synchronize()
    bottom, top = box_faces(v)
    gmsh.model.addPhysicalGroup(2, [bottom], tag=1, name="bottom")
    gmsh.model.addPhysicalGroup(2, [top], tag=2, name="top")
    gmsh.model.addPhysicalGroup(3, [v], tag=3, name="body")
    set_size(0.5)
    gmsh.model.mesh.generate(3)
    write_flavours("box_tet")
    centre = (0.5, 0.5, 0.5)
    for group, area in (("top", 1.0), ("bottom", 1.0), (None, 6.0)):
        record_surface("box_tet", group, area, centre)
    record_volume("box_tet", "body")
    record_volume("box_tet", None)


def box_hex():
    """Box 2 x 1 x 1 of 4 x 2 x 2 hexahedra with two node-data views."""
    new_model("box_hex")
    v = gmsh.model.occ.addBox(0, 0, 0, 2, 1, 1)
    gmsh.model.occ.synchronize()
    for _, s in gmsh.model.getBoundary([(3, v)], oriented=False):
        for _, c in gmsh.model.getBoundary([(2, s)], oriented=False):
            xmin, _, _, xmax, _, _ = gmsh.model.getBoundingBox(1, c)
            gmsh.model.mesh.setTransfiniteCurve(c, 5 if xmax - xmin > 1 else 3)
        gmsh.model.mesh.setTransfiniteSurface(s)
        gmsh.model.mesh.setRecombine(2, s)
    gmsh.model.mesh.setTransfiniteVolume(v)
    gmsh.model.mesh.setRecombine(3, v)
    bottom, top = box_faces(v)
    gmsh.model.addPhysicalGroup(2, [bottom], tag=11, name="bottom")
    gmsh.model.addPhysicalGroup(2, [top], tag=12, name="top")
    gmsh.model.addPhysicalGroup(3, [v], tag=13, name="body")
    gmsh.model.mesh.generate(3)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    tags = [int(t) for t in tags]
    coords = [float(x) for x in coords]
    temperature = gmsh.view.add("temperature")
    gmsh.view.addHomogeneousModelData(temperature, 0, "box_hex", "NodeData", tags, [float(t) for t in tags])
    # Step 0 everywhere, then step 1 on the first five nodes only: the reader keeps step 1.
    displacement = gmsh.view.add("displacement")
    step0 = [x * s for i, x in enumerate(coords) for s in [(0.1, 0.2, 0.3)[i % 3]]]
    step1 = [-x for x in coords[:15]]
    for step, t, values in ((0, tags, step0), (1, tags[:5], step1)):
        gmsh.view.addHomogeneousModelData(displacement, step, "box_hex", "NodeData", t, values, numComponents=3)
    write_flavours("box_hex", with_views=(temperature, displacement))
    centre = (1.0, 0.5, 0.5)
    for group, area in (("top", 2.0), ("bottom", 2.0), (None, 10.0)):
        record_surface("box_hex", group, area, centre)
    record_volume("box_hex", None)


def slab_prism():
    """Unit square of triangles extruded by 0.25 in 2 layers: prisms."""
    new_model("slab_prism")
    s = gmsh.model.occ.addRectangle(0, 0, 0, 1, 1)
    out = gmsh.model.occ.extrude([(2, s)], 0, 0, 0.25, numElements=[2], recombine=True)
    gmsh.model.occ.synchronize()
    volume = [t for d, t in out if d == 3][0]
    bottom, top = box_faces(volume)
    gmsh.model.addPhysicalGroup(2, [top], tag=5, name="top")
    gmsh.model.addPhysicalGroup(3, [volume], tag=6, name="body")
    set_size(0.4)
    gmsh.model.mesh.generate(3)
    write_flavours("slab_prism")
    centre = (0.5, 0.5, 0.125)
    record_surface("slab_prism", "top", 1.0, centre)
    record_surface("slab_prism", None, 3.0, centre)
    record_volume("slab_prism", None)


def hybrid_pyramid():
    """Box [0,2]x[0,1]x[0,1]: hexahedra on the left, tetrahedra on the right and
    pyramids where the two meet; "top" (z = 1) is mixed quads and triangles."""
    new_model("hybrid_pyramid")
    occ = gmsh.model.occ
    left = occ.addBox(0, 0, 0, 1, 1, 1)
    right = occ.addBox(1, 0, 0, 1, 1, 1)
    occ.fragment([(3, left)], [(3, right)])
    occ.synchronize()
    for _, s in gmsh.model.getBoundary([(3, left)], oriented=False):
        for _, c in gmsh.model.getBoundary([(2, s)], oriented=False):
            gmsh.model.mesh.setTransfiniteCurve(c, 3)
        gmsh.model.mesh.setTransfiniteSurface(s)
        gmsh.model.mesh.setRecombine(2, s)
    gmsh.model.mesh.setTransfiniteVolume(left)
    gmsh.model.mesh.setRecombine(3, left)
    tops = [box_faces(v)[1] for v in (left, right)]
    gmsh.model.addPhysicalGroup(2, tops, tag=4, name="top")
    gmsh.model.addPhysicalGroup(3, [left, right], tag=9, name="body")
    set_size(0.5)
    gmsh.model.mesh.generate(3)
    write_flavours("hybrid_pyramid")
    centre = (1.0, 0.5, 0.5)
    record_surface("hybrid_pyramid", "top", 2.0, centre)
    record_surface("hybrid_pyramid", None, 10.0, centre)
    record_volume("hybrid_pyramid", None)


def sparse_tags():
    """Triangles on the unit square with node tags 10 t + 3 and element tags 7 t + 100.

    Gmsh keeps these tags in MSH 4.1; its MSH 2.2 writer renumbers 1..n (same order).
    """
    new_model("sparse_tags")
    s = gmsh.model.occ.addRectangle(0, 0, 0, 1, 1)
    gmsh.model.occ.synchronize()
    gmsh.model.addPhysicalGroup(2, [s], tag=1, name="interface")
    set_size(0.34)
    gmsh.model.mesh.generate(2)
    tags = [int(t) for t in gmsh.model.mesh.getNodes()[0]]
    gmsh.model.mesh.renumberNodes(tags, [10 * t + 3 for t in tags])
    _, elements, _ = gmsh.model.mesh.getElements()
    elements = [int(e) for block in elements for e in block]
    gmsh.model.mesh.renumberElements(elements, [7 * e + 100 for e in elements])
    write_flavours("sparse_tags")
    record_surface("sparse_tags", "interface", 1.0)


def square_tri6():
    """Second-order triangles (type 9) in the physical surface "interface"."""
    new_model("square_tri6")
    s = gmsh.model.occ.addRectangle(0, 0, 0, 1, 1)
    gmsh.model.occ.synchronize()
    gmsh.model.addPhysicalGroup(2, [s], tag=1, name="interface")
    set_size(0.6)
    gmsh.model.mesh.generate(2)
    gmsh.model.mesh.setOrder(2)
    write_flavours("square_tri6")


second_order_manifest = []
SECOND_ORDER_TYPES = {}


def raise_order(name, variants):
    """The current model's mesh raised to order 2 and written as `<name>_o2`
    (complete: Tri6, Quad9, Tet10, Hex27, Prism18, Pyramid14) and, with
    `variants` = 2, as `<name>_o2s` too (incomplete, serendipity: Quad8, Hex20,
    Prism15, Pyramid13). Records the element count of each type and every
    type's reference nodes (Gmsh's node order)."""
    for incomplete in range(variants):
        gmsh.model.mesh.setOrder(1)
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", incomplete)
        gmsh.model.mesh.setOrder(2)
        fixture = f"{name}_o2{'s' if incomplete else ''}"
        write_flavours(fixture)
        # What Gmsh writes: the elements of the entities in physical groups.
        counts = {}
        for dim in (2, 3):
            entities = {t for _, g in gmsh.model.getPhysicalGroups(dim)
                        for t in gmsh.model.getEntitiesForPhysicalGroup(dim, g)}
            for tag in sorted(entities):
                types, elements, _ = gmsh.model.mesh.getElements(dim, tag)
                for t, e in zip(types, elements):
                    counts[int(t)] = counts.get(int(t), 0) + len(e)
                    SECOND_ORDER_TYPES[int(t)] = gmsh.model.mesh.getElementProperties(int(t))
        fields = " ".join(f"type{t}={n}" for t, n in sorted(counts.items()))
        second_order_manifest.append(f"{fixture} {fields}")
    gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 0)


def main():
    gmsh.initialize(readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    for make in (square_tri, square_mixed, box_tet, box_hex, slab_prism, hybrid_pyramid, sparse_tags, square_tri6):
        make()
        # Second order: Tet10 has no incomplete variant; the others have one.
        variants = {box_tet: 1, box_hex: 2, slab_prism: 2, hybrid_pyramid: 2}.get(make, 0)
        if variants:
            raise_order(make.__name__, variants)
    gmsh.finalize()
    with open(os.path.join(HERE, "second_order.txt"), "w") as f:
        f.write("# written by make_fixtures.py: the second-order fixtures and their elements\n")
        f.write("# <fixture> type<gmsh type>=<count> ...   (2D and 3D elements)\n")
        f.write("\n".join(second_order_manifest) + "\n")
        f.write("# reference nodes of each type, Gmsh's node order: ref <type> <name> <u,v,w;...>\n")
        for t, (name, dim, _, n, local, _) in sorted(SECOND_ORDER_TYPES.items()):
            coords = [float(x) for x in local]
            nodes = ";".join(",".join(repr(c) for c in coords[i * dim:(i + 1) * dim]) for i in range(n))
            f.write(f"ref {t} {name.replace(' ', '_')} {nodes}\n")
    with open(os.path.join(HERE, "expected.txt"), "w") as f:
        f.write("# written by make_fixtures.py: what the tests expect to read from the fixtures\n")
        f.write("# surface <fixture> <group|-> nodes= tri3= quad4= area= [centre=x,y,z]\n")
        f.write("# volume <fixture> <group|-> tet4= hex8= prism6= pyramid5=\n")
        f.write("\n".join(manifest) + "\n")


if __name__ == "__main__":
    main()
