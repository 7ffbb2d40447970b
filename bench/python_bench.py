#!/usr/bin/env python3
"""The cost of calling flexure from Python (issue #26): the same work timed through the Python
module and in C++ on the same ~10 000-vertex plate, and the evidence that V is not copied.

Run by ``scripts/bench python [ARGS]`` (not a test). Needs the module on PYTHONPATH
(build/python) and bench/simulate_bench (FLEXURE_SIMULATE_BENCH, else build/bench/
simulate_bench beside this build), whose numbers are the C++ side:

- energy + gradient: ``Problem(..., dof="xyz", membrane=StVK Y = 1e3, nothing held)``'s
  ``energy_and_gradient(x)`` at rest, from Python, against simulate_bench's
  ``iteration_costs.gradient_seconds`` (HessianAssembly::evaluate of the same terms on every
  coordinate and ξ at rest, the fastest of three) on the same patch48 mesh (n = 99, 10 000
  vertices). Fastest of ``--repeat`` Python calls.
- one simulation step: ``Simulation`` with simulate_bench's drape scene (StVK Y = 1e3, gravity
  −9.81 z, the sphere 0,0,−0.35 radius 0.3, Newmark ¼ ½, dt = 1/200 s, from rest) stepped
  ``--steps`` times; the mean time of steps 2 … K against simulate_bench's ``seconds / steps``
  for the same K (``--steps K --hessians exact``).

Each energy runs ``--trials`` times, C++ and Python alternating (the machine may be shared), and
each side's fastest trial is kept.
- zero copy: ``flexure._flexure.data_address(V)`` (the address the binding reads V at) equals
  ``V.ctypes.data`` for a C-contiguous float64 V, and differs for a Fortran-ordered copy.

Prints a table (ratios Python / C++: 1.00 is no overhead) on stderr and JSON on stdout.
"""

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

import flexure
from flexure import _flexure

DT = 1.0 / 200.0
DRAPE_SPHERE = "sphere:0,0,-0.35,0.3"
STVK = {"model": "stvk", "young": 1e3}


def simulate_bench_binary():
    path = os.environ.get("FLEXURE_SIMULATE_BENCH")
    if path:
        return path
    here = os.path.dirname(os.path.abspath(__file__))
    return os.path.join(here, "..", "build", "bench", "simulate_bench")


def cpp_records(binary, n, steps, energies):
    """simulate_bench's records (one per energy, exact Hessian) for the drape scene."""
    out = subprocess.run([binary, "--n", str(n), "--steps", str(steps), "--energies",
                          ",".join(energies), "--hessians", "exact"], check=True,
                         capture_output=True, text=True).stdout
    return {r["energy"]: r for r in json.loads(out)["records"]}


def python_gradient_seconds(V, F, energy, repeat):
    problem = flexure.Problem(V, F, energy=energy, dof="xyz", membrane=STVK,
                              fixed=np.zeros(V.shape[0], dtype=bool), boundary_normals="free")
    x = problem.x0()
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        problem.energy_and_gradient(x)
        best = min(best, time.perf_counter() - start)
    return best, problem.n_free


def python_step_seconds(V, F, energy, steps):
    sim = flexure.Simulation(V, F, energy=energy, membrane=STVK, gravity=(0.0, 0.0, -9.81),
                             obstacles=[DRAPE_SPHERE])
    sim.step(DT)  # the first step builds the Hessian pattern and its analysis, timed apart
    start = time.perf_counter()
    for _ in range(steps - 1):
        sim.step(DT)
    return (time.perf_counter() - start) / (steps - 1), sim.energies()["kinetic"]


def zero_copy(V):
    fortran = np.asfortranarray(V)
    return {"c_contiguous_address_equal": _flexure.data_address(V) == V.ctypes.data,
            "V_ctypes_data": V.ctypes.data, "address_seen_by_cpp": _flexure.data_address(V),
            "fortran_order_copied": _flexure.data_address(fortran) != fortran.ctypes.data}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=99, help="patch48 cells per side (99: 10 000 "
                        "vertices)")
    parser.add_argument("--energies", default="hinge,triavg,cotan,midedge,quadfit")
    parser.add_argument("--steps", type=int, default=11, help="simulation steps (>= 2)")
    parser.add_argument("--trials", type=int, default=3, help="C++/Python alternations per "
                        "energy (the fastest of each side kept)")
    parser.add_argument("--repeat", type=int, default=5, help="energy + gradient calls (fastest)")
    parser.add_argument("--no-simulate", action="store_true", help="skip the step comparison")
    args = parser.parse_args()
    flexure.reuse_freed_memory()  # the allocator setting simulate_bench (the C++ side) runs with
    energies = args.energies.split(",")
    V, F = flexure.mesh("patch48", n=args.n)
    copy = zero_copy(V)
    rows = []
    for energy in energies:
        py_grad = cpp_grad = py_step = cpp_step = float("inf")
        for _ in range(args.trials):
            cpp = cpp_records(simulate_bench_binary(), args.n, args.steps, [energy])[energy]
            cpp_grad = min(cpp_grad, cpp["iteration_costs"]["gradient_seconds"])
            cpp_step = min(cpp_step, cpp["seconds"] / cpp["steps"])
            seconds, unknowns = python_gradient_seconds(V, F, energy, args.repeat)
            py_grad = min(py_grad, seconds)
            if not args.no_simulate:
                seconds, kinetic = python_step_seconds(V, F, energy, args.steps)
                py_step = min(py_step, seconds)
        row = {"energy": energy, "vertices": int(V.shape[0]), "unknowns": unknowns,
               "gradient_seconds_python": py_grad, "gradient_seconds_cpp": cpp_grad,
               "gradient_ratio": py_grad / cpp_grad}
        if not args.no_simulate:
            # The same motion: the kinetic energy after K steps, Python's and simulate_bench's.
            row.update({"step_seconds_python": py_step, "step_seconds_cpp": cpp_step,
                        "step_ratio": py_step / cpp_step, "final_kinetic_python": kinetic,
                        "final_kinetic_cpp": cpp["final_kinetic"]})
        rows.append(row)
        print(f"{energy:8s} E+grad  python {py_grad * 1e3:8.2f} ms  C++ {cpp_grad * 1e3:8.2f} ms"
              f"  ratio {row['gradient_ratio']:.3f}", file=sys.stderr)
        if "step_ratio" in row:
            print(f"{'':8s} step    python {row['step_seconds_python']:8.3f} s   C++ "
                  f"{row['step_seconds_cpp']:8.3f} s   ratio {row['step_ratio']:.3f}   kinetic "
                  f"{row['final_kinetic_python']:.12g} / {row['final_kinetic_cpp']:.12g}",
                  file=sys.stderr)
    print(f"zero copy: data_address(V) = {copy['address_seen_by_cpp']:#x}, V.ctypes.data = "
          f"{copy['V_ctypes_data']:#x}, equal: {copy['c_contiguous_address_equal']}; a "
          f"Fortran-ordered V is copied: {copy['fortran_order_copied']}", file=sys.stderr)
    print(json.dumps({"n": args.n, "vertices": int(V.shape[0]), "steps": args.steps,
                      "trials": args.trials,
                      "zero_copy": copy, "records": rows}, indent=2))
    return 0 if copy["c_contiguous_address_equal"] else 1


if __name__ == "__main__":
    sys.exit(main())
