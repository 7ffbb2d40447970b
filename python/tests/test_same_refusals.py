"""The command and Python refuse the same bad simulation (or fair) for the same reason.

The rules are the library's (optimize::SimulationSpec::validate and the options it validates); the
command maps its flags to the spec's fields and Python its keyword arguments, and each renames the
fields of a message back into its own words. Each case runs through both: `flexure simulate` exits 2
naming the flag, `flexure.Simulation` raises ValueError naming the keyword, and both give the same
reason.
"""

import os
import pathlib
import subprocess

import pytest

import flexure

BASE_FLAGS = {"--energy": "hinge", "--membrane": "stvk", "--dt": "0.01", "--duration": "0.02",
              "--render-style": "none"}
BASE_KEYWORDS = {"energy": "hinge", "membrane": "stvk"}

# (case, the flags, the keyword arguments, what the command names, what Python names, the reason
# both give). A value "EMPTY" is the path of an empty vertex list.
CASES = [
    ("bending plasticity with cotan", ["--energy", "cotan", "--yield-curvature", "0.1"],
     {"energy": "cotan", "yield_curvature": 0.1}, "--yield-curvature: the cotan energy",
     "yield_curvature: the cotan energy", "no per-element rest curvature"),
    ("membrane plasticity without stvk", ["--membrane", "conformal", "--yield-strain", "0.01"],
     {"membrane": "conformal", "yield_strain": 0.01}, "--yield-strain", "yield_strain",
     "membrane plasticity moves the rest metric of"),
    ("hardening without a yield value", ["--hardening", "0.5"], {"hardening": 0.5},
     "--hardening", "hardening", "the plastic hardening needs a yield value"),
    ("negative hardening", ["--yield-curvature", "0.1", "--hardening", "-0.5"],
     {"yield_curvature": 0.1, "hardening": -0.5}, "--hardening -0.5", "hardening -0.5",
     "must be zero or positive"),
    ("negative thickness", ["--fracture-strain", "0.01", "--thickness", "-0.01"],
     {"fracture_strain": 0.01, "thickness": -0.01}, "--thickness", "thickness",
     "must be a finite number ≥ 0, got -0.01"),
    ("unknown integrator", ["--integrator", "leapfrog"], {"integrator": "leapfrog"},
     "--integrator leapfrog", "integrator leapfrog",
     "expected newmark, backward-euler or central-difference"),
    ("unknown mass lumping", ["--mass", "lumped"], {"mass": "lumped"}, "--mass lumped",
     "mass lumped", "expected barycentric or voronoi"),
    ("Newmark beta out of range", ["--beta", "0.9"], {"beta": 0.9}, "--beta 0.9", "beta 0.9",
     "expected 0 < β ≤ 0.5"),
    ("damping with the explicit scheme",
     ["--integrator", "central-difference", "--damping", "rayleigh:1,0"],
     {"integrator": "central-difference", "rayleigh": (1.0, 0.0)}, "--damping", "rayleigh",
     "central"),
    ("an empty vertex list", ["--pin", "vertices:EMPTY"], {"pinned": "vertices:EMPTY"},
     "--pin vertices:", "pinned vertices:", "lists no vertex"),
]


@pytest.fixture(scope="module")
def strip_file(tmp_path_factory):
    folder = tmp_path_factory.mktemp("refusals")
    V, F = flexure.mesh("patch48", 4)
    path = folder / "strip.obj"
    flexure.write_mesh(path, V, F)
    (folder / "empty.txt").write_text("")
    return path


def command(strip_file, flags, out):
    """flexure simulate on the strip with BASE_FLAGS, a flag of `flags` in place of the base's."""
    given = dict(BASE_FLAGS)
    extra = []
    for name, value in zip(flags[::2], flags[1::2]):
        if name in given:
            given[name] = value
        else:
            extra += [name, value]
    words = [word for pair in given.items() for word in pair]
    return [cli_path(), "simulate", "--quiet", "--rest", str(strip_file), *words, *extra, "-o",
            str(out)]


def cli_path():
    return os.environ.get("FLEXURE_CLI") or str(pathlib.Path("cli/flexure").resolve())


@pytest.mark.parametrize("case, flags, keywords, flag_words, keyword_words, reason", CASES,
                         ids=[c[0] for c in CASES])
def test_the_command_and_python_refuse_alike(strip_file, tmp_path, case, flags, keywords,
                                             flag_words, keyword_words, reason):
    empty = str(strip_file.parent / "empty.txt")
    flags = [f.replace("EMPTY", empty) for f in flags]
    keywords = {k: v.replace("EMPTY", empty) if isinstance(v, str) else v
                for k, v in keywords.items()}
    out = tmp_path / "out"
    done = subprocess.run(command(strip_file, flags, out), capture_output=True, text=True)
    assert done.returncode == 2, f"{case}: exit {done.returncode}: {done.stderr}"
    assert not out.exists(), f"{case}: the refused run wrote {out}"
    assert flag_words in done.stderr and reason in done.stderr, f"{case}: {done.stderr}"
    V, F = flexure.read_mesh(strip_file)
    with pytest.raises(ValueError) as refused:
        flexure.Simulation(V, F, **{**BASE_KEYWORDS, **keywords})
    message = str(refused.value)
    assert keyword_words in message and reason in message, f"{case}: {message}"
    # Python's message speaks Python: no C++ field, no flag.
    assert "Options." not in message and "--" not in message, f"{case}: {message}"


def test_a_good_simulation_is_accepted_by_both(strip_file, tmp_path):
    out = tmp_path / "out"
    done = subprocess.run(command(strip_file, ["--pin", "rings:1"], out), capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr
    V, F = flexure.read_mesh(strip_file)
    s = flexure.Simulation(V, F, pinned=1, **BASE_KEYWORDS)
    assert len(s.run(0.02, 0.01)) == 2


def test_time_steps_follow_the_library(strip_file):
    V, F = flexure.read_mesh(strip_file)
    s = flexure.Simulation(V, F, pinned=1, **BASE_KEYWORDS)
    with pytest.raises(ValueError, match=r"^duration 0.015: not a whole number of steps of 0.01"):
        s.run(0.015, 0.01)
    with pytest.raises(ValueError, match=r"^min_dt: expected a step in \(0, dt\]"):
        s.advance(0.01, 0.02)
    assert s.time == 0.0  # nothing was stepped
    assert flexure.__version__.count(".") == 2


def test_every_hessian_mode_of_the_command_is_python_s(plate):
    # One name per concept: the four modes of --hessian, by the same names, and the same refusal.
    V, F = plate
    for mode in ("exact", "projected", "shifted", "exact-projected"):
        _, report = flexure.minimize(V, F, energy="hinge", boundary_surface="quadratic:0.2,0,0.1",
                                     hessian=mode)
        assert report["converged"], mode
    with pytest.raises(ValueError, match="^hessian projected: applies to solver newton"):
        flexure.minimize(V, F, energy="hinge", solver="ceres", hessian="projected")
    with pytest.raises(ValueError, match="^hessian diagonal: expected exact, projected, shifted"):
        flexure.minimize(V, F, energy="hinge", hessian="diagonal")


@pytest.mark.parametrize("flags, keywords, flag_words, keyword_words", [
    (["--energy", "hinge", "--vertex-area", "barycentric"],
     {"energy": "hinge", "vertex_area": "barycentric"}, "--vertex-area applies to --energy cotan",
     "vertex_area applies to energy cotan"),
    (["--energy", "cotan", "--hinge-angle", "tan"], {"energy": "cotan", "hinge_angle": "tan"},
     "--hinge-angle applies to --energy hinge", "hinge_angle applies to energy hinge"),
    (["--energy", "cotan", "--vertex-area", "area"], {"energy": "cotan", "vertex_area": "area"},
     "--vertex-area area: expected voronoi or barycentric",
     "vertex_area area: expected voronoi or barycentric"),
])
def test_energy_options_are_refused_alike(plate, tmp_path, flags, keywords, flag_words,
                                          keyword_words):
    # The command refused options an energy ignores and Python took them: one rule now.
    V, F = plate
    flexure.write_mesh(tmp_path / "p.obj", V, F)
    done = subprocess.run([cli_path(), "energy", "--rest", str(tmp_path / "p.obj"), "--current",
                           str(tmp_path / "p.obj"), *flags], capture_output=True, text=True)
    assert done.returncode == 2 and flag_words in done.stderr, done.stderr
    with pytest.raises(ValueError, match="^" + keyword_words):
        flexure.energy(V, F, V, **keywords)


# A fairing's rules are the library's too (optimize::FairingSpec::validate): (case, the flags of
# `flexure fair`, the keyword arguments of flexure.fair, what the command names, what Python
# names, the reason both give).
FAIR_CASES = [
    ("membrane weight not positive", ["--membrane-weight", "0"], {"membrane_weight": 0},
     "--membrane-weight 0", "membrane_weight 0", "expected a weight > 0"),
    ("unknown start", ["--start", "middle"], {"start": "middle"}, "--start middle",
     "start middle", "expected best, biharmonic or input"),
    ("unknown metric", ["--metric", "intrinsic"], {"metric": "intrinsic"}, "--metric intrinsic",
     "metric intrinsic", "expected input, current or current-exact"),
    ("unknown method", ["--method", "laplace"], {"method": "laplace"}, "--method laplace",
     "method laplace", "expected flexure or cgal"),
    ("unknown membrane", ["--membrane", "rubber"], {"membrane": "rubber"}, "membrane 'rubber'",
     "membrane 'rubber'", "expected stvk, springs, conformal or mips"),
    ("membrane weight with CGAL's fair", ["--method", "cgal", "--membrane-weight", "0.5"],
     {"method": "cgal", "membrane_weight": 0.5}, "--membrane-weight: not with --method cgal",
     "membrane_weight: not with method cgal", "CGAL's linear fair has no membrane"),
    ("slivers allowed with CGAL's fair", ["--method", "cgal", "--allow-slivers"],
     {"method": "cgal", "allow_slivers": True}, "--allow-slivers: not with --method cgal",
     "allow_slivers: not with method cgal", "the smallest-angle rule judges flexure's result"),
    ("remesh edge length not positive", ["--remesh", "--remesh-edge-length", "0"],
     {"remesh": True, "remesh_edge_length": 0}, "--remesh-edge-length 0", "remesh_edge_length 0",
     "expected a finite length > 0"),
    ("remesh iterations without remesh", ["--remesh-iterations", "5"], {"remesh_iterations": 5},
     "--remesh-iterations: only with --remesh", "remesh_iterations: only with remesh",
     "only with"),
    ("vertex area of an energy without one", ["--energy", "hinge", "--vertex-area", "voronoi"],
     {"energy": "hinge", "vertex_area": "voronoi"}, "--vertex-area applies to --energy cotan",
     "vertex_area applies to energy cotan", "only (not hinge)"),
]


@pytest.mark.parametrize("case, flags, keywords, flag_words, keyword_words, reason", FAIR_CASES,
                         ids=[c[0] for c in FAIR_CASES])
def test_the_command_and_python_refuse_a_fair_alike(strip_file, tmp_path, case, flags, keywords,
                                                    flag_words, keyword_words, reason):
    out = tmp_path / "faired.obj"
    done = subprocess.run([cli_path(), "fair", "--quiet", str(strip_file), "--region",
                           "all-interior", *flags, "-o", str(out)], capture_output=True,
                          text=True)
    assert done.returncode == 2, f"{case}: exit {done.returncode}: {done.stderr}"
    assert not out.exists(), f"{case}: the refused fair wrote {out}"
    assert flag_words in done.stderr and reason in done.stderr, f"{case}: {done.stderr}"
    V, F = flexure.read_mesh(strip_file)
    with pytest.raises(ValueError) as refused:
        flexure.fair(V, F, "all-interior", **keywords)
    message = str(refused.value)
    assert keyword_words in message and reason in message, f"{case}: {message}"
    assert "Options." not in message and "Spec." not in message and "--" not in message, message
