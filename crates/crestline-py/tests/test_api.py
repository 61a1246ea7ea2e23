"""The results: lines and their arrays, files, curvature, simplification, distance, pictures."""

import _thread
import copy
import functools
import operator
import pickle
import signal
import threading

import numpy as np
import pytest

import crestline
from conftest import FANDISK, case_path


@pytest.fixture(scope="module")
def lines(fandisk):
    return crestline.extract(*fandisk)


def test_lines_and_their_flat_arrays_agree(lines):
    assert len(lines) > 10
    offsets = lines.offsets
    assert offsets.dtype == np.int64 and offsets[0] == 0 and offsets[-1] == len(lines.points)
    assert len(offsets) == len(lines) + 1
    assert set(lines.kinds) <= {"ridge", "valley", "crease-ridge", "crease-valley"}
    for i, line in enumerate(lines):
        np.testing.assert_array_equal(line.points, lines.points[offsets[i] : offsets[i + 1]])
        assert line.kind == lines.kinds[i]
        assert line.length == lines.lengths[i]
        assert line.strength == lines.strengths[i]
        assert line.closed == lines.closed[i]
        assert line.curvature_integral == lines.curvature_integrals[i]
        path = np.vstack([line.points, line.points[:1]]) if line.closed else line.points
        segments = np.diff(path, axis=0)
        assert np.linalg.norm(segments, axis=1).sum() == pytest.approx(line.length)
    assert lines[-1].length == lines.lengths[-1]
    with pytest.raises(IndexError):
        lines[len(lines)]
    assert lines.total_length == pytest.approx(lines.lengths.sum())
    assert "lines" in repr(lines) and "ridge" in repr(lines[0]) + repr(lines[-1]) + repr(lines)


def test_stats(lines):
    stats = lines.stats
    assert stats["lines"] == len(lines)
    # Crest lines and creases apart, as the JSON lines file counts them.
    for key, kind in [
        ("ridges", "ridge"),
        ("valleys", "valley"),
        ("crease_ridges", "crease-ridge"),
        ("crease_valleys", "crease-valley"),
    ]:
        assert stats[key] == lines.kinds.count(kind), key
    assert stats["creases"] == stats["crease_ridges"] + stats["crease_valleys"]
    assert stats["triangles"] == 12946
    assert "curvature" in stats["stage_seconds"]


def test_write_and_read_back(lines, tmp_path):
    path = tmp_path / "lines.obj"
    lines.write(path)
    back = crestline.read_lines(path)
    # OBJ groups the lines by kind (crest lines first, then creases), so compare as sets.
    assert sorted(back.kinds) == sorted(lines.kinds)
    assert back.stats is None
    np.testing.assert_allclose(np.sort(back.lengths), np.sort(lines.lengths), rtol=1e-9)
    lines.write(tmp_path / "lines.data", format="json")
    assert (tmp_path / "lines.data").read_text().startswith("{")
    # Every format reads back with kinds and strengths; PLY and JSON keep the order too.
    np.testing.assert_array_equal(np.sort(back.strengths), np.sort(lines.strengths))
    for extension in ("ply", "json"):
        path = tmp_path / f"lines.{extension}"
        lines.write(path)
        back = crestline.read_lines(path)
        assert back.kinds == lines.kinds, extension
        np.testing.assert_array_equal(back.strengths, lines.strengths)


def test_methods_and_thresholds(fandisk):
    hpw = crestline.extract(*fandisk)
    ybs = crestline.extract(*fandisk, "ybs")
    strict = crestline.extract(*fandisk, threshold=10.0)
    assert len(strict) < len(hpw)
    # Crease curves are kept whatever the threshold; crest lines must pass it.
    crest = [t for t, k in zip(strict.strengths, strict.kinds) if not k.startswith("crease")]
    assert all(t >= 10.0 for t in crest)
    assert len(ybs) > 0
    assert crestline.extract(*fandisk, threshold="auto").stats["threshold_auto"] in (True, False)
    # fandisk's saliency has a knee: the saliency method takes it, not the split of a curve
    # without one (the stats say which).
    salient = crestline.extract(*fandisk, method="saliency").stats
    assert salient["threshold_auto"] is True and salient["threshold_split"] is False
    # Ridge and valley points each keep the knee over all vertices or a lower one of their own.
    assert 0 < salient["threshold_ridges"] <= salient["threshold"]
    assert 0 < salient["threshold_valleys"] <= salient["threshold"]
    assert hpw.stats["threshold_ridges"] is None and hpw.stats["threshold_valleys"] is None


def test_curvature_of_the_ovoid_is_close_to_exact():
    path = case_path("ovoid/reg20k")
    truth = np.load(str(path).replace(".obj", "_truth.npz"))
    fields = crestline.curvature(*crestline.read_mesh(path))
    scale = np.abs(truth["kmax"]).max()
    assert np.sqrt(np.mean((fields["k_max"] - truth["kmax"]) ** 2)) < 0.02 * scale
    assert np.sqrt(np.mean((fields["k_min"] - truth["kmin"]) ** 2)) < 0.02 * scale
    assert fields["dir_max"].shape == fields["normals"].shape == (len(truth["kmax"]), 3)


def test_simplify_and_feature_distance(fandisk, lines):
    vertices, faces = crestline.simplify(*fandisk, lines, target_faces=2000)
    assert faces.shape == (2000, 3) and faces.dtype == np.int64
    assert faces.max() < len(vertices)
    distance = crestline.feature_distance(*fandisk, lines)
    assert distance.shape == (len(fandisk[0]),)
    diagonal = np.linalg.norm(np.ptp(fandisk[0], axis=0))
    assert distance.min() < 1e-3 * diagonal and np.isfinite(distance).all()
    edges = crestline.feature_distance(*fandisk, lines, edges_only=True)
    assert (edges >= distance - 1e-12).all()
    # Without lines, the default extraction's are used.
    np.testing.assert_array_equal(crestline.feature_distance(*fandisk), distance)


def test_render(fandisk, lines, tmp_path):
    png = crestline.render(*fandisk, lines, size=(200, 150))
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    assert crestline.render(*fandisk, lines, size=(200, 150), up="y") == png
    assert crestline.render(*fandisk, lines, size=(200, 150), wireframe=True) != png
    field = crestline.curvature(*fandisk)["k_max"]
    coloured = crestline.render(*fandisk, lines, field, size=(64, 64))
    assert crestline.render(*fandisk, lines, field, size=(64, 64), field_range=2) == coloured
    assert crestline.render(*fandisk, lines, field, size=(64, 64), field_range=0) != coloured
    assert crestline.render(*fandisk, lines, field, size=(64, 64), field_range=(-1, 1)) != coloured
    with pytest.raises(ValueError):
        crestline.render(*fandisk, field=field, field_range=60)
    for extension in ("png", "svg", "html"):
        path = tmp_path / f"picture.{extension}"
        assert crestline.render(*fandisk, lines, field, path, size=(64, 64)) is None
        assert path.stat().st_size > 0


def test_threads_run_side_by_side(fandisk, lines):
    """The GIL is released during the work: extractions in threads give the same lines."""
    results = [None] * 4

    def work(i):
        results[i] = crestline.extract(*fandisk)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(len(results))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for result in results:
        np.testing.assert_array_equal(result.points, lines.points)


def test_help_shows_the_options():
    assert "threshold" in crestline.extract.__doc__
    assert "keep_orientation" in crestline.extract.__text_signature__
    assert "estimator" in crestline.curvature.__doc__
    assert crestline.__version__
    assert crestline.Lines.write.__doc__


def test_keep_orientation_reaches_the_library(tmp_path):
    """An ovoid wound inward: oriented by default (a ridge), kept as wound on request (a valley)."""
    vertices, faces = crestline.read_mesh(case_path("ovoid/reg5k"))
    inward = faces[:, [0, 2, 1]]
    oriented = crestline.extract(vertices, inward)
    kept = crestline.extract(vertices, inward, keep_orientation=True)
    outward = crestline.extract(vertices, faces)
    assert oriented.kinds == outward.kinds
    assert [k.replace("valley", "ridge") for k in kept.kinds] == [
        k.replace("valley", "ridge") for k in outward.kinds
    ]
    assert kept.kinds != outward.kinds


def in_two_pieces(vertices, faces):
    """The mesh as two patches side by side (x < 0 and x >= 0 by the triangles' centres), each
    with its own copies of the vertices along the seam, as parametric models are exported."""
    pieces_vertices, pieces_faces, offset = [], [], 0
    side = vertices[faces].mean(axis=1)[:, 0] >= 0
    for piece in (faces[~side], faces[side]):
        used, local = np.unique(piece, return_inverse=True)
        pieces_vertices.append(vertices[used])
        pieces_faces.append(local.reshape(piece.shape) + offset)
        offset += len(used)
    return np.vstack(pieces_vertices), np.vstack(pieces_faces)


def test_pieces_side_by_side_are_welded():
    """Patches exported side by side give the lines and the curvature of the joined surface,
    per vertex given; with no_weld the seam cuts the surface."""
    vertices, faces = crestline.read_mesh(case_path("ovoid/reg5k"))
    pieces = in_two_pieces(vertices, faces)
    seam = len(pieces[0]) - len(vertices)
    assert seam > 20
    joined = crestline.extract(vertices, faces)
    welded = crestline.extract(*pieces)
    assert welded.kinds == joined.kinds
    assert welded.total_length == pytest.approx(joined.total_length, rel=1e-3)
    # Unwelded, the crest line ends at the seam on both sides (the mask is per vertex given).
    apart = crestline.extract(*pieces, no_weld=True, mask=np.ones(len(pieces[0])))
    assert len(apart) > len(joined)
    fields = crestline.curvature(*pieces)
    exact = crestline.curvature(vertices, faces)
    assert fields["k_max"].shape == (len(pieces[0]),)
    # Every copy of a vertex has the values of the vertex of the joined mesh at its place.
    where = {tuple(p): i for i, p in enumerate(vertices)}
    at = np.array([where[tuple(p)] for p in pieces[0]])
    np.testing.assert_allclose(fields["k_max"], exact["k_max"][at], rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(fields["dir_max"].shape, (len(pieces[0]), 3))
    distance = crestline.feature_distance(*pieces, welded)
    assert distance.shape == (len(pieces[0]),) and np.isfinite(distance).all()


def test_read_lines_takes_a_format(lines, tmp_path):
    path = tmp_path / "lines.data"
    lines.write(path, format="json")
    with pytest.raises(ValueError, match="extension"):
        crestline.read_lines(path)
    for name in ("json", "JSON"):
        back = crestline.read_lines(path, format=name)
        assert back.kinds == lines.kinds
        np.testing.assert_array_equal(back.strengths, lines.strengths)
    ply = tmp_path / "lines.obj"
    lines.write(ply, format="ply")
    assert crestline.read_lines(ply, format="ply").kinds == lines.kinds
    with pytest.raises(ValueError, match="format must be one of 'obj', 'ply', 'json'"):
        crestline.read_lines(path, format="svg")


def same_lines(a, b):
    assert a.kinds == b.kinds
    for name in ("points", "offsets", "lengths", "strengths", "curvature_integrals", "closed"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


def test_lines_slice(fandisk, lines):
    offsets = lines.offsets
    some = lines[2:5]
    assert isinstance(some, crestline.Lines) and len(some) == 3
    np.testing.assert_array_equal(some.points, lines.points[offsets[2] : offsets[5]])
    assert some.kinds == lines.kinds[2:5] and some.stats is None
    np.testing.assert_array_equal(some.lengths, lines.lengths[2:5])
    for index in (slice(None, None, -1), slice(1, None, 3), slice(-4, None), slice(5, 2), slice(3)):
        part = lines[index]
        assert part.kinds == lines.kinds[index]
        np.testing.assert_array_equal(part.strengths, lines.strengths[index])
        np.testing.assert_array_equal(part.closed, lines.closed[index])
    assert len(lines[len(lines) :]) == 0 and len(lines[-10**30 : 10**30]) == len(lines)
    # A slice keeps the lines' places on the mesh: the distance to all of them is the same.
    np.testing.assert_array_equal(
        crestline.feature_distance(*fandisk, lines[:]), crestline.feature_distance(*fandisk, lines)
    )
    assert lines[np.int64(1)].length == lines[1].length == lines[-len(lines) + 1].length
    with pytest.raises(IndexError):
        lines[10**20]
    with pytest.raises(IndexError):
        lines[-len(lines) - 1]
    with pytest.raises(TypeError, match="integers or slices, not float"):
        lines[1.0]


@pytest.mark.parametrize("protocol", [0, 2, pickle.HIGHEST_PROTOCOL])
def test_lines_pickle(fandisk, lines, protocol):
    back = pickle.loads(pickle.dumps(lines, protocol=protocol))
    assert isinstance(back, crestline.Lines)
    same_lines(back, lines)
    assert back.stats == lines.stats and back.stats is not None
    # The lines' places on the mesh come along: the distance to them is the same to the bit.
    np.testing.assert_array_equal(
        crestline.feature_distance(*fandisk, back), crestline.feature_distance(*fandisk, lines)
    )
    line = pickle.loads(pickle.dumps(lines[3], protocol=protocol))
    assert (line.kind, line.closed, line.length, line.strength) == (
        lines[3].kind,
        lines[3].closed,
        lines[3].length,
        lines[3].strength,
    )
    np.testing.assert_array_equal(line.points, lines[3].points)


def test_lines_copy_and_pickle_of_read_and_empty_lines(fandisk, lines, tmp_path):
    same_lines(copy.copy(lines), lines)
    same_lines(copy.deepcopy(lines), lines)
    lines.write(tmp_path / "lines.ply")
    read = crestline.read_lines(tmp_path / "lines.ply")
    back = pickle.loads(pickle.dumps(read))
    same_lines(back, read)
    assert back.stats is None
    np.testing.assert_array_equal(
        crestline.feature_distance(*fandisk, back), crestline.feature_distance(*fandisk, read)
    )
    empty = pickle.loads(pickle.dumps(lines[:0]))
    assert len(empty) == 0 and empty.points.shape == (0, 3)


def test_stats_are_a_copy(lines):
    stats = lines.stats
    stats["lines"] = -1
    stats["stage_seconds"].clear()
    assert lines.stats["lines"] == len(lines) and lines.stats["stage_seconds"]


@pytest.mark.parametrize(
    "work", [crestline.extract, crestline.feature_distance, crestline.simplify]
)
def test_ctrl_c_stops_the_extraction(fandisk, work):
    """A Ctrl-C that arrives during an extraction ends it with KeyboardInterrupt at the next
    stage, not after the whole run.

    The signal is made pending just before the call, with no Python code between that could
    act on it: `map` calls `_thread.interrupt_main` and then the work (compiled functions
    only), and `results.append` keeps what each returns. Without the checks between stages
    the work would run to its end (and be kept) before the interpreter raised.
    """
    results = []
    calls = [_thread.interrupt_main, functools.partial(work, *fandisk)]
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            list(map(results.append, map(operator.methodcaller("__call__"), calls)))
    finally:
        signal.signal(signal.SIGINT, previous)
    assert results == [None]
    # Nothing is left behind: the next run is whole.
    assert len(crestline.extract(*fandisk)) > 10
