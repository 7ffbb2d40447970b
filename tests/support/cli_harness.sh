# The end-to-end scripts' harness (sourced): $FLEXURE checked, a scratch folder as the working
# directory (removed on exit), `run` with its exit-code check, and assertions on the outputs.
# The sourcing script ends with `finish NAME`.
: "${FLEXURE:?set FLEXURE to the flexure executable}"
FLEXURE="$(realpath "$FLEXURE")"
[ -x "$FLEXURE" ] || { echo "no flexure executable at $FLEXURE" >&2; exit 1; }
work="$(mktemp -d "${TMPDIR:-/tmp}/flexure-e2e.XXXXXX")"
trap 'rm -rf "$work"' EXIT
cd "$work"
failures=0
checks=0

fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

# run EXPECTED_EXIT ARGS...: runs flexure, keeps stdout in out.txt and stderr in err.txt.
run() {
  local expected=$1; shift
  checks=$((checks + 1))
  "$FLEXURE" "$@" >out.txt 2>err.txt
  local code=$?
  [ "$code" -eq "$expected" ] || fail "flexure $* exited $code, expected $expected; stderr: $(cat err.txt)"
}
stderr_has() { grep -qF -- "$1" err.txt || fail "stderr lacks '$1': $(cat err.txt)"; }
stdout_has() { grep -qF -- "$1" out.txt || fail "stdout lacks '$1'"; }
absent() { [ ! -e "$1" ] || fail "$1 exists but should not"; }
near() {  # near KEY VALUE TOLERANCE: the JSON on stdout has KEY within TOLERANCE of VALUE
  python3 -c "import json,sys; d=json.load(open('out.txt')); sys.exit(0 if abs(d['$1']-$2) <= $3 else 1)" \
    || fail "$1 is not $2 ± $3: $(cat out.txt)"
}
# make_strip: strip.obj, the 1 x 1/4 strip (patch48 n = 8, y scaled by 1/4) the pin, tear and
# release runs pull and hang.
make_strip() {
  run 0 mesh --family patch48 --n 8 -o square.obj --quiet
  python3 -c "
lines = []
for l in open('square.obj'):
    if l.startswith('v '):
        _, x, y, z = l.split(); l = 'v %s %.17g %s\n' % (x, float(y) * 0.25, z)
    lines.append(l)
open('strip.obj', 'w').writelines(lines)"
}
is_png() { [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ]; }

# finish NAME: the summary line, and the script's exit status.
finish() {
  echo "$1: $checks runs, $failures failures"
  [ "$failures" -eq 0 ]
}
