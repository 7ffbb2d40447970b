#!/usr/bin/env bash
# flexure info on real meshes from CGAL's demo data (Debian package libcgal-demo): the usable
# ones are described, the broken ones refused with the right problem. Verdicts checked by hand.
set -uo pipefail
: "${FLEXURE:?set FLEXURE to the flexure executable}"
FLEXURE="$(realpath "$FLEXURE")"
archive=/usr/share/doc/libcgal-dev/data.tar.gz
[ -f "$archive" ] || { echo "missing $archive: run scripts/install-deps (libcgal-demo)" >&2; exit 1; }
work="$(mktemp -d "${TMPDIR:-/tmp}/flexure-real.XXXXXX")"
trap 'rm -rf "$work"' EXIT
cd "$work"
meshes=(elephant holes cylinder mesh_with_border blobby-shuffled prim degtri_sliding polygon_mesh
  corner_with_hole triangular_hole)
tar xzf "$archive" $(printf 'data/meshes/%s.off ' "${meshes[@]}") data/meshes/sphere.stl \
  data/meshes/colored_tetra.ply data/meshes/b9.ply
cd data/meshes
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

# expect FILE EXIT TEXT...: flexure info --json FILE exits EXIT and its report contains each TEXT.
expect() {
  local file=$1 code=$2; shift 2
  "$FLEXURE" info --json "$file" >report.json 2>err.txt
  local got=$?
  [ "$got" -eq "$code" ] || fail "$file: exit $got, expected $code: $(cat err.txt)"
  local compact
  compact="$(tr -d ' \n' < report.json)"
  for text in "$@"; do
    [[ "$compact" == *"$text"* ]] || fail "$file: report lacks $text"
  done
}

expect elephant.off 0 '"vertices":2775' '"edges":8337' '"euler_characteristic":-4' '"valid":true'  # closed, genus 3
expect holes.off 0 '"boundary_loops":[136,36,32,28,28,28,16]'
expect cylinder.off 0 '"boundary_loops":[136]'
expect mesh_with_border.off 0 '"boundary_loops":[80]' '"euler_characteristic":1'
expect sphere.stl 0 '"vertices":162' '"faces":320' '"euler_characteristic":2'
expect colored_tetra.ply 0 '"vertices":4' '"valid":true'
expect blobby-shuffled.off 2 '"inconsistent_orientation":3069'
# prim.off counts 7 faces and lists 8: the 8th (the only user of vertices 8, 9, 10) is named.
expect prim.off 2
grep -qF "prim.off: line 24: data after the 7 faces the header counts" err.txt || fail "prim.off: $(cat err.txt)"
expect degtri_sliding.off 2 '"zero_area_face":4'
expect polygon_mesh.off 2 '"non_manifold_vertex":2'
expect b9.ply 2 '"empty":1'  # a point cloud: vertices, no faces

# flexure fair --region holes where CGAL closes every hole by triangles alone (no new vertex): the
# filled mesh is the result, written with exit 0 (it exited 2, "nothing to fair").
fill_only() {
  local file=$1 faces=$2 loops=$3
  "$FLEXURE" fair "$file" --region holes -o filled.off --report filled.json 2>err.txt
  local got=$?
  [ "$got" -eq 0 ] || { fail "fair $file --region holes: exit $got: $(cat err.txt)"; return; }
  grep -qF "nothing to fair" err.txt || fail "fair $file: no notice: $(cat err.txt)"
  expect filled.off 0 "\"faces\":$faces" "\"boundary_loops\":[$loops]"
  grep -qF '"result": "filled"' filled.json || fail "fair $file: report: $(cat filled.json)"
  rm -f filled.off filled.json
}
fill_only corner_with_hole.off 28 ''    # 26 faces (13 quads split) + 2 closing its 4-edge hole
fill_only triangular_hole.off 7 3     # one 3-edge loop closed; the other, whose fill folds, left

echo "real_meshes: $failures failures"
[ "$failures" -eq 0 ]
