"""Extract the feature lines of a mesh and draw them with matplotlib into a PNG.

    pip install ./crates/crestline-py matplotlib
    python examples/python/plot_lines.py crates/crestline-cli/data/fandisk.obj -o fandisk-lines.png

The mesh is drawn as a shaded grey surface, ridges red and valleys blue; sharp creases in the
colour of their family (convex creases, kind "crease-ridge", red; concave ones, "crease-valley",
blue), as `crestline render` draws them, and thicker in the PNG; Polyscope shows each kind as a
curve network of its own. matplotlib has no depth buffer across artists, so lines behind the surface show through; for an interactive view with
proper hidden lines use Polyscope (`pip install polyscope`, then `--polyscope`), or
`crestline.render`, which draws a PNG with hidden lines removed.
"""

import argparse

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection  # noqa: E402

import crestline  # noqa: E402

RED, BLUE = "#d7191c", "#2c7bb6"
# Every kind a line can have: crest lines, and sharp creases in the colour of their family.
COLORS = {"ridge": RED, "valley": BLUE, "crease-ridge": RED, "crease-valley": BLUE}
WIDTHS = {"ridge": 1.5, "valley": 1.5, "crease-ridge": 2.5, "crease-valley": 2.5}


def rgb(color):
    """'#rrggbb' as an (r, g, b) tuple of floats in [0, 1], as Polyscope takes colours."""
    return tuple(int(color[i : i + 2], 16) / 255 for i in (1, 3, 5))


def segments_by_kind(lines):
    """Per kind, the polylines as a list of (k, 3) arrays (closed lines closed again)."""
    out = {}
    for line in lines:
        points = line.points
        if line.closed:
            points = list(points) + [points[0]]
        out.setdefault(line.kind, []).append(points)
    return out


def shade(triangles, light=(0.3, 0.5, 0.8)):
    """A grey per triangle, lighter where it faces the light (two-sided Lambert)."""
    normals = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
    lambert = np.abs(normals @ (np.array(light) / np.linalg.norm(light)))
    grey = 0.55 + 0.4 * lambert
    return np.column_stack([grey, grey, grey])


def plot(vertices, faces, lines, path, elevation=20, azimuth=30):
    fig = plt.figure(figsize=(8, 8))
    ax = fig.add_subplot(projection="3d")
    triangles = vertices[faces]
    surface = Poly3DCollection(triangles, facecolors=shade(triangles), edgecolor="none", alpha=0.5)
    ax.add_collection3d(surface)
    for kind, polylines in segments_by_kind(lines).items():
        ax.add_collection3d(
            Line3DCollection(polylines, colors=COLORS[kind], linewidths=WIDTHS[kind], label=kind)
        )
    low, high = vertices.min(axis=0), vertices.max(axis=0)
    center, half = (low + high) / 2, (high - low).max() / 2
    for axis, c in zip("xyz", center):
        getattr(ax, f"set_{axis}lim")(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=elevation, azim=azimuth, vertical_axis="y")
    ax.set_axis_off()
    ax.legend(loc="upper right")
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)


def show_in_polyscope(vertices, faces, lines):
    import polyscope as ps

    ps.init()
    ps.register_surface_mesh("mesh", vertices, faces)
    for kind, color in COLORS.items():
        chosen = [line for line in lines if line.kind == kind]
        if not chosen:
            continue
        nodes = np.concatenate([line.points for line in chosen])
        edges, start = [], 0
        for line in chosen:
            n = len(line.points)
            edges += [(start + i, start + i + 1) for i in range(n - 1)]
            if line.closed:
                edges.append((start + n - 1, start))
            start += n
        # One network per kind (creases too), each shown or hidden in Polyscope's panel.
        ps.register_curve_network(f"{kind}s", nodes, np.array(edges), color=rgb(color))
    ps.show()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh")
    parser.add_argument("-o", "--output", default="lines.png")
    parser.add_argument("--method", default="hpw", choices=["hpw", "ybs", "saliency"])
    parser.add_argument("--polyscope", action="store_true", help="also open Polyscope's viewer")
    args = parser.parse_args()

    vertices, faces = crestline.read_mesh(args.mesh)
    lines = crestline.extract(vertices, faces, method=args.method)
    print(lines)
    plot(vertices, faces, lines, args.output)
    print(f"wrote {args.output}")
    if args.polyscope:
        show_in_polyscope(vertices, faces, lines)


if __name__ == "__main__":
    main()
