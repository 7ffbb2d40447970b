#!/usr/bin/env bash
# End-to-end runs of `flexure modes`: the spectrum against the exact one, the report and figure,
# the shapes, and the refusals (exit 2, nothing written).
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/support/cli_harness.sh"

# jq-free JSON checks: check PYTHON-EXPRESSION over d = modes.json of DIR.
json_check() {  # json_check DIR EXPRESSION MESSAGE
  python3 -c "import json,sys; d=json.load(open('$1/modes.json')); sys.exit(0 if ($2) else 1)" \
    || fail "$1/modes.json: $3"
}

# The simply supported square: λ against π²(m² + n²), printed and in the report.
run 0 modes --family patch48 --n 16 --energy midedge,cotan,hinge --support simply-supported \
  --count 4 --reference square-simply-supported -o ss
stdout_has "reference"; stdout_has "19.7392"
stderr_has "flexure modes: midedge: 4 modes"; stderr_has "wrote ss/chladni.png"
is_png ss/chladni.png || fail "ss/chladni.png is not a PNG"
json_check ss "[e['energy'] for e in d['energies']] == ['midedge', 'cotan', 'hinge']" "energies"
json_check ss "abs(d['energies'][1]['modes'][0]['relative_error']) < 5e-3" "cotan λ1 within 0.5 %"
json_check ss "d['energies'][2]['modes'][0]['relative_error'] > 0.5" "hinge λ1 is far off (it fails C1)"
json_check ss "all(m['residual'] < 1e-8 for e in d['energies'] for m in e['modes'])" "residuals"
json_check ss "d['energies'][0]['modes'][1]['multiplicity'] == 2" "the (1,2)/(2,1) pair"
json_check ss "'Leissa' not in d['reference']['source']" "the exact reference"
# Same input, same figure (the report differs in its timings only).
run 0 modes --family patch48 --n 16 --energy midedge,cotan,hinge --support simply-supported \
  --count 4 --reference square-simply-supported -o ss2 --quiet
cmp -s ss/chladni.png ss2/chladni.png || fail "a rerun draws another chladni.png"

# The clamped square with shapes; a re-run with fewer shapes leaves no stale ones.
run 0 modes --family delaunay --n 12 --energy midedge --count 3 --write-shapes -o cl
for k in 1 2 3; do [ -s "cl/mode-midedge-$k.obj" ] || fail "cl/mode-midedge-$k.obj missing"; done
json_check cl "d['energies'][0]['clamp'] == 'normals'" "midedge clamps its normals by default"
touch cl/notes.txt
run 0 modes --family delaunay --n 12 --energy midedge --count 2 --write-shapes -o cl --quiet
absent cl/mode-midedge-3.obj
[ -e cl/notes.txt ] || fail "modes removed a file it did not write"
run 0 info cl/mode-midedge-1.obj --json; stdout_has '"valid": true'
run 0 modes --family patch48 --n 8 --energy hinge:tan --count 1 --write-shapes -o tan --quiet
[ -s tan/mode-hinge_tan-1.obj ] || fail "modes: the shape of hinge:tan is not mode-hinge_tan-1.obj"

# A free plate: three rigid modes named, and triavg's spurious zero modes reported.
run 0 modes --family patch48 --n 8 --energy midedge,triavg --support free --count 2 -o free
json_check free "[m['kind'] for m in d['energies'][0]['modes']][:4] == ['rigid'] * 3 + ['flexible']" \
  "midedge: three rigid modes then flexible ones"
json_check free "d['energies'][1]['spurious_zero_modes'] == 4" "triavg: the 4 corner vertices"
json_check free "[m['kind'] for m in d['energies'][1]['modes']].count('flexible') == 2" "triavg: 2 flexible"
stderr_has "4 spurious zero modes"

# Participation ratios: a smooth plate's modes are spread; held everywhere but the centre, the
# modes are localized, flagged in the report and on stderr (quiet or not).
json_check ss "all(0.3 < m['participation'] and not m['localized'] for e in d['energies'] for m in e['modes'])" \
  "a plate's modes spread over it"
run 0 modes --family patch48 --n 16 --energy cotan --fix rings:7 --count 2 -o centre --quiet
json_check centre "all(m['localized'] and m['participation'] < 0.05 for m in d['energies'][0]['modes'])" \
  "modes on the centre's few free vertices are localized"
# The message, not its digits: the second mode's ratio was 0.0212 in CI and is 0.0248 on another
# machine with the same sources (the first, 0.0232, on both); the JSON check above bounds both.
stderr_has "warning: cotan: modes 1 (0.0"
stderr_has "are localized on a few vertices"

# A curved rest: height mode is refused (its z motions are partly tangential), midedge's default
# normals clamp needs a flat plate; the shell's modes in xyz with a ring clamp run.
run 0 mesh --family patch48 --n 6 -o flat6.obj --quiet
awk '/^v /{ $4 = 0.3 * $2 * $2 } { print }' flat6.obj > bent.obj
run 2 modes --mesh bent.obj --energy cotan -o bad
stderr_has "this rest surface is not flat (z spans 0.075 of a largest side 1)"
stderr_has "use --dof xyz with a membrane"; absent bad
run 2 modes --mesh bent.obj --energy midedge --dof xyz --membrane stvk -o bad
stderr_has "--energy midedge clamps its boundary normals by default (--clamp normals)"
stderr_has "clamp with --clamp rings"; absent bad
run 0 modes --mesh bent.obj --energy midedge --dof xyz --membrane stvk --clamp rings --count 2 \
  -o shell --quiet
json_check shell "[m['kind'] for m in d['energies'][0]['modes']] == ['flexible'] * 2" "shell modes"

# A curved shell's modes are drawn in 3-D with a legend per panel (110 + 3 (96 + 130 + 10) wide); a
# flat plate keeps the Chladni map seen from above (110 + 3 (96 + 10)).
run 0 mesh --family patch48 --n 8 --height quadratic:1,0,1 -o bowl.obj --quiet
run 0 modes --mesh bowl.obj --support free --dof xyz --membrane stvk --energy cotan --count 3 \
  --size 96 -o shell --quiet
run 0 modes --family patch48 --n 8 --energy cotan --support free --count 3 --size 96 -o flat --quiet
PYTHONPATH="$(dirname "${BASH_SOURCE[0]}")/support" python3 - <<'PY' || fail "modes: the shell is not drawn in 3-D, or the plate not from above"
import sys
from png_pixels import read_png
shell_width = read_png("shell/chladni.png")[0]
flat_width = read_png("flat/chladni.png")[0]
sys.exit(0 if (shell_width, flat_width) == (110 + 3 * 236, 110 + 3 * 106) else 1)
PY

# The spectrum as a convergence study: orders per energy and family, files, stale ones removed.
run 0 converge --measure modes --support clamped --energies midedge,hinge --families patch48 \
  --n 8 --levels 3 --count 3 -o spectrum
stdout_has "| midedge | order"; stdout_has "| hinge | does not converge"
for f in spectrum.md spectrum.json spectrum.csv spectrum_patch48.png; do
  [ -s "spectrum/$f" ] || fail "converge --measure modes wrote no $f"
done
[ "$(wc -l < spectrum/spectrum.csv)" -eq $((1 + 2 * 3 * 3)) ] || fail "spectrum.csv rows"
run 0 converge --energies cotan --families patch48 --n 8 --levels 1 --amplitudes 0 -o spectrum --quiet
absent spectrum/spectrum.md; [ -s spectrum/summary.md ] || fail "no summary.md after the C1/C2 run"
run 2 converge --measure modes --support free -o bad; stderr_has "--support free"; absent bad
run 2 converge --measure modes --support clamped --count 7 -o bad; stderr_has "Leissa"; stderr_has "--count 7"; absent bad
run 2 converge --measure spectra -o bad; stderr_has "--measure spectra"; absent bad
run 2 converge --support clamped -o bad; stderr_has "--support applies to --measure modes"; absent bad
run 2 converge --measure modes --amplitudes 2 -o bad; stderr_has "--amplitudes applies to --measure c1c2"

# Refusals: exit 2, the option named, nothing written.
run 2 modes --family patch48 --n 8 --energy cotan --clamp normals -o bad; stderr_has "--clamp normals"
absent bad
run 2 modes --family patch48 --n 8 --energy midedge --support free --clamp rings -o bad
stderr_has "--clamp applies to --support clamped"; absent bad
run 2 modes --family patch48 --n 8 --energy midedge:free -o bad; stderr_has "--support"; absent bad
run 2 modes --family patch48 --n 8 --energy midedge --reference square-clamped --support free -o bad
stderr_has "needs --support clamped"; absent bad
run 0 mesh --family patch48 --n 4 -o square.obj --quiet
awk '/^v /{ $2 = 2 * $2 } { print }' square.obj > rect.obj
run 2 modes --mesh rect.obj --energy midedge --reference square-clamped -o bad
stderr_has "is not a flat square plate"; absent bad
run 2 modes --family patch48 --n 2 --energy cotan --count 50 -o bad; stderr_has "--count 50"
absent bad
run 2 modes --mesh rect.obj --family patch48 --energy cotan -o bad; stderr_has "one of the two"
run 2 modes --family patch48 --energy cotan,cotan -o bad; stderr_has "given twice"
run 2 modes --family patch48 --energy cotan --count 0 -o bad; stderr_has "--count"
run 2 modes --family patch48 --energy cotan --support sideways -o bad; stderr_has "sideways"

finish cli_modes
