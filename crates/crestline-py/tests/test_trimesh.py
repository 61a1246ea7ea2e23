"""With trimesh: its arrays go in as they are, and meshes go back and forth."""

import numpy as np
import pytest

import crestline
from conftest import FANDISK

trimesh = pytest.importorskip("trimesh")


def test_trimesh_arrays_go_in_as_they_are():
    mesh = trimesh.load(FANDISK, process=False)
    lines = crestline.extract(mesh.vertices, mesh.faces)
    vertices, faces = crestline.read_mesh(FANDISK)
    reference = crestline.extract(vertices, faces)
    assert lines.kinds == reference.kinds
    np.testing.assert_array_equal(lines.points, reference.points)


def test_round_trip_through_trimesh(tmp_path):
    """crestline's arrays -> trimesh -> a file trimesh writes -> crestline: the same mesh."""
    vertices, faces = crestline.read_mesh(FANDISK)
    mesh = trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
    for extension in ("ply", "off", "stl", "obj"):
        path = tmp_path / f"fandisk.{extension}"
        mesh.export(path)
        back_vertices, back_faces = crestline.read_mesh(path)
        if extension == "stl":
            # STL has no shared vertices: compare the triangles' corners.
            np.testing.assert_allclose(back_vertices[back_faces], vertices[faces], rtol=1e-6)
            continue
        np.testing.assert_allclose(back_vertices, vertices, rtol=1e-7, atol=1e-7)
        np.testing.assert_array_equal(back_faces, faces)


def test_simplified_mesh_goes_to_trimesh():
    mesh = trimesh.creation.icosphere(subdivisions=4)
    vertices, faces = crestline.simplify(mesh.vertices, mesh.faces, ratio=0.25, eta=0)
    small = trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
    assert len(small.faces) == round(0.25 * len(mesh.faces))
    assert small.is_watertight
    assert small.volume == pytest.approx(mesh.volume, rel=0.02)


def test_curvature_of_a_trimesh_sphere():
    radius = 2.0
    mesh = trimesh.creation.icosphere(subdivisions=4, radius=radius)
    fields = crestline.curvature(mesh.vertices, mesh.faces)
    np.testing.assert_allclose(fields["k_max"], 1 / radius, rtol=0.02)
    np.testing.assert_allclose(fields["k_min"], 1 / radius, rtol=0.02)
    # The sphere has no crest lines.
    assert len(crestline.extract(mesh.vertices, mesh.faces)) == 0
