"""Type stubs of the compiled module ``crestline._crestline`` (re-exported by ``crestline``)."""

import os
from typing import Any, Iterator, Literal, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str

PathLike = Union[str, "os.PathLike[str]"]
Method = Literal["hpw", "ybs", "saliency"]
Estimator = Literal["jet-fit", "shape-operator", "cubic-fit"]
LinesFormat = Literal["obj", "ply", "json"]
Creases = Union[Literal["auto", "off"], float]

class Line:
    """One feature line."""

    kind: str
    """"ridge", "valley", "crease-ridge" or "crease-valley" (sharp edges of the mesh)."""
    points: npt.NDArray[np.float64]
    """(k, 3) points in order; a closed line does not repeat its first point."""
    closed: bool
    """True when the last point joins the first."""
    length: float
    """Length in model units."""
    strength: float
    """The strength T = ∫ds · ∫C ds of YBS eq. 5 (scale independent)."""
    curvature_integral: float
    """Integral of |k| along the line."""
    def __reduce__(self) -> Tuple[Any, ...]: ...

class Lines:
    """Feature lines found on a mesh (or read from a file).

    ``len(lines)``, ``lines[i]`` and ``for line in lines`` give ``Line`` objects; ``lines[i:j]``
    (any slice) gives a ``Lines`` of those lines, without ``stats``. All lines at once:
    ``points`` with ``offsets`` (line i is ``points[offsets[i]:offsets[i+1]]``), and per line
    ``kinds``, ``lengths``, ``strengths``, ``curvature_integrals``, ``closed``. ``pickle`` and
    ``copy`` keep everything, the lines' places on the mesh too.
    """

    def __len__(self) -> int: ...
    @overload
    def __getitem__(self, index: int) -> Line: ...
    @overload
    def __getitem__(self, index: slice) -> "Lines": ...
    def __iter__(self) -> Iterator[Line]: ...
    def __reduce__(self) -> Tuple[Any, ...]: ...
    @property
    def points(self) -> npt.NDArray[np.float64]:
        """Every point of every line, line after line: (N, 3) float64."""
    @property
    def offsets(self) -> npt.NDArray[np.int64]:
        """Where each line starts in ``points``, then the number of points: len(lines) + 1 int64."""
    @property
    def kinds(self) -> list[str]:
        """The kind of each line ("ridge", "valley", "crease-ridge", "crease-valley")."""
    @property
    def lengths(self) -> npt.NDArray[np.float64]:
        """The length of each line."""
    @property
    def strengths(self) -> npt.NDArray[np.float64]:
        """The strength T of each line (0 for lines read from OBJ)."""
    @property
    def curvature_integrals(self) -> npt.NDArray[np.float64]:
        """The integral of |k| along each line (0 for lines read from OBJ)."""
    @property
    def closed(self) -> npt.NDArray[np.bool_]:
        """Whether each line is closed."""
    @property
    def total_length(self) -> float:
        """The sum of the lengths."""
    @property
    def stats(self) -> Optional[dict]:
        """Figures about the extraction (as ``crestline extract --stats json``, without the times
        of reading and writing files), a copy each time; None for lines read from a file or
        sliced out of others. ``ridges`` and ``valleys`` count crest lines only,
        ``crease_ridges`` and ``crease_valleys`` the convex and concave creases, as the JSON
        lines file does; ``creases`` is their sum."""
    def write(self, path: PathLike, format: Optional[LinesFormat] = None) -> None:
        """Writes the lines as OBJ, PLY (binary) or JSON, chosen by ``format`` or the extension."""

def read_mesh(
    path: PathLike, format: Optional[Literal["obj", "ply", "off", "stl"]] = None
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]:
    """Reads a mesh file: (vertices (n, 3) float64, faces (m, 3) int64), in file order.

    Raises ValueError for a malformed file, OSError when it cannot be read.
    """

def read_lines(path: PathLike, format: Optional[LinesFormat] = None) -> Lines:
    """Reads feature lines from an OBJ, PLY or JSON file as ``Lines.write`` and ``crestline extract``
    write them, with kinds and strengths; the format follows the extension unless ``format`` names it.

    Raises ValueError for a malformed file or an unknown format, OSError when it cannot be read.
    """

def extract(
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    method: Method = "hpw",
    *,
    threshold: Union[float, Literal["auto"], None] = None,
    min_length: Optional[float] = None,
    smooth_steps: Optional[int] = None,
    smooth_time: Optional[float] = None,
    smooth_along: Optional[float] = None,
    crease_angle: Optional[float] = None,
    creases: Optional[Creases] = None,
    direction_support: Optional[float] = None,
    fair: Optional[float] = None,
    pre_smooth: Optional[int] = None,
    estimator: Optional[Estimator] = None,
    radius: Optional[float] = None,
    degree: Optional[int] = None,
    no_noise_adaptation: bool = False,
    rings: Optional[int] = None,
    mask: Optional[npt.ArrayLike] = None,
    mask_spheres: Optional[Union[Sequence[Sequence[float]], npt.ArrayLike]] = None,
    mask_boxes: Optional[Union[Sequence[Sequence[float]], npt.ArrayLike]] = None,
    no_gaps: bool = False,
    keep_orientation: bool = False,
    no_weld: bool = False,
    no_twicing: bool = False,
    no_debias: bool = False,
    keep_unlocated: bool = False,
    keep_outliers: bool = False,
) -> Lines:
    """Finds the ridges and valleys of the mesh (vertices, faces).

    Options and defaults are those of ``crestline extract``, each named as its flag with ``-``
    written ``_`` (``mask_spheres`` and ``mask_boxes`` hold the repeated ``--mask-sphere`` and
    ``--mask-box``); None means the method's default:

    - method: "hpw" (default), "ybs" or "saliency".
    - threshold: a number or "auto". HPW: strength T, default 1; YBS and saliency: "auto".
    - min_length: fraction of the bounding-box diagonal, of the largest part when the mesh
      has several (default 0.01).
    - smooth_steps (default 2, run on noisy surfaces; a number always runs them; at most 1000), smooth_time
      (default 1, relative to the squared mean edge length).
    - smooth_along: on meshes whose noise the jet fit finds white, the extremality smoothing
      runs up to this many times faster along the lines than across (default 3; 1 is HPW's
      isotropic smoothing); other meshes are smoothed isotropically.
    - crease_angle: degrees (default 0.3 rad, about 17.2; 0 with no_twicing is HPW's plain smoothing).
    - creases: sharp creases, "auto" (default: above the gap in the histogram of dihedral
      angles; on a noisy mesh without one, the gap between face normals filtered within the
      faces; none on scans of smooth shapes), "off", or a dihedral angle in degrees.
    - fair: fairing tolerance as a fraction of the diagonal (off).
    - no_debias: leave the crest lines where they are traced. By default, on
      meshes the jet fit finds noisy, they are moved across by the displacement its widened
      disc causes and, on white noise, by the drift the extremality smoothing measures of
      itself.
    - keep_unlocated: keep the lines the noise moves about, and their ends (HPW and YBS with
      the jet fit; by default, on meshes the jet fit finds white noise on, the lines whose
      extremality crosses zero less than twice as steeply as its estimation noise are dropped,
      and such ends cut off the lines kept).
    - keep_outliers: take every vertex as it is (by default isolated outlier vertices, the
      spikes scanners leave, are put back on the surface of their neighbours first, so that
      they are not ringed with creases and crest lines; stats["outliers_moved"] counts them).
    - pre_smooth: mean-curvature-flow steps first (off; at most 1000).
    - estimator: "jet-fit" (default), "shape-operator" or "cubic-fit". Options of another
      estimator than the one that runs raise ValueError, as on the command line:
    - radius, degree, no_noise_adaptation (jet fit): the disc radius in sample spacings
      (default 2.5, grown on noisy meshes unless no_noise_adaptation), the degree (3 or 4, default 4).
    - rings (cubic fit): the k-ring (1 to 8); selects the cubic fit unless estimator is given.
    - direction_support (shape operator): default 0.5 (0 is the paper's operator).
    - mask, mask_spheres, mask_boxes: per-vertex diffusion factors and regions scaling them
      (rows (x, y, z, r, factor) and (x0, y0, z0, x1, y1, z1, factor): tuples, lists or a numpy array).
    - no_gaps: turn off YBS's gap jumping (method "ybs" only; ValueError otherwise).
    - keep_orientation: keep the winding (default: triangles wound against their neighbours, then
      closed surfaces facing inward, are reversed).
    - no_twicing: plain extremality smoothing as HPW's (default: twiced, the residual smoothed
      and added back, which removes the drift of the zeros).
    - no_weld: keep vertices at the same position apart (default: they are made one first, as
      ``crestline extract`` does; the mask still has one value per vertex given).

    Raises TypeError for arguments of the wrong type (a string or floats where vertex indices are
    needed, a float where a count is), ValueError for bad values (shape, NaN, index out of range,
    a negative count, a mesh without triangles) or options (out of range, or unused by the method
    and estimator that run). The GIL is released during the work; Ctrl-C raises
    KeyboardInterrupt when the stage running ends.
    """

def curvature(
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    estimator: Optional[Estimator] = None,
    *,
    rings: Optional[int] = None,
    radius: Optional[float] = None,
    degree: Optional[int] = None,
    no_noise_adaptation: bool = False,
    direction_support: Optional[float] = None,
    creases: Optional[Creases] = None,
    keep_outliers: bool = False,
    keep_orientation: bool = False,
    no_weld: bool = False,
) -> dict[str, npt.NDArray[Any]]:
    """Per-vertex curvature: "k_max", "k_min", "e_max", "e_min" (n,), "dir_max", "dir_min", "normals" (n, 3).

    One row per vertex given; vertices at the same position are estimated as one (welded)
    unless no_weld.

    Options named and defaulted as the flags of ``crestline curvature``: the jet fit (the cubic
    fit when rings is given), rings 1, radius 2.5, degree 4, direction_support 0.5 (shape
    operator), creases "auto" (the jet fit does not reach across the sharp creases found above
    the gap in the histogram of dihedral angles, or between filtered normals on a noisy mesh;
    "off", or an angle in degrees). Isolated outlier vertices (spikes) are put back on their
    neighbours' surface before the estimation unless keep_outliers, as in ``extract``: the fields
    are those of the surface so repaired, and "outliers" (n,), a bool array, is true at the
    vertices put back. An option of
    another estimator than the one that runs raises ValueError, as does a negative rings or degree.
    """

def simplify(
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    lines: Optional[Lines] = None,
    *,
    ratio: Optional[float] = None,
    target_faces: Optional[int] = None,
    eta: Optional[float] = None,
    eps: Optional[float] = None,
    keep_orientation: bool = False,
    no_weld: bool = False,
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]:
    """Feature-guided QEM simplification (YBS eq. 7): ratio 0.1, eta 1, eps 0.1 by default;
    target_faces is the command line's ``--faces``.

    Vertices at one position are made one first unless no_weld.

    Without ``lines`` they are extracted with the default method (unless eta is 0); Ctrl-C
    interrupts that extraction at its next stage. A negative target_faces raises ValueError.
    """

def feature_distance(
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    lines: Optional[Lines] = None,
    *,
    edges_only: bool = False,
    keep_orientation: bool = False,
    no_weld: bool = False,
) -> npt.NDArray[np.float64]:
    """Geodesic distance from every vertex given to the nearest line (inf where none is reached).

    Vertices at one position are made one first unless no_weld; each copy gets its distance.
    Without ``lines`` they are extracted with the default method; Ctrl-C interrupts that
    extraction at its next stage.
    """

def render(
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    lines: Optional[Lines] = None,
    field: Optional[npt.ArrayLike] = None,
    path: Optional[PathLike] = None,
    *,
    view: Optional[Union[Sequence[float], npt.ArrayLike]] = None,
    size: Optional[Union[Sequence[int], npt.ArrayLike]] = None,
    up: Literal["auto", "y", "z"] = "auto",
    colormap: Literal["auto", "viridis", "diverging"] = "auto",
    field_range: Union[float, Sequence[float], npt.ArrayLike, None] = None,
    line_width: Optional[float] = None,
    no_ridges: bool = False,
    no_valleys: bool = False,
    no_legend: bool = False,
    legend_title: Optional[str] = None,
    wireframe: bool = False,
) -> Optional[bytes]:
    """A picture of the mesh, its lines and a field: PNG bytes, or a .png/.svg/.html file at ``path``.

    view (azimuth, elevation) and size (width, height) are sequences of two numbers (tuples,
    lists, numpy arrays); a negative size raises ValueError.

    Defaults as ``crestline render``: view (30, 20), size (1024, 1024), line width 2.5, colours
    clipped to the 2nd and 98th percentiles of the field (``field_range=p`` for the p-th, 0 for
    the whole range, or ``(min, max)``), up axis
    guessed from the mesh ("auto": "z" when it stands on a flat base along Z, else "y"), no
    wireframe (``wireframe=True`` draws the mesh's edges, hidden ones hidden; PNG and SVG).
    The mesh is drawn as given (neither welded nor turned); ``field`` has one value per vertex.
    """
