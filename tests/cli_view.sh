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

# A simulation folder: its frames, all with the same faces.
mkdir sim
cp sheet.obj sim/frame-00000.obj
sed 's/^v \(.*\) \(.*\) \(.*\)$/v \1 \2 0.25/' sheet.obj >sim/frame-00001.obj
run 0 view sim --style displacement -o sim.html; stderr_has "(1 meshes, 2 frames"

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

finish cli_view
