"""A drape stepped from Python: a plate pinned at two corners falls under gravity (midedge bending
+ StVK membrane, Newmark with a little Rayleigh damping), written as a few frames (OBJ) and, when
OSMesa is available, shaded images of them (one camera for all).

Run: PYTHONPATH=build/python /usr/bin/python3 examples/python/simulation_loop.py [OUT_DIR]
(without OUT_DIR the frames go to a temporary folder that is removed at the end)
"""

import pathlib
import shutil
import sys
import tempfile

import numpy as np

import flexure

V, F = flexure.mesh("patch48", 8)                      # the unit square, 81 vertices
corners = np.isclose(np.abs(V[:, 0]), 0.5) & np.isclose(V[:, 1], 0.5)
drape = flexure.Simulation(V, F, energy="midedge", membrane="stvk", pinned=corners,
                           gravity=[0, 0, -9.81], rayleigh=(1.0, 0.0))

keep = len(sys.argv) > 1                               # else a temporary folder, removed
out = pathlib.Path(sys.argv[1] if keep else tempfile.mkdtemp(prefix="drape-"))
out.mkdir(parents=True, exist_ok=True)
frames = [drape.positions]
start = drape.energies()
for k in range(1, 41):                                 # 0.4 s in steps of 0.01 s
    drape.step(0.01)
    if k % 10 == 0:
        frames.append(drape.positions)
for k, X in enumerate(frames):
    flexure.write_mesh(out / f"frame-{k:02d}.obj", X, F)
framing = np.vstack(frames)                            # one camera for every frame
try:
    for k, X in enumerate(frames):
        image = flexure.render(X, F, style="shaded", size=200, azimuth=25, elevation=30,
                               framing_points=framing)
        flexure.write_png(out / f"frame-{k:02d}.png", image)
except ValueError as error:                            # no OSMesa here: meshes only
    print(f"no images: {error}")

e = drape.energies()
print(f"t = {drape.time:.2f} s: lowest point z = {drape.positions[:, 2].min():.4f}, "
      f"energies {', '.join(f'{k} {v:.4g}' for k, v in e.items())}; "
      f"{len(list(out.iterdir()))} files in {out}{'' if keep else ' (removed)'}")
if not keep:
    shutil.rmtree(out)
assert drape.positions[:, 2].min() < -0.05, "the drape did not fall"
assert np.array_equal(drape.positions[corners], V[corners]), "a pinned corner moved"
assert e["total"] < start["total"], "damping should have dissipated energy"
