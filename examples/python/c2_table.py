"""The spec's C2 table (energy × mesh family) computed live with flexure.converge: the worst
C2 error max_interior |z − p| / max |p| over five quadratics p on the coarsest meshes (n = 8),
with the pass/fail verdict, as `flexure converge` prints it in summary.md.

Run from the build tree: PYTHONPATH=build/python python3 examples/python/c2_table.py
Exits 1 when the table disagrees with the spec's (a CTest test runs it): midedge(clamped) passes
on every family; every other energy fails on the irregular delaunay meshes.
"""

import sys

import flexure

# C2 only: one level, no nonlinear amplitudes, no refinement solution (under a second).
study = flexure.converge(families=["patch48", "stripe", "criss", "delaunay"], n=8, levels=1,
                         amplitudes=0, solution=None, summary=True)
energies, families, cells = flexure.c2_table(study["summary"])

width = max(len(e) for e in energies)
print(f"{'C2 (n = 8)':{width}s} | " + " | ".join(f"{f:>19s}" for f in families))
print("-" * width + "-|-" + "-|-".join("-" * 19 for _ in families))
for energy, row in zip(energies, cells):
    print(f"{energy:{width}s} | " +
          " | ".join(f"{c2:8.1e} {verdict:>10s}" for c2, verdict in row))

sys.stdout.flush()
delaunay = families.index("delaunay")
wrong = [e for e, row in zip(energies, cells)
         if (e == "midedge(clamped)") != all(verdict == "pass" for _, verdict in row)
         or (e != "midedge(clamped)") != (row[delaunay][1] == "fail")]
if wrong:
    print(f"c2_table: rows {', '.join(wrong)} disagree with the spec's table", file=sys.stderr)
    sys.exit(1)
