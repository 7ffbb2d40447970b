"""converge equals `flexure converge`'s results.json; compare_figure equals compare.png's pixels."""

import json
import math

import numpy as np
import pytest

import flexure

# A small study: base n 8, 2 levels, two energies (midedge's ξ and a ν = 1 model), two families
# (one of them seeded), two amplitudes, the default refinement solution.
STUDY = dict(families=["patch48", "delaunay"], energies=["hinge", "midedge"], n=8, levels=2,
             seeds=[3], amplitudes=2)
STUDY_FLAGS = ["--families", "patch48,delaunay", "--energies", "hinge,midedge", "--n", "8",
               "--levels", "2", "--seeds", "3", "--amplitudes", "2"]


def assert_same(python, cli, where="record"):
    """Equal dicts: the same keys, strings/ints/None equal, floats to 1e-12 relative."""
    if isinstance(cli, dict):
        assert isinstance(python, dict), where
        assert set(python) == set(cli), f"{where}: keys {set(python) ^ set(cli)}"
        for key in cli:
            assert_same(python[key], cli[key], f"{where}.{key}")
    elif isinstance(cli, list):
        assert len(python) == len(cli), where
        for k, (p, c) in enumerate(zip(python, cli)):
            assert_same(p, c, f"{where}[{k}]")
    elif isinstance(cli, float) or isinstance(python, float):
        assert math.isclose(python, cli, rel_tol=1e-12, abs_tol=1e-300), f"{where}: {python} {cli}"
    else:
        assert python == cli, f"{where}: {python!r} != {cli!r}"


@pytest.fixture(scope="module")
def cli_results(cli, tmp_path_factory):
    out = tmp_path_factory.mktemp("converge")
    cli("-q", "converge", *STUDY_FLAGS, "-o", out)
    with open(out / "results.json") as f:
        return json.load(f)


@pytest.fixture(scope="module")
def python_results():
    return flexure.converge(**STUDY, summary=True)


def test_records_equal_results_json(cli_results, python_results):
    records = flexure.converge(**STUDY)
    assert len(records) == len(cli_results["records"]) > 0
    kinds = {r["kind"] for r in records}
    assert kinds == {"quadratic", "nonlinear_c2", "refinement"}
    assert_same(records, cli_results["records"], "records")


def test_refinement_fits_and_summary_equal_results_json(cli_results, python_results):
    assert_same(python_results["records"], cli_results["records"], "records")
    assert_same(python_results["refinement"], cli_results["refinement"], "refinement")
    assert_same(python_results["summary"], cli_results["summary"], "summary")


def test_results_do_not_depend_on_threads(python_results):
    one = flexure.converge(**STUDY, threads=1, summary=True)
    assert one == python_results


def test_c2_table_is_the_spec_verdicts(python_results):
    energies, families, cells = flexure.c2_table(python_results["summary"])
    assert energies == ["hinge", "midedge(clamped)"]
    assert families == ["patch48", "delaunay"]
    # The spec's table: midedge reproduces quadratics on every mesh, hinge fails on both.
    assert all(verdict == "pass" for _, verdict in cells[1])
    assert all(verdict == "fail" for _, verdict in cells[0])
    for row in cells:
        for c2, _ in row:
            assert c2 >= 0.0


def test_options_quadratics_and_no_solution():
    records = flexure.converge(families="criss", energies="cotan", n=8, levels=1,
                               quadratics=[(1, 0, 1)], amplitudes=0, solution=None)
    assert [r["kind"] for r in records] == ["quadratic"]
    assert records[0]["quadratic"] == "quadratic:1,0,1"
    assert records[0]["options"]["vertex_area"] == "voronoi"


@pytest.mark.parametrize("arguments, words", [
    (dict(energies=["bogus"]), "energies"),
    (dict(families=["hexagons"]), "families"),
    (dict(levels=9), "levels"),
    (dict(n=2), "^n 2: at least 4 cells"),
    (dict(amplitudes=1), "amplitudes"),
    (dict(quadratics=[(0, 0, 0)]), "quadratic"),
    (dict(quadratics=[(1, 0)]), "quadratics"),
    (dict(solution="polynomial:x^2*y^2"), "biharmonic"),
    (dict(solver="lbfgs"), "solver"),
    (dict(measure="stress"), "measure"),
])
def test_bad_study_raises_value_error_naming_it(arguments, words):
    options = dict(families="patch48", energies="hinge", n=8, levels=1, amplitudes=0)
    options.update(arguments)
    with pytest.raises(ValueError, match=words):
        flexure.converge(**options)


def test_compare_figure_equals_compare_png(cli, tmp_path):
    flags = ["--families", "patch48,delaunay", "--energies", "hinge,midedge:free", "--n", "8",
             "--size", "96"]
    cli("-q", "compare", *flags, "-o", tmp_path)
    image, panels = flexure.compare_figure(families=["patch48", "delaunay"],
                                           energies=["hinge", "midedge:free"], n=8, size=96)
    expected = flexure.read_png(tmp_path / "compare.png")
    assert image.dtype == np.uint8 and image.ndim == 3 and image.shape[2] == 3
    assert image.shape == expected.shape
    assert np.array_equal(image, expected)
    with open(tmp_path / "compare.json") as f:
        cli_panels = json.load(f)["panels"]
    assert [(p["family"], p["energy"]) for p in panels] == \
        [(p["family"], p["energy"]) for p in cli_panels]
    for p, c in zip(panels, cli_panels):
        assert math.isclose(p["c2_error"], c["c2_error"], rel_tol=1e-12, abs_tol=1e-300)


@pytest.mark.parametrize("style", ["error", "curvature"])
def test_compare_figure_scalar_styles_share_the_cli_scale(cli, tmp_path, style):
    # One colour scale over the figure (reports/comparison_figure.h), as flexure compare draws it.
    flags = ["--families", "patch48", "--energies", "hinge,midedge", "--n", "8", "--size", "96",
             "--style", style]
    cli("-q", "compare", *flags, "-o", tmp_path)
    image, _ = flexure.compare_figure(families=["patch48"], energies=["hinge", "midedge"], n=8,
                                      size=96, style=style)
    assert np.array_equal(image, flexure.read_png(tmp_path / "compare.png"))


def test_compare_figure_bad_options():
    with pytest.raises(ValueError, match="size"):
        flexure.compare_figure(size=32)
    with pytest.raises(ValueError, match="solve"):
        flexure.compare_figure(solve="exact", size=64, n=4, families="patch48")
