"""The Python API gives what the command-line tool gives, on the analytic quality cases."""

import csv
import json
import subprocess

import numpy as np
import pytest

import crestline
from conftest import FANDISK, case_path

# One mesh of each analytic surface (regular, irregular, marching cubes, noisy), and the
# three methods with their defaults and with options passed on.
CASES = [
    ("ovoid/reg5k", []),
    ("superquadric/irr20k", []),
    ("bumpy/mc", []),
    ("ring/reg5k", []),
    ("ridge/noisy20k", []),
    ("ridge/noisy20k", ["--smooth-along", "1.5"]),
    ("bumpy/noisy20k", []),
    ("bumpy/noisy20k", ["--no-debias"]),
    ("bumpy/noisy20k", ["--method", "ybs", "--keep-unlocated"]),
    ("bumpy/noisy20k", ["--method", "saliency"]),
    ("bumpy/reg5k", ["--method", "ybs"]),
    ("ovoid/reg5k", ["--method", "saliency"]),
    ("superquadric/reg5k", ["--estimator", "shape-operator", "--threshold", "auto"]),
    ("bumpy/reg5k", ["--radius", "3.5", "--smooth-steps", "1", "--min-length", "0.02"]),
    ("ridge/reg5k", ["--rings", "2", "--no-gaps", "--method", "ybs"]),
    ("bumpy/reg5k", ["--smooth-steps", "2", "--mask-sphere", "0,0,1,0.6,0", "--mask-box", "0,-2,-2,2,2,2,3"]),
    ("superquadric/reg5k", ["--keep-outliers", "--method", "ybs"]),
    ("ovoid/mc", ["--fair", "0.002", "--pre-smooth", "2", "--crease-angle", "0", "--threshold", "5"]),
]


def python_options(args):
    """The keyword arguments of `crestline.extract` that the command-line `args` give."""
    options = {}
    it = iter(args)
    for flag in it:
        name = flag.removeprefix("--").replace("-", "_")
        if name in ("no_gaps", "no_noise_adaptation", "no_debias", "keep_unlocated", "keep_outliers"):
            options[name] = True
            continue
        value = next(it)
        if name in ("mask_sphere", "mask_box"):
            options.setdefault(name + "es" if name == "mask_box" else name + "s", []).append(
                tuple(float(x) for x in value.split(","))
            )
            continue
        if name in ("smooth_steps", "rings", "pre_smooth", "degree"):
            value = int(value)
        elif name in (
            "radius", "min_length", "fair", "crease_angle", "direction_support", "smooth_along"
        ):
            value = float(value)
        elif name == "creases" and value not in ("auto", "off"):
            value = float(value)
        elif name == "threshold" and value != "auto":
            value = float(value)
        options[name] = value
    return options


def cli_lines(cli, mesh, args, tmp_path):
    out = tmp_path / "lines.json"
    subprocess.run([str(cli), "extract", str(mesh), "-o", str(out), "-q", *args], check=True)
    return json.loads(out.read_text())["lines"]


def assert_same_lines(lines, expected):
    assert len(lines) == len(expected)
    assert lines.kinds == [line["kind"] for line in expected]
    assert list(lines.closed) == [line["closed"] for line in expected]
    np.testing.assert_allclose(lines.lengths, [line["length"] for line in expected], rtol=1e-12)
    np.testing.assert_allclose(lines.strengths, [line["strength"] for line in expected], rtol=1e-9)
    for line, want in zip(lines, expected):
        np.testing.assert_allclose(line.points, np.array(want["points"]).reshape(-1, 3), rtol=0, atol=1e-12)


@pytest.mark.parametrize("case, args", CASES, ids=[f"{c} {' '.join(a)}" for c, a in CASES])
def test_extract_matches_cli(cli, tmp_path, case, args):
    path = case_path(case)
    expected = cli_lines(cli, path, args, tmp_path)
    vertices, faces = crestline.read_mesh(path)
    assert_same_lines(crestline.extract(vertices, faces, **python_options(args)), expected)


# The options of `crestline extract` that the cases above leave out, on a CAD part with
# sharp creases.
FANDISK_ARGS = [
    ["--degree", "3", "--no-noise-adaptation"],
    ["--creases", "off"],
    ["--creases", "30", "--radius", "3"],
    ["--method", "ybs", "--creases", "auto"],
    ["--estimator", "shape-operator", "--direction-support", "0.2"],
]


@pytest.mark.parametrize("args", FANDISK_ARGS, ids=[" ".join(a) for a in FANDISK_ARGS])
def test_extract_options_match_cli_on_a_cad_part(cli, tmp_path, fandisk, args):
    expected = cli_lines(cli, FANDISK, args, tmp_path)
    assert_same_lines(crestline.extract(*fandisk, **python_options(args)), expected)


def test_stats_match_cli(cli, tmp_path, fandisk):
    """`Lines.stats` holds the figures of `--stats json`, but for reading and writing files."""
    printed = subprocess.run(
        [str(cli), "extract", str(FANDISK), "-o", str(tmp_path / "lines.json"), "--stats=json", "-q"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    expected = json.loads(printed)
    stats = crestline.extract(*fandisk).stats
    file_times = {"load_seconds", "write_seconds"}
    assert stats.keys() == expected.keys() - file_times
    assert stats["stage_seconds"].keys() == expected["stage_seconds"].keys() - {"load", "write"}
    assert expected["creases"] > 0
    # Crest lines and creases apart, with the keys and counts of the JSON lines file.
    written = json.loads((tmp_path / "lines.json").read_text())
    for key in ("ridges", "valleys", "crease_ridges", "crease_valleys"):
        assert stats[key] == written[key], key
    for key, value in expected.items():
        if key in file_times or key in ("stage_seconds", "jet_fit"):
            continue
        if isinstance(value, float):
            assert stats[key] == pytest.approx(value, rel=1e-12), key
        else:
            assert stats[key] == value, key


@pytest.mark.parametrize("case", ["ring/reg5k", "bumpy/noisy20k", "ovoid/reg5k"])
def test_jet_fit_figures_match_cli(cli, tmp_path, case):
    # The radius, noise level and quartic weight the fit chose: a clean mesh, a noisy one,
    # and a coarse one taken for noisy (quartic weight near 1).
    path = case_path(case)
    printed = subprocess.run(
        [str(cli), "extract", str(path), "-o", str(tmp_path / "lines.obj"), "--stats=json", "-q"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    expected = json.loads(printed)["jet_fit"]
    got = crestline.extract(*crestline.read_mesh(path)).stats["jet_fit"]
    assert got.keys() == expected.keys()
    for key, value in expected.items():
        assert got[key] == pytest.approx(value, rel=1e-12), key
    assert 0.0 <= got["quartic_weight"] <= 1.0


def test_written_files_match_cli(cli, tmp_path, fandisk):
    """`Lines.write` writes the bytes `crestline extract` writes, in every format."""
    vertices, faces = fandisk
    lines = crestline.extract(vertices, faces)
    for extension in ("obj", "ply", "json"):
        ours, theirs = tmp_path / f"py.{extension}", tmp_path / f"cli.{extension}"
        lines.write(ours)
        subprocess.run([str(cli), "extract", str(FANDISK), "-o", str(theirs), "-q"], check=True)
        assert ours.read_bytes() == theirs.read_bytes(), extension


@pytest.mark.parametrize("estimator", ["jet-fit", "shape-operator", "cubic-fit"])
def test_curvature_matches_cli(cli, tmp_path, estimator):
    path = case_path("ovoid/irr20k")
    out = tmp_path / "fields.csv"
    subprocess.run(
        [str(cli), "curvature", str(path), "-o", str(out), "--csv", "--estimator", estimator],
        check=True,
        capture_output=True,
    )
    with open(out) as f:
        rows = list(csv.DictReader(f))
    vertices, faces = crestline.read_mesh(path)
    fields = crestline.curvature(vertices, faces, estimator)
    for name in ("k_max", "k_min", "e_max", "e_min"):
        want = np.array([float(r[name]) for r in rows])
        np.testing.assert_allclose(fields[name], want, rtol=1e-12, atol=1e-12, err_msg=name)
    for name in ("dir_max", "dir_min"):
        want = np.array([[float(r[f"{name}_{c}"]) for c in "xyz"] for r in rows])
        np.testing.assert_allclose(fields[name], want, rtol=1e-12, atol=1e-12, err_msg=name)


def cli_fields(cli, path, args, tmp_path):
    """The fields `crestline curvature --csv` writes, by column."""
    out = tmp_path / "fields.csv"
    subprocess.run(
        [str(cli), "curvature", str(path), "-o", str(out), "--csv", *args],
        check=True,
        capture_output=True,
    )
    with open(out) as f:
        rows = list(csv.DictReader(f))
    return {name: np.array([float(r[name]) for r in rows]) for name in rows[0]}


@pytest.mark.parametrize(
    "args, options",
    [
        ([], {}),
        (["--creases", "off"], {"creases": "off"}),
        (["--creases", "30"], {"creases": 30.0}),
        (
            ["--estimator", "shape-operator", "--direction-support", "0.2"],
            {"estimator": "shape-operator", "direction_support": 0.2},
        ),
    ],
    ids=["defaults", "creases off", "creases 30", "direction support"],
)
def test_curvature_matches_cli_on_a_cad_part(cli, tmp_path, fandisk, args, options):
    # By default the jet fit does not reach across fandisk's sharp creases, as on the command
    # line; with creases "off" it does.
    want = cli_fields(cli, FANDISK, args, tmp_path)
    fields = crestline.curvature(*fandisk, **options)
    for name in ("k_max", "k_min", "e_max", "e_min"):
        np.testing.assert_allclose(fields[name], want[name], rtol=1e-12, atol=1e-12, err_msg=name)
    for name in ("dir_max", "dir_min"):
        for i, c in enumerate("xyz"):
            np.testing.assert_allclose(fields[name][:, i], want[f"{name}_{c}"], rtol=1e-12, atol=1e-12)


def test_rings_select_the_cubic_fit_as_on_the_command_line(cli, tmp_path):
    path = case_path("ovoid/irr20k")
    out = tmp_path / "fields.csv"
    subprocess.run(
        [str(cli), "curvature", str(path), "-o", str(out), "--csv", "--rings", "2"],
        check=True,
        capture_output=True,
    )
    with open(out) as f:
        want = np.array([float(r["k_max"]) for r in csv.DictReader(f)])
    vertices, faces = crestline.read_mesh(path)
    np.testing.assert_allclose(
        crestline.curvature(vertices, faces, rings=2)["k_max"], want, rtol=1e-12, atol=1e-12
    )
    # The jet fit gives other values: rings was not ignored.
    assert np.abs(crestline.curvature(vertices, faces)["k_max"] - want).max() > 1e-6
