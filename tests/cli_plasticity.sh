#!/usr/bin/env bash
# End-to-end runs of `flexure minimize` with plasticity: a plate formed cylindrically and released
# keeps (κ − κ_y)/(1 + γ); a sheet stretched with its width held and released keeps
# (ε − ε_y)/(1 + γ); with yield values nothing reaches the output is byte-identical to a plain
# minimize; refusals exit 2 with nothing written.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/support/cli_harness.sh"

run 0 mesh --family delaunay --n 12 -o sheet.obj --quiet

# κ = 0.2 (z = 0.1 x²), κ_y = 0.1, γ = 0.5: the sprung-back sheet keeps 0.1/1.5 = 0.0667.
run 0 minimize --rest sheet.obj --energy midedge --boundary quadratic:0.1,0,0 --yield-curvature 0.1 \
  --hardening 0.5 --load-steps 4 --release -o sprung.obj --report sprung.json --quiet
python3 - <<'PY' || fail "the sprung-back sheet does not keep (κ − κ_y)/(1 + γ) within 2 %"
import json, math
v = [[float(t) for t in l.split()[1:4]] for l in open("sprung.obj") if l.startswith("v ")]
# Least squares z = c0 + c1 x + c2 y + c3 x²/2 + c4 x y + c5 y²/2 by the normal equations.
rows = [([1, x, y, x * x / 2, x * y, y * y / 2], z) for x, y, z in v]
a = [[sum(r[i] * r[j] for r, _ in rows) for j in range(6)] + [sum(r[i] * z for r, z in rows)]
     for i in range(6)]
for i in range(6):
    pivot = max(range(i, 6), key=lambda k: abs(a[k][i]))
    a[i], a[pivot] = a[pivot], a[i]
    for k in range(6):
        if k != i:
            f = a[k][i] / a[i][i]
            a[k] = [p - f * q for p, q in zip(a[k], a[i])]
c = [a[i][6] / a[i][i] for i in range(6)]
mean, d = (c[3] + c[5]) / 2, math.hypot((c[3] - c[5]) / 2, c[4])
k = (mean - d, mean + d)
expected = 0.1 / 1.5
assert abs(k[1] - expected) < 0.02 * expected and abs(k[0]) < 0.02 * expected, k
p = json.load(open("sprung.json"))["plasticity"]
assert p["yielded_elements"] > 0 and p["plastic_dissipation"] > 0 and len(p["release_pins"]) == 3, p
PY

# No yield value: the same bytes as before plasticity existed (the plain minimize path).
run 0 minimize --rest sheet.obj --energy midedge --boundary quadratic:0.1,0,0 -o plain.obj --quiet
run 0 minimize --rest sheet.obj --energy midedge --boundary quadratic:0.1,0,0 -o plain2.obj \
  --yield-curvature 100 --quiet
cmp -s plain.obj plain2.obj || fail "a yield value nothing reaches changed the minimizer"

# Membrane: the sheet stretched to Green strain 0.03 along x (λ = √1.06) with its boundary held,
# ε_y = 0.01, γ = 0.5, released: every face keeps the strain diag(0.02/1.5, 0) within 2 %.
awk '/^v /{printf "v %.17g %s %s\n", $2 * sqrt(1.06), $3, $4; next} {print}' sheet.obj > stretched.obj
run 0 minimize --rest sheet.obj --init stretched.obj --fix rings:1 --dof xyz --membrane stvk \
  --energy hinge --yield-strain 0.01 --hardening 0.5 --load-steps 2 --release -o kept.obj \
  --report kept.json --quiet
python3 - <<'PY' || fail "the released sheet does not keep the strain (ε − ε_y)/(1 + γ) within 2 %"
import json
def mesh(name):
    v = [[float(t) for t in l.split()[1:4]] for l in open(name) if l.startswith("v ")]
    f = [[int(t) - 1 for t in l.split()[1:4]] for l in open(name) if l.startswith("f ")]
    return v, f
rest, faces = mesh("sheet.obj")
kept, _ = mesh("kept.obj")
expected = 0.02 / 1.5
for f in faces:
    # F = [x1 - x0, x2 - x0] D⁻¹, D the rest edges in x, y; Green strain ½(FᵀF − I).
    (a, c), (b, d) = [[rest[f[k]][i] - rest[f[0]][i] for i in range(2)] for k in (1, 2)]
    det = a * d - b * c
    inv = [[d / det, -b / det], [-c / det, a / det]]
    e = [[kept[f[k]][i] - kept[f[0]][i] for i in range(3)] for k in (1, 2)]
    F = [[e[0][i] * inv[0][j] + e[1][i] * inv[1][j] for j in range(2)] for i in range(3)]
    C = [[sum(F[i][p] * F[i][q] for i in range(3)) for q in range(2)] for p in range(2)]
    strain = (0.5 * (C[0][0] - 1), 0.5 * C[0][1], 0.5 * (C[1][1] - 1))
    assert abs(strain[0] - expected) < 0.02 * expected, (f, strain)
    assert abs(strain[1]) < 0.02 * expected and abs(strain[2]) < 0.02 * expected, (f, strain)
p = json.load(open("kept.json"))["plasticity"]
assert p["yield_strain"] == 0.01 and p["yield_curvature"] is None, p
assert p["yielded_membrane_faces"] == len(faces) and p["yielded_elements"] == 0, p
PY

# No yield value reached: the same bytes as the plain xyz minimize.
run 0 minimize --rest sheet.obj --init stretched.obj --fix rings:1 --dof xyz --membrane stvk \
  --energy hinge -o plainm.obj --quiet
run 0 minimize --rest sheet.obj --init stretched.obj --fix rings:1 --dof xyz --membrane stvk \
  --energy hinge --yield-strain 100 --yield-curvature 100 -o plainm2.obj --quiet
cmp -s plainm.obj plainm2.obj || fail "a yield strain nothing reaches changed the minimizer"

# Refusals: cotan, forming options without a yield value, a yield strain without a stvk
# membrane, linearized.
run 2 minimize --rest sheet.obj --energy cotan --boundary quadratic:0.1,0,0 --yield-curvature 0.1 -o c.obj
stderr_has "cotan"; stderr_has "--yield-curvature"; absent c.obj
run 2 minimize --rest sheet.obj --energy midedge --boundary quadratic:0.1,0,0 --release -o r.obj
stderr_has "need a yield value"; absent r.obj
run 2 minimize --rest sheet.obj --energy midedge --boundary quadratic:0.1,0,0 --yield-strain 0.01 -o s.obj
stderr_has "--yield-strain"; stderr_has "--membrane stvk"; absent s.obj
run 2 minimize --rest sheet.obj --init stretched.obj --fix rings:1 --dof xyz --membrane springs \
  --energy hinge --yield-strain 0.01 -o s.obj
stderr_has "--yield-strain"; stderr_has "springs"; absent s.obj
run 2 minimize --rest sheet.obj --energy midedge --boundary quadratic:0.1,0,0 --yield-curvature 0.1 \
  --linearized -o l.obj
stderr_has "--linearized"; absent l.obj
run 2 minimize --rest sheet.obj --energy midedge --boundary quadratic:0.1,0,0 --yield-curvature -1 -o n.obj
absent n.obj

finish cli_plasticity
