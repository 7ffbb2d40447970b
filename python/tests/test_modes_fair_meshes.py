"""flexure.modes against `flexure modes`' modes.json, flexure.fair against `flexure fair`'s mesh,
flexure.info against `flexure info --json`, and their errors."""

import json
import pathlib
import tarfile

import numpy as np
import pytest

import flexure
from conftest import bent


@pytest.mark.parametrize("energy, extra", [("hinge", []), ("midedge", []),
                                           ("cotan", ["--support", "simply-supported"])])
def test_modes_equal_the_cli_modes_json(cli, plate, tmp_path, energy, extra):
    V, F = plate
    flexure.write_mesh(tmp_path / "plate.obj", V, F)
    cli("-q", "modes", "--mesh", tmp_path / "plate.obj", "--energy", energy, "--count", "4",
        *extra, "-o", tmp_path / "m")
    report = json.loads((tmp_path / "m" / "modes.json").read_text())["energies"][0]
    support = extra[1] if extra else "clamped"
    result = flexure.modes(V, F, energy=energy, count=4, support=support)
    expected = [m["omega_squared"] for m in report["modes"]]
    assert len(expected) >= 4
    np.testing.assert_allclose(result["eigenvalues"][:len(expected)], expected, rtol=1e-12)
    assert result["rigid_modes"] == report["rigid_modes"]
    pairs = list(zip(result["modes"], report["modes"]))
    assert all(not m["localized"] and m["localized"] == r["localized"] for m, r in pairs)
    np.testing.assert_allclose([m["participation"] for m, _ in pairs],
                               [r["participation"] for _, r in pairs], rtol=1e-9)
    assert result["shapes"].shape == (len(result["modes"]), 49, 3)
    for m in result["modes"]:  # M-normalized shapes: Σ m_v |v_v|² = 1
        assert m["nodal_lines"].shape[1:] == (2, 3)
    masses = flexure.Simulation(V, F, energy="hinge").masses
    flexible = [m for m in result["modes"] if not m["zero"]]
    assert sum(masses @ (flexible[0]["shape"] ** 2)) == pytest.approx(1.0, rel=1e-9)


def test_shell_modes_in_xyz_equal_the_cli(cli, tmp_path):
    V, F = flexure.mesh("patch48", 5)
    W = bent(V, 2, amplitude=0.0)  # a curved shell
    flexure.write_mesh(tmp_path / "shell.obj", W, F)
    cli("-q", "modes", "--mesh", tmp_path / "shell.obj", "--energy", "hinge", "--count", "3",
        "--dof", "xyz", "--membrane", "stvk", "--young", "200", "--support", "free",
        "-o", tmp_path / "m")
    report = json.loads((tmp_path / "m" / "modes.json").read_text())["energies"][0]
    result = flexure.modes(W, F, energy="hinge", count=3, dof="xyz",
                           membrane={"model": "stvk", "young": 200}, support="free")
    expected = [m["omega_squared"] for m in report["modes"]]
    assert report["rigid_modes"] == result["rigid_modes"] == 6
    np.testing.assert_allclose(result["eigenvalues"][:len(expected)], expected, rtol=1e-12,
                               atol=1e-12)


def test_modes_errors(plate):
    V, F = plate
    with pytest.raises(ValueError, match="count"):
        flexure.modes(V, F, count=0)
    with pytest.raises(ValueError, match="support"):
        flexure.modes(V, F, support="glued")
    with pytest.raises(ValueError, match="clamp"):
        flexure.modes(V, F, energy="hinge", clamp="normals")
    with pytest.raises(ValueError, match="membrane"):
        flexure.modes(V, F, dof="xyz")
    with pytest.raises(ValueError, match="fixed"):
        flexure.modes(V, F, fixed=[True])
    with pytest.raises(ValueError, match="not flat"):  # height modes of a curved rest
        flexure.modes(bent(V, 2, amplitude=0.0), F)


@pytest.mark.parametrize("region", ["all-interior", "sphere:0.05,0,0,0.2"])
def test_fair_equals_the_cli_mesh(cli, tmp_path, region):
    V, F = flexure.mesh("delaunay", 8, seed=3)
    W = bent(V, 7, amplitude=0.02)
    flexure.write_mesh(tmp_path / "in.obj", W, F)
    cli("-q", "fair", tmp_path / "in.obj", "--region", region, "-o", tmp_path / "out.obj")
    expected, _ = flexure.read_mesh(tmp_path / "out.obj")
    faired, report = flexure.fair(W, F, region=region)
    assert np.abs(faired - expected).max() <= 1e-12
    assert report["converged"] and report["checks"]["passed"]
    assert report["checks"]["triangles_passed"] and report["checks"]["gradient_passed"]
    before = report["before"]["bending"][0]["value"]
    after = report["after"]["bending"][0]["value"]
    assert after < before


def test_fair_cgal_equals_the_cli_mesh(cli, tmp_path):
    V, F = flexure.mesh("delaunay", 8, seed=3)
    W = bent(V, 8, amplitude=0.02)
    flexure.write_mesh(tmp_path / "in.obj", W, F)
    cli("-q", "fair", tmp_path / "in.obj", "--region", "all-interior", "--method", "cgal",
        "-o", tmp_path / "out.obj")
    expected, _ = flexure.read_mesh(tmp_path / "out.obj")
    faired, report = flexure.fair(W, F, region="all-interior", method="cgal")
    assert np.abs(faired - expected).max() <= 1e-12
    assert report["method"] == "cgal" and "termination" not in report
    assert report["after"] == report["cgal"]


def test_fair_report_equals_the_cli_report(cli, tmp_path):
    V, F = flexure.mesh("delaunay", 8, seed=3)
    W = bent(V, 9, amplitude=0.02)
    flexure.write_mesh(tmp_path / "in.obj", W, F)
    cli("-q", "fair", tmp_path / "in.obj", "--region", "all-interior", "-o", tmp_path / "o.obj",
        "--report", tmp_path / "r.json")
    expected = json.loads((tmp_path / "r.json").read_text())
    _, report = flexure.fair(W, F, region="all-interior")
    assert report["slivers"]["passed"] and report["failure"] == ""
    text = json.dumps(expected)
    for value in (report["checks"]["result_min_angle_degrees"],
                  report["slivers"]["cgal_degrees"], report["final_energy"]):
        assert repr(value) in text or f"{value:.17g}" in text, value


def test_fair_remeshed_equals_the_cli(cli, tmp_path):
    # A bent Delaunay plate, its region remeshed then faired: the same mesh, vertices and faces,
    # and the same remesh record as the command's report.
    V, F = flexure.mesh("delaunay", 8, seed=3)
    W = bent(V, 7, amplitude=0.02)
    flexure.write_mesh(tmp_path / "in.obj", W, F)
    cli("-q", "fair", tmp_path / "in.obj", "--region", "all-interior", "--remesh",
        "--remesh-iterations", "2", "-o", tmp_path / "out.obj", "--report", tmp_path / "r.json")
    expected_V, expected_F = flexure.read_mesh(tmp_path / "out.obj")
    expected = json.loads((tmp_path / "r.json").read_text())["remesh"]
    faired, report = flexure.fair(W, F, region="all-interior", remesh=True, remesh_iterations=2)
    remesh = report["remesh"]
    assert faired.shape == expected_V.shape and np.abs(faired - expected_V).max() <= 1e-12
    assert np.array_equal(remesh["F"], expected_F)
    for key in ("target_edge_length", "faces_before", "faces_after", "hausdorff_distance",
                "min_angle_degrees_before", "min_angle_degrees_after"):
        assert remesh[key] == pytest.approx(expected[key], rel=1e-12, abs=1e-15), key
    assert remesh["iterations"] == 2 and remesh["hausdorff_distance"] > 0
    assert report["converged"]
    # Without remesh, no record and the input's connectivity.
    assert "remesh" not in flexure.fair(W, F, region="all-interior")[1]


def test_fair_report_names_the_membrane_weight_of_its_result():
    # On the current metric the membrane fades w = 0.1 -> 0.01 (one stage); the input's has no fade.
    V, F = flexure.mesh("delaunay", 8, seed=3)
    W = bent(V, 9, amplitude=0.02)
    _, current = flexure.fair(W, F, region="all-interior", metric="current")
    assert current["converged"] and current["membrane_weight"] == 0.1
    assert current["membrane_fade_stages"] == 1 and current["membrane_final_weight"] == 0.1 * 0.1
    _, given = flexure.fair(W, F, region="all-interior")
    assert given["membrane_fade_stages"] == 0
    assert given["membrane_final_weight"] == given["membrane_weight"] == 1.0


def test_fair_by_mask_equals_by_spec(plate):
    V, F = plate
    W = bent(V, 4, amplitude=0.02)
    mask = flexure.vertex_rings(V, F) >= 2
    by_mask, _ = flexure.fair(W, F, region=mask)
    by_spec, _ = flexure.fair(W, F, region="all-interior")
    np.testing.assert_array_equal(by_mask, by_spec)
    np.testing.assert_array_equal(by_mask[~mask], W[~mask])


def test_fair_errors(plate):
    V, F = plate
    with pytest.raises(ValueError, match="region"):
        flexure.fair(V, F, region=np.ones(5, dtype=bool))
    with pytest.raises(ValueError, match="region"):
        flexure.fair(V, F, region="cube:1")
    with pytest.raises(ValueError, match="metric"):
        flexure.fair(V, F, region="all-interior", metric="other")
    with pytest.raises(ValueError, match="method"):
        flexure.fair(V, F, region="all-interior", method="laplace")
    with pytest.raises(ValueError, match="membrane_weight"):
        flexure.fair(V, F, region="all-interior", membrane_weight=-1)


def test_info_equals_the_cli(cli, tmp_path):
    V, F = flexure.mesh("delaunay", 6, seed=2)
    flexure.write_mesh(tmp_path / "m.obj", V, F)
    expected = cli.json("info", "--json", tmp_path / "m.obj")
    info = flexure.info(V, F)
    for key in ("vertices", "faces", "edges", "components", "euler_characteristic",
                "boundary_loops", "area", "edge_length"):
        assert info[key] == expected[key], key
    assert info["validation"]["valid"] is True
    for side in ("interior", "boundary"):
        assert {str(k): v for k, v in info["valence_histogram"][side].items()} == \
            {str(k): v for k, v in expected["valence_histogram"][side].items()} or \
            info["valence_histogram"][side] == expected["valence_histogram"][side]


def test_rings_and_loops(plate):
    V, F = plate
    rings = flexure.vertex_rings(V, F)
    assert (rings == 0).sum() == 24 and rings.max() == 3
    assert flexure.boundary_rings(V, F, 1).sum() == 24
    assert flexure.boundary_rings(V, F, 0).sum() == 0
    loops = flexure.boundary_loops(V, F)
    assert len(loops) == 1 and sorted(loops[0]) == sorted(np.flatnonzero(rings == 0))
    with pytest.raises(ValueError, match="k"):
        flexure.boundary_rings(V, F, -1)


def test_info_reports_an_invalid_mesh():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.0]])
    F = np.array([[0, 1, 2], [0, 1, 2]])
    info = flexure.info(V, F)
    assert info["validation"]["valid"] is False and info["validation"]["problems"]


@pytest.fixture(scope="module")
def lion(tmp_path_factory):
    """CGAL's demo mesh lion-head.off (Debian libcgal-demo's data archive): (path, V, F)."""
    archive = pathlib.Path("/usr/share/doc/libcgal-dev/data.tar.gz")
    if not archive.exists():
        pytest.skip(f"{archive} (libcgal-dev) is not installed")
    folder = tmp_path_factory.mktemp("cgal")
    with tarfile.open(archive) as tar:
        tar.extract("data/meshes/lion-head.off", folder)
    path = folder / "data" / "meshes" / "lion-head.off"
    return (path, *flexure.read_mesh(path))


def test_fair_equals_the_cli_on_a_cgal_demo_mesh(cli, lion, tmp_path):
    path, V, F = lion
    centre = V[1000]  # the region of tests/test_fairing.cpp's lion tests
    region = f"sphere:{centre[0]!r},{centre[1]!r},{centre[2]!r},0.15"
    cli("-q", "fair", path, "--region", region, "-o", tmp_path / "out.obj")
    expected, _ = flexure.read_mesh(tmp_path / "out.obj")
    faired, report = flexure.fair(V, F, region=region)
    assert np.abs(faired - expected).max() <= 1e-12
    mask = np.linalg.norm(V - centre, axis=1) <= 0.15
    assert report["region_vertices"] == mask.sum() > 10
    assert report["converged"] and report["after"]["max_displacement"] > 0
    np.testing.assert_array_equal(faired[~mask], V[~mask])


def test_info_on_a_cgal_demo_mesh(cli, lion):
    path, V, F = lion
    expected = cli.json("info", "--json", path)
    info = flexure.info(V, F)
    for key in ("vertices", "faces", "edges", "components", "euler_characteristic",
                "boundary_loops", "area"):
        assert info[key] == expected[key], key
