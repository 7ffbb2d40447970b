#!/usr/bin/env bash
# End-to-end runs of `flexure simulate --obstacle mesh:FILE[@MOTION]`: a sheet dropped on a static
# box mesh rests on its top, the box drawn in the frames and written once as obstacle-0.obj; a
# sphere mesh driven through a pinned sheet pushes it (report.json: its motion, the balance
# driven); refusals (exit 2, naming the option): an unreadable file, a quad mesh, a mesh without
# faces, an obstacle through the shell at the start; and a box driven into the pinned boundary
# (exit 3 naming the time and a pair).
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/support/cli_harness.sh"

# box.obj: [-0.7, 0.7]² × [-0.3, 0] (12 triangles); sheet.obj: the patch48 plate 0.1 above it.
python3 - <<'PY'
lo, hi = (-0.7, -0.7, -0.3), (0.7, 0.7, 0.0)
with open("box.obj", "w") as f:
    for v in range(8):
        f.write("v %g %g %g\n" % tuple((hi if v >> c & 1 else lo)[c] for c in range(3)))
    for t in [(0,2,1),(1,2,3),(4,5,6),(5,7,6),(0,1,4),(1,5,4),(2,6,3),(3,6,7),(0,4,2),(2,4,6),(1,3,5),(3,7,5)]:
        f.write("f %d %d %d\n" % tuple(i + 1 for i in t))
with open("quads.obj", "w") as f:
    f.write("v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nf 1 2 3 4\n")
with open("points.obj", "w") as f:
    f.write("v 0 0 1\nv 1 0 1\nv 1 1 1\n")
PY
run 0 mesh --family patch48 --n 6 -o plate.obj --quiet
python3 -c "
out = []
for l in open('plate.obj'):
    if l.startswith('v '):
        _, x, y, z = l.split(); l = 'v %s %s %.17g\n' % (x, y, float(z) + 0.1)
    out.append(l)
open('sheet.obj', 'w').writelines(out)"

run 0 simulate --rest sheet.obj --energy hinge --membrane stvk --gravity 0,0,-9.81 \
  --obstacle mesh:box.obj --integrator backward-euler --damping rayleigh:10,0 --dt 0.02 \
  --duration 0.6 --fps 10 --render-size 128 -o rest
[ -f rest/obstacle-0.obj ] || fail "rest/obstacle-0.obj not written"
is_png rest/frames/frame-00006.png || fail "rest/frames/frame-00006.png is not a PNG"
python3 - <<'PY' || fail "sheet on the box: frames or report"
import glob, json
r = json.load(open("rest/report.json"))
m = r["mesh_obstacles"]
assert len(m) == 1 and m[0]["faces"] == 12 and m[0]["motion"]["kind"] == "none", m
assert m[0]["mesh"] == "obstacle-0.obj"
assert r["energy_balance"]["verdict"] != "driven", r["energy_balance"]
frames = sorted(glob.glob("rest/frame-*.obj"))
assert len(frames) == 7, frames
for name in frames:  # the shell's own frames: above the box's top face
    z = [float(l.split()[3]) for l in open(name) if l.startswith("v ")]
    assert len(z) == 49 and min(z) > 0.0, (name, min(z))
z = [float(l.split()[3]) for l in open(frames[-1]) if l.startswith("v ")]
assert max(z) < 0.05, max(z)  # come down onto the top
PY

# A ball of radius 0.06 driven down through a sheet pinned at its boundary at 1 m/s.
run 0 mesh --family sphere --n 8 -o unit.obj --quiet
# ball.obj centred 0.2 above the plate; through.obj the same ball centred on it.
python3 -c "
for name, height in (('ball.obj', 0.2), ('through.obj', 0.0)):
    out = []
    for l in open('unit.obj'):
        if l.startswith('v '):
            x, y, z = map(float, l.split()[1:])
            l = 'v %.17g %.17g %.17g\\n' % (0.12 * x + 0.03, 0.12 * y + 0.02, 0.12 * z + height)
        out.append(l)
    open(name, 'w').writelines(out)"
run 0 simulate --rest plate.obj --energy hinge --membrane stvk --pin rings:1 --self-contact off \
  --obstacle mesh:ball.obj@translate:0,0,-1 --damping rayleigh:5,0 --dt 0.02 --duration 0.24 \
  --fps 25 --render-size 128 -o pushed
python3 - <<'PY' || fail "pushed sheet: report or frames"
import glob, json
r = json.load(open("pushed/report.json"))
m = r["mesh_obstacles"][0]
assert m["motion"] == {"kind": "translate", "velocity": [0.0, 0.0, -1.0]}, m
assert r["energy_balance"]["verdict"] == "driven", r["energy_balance"]
last = sorted(glob.glob("pushed/frame-*.obj"))[-1]
z = [float(l.split()[3]) for l in open(last) if l.startswith("v ")]
assert min(z) < -0.09, min(z)
PY
[ -f pushed/frames/frame-00006.png ] || fail "pushed: no frame images"

# Refusals: exit 2 naming the option, nothing written.
B="--rest plate.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.02 --render-style none"
run 2 simulate $B --obstacle mesh:nothing.obj -o bad
stderr_has "nothing.obj"; absent bad
run 2 simulate $B --obstacle mesh:quads.obj -o bad
stderr_has "--obstacle mesh:quads.obj: quads.obj is not a triangle mesh"; absent bad
run 2 simulate $B --obstacle mesh:points.obj -o bad
stderr_has "--obstacle mesh:points.obj: points.obj has no faces"; absent bad
run 2 simulate $B --obstacle mesh:box.obj@translate:0,0 -o bad
stderr_has "--obstacle mesh:box.obj@translate:0,0"; absent bad
run 2 simulate $B --obstacle mesh:through.obj -o bad
stderr_has "--obstacle mesh:through.obj intersects the shell"; absent bad
run 2 minimize --rest plate.obj --energy hinge --boundary quadratic:0,0,0 --obstacle mesh:box.obj \
  -o minimized.obj
stderr_has "mesh obstacles are for flexure simulate"

# The box driven down onto the pinned boundary: exit 3 at about t = 0.1 (it starts 0.1 above),
# naming a pair with it.
python3 -c "
out = []
for l in open('box.obj'):
    if l.startswith('v '):
        x, y, z = map(float, l.split()[1:])
        l = 'v %g %g %g\\n' % (0.5 + x / 7, y / 7, 0.1 + (z + 0.3) / 2)
    out.append(l)
open('hammer.obj', 'w').writelines(out)"
run 3 simulate --rest plate.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.2 \
  --render-style none --pin rings:1 --obstacle mesh:hammer.obj@translate:0,0,-1 -o hammered
stderr_has "could not proceed at t = 0."; stderr_has "of --obstacle mesh:hammer.obj@translate:0,0,-1"
python3 -c "import json,sys; t=json.load(open('hammered/report.json'))['reached_time']; sys.exit(0 if 0.08 <= t <= 0.105 else 1)" \
  || fail "hammered: not stopped near t = 0.1, where the box reaches the pins"

finish cli_mesh_obstacles
