"""flexure.study: the convergence studies (``flexure converge``: C1/C2 and the spectrum) and the
comparison figure (``flexure compare``) from Python: records and pixels, and the command's files
on request (written by the same library code, reports/)."""

import json
import numbers
import os

from . import _checks
from . import _flexure

DEFAULT_SOLUTION = "polynomial:x^4-3*x^2*y^2"


def _strings(values, name):
    if isinstance(values, str):
        values = values.split(",")
    values = [str(v).strip() for v in values]
    if not values or any(not v for v in values):
        raise ValueError(f"{name}: give a non-empty list of names")
    return values


def _output_folder(out_dir):
    """out_dir as a path string; ValueError when it, or its nearest existing ancestor, is a file."""
    try:
        path = os.fspath(out_dir)
    except TypeError:
        raise ValueError(f"out_dir: {out_dir!r} is not a path") from None
    if isinstance(path, bytes):
        path = os.fsdecode(path)
    if not path:
        raise ValueError("out_dir: give a folder name")
    existing = os.path.normpath(os.path.abspath(path))
    while not os.path.exists(existing) and os.path.dirname(existing) != existing:
        existing = os.path.dirname(existing)
    if not os.path.isdir(existing):
        raise ValueError(f"out_dir {path}: '{existing}' is a file, not a directory")
    return path


def _refuse(name, value, measure):
    if value is not None:
        raise ValueError(f"{name}: applies to measure '{measure}' only")


def _spectrum_arguments(families, energies, n, levels, seeds, poisson, support, count):
    a = _flexure.SpectrumArguments()
    if families is not None:
        a.families = _strings(families, "families")
    if energies is not None:
        a.energies = _strings(energies, "energies")
    a.seeds = seeds
    a.n = _checks.number(n, "n", positive=True, integer=True)
    a.levels = _checks.number(levels, "levels", positive=True, integer=True)
    a.count = _checks.number(6 if count is None else count, "count", positive=True, integer=True)
    a.support = "simply-supported" if support is None else str(support)
    if poisson is not None:
        a.poisson = _checks.number(poisson, "poisson")
    return a


def _study_arguments(families, energies, n, levels, seeds, amplitudes, quadratics, solution,
                     poisson, solver, hessian, threads):
    a = _flexure.StudyArguments()
    if families is not None:
        a.families = _strings(families, "families") if families else []
    if energies is not None:
        a.energies = _strings(energies, "energies")
    a.seeds = seeds
    a.n = _checks.number(n, "n", positive=True, integer=True)
    a.levels = _checks.number(levels, "levels", positive=True, integer=True)
    a.amplitudes = _checks.number(4 if amplitudes is None else amplitudes, "amplitudes",
                                  integer=True)
    if quadratics is not None:
        qs = []
        for q in quadratics:
            q = list(q)
            if len(q) != 3:
                raise ValueError(f"quadratics: entry {q} is not (a, b, c)")
            qs.append([_checks.number(c, "quadratics") for c in q])
        if not qs:
            raise ValueError("quadratics: give at least one (a, b, c)")
        a.quadratics = qs
    a.solution = "none" if solution is None else str(solution)
    if poisson is not None:
        a.poisson = _checks.number(poisson, "poisson")
    a.solver, a.hessian = str(solver), str(hessian)
    a.threads = _checks.number(threads, "threads", positive=True, integer=True)
    return a


def converge(families=None, energies=None, n=8, levels=3, seeds=(1,), amplitudes=None,
             quadratics=None, solution=DEFAULT_SOLUTION, poisson=None, solver="newton",
             hessian="exact", threads=2, measure="c1c2", support=None, count=None,
             summary=False, tables=False, out_dir=None):
    """Run the convergence study of ``flexure converge`` and return its records.

    measure="c1c2" (default): for every energy on every mesh family (the square [−1/2, 1/2]²,
    unit length L, meshes of n, 2n, … 2^(levels−1) n cells per side), C1 and C2 on each
    quadratic p = a x² + b xy + c y² (rings 0 and 1 held on z = p), the nonlinear C2 at boundary
    amplitudes ε = 2⁻¹ … 2^−amplitudes on the coarsest level, and the refinement against the
    biharmonic ``solution`` (None or "none": no refinement).

    measure="modes" (``flexure converge --measure modes``): the smallest vibration frequencies
    λ₁ … λ_count of the square plate (``support`` "simply-supported", exact λ, or "clamped",
    Leissa 1973) on every energy and family over the levels, against the reference λ.

    families: names or a comma-separated string ("patch48", "stripe", "criss", "delaunay"; None:
    all four for c1c2, patch48 and delaunay for modes); energies: specs as ``--energies`` takes
    them ("hinge", "hinge:tan", "triavg", "cotan", "cotan:barycentric", "midedge",
    "midedge:free", "quadfit"; None: the spec's seven rows for c1c2, the five discretizations for
    modes); n: cells per side of the coarsest level (≥ 4); levels: 1 … 8; seeds: delaunay's.
    c1c2 only: amplitudes 0 or 2 … 12 (None: 4); quadratics: a list of (a, b, c) (None: the
    default five); solution; solver "newton" | "ceres" and hessian "exact" | "projected" for
    the nonlinear C2 solves; threads: cases run at once (results do not depend on it). modes
    only: support (None: "simply-supported"), count 1 … 12 (None: 6; clamped: at most 6).
    poisson: ν for triavg, midedge, quadfit (None: 0.3). An argument of the other measure
    raises ValueError. The GIL is released during the study.

    Returns, c1c2: a list of dicts, one per record, results.json's "records": kind ("quadratic" |
    "nonlinear_c2" | "refinement"), energy (the label), options, family, seed, n, level, h (1/n,
    in L), vertices, free_vertices, factorizations; quadratic records: quadratic,
    energy_per_area (k_B/L²), density, c1, c1_verdict, c2, c2_verdict (relative errors,
    dimensionless); nonlinear_c2: quadratic, amplitudes, errors, order, converged; refinement:
    solution, error, discrete_energy, exact_energy (k_B), energy_error, order, energy_order,
    verdict, energy_verdict. With ``summary=True``, a dict {"records", "refinement", "summary"}:
    results.json's three lists (the refinement fits and the energy × family table, worst C1/C2
    on the coarsest level and the orders).

    Returns, modes: a list of dicts, one per energy and mesh sequence, spectrum.json's "series":
    energy (label), family, seed (delaunay's, else None), clamp ("rings" | "normals" when
    clamped, else None), n (per level), h (1/n, in L), lambda (per level, λ₁ … λ_count, λ =
    ω L² √(ρh/D), dimensionless), relative_error (per level and mode, |λ/λ_ref − 1|), order (per
    mode, the least-squares slope in h, or None), verdict (per mode). With ``summary=True``,
    spectrum.json's dict: support, count, reference (λ_ref), reference_source, lambda (its
    definition), series.

    ``tables=True``: the dict of ``summary=True`` and the text files as strings, keyed by their
    names ("results.csv", "summary.md"; modes: "spectrum.csv", "spectrum.md").
    ``out_dir``: a folder (created if missing) that receives the files ``flexure converge -o``
    writes (results.json, results.csv, summary.md and the PNG plots; modes: spectrum.json,
    spectrum.csv, spectrum.md, spectrum_<family>.png), all or none; the files of an earlier
    study there that this one did not write are removed. The return value is as without it.
    """
    if measure not in ("c1c2", "modes"):
        raise ValueError(f"measure: {measure!r}, expected 'c1c2' or 'modes'")
    folder = "" if out_dir is None else _output_folder(out_dir)
    if isinstance(seeds, numbers.Integral):
        seeds = [seeds]
    seeds = [_checks.number(s, "seeds", integer=True) for s in seeds]
    if any(s < 0 for s in seeds):
        raise ValueError(f"seeds: must be >= 0 (got {seeds})")
    if measure == "modes":
        _refuse("amplitudes", amplitudes, "c1c2")
        _refuse("quadratics", quadratics, "c1c2")
        if solution != DEFAULT_SOLUTION:
            raise ValueError("solution: applies to measure 'c1c2' only")
        a = _spectrum_arguments(families, energies, n, levels, seeds, poisson, support, count)
        text, files = _flexure.spectrum(a, bool(tables), folder)
        data = json.loads(text)
        result = data if summary or tables else data["series"]
    else:
        _refuse("support", support, "modes")
        _refuse("count", count, "modes")
        a = _study_arguments(families, energies, n, levels, seeds, amplitudes, quadratics,
                             solution, poisson, solver, hessian, threads)
        text, files = _flexure.converge(a, bool(tables), folder)
        data = json.loads(text)
        if not (summary or tables):
            return data["records"]
        result = {key: data[key] for key in ("records", "refinement", "summary")}
    if tables:
        result.update(files)
    return result


def c2_table(summary):
    """The C2 table (energy × family) of ``converge(..., summary=True)["summary"]``.

    Returns (energies, families, cells): the row and column labels in the study's order and
    cells[i][j] = (worst C2 over the quadratics on the coarsest level, "pass" | "fail" |
    "inconclusive").
    """
    energies, families, cells = [], [], {}
    for row in summary:
        if row["energy"] not in energies:
            energies.append(row["energy"])
        if row["family"] not in families:
            families.append(row["family"])
        cells[row["energy"], row["family"]] = (row["c2"], row["c2_verdict"])
    return energies, families, [[cells[e, f] for f in families] for e in energies]


def compare_figure(families=("patch48", "stripe", "delaunay"), energies=None,
                   boundary="quadratic:0.3,-0.7,0.5", n=16, solve="linearized",
                   style="reflection", size=400, stripes=12, threads=2):
    """The comparison figure of ``flexure compare`` as an H×W×3 uint8 array (rows top to bottom).

    Every energy's minimizer of the flat-plate test problem (rings 0 and 1 lifted onto
    z = p(x, y), p = ``boundary``; height mode; midedge's boundary normals clamped) on every
    family's mesh of n cells per side, rendered alike (``style``, ``size`` pixels square per
    panel, ``stripes``) beside the exact sample of p, composed into the labelled grid with each
    panel's C2 error over it: the pixels of compare.png for the same options. families: rows;
    energies: columns after the reference (specs as ``converge`` takes them; None: the
    registered energies); solve: "linearized" | "nonlinear".

    Returns ``(image, panels)``: image H×W×3 uint8; panels a list of dicts (family, energy,
    c2_error, converged, iterations, final_energy), row by row. Uses an OSMesa context of its
    own; call from one thread.
    """
    a = _flexure.CompareArguments()
    a.families = _strings(families, "families")
    if energies is not None:
        a.energies = _strings(energies, "energies")
    a.boundary, a.solve, a.style = str(boundary), str(solve), str(style)
    a.n = _checks.number(n, "n", positive=True, integer=True)
    a.size = _checks.number(size, "size", positive=True, integer=True)
    a.stripes = _checks.number(stripes, "stripes", positive=True, integer=True)
    a.threads = _checks.number(threads, "threads", positive=True, integer=True)
    image, panels = _flexure.compare_figure(a)
    return image, [dict(p) for p in panels]
