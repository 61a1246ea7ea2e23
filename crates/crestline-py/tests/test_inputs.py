"""What the functions accept: dtypes, layouts, array-likes; and what they refuse."""

import numpy as np
import pytest

import crestline
from conftest import FANDISK, REPO, case_path, tetrahedron


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
        ([[0, 0, 0], [1, float("nan"), 0], [0, 1, 0]], [[0, 1, 2]], "non-finite coordinate"),
        ([[0, 0, 0], [1, float("inf"), 0], [0, 1, 0]], [[0, 1, 2]], "non-finite coordinate"),
        ([[0, 0, 0], [1, 0]], [[0, 1, 2]], "vertices is not an array of numbers"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2], [0, 1]], "faces is not an array of numbers"),
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
        (dict(radius=-1.0), "radius must be above 0 and at most 10"),
        (dict(radius=float("nan")), "radius must be above 0 and at most 10"),
        (dict(radius=1e6), "radius must be above 0 and at most 10"),
        (dict(rings=9), "^rings must be a whole number from 1 to 8, got 9$"),
        (dict(rings=0), "^rings must be a whole number from 1 to 8, got 0$"),
        (dict(creases="sometimes"), "creases takes 'auto', 'off' or an angle in degrees"),
        (dict(creases=180.0), "creases takes 'auto', 'off' or an angle in degrees between 0 and 180"),
        (dict(creases=float("nan")), "creases takes"),
        (dict(degree=5), "degree must be 3 or 4"),
        (dict(smooth_time=-1.0, smooth_steps=2), "invalid input"),
        (dict(mask=[1.0, 2.0]), r"mask must have shape \(4,\)"),
        (dict(mask=[1.0, -1.0, 1.0, 1.0], smooth_steps=2), "invalid input"),
        (dict(direction_support=-1.0, estimator="shape-operator"), "direction support"),
    ],
)
def test_bad_options_raise_value_error(options, message):
    with pytest.raises(ValueError, match=message):
        crestline.extract(*tetrahedron(), **options)


TRIANGLE = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]


@pytest.mark.parametrize(
    "vertices, faces, message",
    [
        # Values of the wrong kind where vertex indices are needed.
        (TRIANGLE, [[0.0, 1.0, 2.0]], "faces must hold integer vertex indices, got dtype float64"),
        (TRIANGLE, np.array([[0, 1, 2]], dtype=np.float32), "indices, got dtype float32"),
        (TRIANGLE, np.array([[True, False, True]]), "integer vertex indices, got dtype bool"),
        (TRIANGLE, [["0", "1", "2"]], "integer vertex indices, got dtype <U1"),
        (TRIANGLE, np.array([[0, 1, 2]], dtype="datetime64[s]"), "integer vertex indices"),
        # Values of the wrong kind where coordinates are needed.
        ([["a", "b", "c"]], [[0, 1, 2]], "vertices must hold real numbers, got dtype <U1"),
        (np.array(TRIANGLE, dtype=complex), [[0, 1, 2]], "real numbers, got dtype complex128"),
        (np.array(TRIANGLE, dtype=float).astype(str), [[0, 1, 2]], "real numbers, got dtype <U32"),
        (np.zeros(3, dtype=[("x", "f8"), ("y", "f8"), ("z", "f8")]), [[0, 1, 2]], "real numbers"),
        (np.array([[0, 0, 0], [1, 0, 0], [0, 1, None]], dtype=object), [[0, 1, 2]], "real numbers"),
        # No array at all.
        ("not an array", [[0, 1, 2]], "vertices must be an array-like, got str"),
        (None, [[0, 1, 2]], "vertices must be an array-like, got NoneType"),
        (3.0, [[0, 1, 2]], "vertices must be an array-like, got float"),
        ({"a": 1}, [[0, 1, 2]], "vertices must be an array-like, got dict"),
        ((row for row in TRIANGLE), [[0, 1, 2]], "vertices must be an array-like, got generator"),
        (TRIANGLE, None, "faces must be an array-like, got NoneType"),
    ],
)
def test_wrong_types_raise_type_error(vertices, faces, message):
    for function in (crestline.extract, crestline.curvature, crestline.feature_distance):
        with pytest.raises(TypeError, match=message):
            function(vertices, faces)


def test_arrays_of_python_numbers_and_empty_arrays_of_any_dtype():
    vertices, faces = tetrahedron()
    reference = crestline.curvature(vertices, faces)
    # Object arrays of numbers are read by their elements.
    fields = crestline.curvature(vertices.astype(object), faces.astype(object))
    np.testing.assert_array_equal(fields["k_max"], reference["k_max"])
    # Empty is empty whatever the dtype numpy gave it (and no triangles are nothing to
    # extract from, as on the command line).
    for no_faces in ([], np.zeros((0, 3)), np.zeros((0, 3), dtype=str)):
        assert crestline.curvature(vertices, no_faces)["k_max"].shape == (4,)
        with pytest.raises(ValueError, match="no triangles"):
            crestline.extract(vertices, no_faces)


@pytest.mark.parametrize(
    "options, message",
    [
        (dict(threshold=[1]), "threshold takes a number or 'auto', got list"),
        (dict(mask="abc"), "mask must be an array-like, got str"),
        (dict(mask=[["a"]] * 4), "mask must hold real numbers"),
        (dict(smooth_steps=1.5), "smooth_steps must be a non-negative integer, got float"),
        (dict(rings="2"), "rings must be a non-negative integer, got str"),
        (dict(mask_spheres="abc"), "mask_spheres must be a sequence of"),
        (dict(mask_spheres=[(0, 0, 0, "1", 0.5)]), r"mask_spheres\[0\]\[3\] must be a number, got str"),
    ],
)
def test_options_of_the_wrong_type_raise_type_error(options, message):
    with pytest.raises(TypeError, match=message):
        crestline.extract(*tetrahedron(), **options)


def test_other_functions_options_of_the_wrong_type_raise_type_error():
    vertices, faces = tetrahedron()
    with pytest.raises(TypeError, match="field must be an array-like, got str"):
        crestline.render(vertices, faces, field="abc")
    with pytest.raises(TypeError, match="field_range must be a sequence of 2 numbers"):
        crestline.render(vertices, faces, field_range="x")
    with pytest.raises(TypeError, match="view must be a sequence of 2 numbers"):
        crestline.render(vertices, faces, view="ab")
    with pytest.raises(TypeError, match=r"size\[1\] must be a non-negative integer, got float"):
        crestline.render(vertices, faces, size=(64, 64.5))
    with pytest.raises(TypeError, match="degree must be a non-negative integer"):
        crestline.curvature(vertices, faces, degree=4.0)
    with pytest.raises(TypeError, match="target_faces must be a non-negative integer"):
        crestline.simplify(vertices, faces, target_faces="2")


@pytest.mark.parametrize(
    "function, options, message",
    [
        (crestline.extract, dict(rings=-1), "rings must be a non-negative integer, got -1"),
        (crestline.extract, dict(smooth_steps=-2), "smooth_steps must be a non-negative integer"),
        (crestline.extract, dict(pre_smooth=-1), "pre_smooth must be a non-negative integer"),
        (crestline.extract, dict(smooth_steps=2**70), "smooth_steps must be an integer from 0 to"),
        (crestline.extract, dict(rings=np.int64(-3)), "rings must be a non-negative integer, got -3"),
        (crestline.curvature, dict(rings=-1), "rings must be a non-negative integer, got -1"),
        (crestline.curvature, dict(degree=-1), "degree must be a non-negative integer, got -1"),
        (crestline.simplify, dict(target_faces=-5), "target_faces must be a non-negative integer"),
        (crestline.render, dict(size=(-5, 64)), r"size\[0\] must be a non-negative integer, got -5"),
        (crestline.render, dict(size=(64, 2**32)), r"size\[1\] must be an integer from 0 to 4294967295"),
    ],
)
def test_negative_counts_raise_value_error(function, options, message):
    with pytest.raises(ValueError, match=message):
        function(*tetrahedron(), **options)


@pytest.mark.parametrize("name", ["pre_smooth", "smooth_steps"])
def test_smoothing_steps_have_a_ceiling(name):
    # A thousand steps at most: more is a mistake that ran for ever, and Ctrl-C reaches
    # Python only between stages.
    with pytest.raises(ValueError, match=r"steps must be at most 1000, got 1000000000"):
        crestline.extract(*tetrahedron(), **{name: 10**9})


def test_counts_take_numpy_integers(fandisk):
    vertices, faces = fandisk
    np.testing.assert_array_equal(
        crestline.extract(vertices, faces, smooth_steps=np.int32(3)).points,
        crestline.extract(vertices, faces, smooth_steps=3).points,
    )


def test_view_and_size_take_any_sequence(fandisk):
    vertices, faces = fandisk
    png = crestline.render(vertices, faces, view=(40, 10), size=(48, 32))
    for view, size in [
        ([40, 10], [48, 32]),
        (np.array([40.0, 10.0]), np.array([48, 32])),
        (np.array([40, 10], dtype=np.int32), (np.uint16(48), np.int64(32))),
        (range(40, 9, -30), range(48, 31, -16)),
    ]:
        assert crestline.render(vertices, faces, view=view, size=size) == png
    field = np.arange(len(vertices), dtype=float)
    coloured = crestline.render(vertices, faces, None, field, size=(32, 32), field_range=(10, 20))
    for field_range in ([10, 20], np.array([10.0, 20.0])):
        again = crestline.render(vertices, faces, None, field, size=(32, 32), field_range=field_range)
        assert again == coloured
    for bad in ((64,), [64, 64, 3]):
        with pytest.raises(ValueError, match=r"size must have 2 values \(width, height\)"):
            crestline.render(vertices, faces, size=bad)
    with pytest.raises(ValueError, match=r"view must have 2 values \(azimuth, elevation\), got 3"):
        crestline.render(vertices, faces, view=np.zeros(3))
    with pytest.raises(ValueError, match="field_range must have 2 values"):
        crestline.render(vertices, faces, field=field, field_range=(1, 2, 3))


def test_mask_regions_take_any_sequence(fandisk):
    vertices, faces = fandisk
    centre = vertices.mean(axis=0)
    sphere = (*centre, 0.5, 0.2)
    box = (*(centre - 0.3), *(centre + 0.3), 0.1)
    reference = crestline.extract(
        vertices, faces, smooth_steps=2, mask_spheres=[sphere], mask_boxes=[box]
    )
    for spheres, boxes in [(np.array([sphere]), np.array([box])), ([list(sphere)], (list(box),))]:
        lines = crestline.extract(
            vertices, faces, smooth_steps=2, mask_spheres=spheres, mask_boxes=boxes
        )
        np.testing.assert_array_equal(lines.points, reference.points)
    with pytest.raises(ValueError, match=r"mask_spheres\[0\] must have 5 values"):
        crestline.extract(vertices, faces, mask_spheres=[(0, 0, 0, 1)])
    with pytest.raises(ValueError, match=r"mask_boxes\[1\] must have 7 values"):
        crestline.extract(vertices, faces, mask_boxes=[box, box[:6]])


def test_a_smoothing_option_makes_the_smoothing_run_on_a_clean_mesh(fandisk):
    # The jet fit finds fandisk clean: by default no extremality smoothing runs there. A
    # smoothing option given runs the default steps, as `crestline extract` does.
    vertices, faces = fandisk
    plain = crestline.extract(vertices, faces)
    two_steps = crestline.extract(vertices, faces, smooth_steps=2)
    assert not np.array_equal(plain.points, two_steps.points)
    timed = crestline.extract(vertices, faces, smooth_time=1.0)
    np.testing.assert_array_equal(timed.points, two_steps.points)
    with pytest.raises(ValueError, match="smooth_time: .* does not run with smooth_steps=0"):
        crestline.extract(vertices, faces, smooth_steps=0, smooth_time=1.0)


def test_smoothing_along_the_lines_shapes_white_noise_only(fandisk):
    # The jet fit finds the noise of the public noisy ridge white: there the factor changes
    # the lines. Fandisk is clean (no smoothing runs), and `smooth_along` does not make it run.
    vertices, faces = crestline.read_mesh(case_path("ridge/noisy20k"))
    default = crestline.extract(vertices, faces)
    isotropic = crestline.extract(vertices, faces, smooth_along=1.0)
    assert not np.array_equal(default.points, isotropic.points)
    np.testing.assert_array_equal(
        crestline.extract(*fandisk).points, crestline.extract(*fandisk, smooth_along=1.0).points
    )
    with pytest.raises(ValueError, match="smooth_along: .* does not run with smooth_steps=0"):
        crestline.extract(*fandisk, smooth_steps=0, smooth_along=2.0)


def test_negative_mask_factors_are_refused_before_the_work(fandisk):
    vertices, faces = fandisk
    with pytest.raises(ValueError, match=r"mask_spheres\[0\]: factor -1.* >= 0"):
        crestline.extract(vertices, faces, mask_spheres=[(0, 0, 0, 1, -1)])
    with pytest.raises(ValueError, match=r"mask_spheres\[1\]: radius -1.* >= 0"):
        crestline.extract(vertices, faces, mask_spheres=[(0, 0, 0, 1, 1), (0, 0, 0, -1, 1)])
    with pytest.raises(ValueError, match=r"mask_boxes\[1\]: factor NaN.* >= 0"):
        crestline.extract(
            vertices, faces, mask_boxes=[(0, 0, 0, 1, 1, 1, 1), (0, 0, 0, 1, 1, 1, float("nan"))]
        )


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
    for args, has_triangles in [
        ((vertices, faces), True),
        ((vertices, faces[:1]), True),
        ((vertices, np.zeros((0, 3), dtype=np.int64)), False),
        ((np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)), False),
        (([], []), False),
        # Degenerate triangles only: dropped, leaving nothing.
        ((vertices, [[0, 0, 1], [1, 2, 2]]), False),
    ]:
        for method in ("hpw", "ybs", "saliency"):
            if has_triangles:
                assert len(crestline.extract(*args, method=method)) == 0
            else:
                with pytest.raises(ValueError, match="no triangles"):
                    crestline.extract(*args, method=method)
        fields = crestline.curvature(*args)
        assert fields["k_max"].shape == (len(args[0]),)


@pytest.mark.parametrize(
    "vertices, faces, message",
    [
        (tetrahedron()[0], np.zeros((0, 3), dtype=np.int64), r"no triangles \(4 vertices, 0 degenerate"),
        ([], [], r"no triangles \(0 vertices"),
        (tetrahedron()[0], [[0, 0, 1], [1, 2, 2]], r"no triangles \(4 vertices, 2 degenerate triangles dropped\)"),
    ],
)
def test_extract_refuses_a_mesh_without_triangles(vertices, faces, message):
    # As `crestline extract` does: nothing to work on is an error, not "0 lines".
    with pytest.raises(ValueError, match=message + ".*nothing to work on"):
        crestline.extract(vertices, faces)


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


def test_outputs_in_a_missing_folder_name_the_folder(tmp_path, fandisk):
    # The command line's message, not the name of the temporary file written first.
    vertices, faces = fandisk
    lines = crestline.extract(vertices, faces)
    folder = tmp_path / "no" / "such"
    for write in (
        lambda: lines.write(folder / "lines.obj"),
        lambda: crestline.render(vertices, faces, lines, path=folder / "picture.png"),
    ):
        with pytest.raises(FileNotFoundError) as raised:
            write()
        message = str(raised.value)
        assert f"the folder {folder} does not exist" in message
        assert ".part" not in message and ".crestline-" not in message


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
    "options, message",
    [
        (
            {"estimator": "shape-operator", "creases": "auto"},
            "options that estimator 'shape-operator' would not use: creases",
        ),
        ({"direction_support": 0.3}, "direction_support .it applies to the shape-operator estimator"),
        (
            {"estimator": "jet-fit", "rings": 2},
            r"^options that estimator 'jet-fit' would not use: rings \(it applies to the cubic-fit "
            r"estimator; this run uses jet-fit\)$",
        ),
    ],
)
def test_curvature_names_the_unused_options(fandisk, options, message):
    with pytest.raises(ValueError, match=message):
        crestline.curvature(*fandisk, **options)


@pytest.mark.parametrize(
    "options, message",
    [
        (
            {"estimator": "shape-operator", "radius": 3},
            r"^options that method 'hpw' would not use: radius \(it applies to the jet-fit "
            r"estimator; this run uses shape-operator\)$",
        ),
        ({"direction_support": 0.3}, "direction_support .it applies to the shape-operator estimator; this run uses jet-fit"),
        ({"rings": 2, "estimator": "jet-fit"}, "rings .it applies to the cubic-fit estimator; this run uses jet-fit"),
        ({"rings": 2, "degree": 3}, "degree .it applies to the jet-fit estimator; this run uses cubic-fit"),
        ({"estimator": "cubic-fit", "no_noise_adaptation": True}, "no_noise_adaptation"),
        ({"no_gaps": True}, r"^options that method 'hpw' would not use: no_gaps \(gap jumping is part of method 'ybs' only\)$"),
        ({"method": "saliency", "no_gaps": True}, "options that method 'saliency' would not use: no_gaps"),
        ({"rings": 2, "no_debias": True}, "would not use: no_debias .the lines are moved back by the jet fit's bias only"),
        ({"method": "saliency", "keep_unlocated": True}, r"^options that method 'saliency' would not use: keep_unlocated \(HPW and YBS drop"),
        ({"rings": 2, "keep_unlocated": True}, "would not use: keep_unlocated .only the jet fit measures the noise"),
        ({"rings": 2, "smooth_along": 2.0}, "would not use: smooth_along .only the jet fit tells white noise"),
        (
            {"no_gaps": True, "radius": 3, "estimator": "cubic-fit"},
            "would not use: no_gaps .gap jumping is part of method 'ybs' only.; radius .it applies",
        ),
    ],
)
def test_extract_refuses_options_the_run_would_not_use(fandisk, options, message):
    # As `crestline extract` refuses them ("options that --method hpw would not use"),
    # before any work.
    with pytest.raises(ValueError, match=message):
        crestline.extract(*fandisk, **options)


def test_a_noisy_part_has_its_creases_between_filtered_normals(fandisk):
    # A machined part as a scan gives it (noise of 0.1 of the mean edge along the normals):
    # its dihedral angles have no gap, the filtered normals' have (`lines::crease`, step 2b).
    path = case_path("bumpy/reg5k").parents[2] / "cad" / "hex_nut-uniform.obj"
    if not path.is_file():
        pytest.skip(f"{path} not found (set CRESTLINE_SHARED)")
    vertices, faces = crestline.read_mesh(path)
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    mean_edge = np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1).mean()
    area_normals = np.cross(vertices[faces[:, 1]] - vertices[faces[:, 0]], vertices[faces[:, 2]] - vertices[faces[:, 0]])
    normals = np.zeros_like(vertices)
    for k in range(3):
        np.add.at(normals, faces[:, k], area_normals)
    normals /= np.maximum(np.linalg.norm(normals, axis=1), 1e-300)[:, None]
    noise = np.random.default_rng(3).normal(0.0, 0.1 * mean_edge, len(vertices))
    noisy = crestline.extract(vertices + normals * noise[:, None], faces)
    assert noisy.stats["crease_normals_filtered"]
    assert noisy.stats["creases"] >= 30
    clean = crestline.extract(*fandisk)
    assert clean.stats["creases"] > 0
    assert not clean.stats["crease_normals_filtered"]


def test_extract_drops_the_lines_the_noise_moves_about_unless_told_to_keep_them():
    # The public noisy bumps: white noise, whose weak crests give lines that wander.
    vertices, faces = crestline.read_mesh(case_path("bumpy/noisy20k"))
    default = crestline.extract(vertices, faces)
    assert default.stats["jet_fit"]["white_noise"]
    assert default.stats["jet_fit"]["noise_growth"] == pytest.approx(1.0, abs=0.1)
    assert default.stats["lines_unlocated"] > 0
    assert default.stats["lines_trimmed"] > 0
    kept = crestline.extract(vertices, faces, keep_unlocated=True)
    assert kept.stats["lines_unlocated"] == 0
    assert kept.stats["lines_trimmed"] == 0
    assert len(kept) > len(default)


def spiky_ellipsoid():
    """The public clean ellipsoid's vertices, the same with two of them three mean edges off
    the surface (one out, one in), and its faces."""
    vertices, faces = crestline.read_mesh(case_path("ovoid/reg20k"))
    normals = np.zeros_like(vertices)
    corners = vertices[faces]
    area = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    for k in range(3):
        np.add.at(normals, faces[:, k], area)
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    edge = np.linalg.norm(corners[:, 0] - corners[:, 1], axis=1).mean()
    spiky = vertices.copy()
    spiky[100] += 3 * edge * normals[100]
    spiky[2000] -= 3 * edge * normals[2000]
    return vertices, spiky, faces


def test_extract_puts_spikes_back_unless_told_to_keep_them():
    vertices, spiky, faces = spiky_ellipsoid()
    clean = crestline.extract(vertices, faces)
    assert clean.stats["outliers_moved"] == 0
    repaired = crestline.extract(spiky, faces)
    assert repaired.stats["outliers_moved"] == 2
    assert repaired.stats["creases"] == 0
    assert len(repaired) == len(clean)
    kept = crestline.extract(spiky, faces, keep_outliers=True)
    assert kept.stats["outliers_moved"] == 0
    assert kept.stats["creases"] > 0


def test_curvature_puts_spikes_back_unless_told_to_keep_them():
    # The spikes of `spiky_ellipsoid`: the fields are those of the repaired surface, close to the
    # clean mesh's everywhere; kept, every fit whose disc holds a spike is thrown off.
    vertices, spiky, faces = spiky_ellipsoid()
    clean = crestline.curvature(vertices, faces)
    scale = np.abs(clean["k_max"]).max()

    def worst(fields):
        return max(np.abs(fields[k] - clean[k]).max() for k in ("k_max", "k_min")) / scale

    repaired = crestline.curvature(spiky, faces)
    assert worst(repaired) < 0.005
    assert repaired["outliers"].dtype == bool
    assert sorted(np.flatnonzero(repaired["outliers"])) == [100, 2000]
    assert not clean["outliers"].any()
    kept = crestline.curvature(spiky, faces, keep_outliers=True)
    assert worst(kept) > 0.15
    assert not kept["outliers"].any()


def test_extract_says_a_raw_marching_cubes_mesh_is_one(fandisk):
    # A torus as scikit-image's marching cubes leaves it (every vertex on a grid edge).
    torus = REPO / "crates" / "crestline" / "tests" / "data" / "raw_marching_cubes_torus.obj"
    vertices, faces = crestline.read_mesh(str(torus))
    grid = crestline.extract(vertices, faces).stats["marching_cubes_grid"]
    assert grid is not None and len(grid) == 3
    assert all(abs(h - 0.0823529) < 1e-6 for h in grid)
    assert crestline.extract(*fandisk).stats["marching_cubes_grid"] is None


def test_extract_takes_the_jet_fit_and_crease_options(fandisk):
    vertices, faces = fandisk
    default = crestline.extract(vertices, faces)
    assert default.stats["creases"] > 0
    assert crestline.extract(vertices, faces, creases="off").stats["creases"] == 0
    assert crestline.extract(vertices, faces, creases="auto").stats["creases"] == default.stats["creases"]
    steep = crestline.extract(vertices, faces, creases=60)
    assert steep.stats["crease_threshold_degrees"] == pytest.approx(60)
    other = crestline.extract(vertices, faces, degree=3, no_noise_adaptation=True)
    assert other.stats["jet_fit"]["quartic_weight"] == 0
    for estimator in (None, "jet-fit"):
        crestline.extract(vertices, faces, estimator=estimator, radius=3, degree=4)
    crestline.extract(vertices, faces, method="ybs", no_gaps=True)
    crestline.extract(vertices, faces, estimator="shape-operator", direction_support=0.2)
    crestline.extract(vertices, faces, rings=2)


def test_docstrings_name_the_command_line_flags():
    assert "--mask-sphere" in crestline.extract.__doc__
    assert "--mask-box" in crestline.extract.__doc__
    assert "--faces" in crestline.simplify.__doc__


@pytest.mark.parametrize(
    "options, what",
    [
        ({"threshold": float("nan")}, "threshold"),
        ({"threshold": -1.0}, "threshold"),
        ({"min_length": -0.01}, "minimum line length"),
        ({"fair": float("inf")}, "fairing tolerance"),
        ({"smooth_time": 0.0}, "smoothing time step"),
        ({"smooth_along": 0.0}, "smoothing factor along the lines"),
        ({"smooth_along": float("nan")}, "smoothing factor along the lines"),
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


def test_stats_count_the_vertices_fitted_on_the_triangles():
    # An open cylinder as CAD exporters write it, one strip of triangles as long as it: every
    # disc is a row of vertices along a rim and is sampled on the triangles.
    n = 64
    angles = 2 * np.pi * np.arange(n) / n
    ring = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    vertices = np.concatenate([np.c_[ring, np.zeros(n)], np.c_[ring, np.full(n, 4.0)]])
    j = np.arange(n)
    k = (j + 1) % n
    faces = np.concatenate([np.stack([j, k, n + k], 1), np.stack([j, n + k, n + j], 1)]).astype(np.uint32)
    strip = crestline.extract(vertices, faces)
    assert strip.stats["jet_fit"]["triangle_sampled_vertices"] == 2 * n
    clean = crestline.extract(*crestline.read_mesh(case_path("ovoid/reg20k")))
    assert clean.stats["jet_fit"]["triangle_sampled_vertices"] == 0
