"""Fairing a region of a real mesh from Python, shown in a matplotlib figure: CGAL's lion head
(Debian's libcgal-demo data), the vertices within 0.22 of a point on its mane faired by flexure
(midedge bending on a flat rest + a MIPS membrane) and by CGAL's linear fair, reflection lines of
the input and of both results side by side, with one framing.

Run: PYTHONPATH=build/python /usr/bin/python3 examples/python/fair_lion.py [OUT.png]
(without OUT.png the figure goes to a temporary folder that is removed at the end)
"""

import pathlib
import shutil
import sys
import tarfile
import tempfile

import matplotlib

matplotlib.use("Agg")  # no display: the figure goes to a file
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import flexure  # noqa: E402

ARCHIVE = "/usr/share/doc/libcgal-dev/data.tar.gz"  # libcgal-demo's meshes
CENTRE, RADIUS = np.array([-0.237469, 0.312627, 0.185747]), 0.22

keep = len(sys.argv) > 1
work = pathlib.Path(tempfile.mkdtemp(prefix="fair-lion-"))
out = pathlib.Path(sys.argv[1]) if keep else work / "fair-lion.png"
try:
    with tarfile.open(ARCHIVE) as tar:
        tar.extract("data/meshes/lion-head.off", work)
    V, F = flexure.read_mesh(work / "data/meshes/lion-head.off")

    region = np.linalg.norm(V - CENTRE, axis=1) < RADIUS
    faired, report = flexure.fair(V, F, region=region)
    cgal, _ = flexure.fair(V, F, region=region, method="cgal")
    before, after = report["before"]["bending"], report["after"]["bending"]
    # Every energy that can be evaluated on the lion (quadfit's fits need a regular enough
    # neighbourhood: its error says which) is lower after.
    measured = [(b, a) for b, a in zip(before, after) if "error" not in b and "error" not in a]
    print(f"lion: {report['region_vertices']} vertices faired in {report['iterations']} "
          f"Newton iterations; " +
          ", ".join(f"{b['energy']} {b['value']:.3g} -> {a['value']:.3g}" for b, a in measured))
    assert report["converged"], report["failure"]
    assert len(measured) >= 4 and all(a["value"] < b["value"] for b, a in measured)
    assert np.array_equal(faired[~region], V[~region]), "only the region moves"

    # The patch around the region (the faces within 1.5 R of its centre), seen along the region's
    # mean normal with one camera for the three images.
    near = np.linalg.norm(V - CENTRE, axis=1) < 1.5 * RADIUS
    patch = F[near[F].all(axis=1)]
    used = np.unique(patch)
    index = np.full(len(V), -1)
    index[used] = np.arange(len(used))
    patch = index[patch]
    corners = V[F[region[F].all(axis=1)]]
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]).sum(axis=0)
    normal /= np.linalg.norm(normal)
    view = dict(size=360, stripes=16, framing_points=np.vstack([V[used], faired[used]]),
                elevation=np.degrees(np.arcsin(normal[2])),
                azimuth=np.degrees(np.arctan2(normal[0], -normal[1])))
    images = {title: flexure.render(X[used], patch, **view)
              for title, X in (("input", V), ("flexure (midedge + MIPS)", faired),
                               ("CGAL's fair", cgal))}
    figure, axes = plt.subplots(1, 3, figsize=(10.8, 3.9), dpi=100)
    for axis, (title, image) in zip(axes, images.items()):
        axis.imshow(image)
        axis.set_title(title)
        axis.axis("off")
    figure.tight_layout()
    figure.savefig(out)
    print(f"reflection lines: {out}{'' if keep else ' (removed)'}")
finally:
    shutil.rmtree(work)
