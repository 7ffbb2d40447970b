#!/usr/bin/env bash
# End-to-end runs of `flexure simulate` with plasticity (--yield-curvature, --yield-strain,
# --hardening): a free plate released from a bend past κ_y, and one let go stretched past ε_y, keep
# kinetic + elastic + plastic dissipation at the start's total (undamped Newmark) and their
# dissipation never decreases; moving pins bend a plate past κ_y; a yield value nothing reaches
# changes no frame; refusals (exit 2, nothing written).
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/support/cli_harness.sh"

# plastic_balance DIR: the run's energies.csv keeps total + D at its start value within 1 %, D
# starts above 0 (the start is past the yield surface: it yields at once) and never decreases.
plastic_balance() {
  python3 - "$1" <<'PY' || fail "$1: plastic dissipation or energy balance"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1] + "/energies.csv")))
d = [float(r["plastic_dissipation"]) for r in rows]
balanced = [float(r["total"]) + x for r, x in zip(rows, d)]
assert d[0] > 0, "the start is past the yield surface: it yields at once"
assert all(b >= a for a, b in zip(d, d[1:])), "the dissipation decreased"
drift = max(abs(b - balanced[0]) for b in balanced) / balanced[0]
assert drift < 0.01, drift
PY
}

run 0 mesh --family delaunay --n 8 -o flat.obj --quiet
# The same connectivity on z = 0.05 x² (curvature 0.1).
run 0 mesh --family delaunay --n 8 --height quadratic:0.05,0,0 -o bent.obj --quiet
run 0 simulate --rest flat.obj --init bent.obj --energy midedge --membrane stvk \
  --yield-curvature 0.05 --hardening 0.5 --dt 0.005 --duration 0.25 --render-style none -o pl
stderr_has "flexure simulate: plastic: "
head -1 pl/energies.csv | grep -qx "time,kinetic,midedge,stvk,gravity,plastic_dissipation,total" \
  || fail "energies.csv header: $(head -1 pl/energies.csv)"
plastic_balance pl
python3 - <<'PY' || fail "plastic run: report"
import csv, json
d = [float(r["plastic_dissipation"]) for r in csv.DictReader(open("pl/energies.csv"))]
r = json.load(open("pl/report.json"))
p = r["plasticity"]
assert p["element"] == "face" and p["elements"] > 0 and 0 < p["yielded_elements"] == len(p["yielded"])
assert p["yield_curvature"] == 0.05 and p["hardening"] == 0.5
assert 0 < p["largest_plastic_curvature"] < 0.1
assert abs(p["plastic_dissipation"] - d[-1]) <= 1e-12 * d[-1]
assert abs(r["energy_balance"]["plastic_dissipation"] - d[-1]) <= 1e-12 * d[-1]
h = p["dissipation_history"]
assert len(h["time"]) == len(h["plastic_dissipation"]) == r["frames"]
assert r["energy_balance"]["verdict"] == "balanced", r["energy_balance"]
PY

# A plate whose edge x > 0.4 is held and turned about the y axis through (0.4, 0, 0) at 2 rad/s:
# the rest of the plate, dragged through the air, bends past κ_y and yields.
run 0 simulate --rest flat.obj --energy hinge --membrane stvk --pin box:0.4,0.5,-1,1,-1,1 \
  --pin-motion rotate:0,1,0,0.4,0,0,2 --yield-curvature 0.2 --dt 0.01 --duration 0.2 \
  --render-style none -o turned
python3 - <<'PY' || fail "turned plate: expected yielded hinges and dissipation"
import json
p = json.load(open("turned/report.json"))["plasticity"]
assert p["element"] == "face" and p["yielded_elements"] > 0 and p["plastic_dissipation"] > 0, p
PY

# A plastic can (a vertical cylinder of height 1) pressed onto the floor by its top ring, pinned
# and moving down at 0.5 for 0.8 s: every step converges (exit 0), most faces yield, the wall
# ends above the floor, self-contact pairs repel and the smallest distance between repelling
# primitives (and to the floor) stays positive at every step's end, and the top ends where the
# pins put it (z = 0.5 − 0.4). (The exact face-pair crossing test of self-contact runs is in
# tests/test_self_contact.cpp; the command has no crossing check of its own.)
run 0 mesh --family cylinder --n 32 -o can.obj --quiet
run 0 simulate --rest can.obj --energy hinge --stiffness 0.2 --membrane stvk --young 1000 \
  --gravity 0,0,-9.81 --obstacle plane:0,0,1,-0.52 --pin "box:-1,1,-1,1,0.49,1@translate:0,0,-0.5" \
  --yield-curvature 1 --damping rayleigh:4,0 --dt 0.005 --duration 0.8 --fps 10 \
  --render-style none -o pressed
python3 - <<'PY' || fail "can pressed by pins: report or last frame"
import json
r = json.load(open("pressed/report.json"))
assert r["completed"] and not r["partial"] and r["frames"] == 9, r["failure"]
p, c = r["plasticity"], r["contact"]
assert p["yielded_elements"] > p["elements"] / 2, p["yielded_elements"]
assert c["self_contact"] and c["pairs_per_step"]["peak"] > 0 and c["smallest_distance"] > 0, c
assert r["smallest_obstacle_distance"] > 0, r["smallest_obstacle_distance"]
z = [float(l.split()[3]) for l in open("pressed/frame-00008.obj") if l.startswith("v ")]
assert min(z) > -0.52 and abs(max(z) - 0.1) < 1e-9, (min(z), max(z))
PY

# Nothing reaches a yield curvature of 1e6: the same frames, byte for byte, as without plasticity;
# and without it no plasticity section nor column.
run 0 simulate --rest flat.obj --init bent.obj --energy midedge --membrane stvk --dt 0.01 \
  --duration 0.05 --render-style none -o plain
run 0 simulate --rest flat.obj --init bent.obj --energy midedge --membrane stvk --dt 0.01 \
  --duration 0.05 --render-style none --yield-curvature 1e6 -o never
run 0 simulate --rest flat.obj --init bent.obj --energy midedge --membrane stvk --dt 0.01 \
  --duration 0.05 --render-style none --yield-strain 1e6 -o never-m
for f in plain/frame-*.obj; do
  cmp -s "$f" "never/$(basename "$f")" || fail "$f: a yield value nothing reaches changed a frame"
  cmp -s "$f" "never-m/$(basename "$f")" || fail "$f: a yield strain nothing reaches changed a frame"
done
head -1 plain/energies.csv | grep -q plastic && fail "plain run: a plastic_dissipation column"
python3 -c "import json,sys; d=json.load(open('plain/report.json')); sys.exit('plasticity' in d or 'plastic_dissipation' in d['energy_balance'])" \
  || fail "plain run: a plasticity section in report.json"
python3 -c "import json,sys; p=json.load(open('never/report.json'))['plasticity']; sys.exit(p['yielded_elements'] != 0 or p['plastic_dissipation'] != 0)" \
  || fail "a yield value nothing reaches: something yielded"

# Membrane plasticity: a free plate let go stretched by 3 % along x (Green strain 0.0305, past
# ε_y = 0.01) yields at once and in its vibration; undamped Newmark keeps kinetic + elastic +
# plastic dissipation at the start's total, the dissipation never decreases, every face yields.
python3 - <<'PY'
out = []
for line in open("flat.obj"):
    if line.startswith("v "):
        x, y, z = map(float, line.split()[1:4])
        line = "v %.17g %.17g %.17g\n" % (1.03 * x, y, z)
    out.append(line)
open("stretched.obj", "w").writelines(out)
PY
run 0 simulate --rest flat.obj --init stretched.obj --energy midedge --membrane stvk \
  --yield-strain 0.01 --hardening 0.5 --dt 0.0005 --duration 0.05 --fps 40 \
  --render-style plastic --render-size 64 -o mem
stderr_has "membrane faces yielded"
is_png mem/frames/frame-00002.png || fail "mem/frames/frame-00002.png is not a PNG"
plastic_balance mem
python3 - <<'PY' || fail "membrane plastic run: report"
import csv, json
d = [float(r["plastic_dissipation"]) for r in csv.DictReader(open("mem/energies.csv"))]
r = json.load(open("mem/report.json"))
p = r["plasticity"]
assert p["yield_strain"] == 0.01 and p["yield_curvature"] is None and p["element"] is None, p
assert p["membrane_faces"] > 0 and p["yielded_membrane_faces"] == p["membrane_faces"], p
assert len(p["yielded_faces"]) == p["yielded_membrane_faces"]
assert p["yielded_elements"] == 0 and p["largest_plastic_curvature"] == 0
assert 0 < p["largest_plastic_strain"] < 0.0305
assert abs(p["plastic_dissipation"] - d[-1]) <= 1e-12 * d[-1]
assert abs(r["energy_balance"]["plastic_dissipation"] - d[-1]) <= 1e-12 * d[-1]
assert r["energy_balance"]["verdict"] == "balanced", r["energy_balance"]
PY

# Frames coloured by the plastic strain, with a legend (wider than the square frame).
run 0 simulate --rest flat.obj --init bent.obj --energy hinge --membrane stvk --yield-curvature 0.05 \
  --dt 0.01 --duration 0.02 --fps 100 --render-style plastic --render-size 64 -o coloured
is_png coloured/frames/frame-00002.png || fail "coloured/frames/frame-00002.png is not a PNG"
python3 -c "
import struct, sys
w, h = struct.unpack('>II', open('coloured/frames/frame-00002.png', 'rb').read()[16:24])
sys.exit(0 if w > h == 64 else 1)" || fail "the plastic style's frames have no legend strip"

# Refusals, before any work.
run 2 simulate --rest flat.obj --energy cotan --membrane stvk --yield-curvature 0.1 --dt 0.01 \
  --duration 0.02 -o c
stderr_has "cotan"; stderr_has "--yield-curvature"; absent c
# With fracture the plastic state carries across the cuts (tests/cli_release_fracture.sh): accepted.
run 0 simulate --rest flat.obj --energy hinge --membrane stvk --yield-curvature 0.1 \
  --fracture-strain 0.1 --dt 0.01 --duration 0.02 --render-style none -o f
[ -s f/report.json ] || fail "f: plasticity with fracture wrote no report"
run 2 simulate --rest flat.obj --energy hinge --membrane stvk --yield-curvature 0.1 \
  --checkpoint 1 --dt 0.01 --duration 0.02 -o k
stderr_has "--checkpoint"; absent k
run 2 simulate --rest flat.obj --energy hinge --membrane springs --yield-strain 0.01 --dt 0.01 \
  --duration 0.02 -o m
stderr_has "--yield-strain"; stderr_has "stvk"; absent m
run 0 simulate --rest flat.obj --energy hinge --membrane stvk --yield-strain 0.01 \
  --fracture-strain 0.1 --dt 0.01 --duration 0.02 --render-style none -o mf
[ -s mf/report.json ] || fail "mf: membrane plasticity with fracture wrote no report"
run 2 simulate --rest flat.obj --energy hinge --membrane stvk --hardening 0.5 --dt 0.01 \
  --duration 0.02 -o h
stderr_has "--hardening"; absent h
run 2 simulate --rest flat.obj --energy hinge --membrane stvk --render-style plastic --dt 0.01 \
  --duration 0.02 -o r
stderr_has "--render-style plastic"; stderr_has "--yield-curvature"; absent r

finish cli_simulate_plasticity
