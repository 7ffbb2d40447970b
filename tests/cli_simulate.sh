#!/usr/bin/env bash
# End-to-end runs of `flexure simulate`: frames, energy history and report; re-runs; refusals
# (exit 2, nothing written) and a run that cannot proceed (exit 3, the report and the frames
# computed before the failure); the energy balance.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/support/cli_harness.sh"

report_check() {  # report_check DIR EXPRESSION MESSAGE: a Python test over d = report.json
  python3 -c "import json,sys; d=json.load(open('$1/report.json')); sys.exit(0 if ($2) else 1)" \
    || fail "$1/report.json: $3"
}

run 0 mesh --family delaunay --n 8 -o plate.obj --quiet
# A clamped plate sagging under gravity, damped: 20 steps, a frame every 0.05 s.
run 0 simulate --rest plate.obj --energy midedge --membrane stvk --pin rings:2 --gravity 0,0,-9.81 \
  --damping rayleigh:20,0 --dt 0.01 --duration 0.2 --fps 20 -o sag
stderr_has "flexure simulate: t = 0.2 / 0.2 s"; stderr_has "wrote 5 frames"
for k in 0 1 2 3 4; do
  [ -s "sag/frame-0000$k.obj" ] || fail "sag/frame-0000$k.obj missing"
  is_png "sag/frames/frame-0000$k.png" || fail "sag/frames/frame-0000$k.png is not a PNG"
done
absent sag/frame-00005.obj; absent sag/frame-00000.png; absent sag/frames/frame-00005.png
[ "$(wc -l < sag/energies.csv)" -eq 22 ] || fail "energies.csv: a header and 21 samples"
head -1 sag/energies.csv | grep -qx "time,kinetic,midedge,stvk,gravity,total" \
  || fail "energies.csv header: $(head -1 sag/energies.csv)"
is_png sag/energies.png || fail "sag/energies.png is not a PNG"
report_check sag "d['completed'] and d['steps'] == 20 and d['step_halvings'] == 0" "20 steps"
report_check sag "d['final_energies']['total'] < 0" "gravity did work: the total fell below 0"
# The energy balance: the total with the work done against damping stays within the tolerance.
report_check sag "d['energy_balance']['verdict'] == 'balanced' and d['energy_balance']['tolerance'] == 0.05 \
  and d['energy_balance']['relative_drift'] < 0.05 and d['energy_balance']['dissipated'] > 0 \
  and not d['partial']" "the energy balance"
stderr_has "energy balance: the total (with the work done against damping) drifted by"
run 0 info sag/frame-00004.obj --json; stdout_has '"valid": true'
# Undamped backward Euler dissipates numerically what no damping accounts for: its balance ends
# 'dissipated' far beyond the tolerance, what the scheme does (exit 0).
run 0 simulate --rest plate.obj --energy hinge --membrane stvk --pin rings:2 --gravity 0,0,-9.81 \
  --integrator backward-euler --dt 0.01 --duration 0.2 --render-style none -o lossy
report_check lossy "d['completed'] and d['energy_balance']['verdict'] == 'dissipated' \
  and d['energy_balance']['relative_drift'] > 0.05 and d['failure'] is None" "the dissipated balance"
# A run that ends having gained more than the tolerance is a numerical failure (exit 3) with every
# frame and output written and the report naming the drift: a sphere shattering on a floor with
# its fragments passing through each other (no self-contact) gains 7.3 % of its peak kinetic
# energy.
run 0 mesh --family sphere --n 16 -o bulb.obj --quiet
B="--rest bulb.obj --energy hinge --membrane stvk --young 1000 --gravity 0,0,-9.81 \
  --obstacle plane:0,0,1,-0.6 --fracture-strain 0.02 --thickness 0.01 --dt 0.005 --duration 0.4 \
  --fps 20 --render-style none --self-contact off"
run 3 simulate $B -o gained
stderr_has "numerical failure: energy balance: gained"; stderr_has "beyond the 5 % tolerance"
report_check gained "d['completed'] and d['energy_balance']['verdict'] == 'gained' \
  and d['energy_balance']['relative_drift'] > 0.05 and d['failure'].startswith('energy balance: \
gained ')" "the gained balance"
[ -s gained/frame-00008.obj ] && [ -s gained/energies.csv ] || fail "gained: its frames are gone"
# A drift within a looser tolerance is balanced: the same run, exit 0.
run 0 simulate $B --energy-tolerance 0.5 -o gained-within
report_check gained-within "d['energy_balance']['verdict'] == 'balanced' and d['failure'] is None" \
  "a drift within --energy-tolerance 0.5"
# A plate at rest with no load: its total drifts by round-off only (~1e-28 on a peak kinetic
# energy of ~1e-28), which is "balanced", not a warning.
run 0 simulate --rest plate.obj --energy hinge --membrane stvk --pin rings:1 --dt 0.01 \
  --duration 0.1 --render-style none -o still
grep -q "warning" err.txt && fail "a plate at rest warned: $(cat err.txt)"
report_check still "d['energy_balance']['verdict'] == 'balanced' and \
  abs(d['energy_balance']['largest_drift']) <= d['energy_balance']['roundoff'] < 1e-6" \
  "a plate at rest is balanced within round-off"
# The last frame sags: its lowest z is below 0.
python3 -c "
import sys
z = [float(l.split()[3]) for l in open('sag/frame-00004.obj') if l.startswith('v ')]
sys.exit(0 if min(z) < 0 else 1)" || fail "the plate did not sag"

# A shorter re-run into the same folder leaves exactly its own frames.
touch sag/notes.txt
run 0 simulate --rest plate.obj --energy hinge --membrane springs --pin rings:1 --dt 0.01 \
  --duration 0.05 --fps 20 -o sag --quiet --integrator backward-euler --render-style none
absent sag/frame-00002.obj; absent sag/frames/frame-00000.png; [ -e sag/notes.txt ] || fail "simulate removed a file it did not write"
report_check sag "d['integrator'] == 'backward-euler'" "the integrator"

# Bending damping with Rayleigh's: the run completes and the report names both.
run 0 simulate --rest plate.obj --energy midedge --membrane stvk --pin rings:2 --gravity 0,0,-9.81 \
  --damping rayleigh:2,0 --damping bend:0.01 --dt 0.01 --duration 0.05 --render-style none \
  -o bent --quiet
report_check bent "d['completed'] and d['damping'] == ['rayleigh:2,0', 'bend:0.01']" "both dampings"

# Moving pins: the rim turns a quarter about z (0.25 s at 2 pi rad/s); the last frame's pinned
# corner (0.5, 0.5) is at (-0.5, 0.5).
run 0 mesh --family patch48 --n 6 -o sheet.obj --quiet
run 0 simulate --rest sheet.obj --energy hinge --membrane stvk --pin rings:1 \
  --pin-motion rotate:0,0,1,0,0,0,6.283185307179586 --dt 0.01 --duration 0.25 --fps 4 \
  --render-style none -o turn --quiet
report_check turn "d['completed'] and d['pin_motion'].startswith('rotate:')" "the pin motion"
python3 -c "
import sys
v = [[float(x) for x in l.split()[1:]] for l in open('turn/frame-00001.obj') if l.startswith('v ')]
sys.exit(0 if any(abs(x + 0.5) < 1e-9 and abs(y - 0.5) < 1e-9 for x, y, z in v) else 1)" \
  || fail "the pinned corner did not turn to (-0.5, 0.5)"
run 2 simulate --rest sheet.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
  --pin-motion translate:1,0,0 -o bad; stderr_has "give them with --pin"; absent bad
run 2 simulate --rest sheet.obj --energy hinge --membrane stvk --pin rings:1 --dt 0.01 \
  --duration 0.1 --pin-motion rotate:0,0,0,0,0,0,1 -o bad; stderr_has "the axis is zero"; absent bad
run 2 simulate --rest sheet.obj --energy hinge --membrane stvk --pin rings:1 --dt 0.01 \
  --duration 0.1 --pin-motion twist:1 -o bad; stderr_has "--pin-motion twist:1: expected"; absent bad
# Too few numbers, a number that is not finite: the count is named.
for spec in rotate:0,0,1,0,0,0 translate:1,2 translate:1,2,inf; do
  run 2 simulate --rest sheet.obj --energy hinge --membrane stvk --pin rings:1 --dt 0.01 \
    --duration 0.1 --pin-motion "$spec" -o bad; stderr_has "--pin-motion $spec: expected"
  stderr_has "finite numbers)"; absent bad
done

# --video: an MP4 of the frames when ffmpeg is installed, else exit 2 saying so, nothing written.
if command -v ffmpeg >/dev/null; then
  run 0 simulate --rest sheet.obj --energy hinge --membrane stvk --pin rings:1 --dt 0.01 \
    --duration 0.1 --fps 20 --render-size 64 -o clip --video clip.mp4 --quiet
  [ "$(head -c 8 clip.mp4 | tail -c 4)" = ftyp ] || fail "clip.mp4 is not an MP4"
  cp clip.mp4 first.mp4
  run 0 simulate --rest sheet.obj --energy hinge --membrane stvk --pin rings:1 --dt 0.01 \
    --duration 0.1 --fps 20 --render-size 64 -o clip --video clip.mp4 --quiet
  cmp -s clip.mp4 first.mp4 || fail "the same run gave a different clip.mp4"
else
  run 2 simulate --rest sheet.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
    -o clip --video clip.mp4; stderr_has "ffmpeg is not installed"; absent clip; absent clip.mp4
fi
run 2 simulate --rest sheet.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
  --render-style none -o clip2 --video clip2.mp4; stderr_has "not with --render-style none"
absent clip2; absent clip2.mp4
run 2 simulate --rest sheet.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
  -o clip2 --video clip2.avi; stderr_has "expected a .mp4"; absent clip2

# The static counterpart: minimize under gravity (Newton only).
run 0 minimize --rest plate.obj --energy midedge --dof xyz --membrane stvk --boundary quadratic:0,0,0 \
  --gravity 0,0,-9.81 -o static.obj --report static.json --quiet
python3 -c "
import json, sys
d = json.load(open('static.json')); z = [float(l.split()[3]) for l in open('static.obj') if l.startswith('v ')]
sys.exit(0 if d['converged'] and d['load']['gravity'] == '0,0,-9.81' and min(z) < 0 else 1)" \
  || fail "minimize --gravity: no converged sag"
run 2 minimize --rest plate.obj --energy hinge --dof xyz --membrane stvk --boundary quadratic:0,0,0 \
  --gravity 0,0,-9.81 --solver ceres -o bad.obj; stderr_has "needs the nonlinear Newton"; absent bad.obj
run 2 minimize --rest plate.obj --energy hinge --boundary quadratic:0,0,0 --gravity 0,0 -o bad.obj
stderr_has "--gravity 0,0: expected 3"; absent bad.obj
run 2 minimize --rest plate.obj --energy hinge --boundary quadratic:0,0,0 --gravity 0,0,-9.81, \
  -o bad.obj; stderr_has "expected 3"; absent bad.obj

# Refusals: exit 2, the option named, nothing written.
run 2 simulate --rest plate.obj --energy hinge --dt 0.01 --duration 0.1 -o bad
stderr_has "give a membrane"; absent bad
run 2 simulate --rest plate.obj --energy hinge --membrane stvk --dt 0 --duration 0.1 -o bad
stderr_has "--dt"; absent bad
run 2 simulate --rest plate.obj --energy hinge --membrane stvk --dt 0.1 --duration 0.01 -o bad
stderr_has "--duration"; absent bad
run 2 simulate --rest plate.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
  --damping viscous:1 -o bad; stderr_has "rayleigh:alpha,beta"; absent bad
run 2 simulate --rest plate.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
  --damping bend:-1 -o bad; stderr_has "bend:c"; absent bad
run 2 simulate --rest plate.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
  --damping bend:1 --damping bend:2 -o bad; stderr_has "each at most once"; absent bad
run 2 simulate --rest plate.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
  --gravity 0,-9.81 -o bad; stderr_has "--gravity 0,-9.81"; absent bad
run 2 simulate --rest plate.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
  --integrator central-difference --damping rayleigh:1,0 -o bad; stderr_has "central-difference"
absent bad
run 2 simulate --rest plate.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
  --integrator leapfrog -o bad; stderr_has "--integrator leapfrog: expected newmark"; absent bad
run 2 simulate --rest plate.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
  --pin box:5,6,0,1,0,1 -o bad; stderr_has "--pin box:5,6,0,1,0,1: the box holds no vertex"
absent bad
run 2 simulate --rest plate.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
  --render-style curvature -o bad; stderr_has "--render-style curvature"; absent bad
run 0 mesh --family patch48 --n 4 -o other.obj --quiet
run 2 simulate --rest plate.obj --init other.obj --energy hinge --membrane stvk --dt 0.01 \
  --duration 0.1 -o bad; stderr_has "connectivity"; absent bad

# Obstacles: a sheet falls onto a plane 0.02 below it and onto a sphere; the contact energy is a
# column, the report's smallest distance stays positive (no vertex ever inside).
run 0 simulate --rest sheet.obj --energy hinge --membrane stvk --gravity 0,0,-9.81 \
  --obstacle plane:0,0,1,-0.02 --obstacle sphere:0.3,0.3,-0.5,0.47 --damping rayleigh:2,0 \
  --dt 0.01 --duration 0.3 --render-style none -o drop --quiet
head -1 drop/energies.csv | grep -qx "time,kinetic,hinge,stvk,gravity,contact,total" \
  || fail "energies.csv header with contact: $(head -1 drop/energies.csv)"
report_check drop "d['completed'] and 0 < d['smallest_obstacle_distance'] < d['obstacle_layer'] \
  and len(d['obstacles']) == 2" "contact without penetration"
# The frames show the scene: shaded (the default), the obstacles drawn in their warm colour, the
# time written at the top left; highlight lines (moiré at frame sizes) are refused.
run 0 simulate --rest sheet.obj --energy hinge --membrane stvk --gravity 0,0,-9.81 \
  --obstacle sphere:0,0,-0.32,0.3 --damping rayleigh:2,0 --dt 0.01 --duration 0.1 --fps 10 \
  --render-size 160 -o scene --quiet
PYTHONPATH="$(dirname "${BASH_SOURCE[0]}")/support" python3 - <<'PY' || fail "simulate frames: no obstacle or no time stamp"
import sys
from png_pixels import read_png
w, h, rows = read_png("scene/frames/frame-00001.png")
warm = sum(1 for row in rows for (r, g, b) in row if r > g + 30 and g > b + 30 and r > 120)
ink = sum(1 for row in rows[:20] for (r, g, b) in row[:80] if r < 100 and g < 100 and b < 100)
sys.exit(0 if (w, h) == (160, 160) and warm > 200 and ink > 10 else 1)
PY
run 0 simulate --rest sheet.obj --energy hinge --membrane stvk --gravity 0,0,-9.81 --pin rings:1 \
  --dt 0.01 --duration 0.05 --fps 20 --render-size 96 --render-style displacement --exaggerate 5 \
  -o scene-displacement --quiet
is_png scene-displacement/frames/frame-00001.png || fail "simulate --render-style displacement: no frame"
run 2 simulate --rest sheet.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
  --render-style highlight -o bad; stderr_has "--render-style highlight"; absent bad
# minimize under gravity held up by a plane: converged, every vertex above it.
run 0 minimize --rest plate.obj --energy cotan --boundary quadratic:0,0,0 --gravity 0,0,-200 \
  --obstacle plane:0,0,1,-0.02 -o held.obj --report held.json --quiet
python3 -c "
import json, sys
d = json.load(open('held.json')); z = [float(l.split()[3]) for l in open('held.obj') if l.startswith('v ')]
sys.exit(0 if d['converged'] and min(z) > -0.02 and 0 < d['smallest_obstacle_distance'] < d['obstacle_layer'] else 1)" \
  || fail "minimize --obstacle: not held above the plane"
# Refusals: a malformed obstacle, a start inside one (the vertex named), the explicit scheme.
for spec in plane:0,0,1 plane:0,0,0,1 sphere:0,0,0,-1 box:0,0,0,1; do
  run 2 simulate --rest sheet.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
    --obstacle "$spec" -o bad; stderr_has "--obstacle $spec"; absent bad
done
run 2 simulate --rest sheet.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
  --obstacle sphere:0.5,0.5,0,0.1 -o bad; stderr_has "vertex 48 of the start is inside"; absent bad
run 2 simulate --rest sheet.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
  --obstacle plane:0,0,1,0 -o bad; stderr_has "is inside or on the obstacle"; absent bad
run 2 simulate --rest sheet.obj --energy hinge --membrane stvk --dt 0.01 --duration 0.1 \
  --obstacle plane:0,0,1,-1 --integrator central-difference -o bad; stderr_has "central-difference"
absent bad
run 2 minimize --rest plate.obj --energy cotan --boundary quadratic:0,0,0 --obstacle plane:0,0,1,0.1 \
  -o bad.obj; stderr_has "of the start is inside"; absent bad.obj
run 2 minimize --rest plate.obj --energy cotan --boundary quadratic:0,0,0 --linearized \
  --obstacle plane:0,0,1,-0.1 -o bad.obj; stderr_has "needs the nonlinear Newton"; absent bad.obj

# The explicit scheme cannot keep the shell from passing through itself: refused while
# self-contact is on (the default), before any work.
run 2 simulate --rest plate.obj --energy hinge --membrane stvk --pin rings:2 \
  --integrator central-difference --dt 0.01 --duration 0.1 -o explicit
stderr_has "--self-contact: the explicit central-difference scheme"; absent explicit
# The explicit scheme far above its stability limit gains energy at its first step: exit 3, the
# report says where and by how much; the frame of the start is kept and the report says partial.
run 3 simulate --rest plate.obj --energy hinge --membrane stvk --pin rings:2 --gravity 0,0,-9.81 \
  --integrator central-difference --self-contact off --dt 0.01 --min-dt 0.01 --duration 5 -o blown
stderr_has "could not proceed"; stderr_has "blown/report.json"; stderr_has "the total energy grew by"
report_check blown "not d['completed'] and d['partial'] and 'a step of 0.01 s failed' in d['failure']" "the failure"
[ -s blown/frame-00000.obj ] && [ -s blown/energies.csv ] || fail "blown: the start's frame and energies are gone"

# simulate.md's cotan drape at dt 0.01 (patch48 n = 12) used to blow up (total -0.79 -> +26.8 at
# t = 1) and exit 0. Without halving it now stops where a step gains more than 5 % of the peak
# kinetic energy, keeping the 19 frames to t = 0.6 (meshes, images, energies), exit 3 (without
# self-contact, which would change where: its folds touch).
run 0 mesh --family patch48 --n 12 -o drape-sheet.obj --quiet
run 3 simulate --rest drape-sheet.obj --energy cotan --stiffness 0.01 --membrane stvk --young 1000 \
  --gravity 0,0,-9.81 --obstacle sphere:0,0,-0.32,0.3 --damping rayleigh:2,0 --dt 0.01 \
  --min-dt 0.01 --duration 1 --render-size 64 --self-contact off -o drape
stderr_has "the total energy grew by"; stderr_has "the 19 frames to t = 0.6"
report_check drape "d['partial'] and abs(d['reached_time'] - 0.6) < 1e-9 and d['frames'] == 19 \
  and 'the total energy grew by' in d['failure'] and d['energy_balance']['peak_kinetic'] > 0.6" \
  "the partial drape"
[ "$(wc -l < drape/energies.csv)" -eq 62 ] || fail "drape/energies.csv: a header and 61 samples"
[ -s drape/frame-00018.obj ] && is_png drape/frames/frame-00018.png || fail "drape: frame 18 missing"
absent drape/frame-00019.obj
run 2 simulate --rest drape-sheet.obj --energy cotan --membrane stvk --dt 0.01 --duration 0.1 \
  --energy-tolerance 0 -o bad; stderr_has "--energy-tolerance"; absent bad
# --step-tolerance ε_v (the Newton stop ‖Δx‖∞/h ≤ ε_v l) not > 0 and finite: refused before any
# work, naming the flag (the library's rule, DynamicsOptions.stepTolerance).
for bad in 0 -1e-3 inf; do
  run 2 simulate --rest drape-sheet.obj --energy cotan --membrane stvk --dt 0.01 --duration 0.1 \
    --step-tolerance "$bad" -o bad; stderr_has "--step-tolerance"; absent bad
done
# --quasi-newton-pairs m (L-BFGS steps on the kept factor): the sagging plate's last frame within
# 1e-3 of its diagonal of the chord steps' (m = 0); m outside 0..100 refused before any
# work, naming the flag.
for m in 0 6; do
  run 0 simulate --rest plate.obj --energy midedge --membrane stvk --pin rings:2 \
    --gravity 0,0,-9.81 --damping rayleigh:20,0 --dt 0.01 --duration 0.2 --fps 20 \
    --render-style none --quasi-newton-pairs $m -o sag-pairs-$m
done
python3 -c "
def vertices(path):
    return [[float(t) for t in l.split()[1:4]] for l in open(path) if l.startswith('v ')]
a, b = vertices('sag-pairs-0/frame-00004.obj'), vertices('sag-pairs-6/frame-00004.obj')
diagonal = sum((max(p[i] for p in a) - min(p[i] for p in a)) ** 2 for i in range(3)) ** 0.5
assert len(a) == len(b) > 0
assert max(abs(p[i] - q[i]) for p, q in zip(a, b) for i in range(3)) <= 1e-3 * diagonal
" || fail "sag-pairs-6: the last frame differs from the chord steps' by more than 1e-3 l"
for bad in -1 101; do
  run 2 simulate --rest drape-sheet.obj --energy cotan --membrane stvk --dt 0.01 --duration 0.1 \
    --quasi-newton-pairs "$bad" -o bad; stderr_has "--quasi-newton-pairs"; absent bad
done

# --friction μ: a sheet falling on a floor under gravity tilted along x, undamped (report.json
# carries μ, the work against friction counted as dissipated); μ < 0 or not finite refused before
# any work (exit 2, naming the flag, nothing written).
run 0 simulate --rest plate.obj --energy hinge --membrane stvk --gravity 3,0,-9.81 \
  --obstacle plane:0,0,1,-0.01 --friction 0.4 --integrator backward-euler --dt 0.01 \
  --duration 0.2 --render-style none -o rubbed
report_check rubbed "d['completed'] and d['friction'] == 0.4 \
  and d['energy_balance']['dissipated'] > 0 and d['energy_balance']['verdict'] != 'gained'" \
  "a run with friction"
for mu in -0.1 nan inf; do
  run 2 simulate --rest plate.obj --energy hinge --membrane stvk --obstacle plane:0,0,1,-0.01 \
    --friction $mu --dt 0.01 --duration 0.1 -o bad; stderr_has "--friction"; absent bad
done

# --checkpoint N writes DIR/checkpoint.json every N steps; --resume DIR continues from it. A run
# stopped after step 25 (its last checkpoint at step 20, the contact under way) and resumed to
# 0.45 s gives the frames and energies of the run that went through, bit for bit (the factor kept
# for chord steps is dropped at each checkpoint, in both).
A="--rest sheet.obj --energy hinge --membrane stvk --gravity 0,0,-9.81 --obstacle sphere:0,0,-0.3,0.25 \
  --damping rayleigh:2,0 --dt 0.01 --fps 20 --render-style none --quiet --checkpoint 10"
run 0 simulate $A --duration 0.45 -o through
run 0 simulate $A --duration 0.25 -o stopped
python3 -c "import json,sys; c=json.load(open('stopped/checkpoint.json')); sys.exit(0 if c['step'] == 20 else 1)" \
  || fail "stopped/checkpoint.json: not the state after step 20"
run 0 simulate $A --duration 0.45 -o stopped --resume stopped
cmp -s through/energies.csv stopped/energies.csv || fail "resumed: energies.csv differs"
for k in 0 1 2 3 4 5 6 7 8 9; do
  cmp -s through/frame-0000$k.obj stopped/frame-0000$k.obj || fail "resumed: frame $k differs"
done
report_check stopped "d['completed'] and d['steps'] == 45" "the resumed run's counts"
# Refused before any work (exit 2, nothing written): other options, another mesh, no checkpoint.
run 2 simulate ${A/--dt 0.01/--dt 0.005} --duration 0.45 -o other --resume stopped
stderr_has "--resume stopped"; stderr_has "was made with other options"; absent other
run 0 mesh --family patch48 --n 7 -o sheet7.obj --quiet
run 2 simulate ${A/sheet.obj/sheet7.obj} --duration 0.45 -o other --resume stopped
stderr_has "another rest mesh"; absent other
run 2 simulate $A --duration 0.45 -o other --resume sag; stderr_has "no checkpoint"; absent other
# A checkpoint whose per-vertex self-contact stiffness does not fit the mesh: refused, nothing
# rewritten.
cp -r stopped broken
python3 -c "import json; p='broken/checkpoint.json'; c=json.load(open(p)); \
c['self_contact_stiffness'] = c['self_contact_stiffness'][:-1]; json.dump(c, open(p, 'w'))"
cp broken/energies.csv broken-energies.csv
run 2 simulate $A --duration 0.45 -o broken --resume broken
stderr_has "broken/checkpoint.json"; stderr_has "vertex stiffnesses"
cmp -s broken/energies.csv broken-energies.csv || fail "a refused resume rewrote energies.csv"

# Fracture: a strip 1 x 0.25 hanging from its pinned end (x >= 0.45) under gravity along -x, with
# a fracture strain below the peak membrane strain at the pins (about 0.011 at t = 0.04): it tears
# across its whole width near the pins, the lower piece falls, and the run ends with 2 fragments.
make_strip
TEAR="--rest strip.obj --energy hinge --membrane stvk --pin box:0.45,0.6,-1,1,-1,1 \
  --gravity=-9.81,0,0 --damping rayleigh:5,0 --dt 0.005 --duration 0.3 --fps 20"
run 0 simulate $TEAR --fracture-strain 0.01 --render-style none -o tear --quiet
report_check tear "d['completed'] and d['fracture']['fragments'] == 2 and len(d['fracture']['cracks']) >= 1" \
  "the strip tears into 2 fragments"
# The crack grows from its tip across the strip (y from -0.125 to 0.125) near the pins (x in
# [0.3, 0.45]), each growth starting where the last one stopped (at either end of its polyline,
# which runs from its inner end when the crack starts at the other edge).
report_check tear "[round(abs(p[1]), 12) for c in d['fracture']['cracks'] for p in c['polyline_rest']].count(0.125) == 2 and \
  all(0.3 <= p[0] <= 0.45 for c in d['fracture']['cracks'] for p in c['polyline_rest']) and \
  all({tuple(a['polyline_rest'][0]), tuple(a['polyline_rest'][-1])} & \
      {tuple(b['polyline_rest'][0]), tuple(b['polyline_rest'][-1])} \
      for a, b in zip(d['fracture']['cracks'], d['fracture']['cracks'][1:]))" "the crack's polyline"
# The search in time discards steps only for the faces a crack can start from, not for its lips,
# and does not try a step that starts over the band: 6 discarded (77 before, the same cracks).
report_check tear "d['step_halvings'] <= 30" "the search in time discarded needless steps"
report_check tear "d['energy_balance']['verdict'] == 'balanced' and \
  d['energy_balance']['relative_drift'] < d['energy_balance']['tolerance']" "the energy balance"
[ -s tear/fragment-0.obj ] && [ -s tear/fragment-1.obj ] || fail "tear/fragment-K.obj missing"
absent tear/fragment-2.obj
# The fragments have every vertex of the cut mesh; the free one fell (0.26 s: about 0.33 along -x).
python3 -c "
import sys
def xs(f): return [float(l.split()[1]) for l in open(f) if l.startswith('v ')]
a, b = xs('tear/fragment-0.obj'), xs('tear/fragment-1.obj')
last = xs('tear/frame-00006.obj')
sys.exit(0 if len(a) + len(b) == len(last) > 81 and min(a + b) < -0.7 else 1)" \
  || fail "the fragments are not the cut mesh's pieces, or the free one did not fall"
# Without the flags the run is the one simulate made before: no fracture section, no fragments.
run 0 simulate $TEAR --render-style none -o whole --quiet
report_check whole "'fracture' not in d" "no fracture section"; absent whole/fragment-0.obj
cmp -s tear/frame-00000.obj whole/frame-00000.obj || fail "the start differs with fracture on"
run 2 simulate $TEAR --thickness 0.01 -o bad --quiet; stderr_has "give --fracture-strain"; absent bad
# Midedge tears the same strip too (its ξ re-solved on each cut mesh), balanced.
run 0 simulate ${TEAR/hinge/midedge} --fracture-strain 0.01 --render-style none -o tear-midedge \
  --quiet
report_check tear-midedge "d['fracture']['fragments'] == 2" "the midedge strip in two pieces"
report_check tear-midedge "d['energy_balance']['verdict'] == 'balanced'" "a balanced midedge tear"
run 2 simulate $TEAR --fracture-strain 0.01 --checkpoint 5 -o bad --quiet
stderr_has "not with --checkpoint"; absent bad

# flexure run checks every step's option values before the first runs: a misspelt energy in
# step 2 exits 2 naming it, and step 1's mesh is not made.
cat > misspelt.json <<'SPEC'
{"steps": [
  {"command": "mesh", "options": {"family": "patch48", "n": 4, "o": "step1.obj"}},
  {"command": "simulate", "options": {"rest": "step1.obj", "energy": "midedgee", "membrane": "stvk",
                                      "dt": 0.01, "duration": 0.1, "o": "step2"}}
]}
SPEC
run 2 run misspelt.json; stderr_has "unknown energy 'midedgee'"; stderr_has "step 2 would fail"
absent step1.obj; absent step2
# simulate checks all its option values so (here a misspelt membrane and a bad damping).
sed 's/"midedgee", "membrane": "stvk"/"midedge", "membrane": "stvkk"/' misspelt.json > membrane.json
run 2 run membrane.json; stderr_has "stvkk"; stderr_has "step 2 would fail"; absent step1.obj
sed 's/"membrane": "stvk",/"membrane": "stvk", "damping": "viscous:1",/' misspelt.json \
  | sed 's/midedgee/midedge/' > damping.json
run 2 run damping.json; stderr_has "--damping viscous:1"; stderr_has "step 2 would fail"
absent step1.obj; absent step2
# A boundary surface is read with the flags too (minimize, compare, energy, mesh --height).
cat > surface.json <<'SPEC'
{"steps": [
  {"command": "mesh", "options": {"family": "patch48", "n": 4, "o": "step1.obj"}},
  {"command": "minimize", "options": {"rest": "step1.obj", "energy": "hinge",
                                      "boundary": "quadratc:1,0,1", "o": "step2.obj"}}
]}
SPEC
run 2 run surface.json; stderr_has "--boundary: bad surface 'quadratc:1,0,1'"
stderr_has "step 2 would fail"; absent step1.obj; absent step2.obj

# An energy step is checked with the others: its misspelt energy exits 2 before step 1 runs.
cat > energy_step.json <<'SPEC'
{"steps": [
  {"command": "mesh", "options": {"family": "patch48", "n": 4, "o": "step1.obj"}},
  {"command": "energy", "options": {"energy": "midedgee", "rest": "step1.obj",
                                    "current": "step1.obj"}}
]}
SPEC
run 2 run energy_step.json; stderr_has "unknown energy 'midedgee'"; stderr_has "step 2 would fail"
absent step1.obj

# The run's length and pins are refused as a person would want, before any work:
# a duration between two steps (it would run to the next whole step without a word),
S="simulate --rest plate.obj --energy hinge --membrane stvk --render-style none --quiet"
run 2 $S --dt 0.01 --duration 0.015 -o bad
stderr_has "--duration 0.015: not a whole number of steps of 0.01 (1.5); give 0.01 or 0.02"
absent bad
# a release after the end (the group would never be let go),
run 2 $S --dt 0.01 --duration 0.1 --pin rings:1@release:5 -o bad
stderr_has "--pin SET@release:T 5: after the run's end (--duration 0.1)"; absent bad
# an empty vertex list (as an empty box: it pins nothing),
: > empty.txt
run 2 $S --dt 0.01 --duration 0.1 --pin vertices:empty.txt -o bad
stderr_has "--pin vertices:empty.txt: empty.txt lists no vertex"; absent bad
# a negative thickness, in a line a person reads (no 300-digit range),
run 2 $S --dt 0.01 --duration 0.1 --fracture-strain 0.01 --thickness -0.01 -o bad
stderr_has "--thickness must be a finite number ≥ 0, got -0.01"; absent bad
[ "$(wc -c < "err.txt")" -lt 200 ] || fail "the thickness refusal is $(wc -c < "err.txt") bytes"
# and an unknown option: the useful line first, not CLI11's "were not expected".
run 2 $S --dt 0.01 --duration 0.1 --dampning bend:1 -o bad
[ "$(head -1 "err.txt")" = "flexure: '--dampning' is not an option; did you mean '--damping'?" ] \
  || fail "the first line is not the hint: $(head -1 "err.txt")"
! grep -qF "not expected" err.txt || fail "CLI11's words came too: $(cat err.txt)"; absent bad

finish cli_simulate
