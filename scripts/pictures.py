#!/usr/bin/env python3
"""The pictures of docs/examples.md: a field transferred across the curved, non-matching
interface of `seam example operator`, and the coverage / normal-gap map of
`seam check` on the same interface.

usage: python3 scripts/pictures.py [--seam target/release/seam] [--out docs]

Needs pyvista and vtk (pip install pyvista vtk); renders off-screen, no display.
"""
import argparse
import pathlib
import subprocess
import tempfile

import pyvista as pv


def run(seam, *args):
    subprocess.run([seam, *args], check=True, stdout=subprocess.DEVNULL)


def render(mesh, scalars, bar, title, path, overlay=None, cmap="viridis"):
    """One picture: `mesh` coloured by `scalars` with its quads' edges, and the
    edges of `overlay` (the master mesh) drawn thin on top."""
    p = pv.Plotter(off_screen=True, window_size=(1000, 760))
    p.set_background("white")
    p.add_mesh(
        mesh,
        scalars=scalars,
        cmap=cmap,
        show_edges=True,
        edge_color="#303030",
        line_width=0.8,
        scalar_bar_args={
            "title": bar,
            "color": "black",
            "vertical": False,
            "position_x": 0.2,
            "position_y": 0.04,
            "width": 0.6,
            "title_font_size": 16,
            "label_font_size": 14,
        },
    )
    if overlay is not None:
        p.add_mesh(overlay, style="wireframe", color="white", line_width=0.6, opacity=0.7)
    p.add_text(title, position="upper_edge", font_size=12, color="black")
    p.view_vector((1.0, 0.9, 0.35), viewup=(0, 0, 1))
    p.reset_camera()
    p.camera.zoom(1.2)
    p.screenshot(str(path))
    p.close()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seam", default="target/release/seam")
    ap.add_argument("--out", default="docs")
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    pv.OFF_SCREEN = True
    with tempfile.TemporaryDirectory() as tmp:
        t = pathlib.Path(tmp)
        run(a.seam, "example", "operator", "-o", str(t / "ex"))
        master, slave = str(t / "ex/master.msh"), str(t / "ex/slave.msh")
        run(a.seam, "transfer", master, slave, "-o", str(t / "f.vtu"), "--expr", "sin(4*z)*y + x", "--name", "f")
        run(a.seam, "check", master, slave, "--vtu", str(t / "check.vtu"))
        field = pv.read(t / "f.vtu")
        gap = pv.read(t / "check.vtu")
        gap.point_data["gap"] = 1e3 * gap.point_data["normal_gap"]
        # The master's triangles, for the overlay: written by seam itself as VTU.
        run(a.seam, "transfer", slave, master, "-o", str(t / "master.vtu"), "--expr", "0")
        master_mesh = pv.read(t / "master.vtu")
        render(
            field,
            "f",
            "f",
            "f = sin 4z·y + x: master triangles (white) to slave quads",
            out / "transfer.png",
            overlay=master_mesh,
        )
        render(
            gap,
            "gap",
            "normal gap × 1000",
            "seam check: signed normal gap per slave node",
            out / "gap.png",
            overlay=master_mesh,
            cmap="coolwarm",
        )
    print("wrote", out / "transfer.png", out / "gap.png")


if __name__ == "__main__":
    main()
