"""Fairing a bumpy region of a mesh from Python: flexure.fair moves the region's vertices to
minimize midedge bending (flat rest) + a MIPS membrane; reflection lines before and after, with
one framing, side by side in a PNG.

Run: PYTHONPATH=build/python /usr/bin/python3 examples/python/fair_mesh.py [OUT.png]
(without OUT.png the figure goes to a temporary folder that is removed at the end)
"""

import pathlib
import shutil
import sys
import tempfile

import numpy as np

import flexure

V, F = flexure.mesh("delaunay", 12, seed=4)            # an irregular unit square
rng = np.random.default_rng(2)
W = V.copy()
W[:, 2] = 0.2 * (V[:, 0] ** 2 + V[:, 1] ** 2)          # a bowl...
region = np.hypot(V[:, 0], V[:, 1]) < 0.25
W[region, 2] += 0.01 * rng.standard_normal(region.sum())   # ...with noise in the middle

faired, report = flexure.fair(W, F, region=region)
before = report["before"]["bending"][0]
after = report["after"]["bending"][0]
print(f"fair: {report['region_vertices']} vertices moved, E_{before['energy']} "
      f"{before['value']:.4g} -> {after['value']:.4g}, smallest angle "
      f"{report['checks']['input_min_angle_degrees']:.1f} -> "
      f"{report['checks']['result_min_angle_degrees']:.1f} deg, "
      f"checks {'passed' if report['checks']['passed'] else report['checks']['failure']}")
assert report["converged"] and after["value"] < before["value"]
assert np.array_equal(faired[~region], W[~region]), "only the region moves"

keep = len(sys.argv) > 1                               # else a temporary folder, removed
out = pathlib.Path(sys.argv[1] if keep else pathlib.Path(tempfile.mkdtemp(prefix="fair-")) /
                   "fair.png")
try:
    framing = np.vstack([W, faired])
    images = [flexure.render(X, F, size=320, elevation=60, framing_points=framing)
              for X in (W, faired)]
except ValueError as error:                            # no OSMesa here: no figure
    print(f"no figure: {error}")
else:
    flexure.write_png(out, np.hstack(images))
    assert flexure.read_png(out).shape == (320, 640, 3)
    print(f"before | after: {out}{'' if keep else ' (removed)'}")
if not keep:
    shutil.rmtree(out.parent)
