#!/usr/bin/env bash
# flexure view end to end, without a browser (tests/viewer/ loads the pages in one): what it
# writes, and its refusals (exit 2, naming the file or the option, no page written).
set -uo pipefail
support="$(cd "$(dirname "${BASH_SOURCE[0]}")/support" && pwd)"
source "$support/cli_harness.sh"

run 0 mesh --family patch48 --n 6 -o sheet.obj --quiet
run 0 mesh --family sphere --n 8 -o sphere.obj --quiet
run 0 view sheet.obj sphere.obj -o two.html
stderr_has "wrote two.html (2 meshes, 2 frames"
grep -q "<canvas id=\"view\">" two.html || fail "two.html has no canvas"
grep -q "REVISION=\"111\"\|REVISION = \"111\"\|\"111\"" two.html || fail "two.html lacks three.js r111"
if grep -qE "(src|href)=\"https?:" two.html; then fail "two.html loads something from the network"; fi
run 0 view sheet.obj sphere.obj -o again.html --quiet
cmp -s two.html again.html || fail "the same inputs gave different pages"
grep -q '"multisample":false' two.html || fail "two.html is multisampled by default"
run 0 view sheet.obj -o smooth.html --multisample --quiet
grep -q '"multisample":true' smooth.html || fail "--multisample did not reach the page"

# A simulation folder: its frames, all with the same faces.
mkdir sim
cp sheet.obj sim/frame-00000.obj
sed 's/^v \(.*\) \(.*\) \(.*\)$/v \1 \2 0.25/' sheet.obj >sim/frame-00001.obj
run 0 view sim --style displacement -o sim.html; stderr_has "(1 meshes, 2 frames"

# A run that fractured: the faces change after the cut, its lips (cracks.json) on the page.
run 0 --quiet run "$support/../../examples/tear-strip.json"
test -f tear/cracks.json || fail "a run that fractured wrote no cracks.json"
run 0 view tear -o tear.html; stderr_has "(1 meshes, 7 frames"
grep -q '"faceChanges":\[{"frame":3,' tear.html || fail "tear.html has no face change at frame 3"
cp -r tear tear-broken; echo '{"lips": [[[0, 99999]]]}' >tear-broken/cracks.json
run 2 view tear-broken -o page.html; stderr_has "tear-broken/cracks.json"; absent page.html
cp -r tear tear-nolips; rm tear-nolips/cracks.json
run 2 view tear-nolips -o page.html; stderr_has "tear-nolips/frame-00003.obj"; absent page.html

# A run with plasticity: its plastic.json coloured (--style plastic), the legend titled by it.
run 0 mesh --family patch48 --n 8 -o plate8.obj --quiet
run 0 simulate --rest plate8.obj --energy hinge --stiffness 0.05 --membrane stvk --young 1000 \
  --pin box:-0.5,-0.4,-1,1,-1,1 --pin "box:0.4,0.5,-1,1,-1,1@rotate:0,-1,0,0,0,0,1.57" \
  --yield-curvature 0.5 --damping rayleigh:4,0 --dt 0.02 --duration 0.6 --fps 10 \
  --render-style none -o bent --quiet
test -f bent/plastic.json || fail "a run with a yield value wrote no plastic.json"
run 0 view bent --style plastic -o plastic.html; stderr_has "(1 meshes, 7 frames"
grep -q '"fieldTitle":"plastic strain (1 / length)"' plastic.html || fail "plastic.html's legend"
grep -q '"fieldOnFaces":true' plastic.html || fail "plastic.html's field is not per face"
run 2 view bent sheet.obj --style plastic -o page.html; stderr_has "sheet.obj"; absent page.html
run 2 view tear --style plastic -o page.html; stderr_has "tear: no plastic.json"; absent page.html

# Per-face and reference fields: each face's smallest angle (on the cut faces of a fracture too),
# each vertex's distance to another mesh's surface.
run 0 view sheet.obj tear --style angle -o angle.html; stderr_has "(2 meshes, 8 frames"
grep -q '"fieldOnFaces":true' angle.html || fail "angle.html has no per-face field"
grep -q '"range":\[0,60\]' angle.html || fail "angle.html's legend is not [0, 60]"
run 0 view sphere.obj --style error --reference sheet.obj -o error.html --quiet
grep -q '"fieldTitle":"error: distance to sheet.obj"' error.html || fail "error.html's legend"
run 2 view sphere.obj --style error -o page.html; stderr_has "--reference"; absent page.html
run 2 view sphere.obj --style angle --reference sheet.obj -o page.html
stderr_has "--reference applies to --style displacement and error"; absent page.html
run 2 view sphere.obj --style error --reference nowhere.obj -o page.html; stderr_has "nowhere.obj"
absent page.html

# A modes folder (flexure modes --write-shapes): each energy's mesh with its modes.
run 0 modes --family patch48 --n 6 --energy midedge,cotan --count 3 --write-shapes -o modes --quiet
test -f modes/rest.obj || fail "flexure modes --write-shapes wrote no rest.obj"
run 0 view modes -o modes.html; stderr_has "(2 meshes, 2 frames"
grep -q '"label":"mode 3: ' modes.html || fail "modes.html has no mode 3"
grep -q '"lineEnds":"[A-Za-z0-9+/]' modes.html || fail "modes.html has no nodal line"

# A fairing report: the input, CGAL's fair (--cgal-output) and the result, the region outlined.
run 0 mesh --family patch48 --n 8 --height quadratic:1,0,1 -o bowl.obj --quiet
run 0 fair bowl.obj --region rings:40,1 -o faired.obj --cgal-output cgal.obj --report fair.json \
  --quiet
grep -q '"indices"' fair.json || fail "fair.json has no region indices"
grep -q '"cgal_output": "cgal.obj"' fair.json || fail "fair.json does not name cgal.obj"
run 0 view fair.json -o fair.html; stderr_has "(3 meshes, 3 frames"
grep -q '"name":"CGAL fair: cgal.obj"' fair.html || fail "fair.html has no CGAL mesh"
grep -q '"outline":{"lineEnds":"[A-Za-z0-9+/]' fair.html || fail "fair.html has no outline"
# Its paths resolve beside the report when the working directory is another.
mkdir elsewhere
(cd elsewhere && "$FLEXURE" view ../fair.json -o fair.html --quiet) ||
  fail "view ../fair.json from another folder"
test -f elsewhere/fair.html || fail "no elsewhere/fair.html"
run 0 fair bowl.obj --region rings:40,1 -o faired2.obj --report fair2.json --quiet
run 0 view fair2.json -o fair2.html; stderr_has "(2 meshes, 2 frames"

# Refusals, before any page is written.
run 2 view sheet.obj -o page.png; stderr_has "--output 'page.png'"; absent page.png
run 2 view missing.obj -o page.html; stderr_has "missing.obj"; absent page.html
run 2 view sheet.obj -o page.html --style wavy; stderr_has "--style"; stderr_has "wavy"
absent page.html
run 2 view sheet.obj -o page.html --stripe-width 1.5; stderr_has "--stripe-width"; absent page.html
run 2 view sheet.obj -o page.html --style displacement; stderr_has "--reference"; absent page.html
run 2 view sheet.obj -o page.html --style displacement --reference sphere.obj
stderr_has "--reference sphere.obj"; absent page.html
run 2 view sheet.obj -o page.html --curvature-energy cotan; stderr_has "--curvature-energy"
run 2 view sheet.obj -o page.html --style curvature --curvature-energy nope; stderr_has "nope"
mkdir empty
run 2 view empty -o page.html; stderr_has "empty: a folder given to view"; absent page.html
cp sphere.obj sim/frame-00002.obj
run 2 view sim -o page.html; stderr_has "sim/frame-00002.obj"; absent page.html
run 2 view sheet.obj -o sheet.obj; stderr_has "sheet.obj"
# A modes folder without its shapes, with a shape of another mesh, with a broken report.
run 0 modes --family patch48 --n 6 --energy midedge --count 2 -o noshapes --quiet
run 2 view noshapes -o page.html; stderr_has "noshapes: a modes folder without"
stderr_has "--write-shapes"; absent page.html
cp -r modes badshape; cp sphere.obj badshape/mode-cotan-2.obj
run 2 view badshape -o page.html; stderr_has "badshape/mode-cotan-2.obj"; absent page.html
cp -r modes badreport; echo '{"energies": 3' >badreport/modes.json
run 2 view badreport -o page.html; stderr_has "badreport/modes.json"; absent page.html
run 2 view modes --style curvature -o page.html; stderr_has "modes: a modes folder"
absent page.html
run 2 view modes --style angle -o page.html; stderr_has "modes: a modes folder"; absent page.html
# A fairing report without its result, without region indices, with a result of other vertices.
sed 's/"output": "faired.obj"/"output": null/' fair.json >unconverged.json
run 2 view unconverged.json -o page.html; stderr_has "unconverged.json: the fair did not converge"
absent page.html
sed 's/"indices"/"vertex_list"/' fair.json >old.json
run 2 view old.json -o page.html; stderr_has "old.json: the report has no region indices"
sed 's/"cgal.obj"/"sphere.obj"/' fair.json >wrong.json
run 2 view wrong.json -o page.html; stderr_has "sphere.obj"; absent page.html
run 2 fair bowl.obj --region rings:40,1 -o same.obj --cgal-output same.obj
stderr_has "--cgal-output"; absent same.obj
# A simulation report with an obstacle that is no sphere or plane.
cp -r sim badobstacle && rm badobstacle/frame-00002.obj
echo '{"obstacles": ["cone:0,0,1"]}' >badobstacle/report.json
run 2 view badobstacle -o page.html; stderr_has "badobstacle/report.json"; absent page.html
echo '{"obstacles": ["sphere:0,0,-1,0.5"]}' >badobstacle/report.json
run 0 view badobstacle -o obstacle.html --quiet
grep -q '"spheres":\[\[0,0,-1,0.5\]\]' obstacle.html || fail "obstacle.html has no sphere"
# modes refuses to write its rest.obj over the input mesh.
run 2 modes --mesh modes/rest.obj --energy midedge --count 2 --write-shapes -o modes
stderr_has "modes/rest.obj"; stderr_has "--write-shapes"

finish cli_view
