"""Ridges, valleys and crest lines on triangle meshes: numpy arrays in, numpy arrays out.

>>> import crestline
>>> vertices, faces = crestline.read_mesh("fandisk.obj")
>>> lines = crestline.extract(vertices, faces)          # HPW, the command line's defaults
>>> lines.points, lines.offsets, lines.kinds            # all lines as flat arrays
>>> lines.write("lines.obj")

Every function takes any array-like (a ``trimesh.Trimesh``'s ``.vertices`` and ``.faces`` as
they are, float32 and int32 too), releases the GIL while it works, and raises ``TypeError``
for arguments of the wrong type (a string where an array is needed, floats where vertex
indices are) and ``ValueError`` for bad values (a wrong shape, NaN, a negative count). Ctrl-C
stops an extraction at its next stage. ``Lines`` slice (``lines[:10]``) and pickle. Names and
defaults are those of the ``crestline`` command-line tool.
"""

from ._crestline import (
    Line,
    Lines,
    __version__,
    curvature,
    extract,
    feature_distance,
    read_lines,
    read_mesh,
    render,
    simplify,
)

__all__ = [
    "Line",
    "Lines",
    "__version__",
    "curvature",
    "extract",
    "feature_distance",
    "read_lines",
    "read_mesh",
    "render",
    "simplify",
]
