#!/usr/bin/env bash
# End-to-end: a pin group let go on a shell that fractures (`--pin SET@MOTION@release:T` with
# `--fracture-strain`). A strip 1 × ¼ (hinge + StVK, gravity −1 along z, undamped, ε_f = 0.01) held
# at its left end and pulled at its right end at 0.05 tears across near the left grip at
# t = 0.1725–0.1765 (8 cuts, two pieces). Never let go, the pull tears it again (three pieces) and
# the grip's points stay on the pin's line. Let go at 0.205, after the tear (the cut mesh numbers its
# vertices anew; the group carried across is the same material points): no later crack, none of the
# grip's points on the line at the end, the pins' work booked, the balance checked from the release
# on and `balanced`. Let go at 0.145, before the tear: it tears later all the same (first crack at
# 0.258, from the wave the release sends along the stretched strip) into two pieces, `balanced`.
# With a yield curvature the plastic strains carry across the cuts.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/support/cli_harness.sh"

make_strip
BASE="--rest strip.obj --energy hinge --membrane stvk --gravity=0,0,-1 --fracture-strain 0.01 \
  --thickness 0.01 --dt 0.005 --duration 0.4 --fps 10 --render-style none --quiet"
LEFT="box:-0.6,-0.45,-1,1,-1,1"; RIGHT="box:0.45,0.6,-1,1,-1,1@translate:0.05,0,0"
run 0 simulate $BASE --pin $LEFT --pin $RIGHT -o held
run 0 simulate $BASE --pin $LEFT --pin $RIGHT@release:0.205 -o after
run 0 simulate $BASE --pin $LEFT --pin $RIGHT@release:0.145 -o before

# report.json: DIR FIRST_CRACK_AFTER LAST_CRACK_BEFORE FRAGMENTS VERDICT PIN_WORK_POSITIVE
report() {
  python3 -c "
import json, sys
r = json.load(open('$1/report.json')); f = r['fracture']; b = r['energy_balance']
times = [c['time'] for c in f['cracks']]
ok = (r['completed'] and times and min(times) > $2 and max(times) < $3
      and f['fragments'] == $4 and b['verdict'] == '$5' and (b['pin_work'] > 0) == $6)
sys.exit(0 if ok else 1)" || fail "$1/report.json: cracks in ($2, $3), $4 fragments, '$5', pin work > 0: $6"
}
report held 0.17 0.3 3 driven False
report after 0.17 0.205 2 balanced True
report before 0.2 0.3 2 balanced True

# The last frame (t = 0.4): how many of the right grip's rest points are on the pin's line
# (x̄ + 0.4 × 0.05, ȳ, 0) and of the left grip's where they started, to 1e-12.
on_line() {
  python3 -c "
import sys
def v(f): return [tuple(map(float, l.split()[1:4])) for l in open(f) if l.startswith('v ')]
rest, last = v('strip.obj'), v('$1/frame-00004.obj')
def count(grip, shift):
    return sum(any(max(abs(x[0] - r[0] - shift), abs(x[1] - r[1]), abs(x[2] - r[2])) <= 1e-12
                   for x in last) for r in rest if grip(r))
sys.exit(0 if (count(lambda r: r[0] >= 0.45, 0.02), count(lambda r: r[0] <= -0.45, 0.0)) == ($2, 9)
         else 1)" || fail "$1: expected $2 of the right grip's 9 points on the pin's line, 9 left ones still"
}
on_line held 9
on_line after 0
on_line before 0

# Plasticity with fracture (and the release): with --yield-curvature 0.01 the sagging strip's hinges
# yield before it tears (D > 0 at t = 0.1, the first crack after 0.17), the cuts carry the plastic
# strains (plastic_dynamics.h), D never falls over the frames, and the run completes `balanced`
# with two pieces; the plastic state is per face of the final, cut, mesh.
run 0 simulate $BASE --pin $LEFT --pin $RIGHT@release:0.205 --yield-curvature 0.01 -o plastic
python3 -c "
import json, sys
r = json.load(open('plastic/report.json')); f = r['fracture']; p = r['plasticity']
d = p['dissipation_history']['plastic_dissipation']
first = min(c['time'] for c in f['cracks'])
ok = (r['completed'] and first > 0.17 and f['fragments'] == 2 and d[1] > 0
      and all(b >= a for a, b in zip(d, d[1:])) and p['plastic_dissipation'] == d[-1]
      and r['energy_balance']['plastic_dissipation'] == d[-1]
      and r['energy_balance']['verdict'] == 'balanced' and 0 < p['yielded_elements']
      and p['elements'] <= f['faces'] and p['elements'] > 0.9 * f['faces'])
sys.exit(0 if ok else 1)" || fail "plastic/report.json: yielded before the tear, D rising, balanced"

finish cli_release_fracture
