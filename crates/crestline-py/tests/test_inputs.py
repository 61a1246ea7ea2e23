"""What the functions accept: dtypes, layouts, array-likes; and what they refuse."""

import numpy as np
import pytest

import crestline
from conftest import FANDISK, case_path, tetrahedron


def same_lines(a, b):
    assert a.kinds == b.kinds
    np.testing.assert_array_equal(a.offsets, b.offsets)
    np.testing.assert_array_equal(a.points, b.points)
    np.testing.assert_array_equal(a.strengths, b.strengths)


@pytest.fixture(scope="module")
def mesh():
    return crestline.read_mesh(case_path("bumpy/reg5k"))


@pytest.fixture(scope="module")
def reference(mesh):
    return crestline.extract(*mesh)


def test_read_mesh_gives_float64_and_int64(mesh):
    vertices, faces = mesh
    assert vertices.dtype == np.float64 and vertices.shape == (2562, 3)
    assert faces.dtype == np.int64 and faces.shape == (5120, 3)
    assert vertices.flags.c_contiguous and faces.flags.c_contiguous


def test_int32_and_unsigned_faces(mesh, reference):
    vertices, faces = mesh
    for dtype in (np.int32, np.uint32, np.uint64):
        same_lines(crestline.extract(vertices, faces.astype(dtype)), reference)


def test_float32_vertices(mesh):
    vertices, faces = mesh
    single = vertices.astype(np.float32)
    # float32 is read as it is, so the result is that of its values in float64.
    same_lines(
        crestline.extract(single, faces),
        crestline.extract(single.astype(np.float64), faces),
    )


def test_non_contiguous_arrays(mesh, reference):
    vertices, faces = mesh
    fortran_v, fortran_f = np.asfortranarray(vertices), np.asfortranarray(faces)
    assert not fortran_v.flags.c_contiguous
    same_lines(crestline.extract(fortran_v, fortran_f), reference)
    # Every other column of a wider array, and a reversed view of the faces' rows.
    wide = np.zeros((len(vertices), 6))
    wide[:, ::2] = vertices
    strided = wide[:, ::2]
    assert not strided.flags.c_contiguous
    reversed_faces = faces[::-1][::-1]
    same_lines(crestline.extract(strided, reversed_faces), reference)
    # A transposed array transposed back: the same values, in column-major order.
    columns = np.ascontiguousarray(faces.T).T
    assert not columns.flags.c_contiguous
    same_lines(crestline.extract(vertices, columns), reference)


def test_lists_and_tuples(mesh, reference):
    vertices, faces = mesh
    same_lines(crestline.extract(vertices.tolist(), tuple(map(tuple, faces.tolist()))), reference)


def test_curvature_accepts_the_same(mesh):
    vertices, faces = mesh
    a = crestline.curvature(vertices, faces)
    b = crestline.curvature(np.asfortranarray(vertices), faces.astype(np.int32))
    for name in a:
        np.testing.assert_array_equal(a[name], b[name])


@pytest.mark.parametrize(
    "vertices, faces, message",
    [
        (np.zeros((4, 2)), [[0, 1, 2]], r"vertices must have shape \(n, 3\), got \(4, 2\)"),
        (np.zeros(12), [[0, 1, 2]], r"vertices must have shape \(n, 3\), got \(12,\)"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2, 3]], r"faces must have shape \(n, 3\)"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 3]], "refers to a vertex beyond"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, -1]], r"outside \[0, 2\^32\)"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2**40]], r"outside \[0, 2\^32\)"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0.0, 1.0, 2.0]], "integer vertex indices"),
        ([[0, 0, 0], [1, float("nan"), 0], [0, 1, 0]], [[0, 1, 2]], "non-finite coordinate"),
        ([[0, 0, 0], [1, float("inf"), 0], [0, 1, 0]], [[0, 1, 2]], "non-finite coordinate"),
        ([["a", "b", "c"]], [[0, 1, 2]], "vertices is not an array of numbers"),
        ([[0, 0, 0], [1, 0]], [[0, 1, 2]], "vertices is not an array of numbers"),
        ("not an array", [[0, 1, 2]], "vertices"),
    ],
)
def test_bad_arrays_raise_value_error(vertices, faces, message):
    with pytest.raises(ValueError, match=message):
        crestline.extract(vertices, faces)
    with pytest.raises(ValueError, match=message):
        crestline.curvature(vertices, faces)


@pytest.mark.parametrize(
    "options, message",
    [
        (dict(method="cgal"), "method must be one of"),
        (dict(estimator="magic"), "estimator must be one of"),
        (dict(threshold="high"), "threshold takes a number or 'auto'"),
        (dict(threshold=[1]), "threshold takes a number or 'auto'"),
        (dict(radius=-1.0), "radius must be a positive number"),
        (dict(radius=float("nan")), "radius must be a positive number"),
        (dict(rings=9), "ring"),
        (dict(smooth_time=-1.0, smooth_steps=2), "invalid input"),
        (dict(mask=[1.0, 2.0]), r"mask must have shape \(4,\)"),
        (dict(mask=[1.0, -1.0, 1.0, 1.0], smooth_steps=2), "invalid input"),
        (dict(direction_support=-1.0, estimator="shape-operator"), "direction support"),
    ],
)
def test_bad_options_raise_value_error(options, message):
    with pytest.raises(ValueError, match=message):
        crestline.extract(*tetrahedron(), **options)


def test_bad_options_of_the_other_functions():
    vertices, faces = tetrahedron()
    with pytest.raises(ValueError, match="estimator must be one of"):
        crestline.curvature(vertices, faces, "nope")
    with pytest.raises(ValueError, match="not both"):
        crestline.simplify(vertices, faces, ratio=0.5, target_faces=2)
    with pytest.raises(ValueError):
        crestline.simplify(vertices, faces, ratio=2.0, eta=0)
    with pytest.raises(ValueError, match="up must be"):
        crestline.render(vertices, faces, up="x")
    with pytest.raises(ValueError, match=r"field must have shape \(4,\)"):
        crestline.render(vertices, faces, field=[1.0])
    with pytest.raises(ValueError, match="picture format"):
        crestline.render(vertices, faces, path="picture.gif")
    with pytest.raises(TypeError):
        crestline.simplify(vertices, faces, lines="lines.obj")


def test_small_and_empty_meshes_do_not_crash():
    vertices, faces = tetrahedron()
    for args in [
        (vertices, faces),
        (vertices, faces[:1]),
        (vertices, np.zeros((0, 3), dtype=np.int64)),
        (np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)),
        ([], []),
        # Degenerate triangles only: dropped, leaving nothing.
        (vertices, [[0, 0, 1], [1, 2, 2]]),
    ]:
        for method in ("hpw", "ybs", "saliency"):
            lines = crestline.extract(*args, method=method)
            assert len(lines) == 0
        fields = crestline.curvature(*args)
        assert fields["k_max"].shape == (len(args[0]),)


def test_bad_files(tmp_path):
    with pytest.raises(FileNotFoundError, match="missing.obj"):
        crestline.read_mesh(tmp_path / "missing.obj")
    broken = tmp_path / "broken.obj"
    broken.write_text("v 0 0 0\nv 1 0 0\nv 0 1 zero\nf 1 2 3\n")
    with pytest.raises(ValueError, match=r"broken.obj: line 3"):
        crestline.read_mesh(broken)
    with pytest.raises(ValueError, match="format must be one of"):
        crestline.read_mesh(FANDISK, format="dxf")
    with pytest.raises(ValueError, match="extension"):
        crestline.read_mesh(tmp_path / "mesh.dxf")
    lines = crestline.extract(*crestline.read_mesh(FANDISK))
    with pytest.raises(ValueError, match="extension"):
        lines.write(tmp_path / "lines.txt")
    with pytest.raises(OSError):
        lines.write(tmp_path / "no" / "such" / "folder" / "lines.obj")


@pytest.mark.parametrize(
    "options",
    [
        {"estimator": "jet-fit", "rings": 2},
        {"estimator": "shape-operator", "radius": 3.0},
        {"estimator": "cubic-fit", "degree": 3},
        {"rings": 2, "no_noise_adaptation": True},
    ],
)
def test_options_of_another_estimator_are_refused(fandisk, options):
    with pytest.raises(ValueError, match="would not use"):
        crestline.curvature(*fandisk, **options)


@pytest.mark.parametrize(
    "options, what",
    [
        ({"threshold": float("nan")}, "threshold"),
        ({"threshold": -1.0}, "threshold"),
        ({"min_length": -0.01}, "minimum line length"),
        ({"fair": float("inf")}, "fairing tolerance"),
        ({"smooth_time": 0.0}, "smoothing time step"),
        ({"crease_angle": 1000.0}, "crease angle"),
        ({"crease_angle": -5.0}, "-5"),
    ],
)
def test_extract_options_out_of_range_are_refused(fandisk, options, what):
    with pytest.raises(ValueError, match=what):
        crestline.extract(*fandisk, **options)


def test_triangles_given_twice_are_dropped(fandisk):
    vertices, faces = fandisk
    once = crestline.extract(vertices, faces)
    twice = crestline.extract(vertices, np.vstack([faces, faces[:, ::-1]]))
    assert len(twice) == len(once)
    np.testing.assert_array_equal(twice.points, once.points)
