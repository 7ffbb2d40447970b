"""flexure.study: the C1/C2 convergence study (``flexure converge``) and the comparison figure
(``flexure compare``) from Python, as data and pixels rather than files."""

import numbers

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


def converge(families=("patch48", "stripe", "criss", "delaunay"), energies=None, n=8, levels=3,
             seeds=(1,), amplitudes=4, quadratics=None, solution=DEFAULT_SOLUTION, poisson=None,
             solver="newton", hessian="exact", threads=2, measure="c1c2", summary=False,
             tables=False, out_dir=None):
    """Run the convergence study of ``flexure converge`` and return its records.

    The study: for every energy on every mesh family (the square [−1/2, 1/2]², unit length L,
    meshes of n, 2n, … 2^(levels−1) n cells per side), C1 and C2 on each quadratic
    p = a x² + b xy + c y² (rings 0 and 1 held on z = p), the nonlinear C2 at boundary
    amplitudes ε = 2⁻¹ … 2^−amplitudes on the coarsest level, and the refinement against the
    biharmonic ``solution`` (None or "none": no refinement).

    families: names or a comma-separated string ("patch48", "stripe", "criss", "delaunay");
    energies: specs as ``--energies`` takes them ("hinge", "hinge:tan", "triavg", "cotan",
    "cotan:barycentric", "midedge", "midedge:free", "quadfit"; None: the spec's seven rows);
    n: cells per side of the coarsest level (≥ 4); levels: 1 … 8; seeds: delaunay's; amplitudes:
    0 or 2 … 12; quadratics: a list of (a, b, c) (None: the default five); poisson: ν for
    triavg, midedge, quadfit (None: 0.3); solver "newton" | "ceres" and hessian "exact" |
    "projected" for the nonlinear C2 solves; threads: cases run at once (results do not depend
    on it). The GIL is released during the study.

    Returns a list of dicts, one per record, with the fields and values results.json's "records"
    has: kind ("quadratic" | "nonlinear_c2" | "refinement"), energy (the label), options, family,
    seed, n, level, h (1/n, in L), vertices, free_vertices, factorizations; quadratic records:
    quadratic, energy_per_area (k_B/L²), density, c1, c1_verdict, c2, c2_verdict (relative
    errors, dimensionless); nonlinear_c2: quadratic, amplitudes, errors, order, converged;
    refinement: solution, error, discrete_energy, exact_energy (k_B), energy_error, order,
    energy_order, verdict, energy_verdict. With ``summary=True``, a dict {"records",
    "refinement", "summary"}: results.json's three lists (the refinement fits and the
    energy × family table, worst C1/C2 on the coarsest level and the orders).

    ``tables`` / ``out_dir`` (summary.md, results.csv and the plots): not available from Python —
    those writers live in the command-line tool (cli/study_outputs.cpp), not the library; run
    ``flexure converge -o DIR`` for the files. ``measure="modes"`` (the spectrum study) is not
    bound either. Both raise NotImplementedError.
    """
    if measure != "c1c2":
        if measure == "modes":
            raise NotImplementedError("measure \"modes\": the spectrum study is not bound in "
                                      "Python; run flexure converge --measure modes -o DIR")
        raise ValueError(f"measure: {measure!r}, expected 'c1c2' or 'modes'")
    if tables or out_dir is not None:
        raise NotImplementedError("tables / out_dir: summary.md, results.csv and the plots are "
                                  "written by the command-line tool, not the library; run "
                                  "flexure converge -o DIR (converge(summary=True) returns the "
                                  "data they are made from)")
    a = _flexure.StudyArguments()
    a.families = _strings(families, "families") if families else []
    if energies is not None:
        a.energies = _strings(energies, "energies")
    if isinstance(seeds, numbers.Integral):
        seeds = [seeds]
    seeds = [_checks.number(s, "seeds", integer=True) for s in seeds]
    if any(s < 0 for s in seeds):
        raise ValueError(f"seeds: must be >= 0 (got {seeds})")
    a.seeds = seeds
    a.n = _checks.number(n, "n", positive=True, integer=True)
    a.levels = _checks.number(levels, "levels", positive=True, integer=True)
    a.amplitudes = _checks.number(amplitudes, "amplitudes", integer=True)
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
    results = _flexure.converge(a)
    if summary:
        return {key: list(results[key]) for key in ("records", "refinement", "summary")}
    return list(results["records"])


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
