"""flexure view's pages in a real browser (headless Chromium over the DevTools Protocol, WebGL on
SwiftShader): a mesh is drawn (not a blank canvas), reflection lines show both stripe colours, the
slider changes the frame shown, a field's legend shows its range, a modes folder's selector and
amplitude slider change the mode drawn and its nodal lines are drawn, a fairing report's three
meshes are drawn with the region outlined green, a simulation's obstacles are drawn, and no page logs a console error or requests
anything but itself.

Usage: test_viewer_pages.py FLEXURE WORKDIR [--screenshots DIR]
(How fast the pages are is measured by scripts/bench view, not here.)
"""
import json
import math
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdp import Browser  # noqa: E402

# The start of every pixel script: the page drawn and its drawing buffer (w × h, RGBA) read into p.
READ = """  flexureViewer.draw();
  const gl = flexureViewer.renderer.getContext();
  const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
  const p = new Uint8Array(4 * w * h);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, p);
"""

# Counts over the drawing buffer: pixels that are not the white background, dark ones
# (stripes: the shader's dark colour is 0.06), light ones (0.96), for the whole canvas and for
# each half (side-by-side views).
PIXELS = "(() => {\n" + READ + """  const r = {drawn: 0, dark: 0, light: 0, left: 0, right: 0, total: w * h, sum: 0};
  for (let y = 0; y < h; ++y) for (let x = 0; x < w; ++x) {
    const i = 4 * (y * w + x), c = p[i] + p[i + 1] + p[i + 2];
    r.sum += (x * 7 + y * 13) % 251 * c;
    if (c >= 3 * 254) continue;
    r.drawn += 1;
    if (x < w / 2) r.left += 1; else r.right += 1;
    if (c < 3 * 40) r.dark += 1;
    if (c > 3 * 230 && p[i] === p[i + 1]) r.light += 1;
  }
  return r;
})()"""

failures = []


def check(condition, what):
    print(("ok    " if condition else "FAIL  ") + what)
    if not condition:
        failures.append(what)


def flexure(binary, *args, expect=0):
    result = subprocess.run([binary, *args], capture_output=True, text=True)
    if result.returncode != expect:
        raise SystemExit("flexure %s: exit %d, expected %d\n%s" %
                         (" ".join(args), result.returncode, expect, result.stderr))
    return result


def write_obj(path, positions, faces):
    with open(path, "w") as f:
        for p in positions:
            f.write("v %.9g %.9g %.9g\n" % tuple(p))
        for t in faces:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


def read_obj(path):
    positions, faces = [], []
    for line in open(path):
        parts = line.split()
        if parts and parts[0] == "v":
            positions.append([float(x) for x in parts[1:4]])
        elif parts and parts[0] == "f":
            faces.append([int(x.split("/")[0]) - 1 for x in parts[1:4]])
    return positions, faces


def simulation_folder(sheet, folder, frames, obstacles=None):
    """A folder as flexure simulate writes it: the sheet sagging into z = -a (x² + y²)."""
    os.makedirs(folder, exist_ok=True)
    positions, faces = read_obj(sheet)
    times = []
    for k in range(frames):
        a = 0.8 * k / (frames - 1)
        moved = [[x, y, z - a * (x * x + y * y) - 0.1 * a] for x, y, z in positions]
        write_obj(os.path.join(folder, "frame-%05d.obj" % k), moved, faces)
        times.append(0.05 * k)
    with open(os.path.join(folder, "report.json"), "w") as f:
        json.dump({"frames": frames, "frame_times": times,
                   **({"obstacles": obstacles} if obstacles else {})}, f)


def load(browser, page, timeout=120):
    start = time.time()
    browser.load("file://" + os.path.abspath(page), timeout=timeout)
    browser.wait_for("document.body.dataset.drawnFrame === '0'", timeout=timeout)
    return time.time() - start


def clean(browser, page):
    url = "file://" + os.path.abspath(page)
    check(browser.console_errors() == [], page + ": no console error " + str(browser.console_errors()))
    others = [u for u in browser.requests() if u != url]
    check(others == [], page + ": no request but the page itself " + str(others))


def bumpy_bowl(bowl, out):
    """The bowl with a cone-shaped bump of height 0.05 and radius 0.2 at its apex: a region to fair."""
    positions, faces = read_obj(bowl)
    for p in positions:
        d = math.hypot(p[0], p[1])
        p[2] += 0.05 * max(0.0, 1.0 - d / 0.2)
    write_obj(out, positions, faces)


def pixel_count(condition):
    """A script counting the drawn pixels whose colour (r, g, b: 0..255) meets `condition`."""
    return "(() => {\n" + READ + """  let n = 0;
  for (let i = 0; i < p.length; i += 4) {
    const r = p[i], g = p[i + 1], b = p[i + 2];
    if (%s) n += 1;
  }
  return n;
})()""" % condition


# The nodal lines' red (the reflection stripes are grey), the obstacles' orange (0.86, 0.62, 0.36)
# lit: red well above blue, and the cracks' magenta (the renderer's crack colour).
RED = pixel_count("r > 150 && g < 90 && b < 90")
ORANGE = pixel_count("r > 80 && r > g + 20 && g > b + 20")
MAGENTA = pixel_count("r > 200 && g < 80 && b > 150")


# Pixels of the outline's green (0, 0.8, 0.2) in each third of the canvas.
GREEN = "(() => {\n" + READ + """  const thirds = [0, 0, 0];
  for (let y = 0; y < h; ++y) for (let x = 0; x < w; ++x) {
    const i = 4 * (y * w + x);
    if (p[i + 1] > 150 && p[i] < 80 && p[i + 2] < 120) thirds[Math.min(2, Math.floor(3 * x / w))] += 1;
  }
  return thirds;
})()"""


def fairing_page(browser, shots):
    """A fairing report: input, CGAL's fair and flexure's side by side, the region outlined on each."""
    load(browser, "fair.html")
    names = browser.evaluate("document.getElementById('names').innerText")
    check("input: bumpy.obj" in names and "CGAL fair: cgal.obj" in names and
          "flexure midedge: faired.obj" in names, "fair.html: the three meshes named %r" % names)
    outline = browser.evaluate("document.body.dataset.outlineSegments").split(",")
    check(len(outline) == 3 and len(set(outline)) == 1 and int(outline[0]) > 20,
          "fair.html: the same outline on each mesh (%s segments)" % outline)
    green = browser.evaluate(GREEN)
    check(all(g > 100 for g in green), "fair.html: the outline drawn green in each view %s" % green)
    browser.evaluate("flexureViewer.scenes.forEach(s => s.children.forEach("
                     "c => { if (c.isLineSegments) c.visible = false; }))")
    check(all(g < 5 for g in browser.evaluate(GREEN)), "fair.html: no green without the outline")
    browser.evaluate("flexureViewer.scenes.forEach(s => s.children.forEach("
                     "c => { if (c.isLineSegments) c.visible = true; })); flexureViewer.draw()")
    px = browser.evaluate(PIXELS)
    check(px["drawn"] > 0.05 * px["total"], "fair.html: meshes drawn %s" % px)
    if shots:
        browser.screenshot(os.path.join(shots, "view-fair.png"))
    clean(browser, "fair.html")


def cap_page(browser):
    """A fairing report of a cap at +x of a sphere: the camera looks at it along its mean normal
    (+x, a known answer), as flexure fair's figure does."""
    load(browser, "cap.html")
    e = browser.evaluate("(() => { const c = flexureViewer.camera.position.clone()"
                         ".sub(flexureViewer.controls.target).normalize(); return [c.x, c.y, c.z]; })()")
    check(e[0] > 0.999, "cap.html: the camera looks at the cap along +x %s" % e)
    clean(browser, "cap.html")


def obstacles_page(browser, shots):
    """A simulation folder whose report lists a sphere and a plane: both drawn, in orange."""
    load(browser, "obstacles.html")
    check(browser.evaluate("document.body.dataset.obstacles") == "2",
          "obstacles.html: a sphere and a plane added")
    orange = browser.evaluate(ORANGE)
    browser.evaluate("flexureViewer.scenes.forEach(s => s.children.forEach("
                     "c => { if (c.isMesh && c.material.isMeshLambertMaterial) c.visible = false; }))")
    hidden = browser.evaluate(ORANGE)
    check(orange > 0.02 * 700000 and hidden < 100,
          "obstacles.html: the obstacles drawn orange (%d pixels, %d hidden)" % (orange, hidden))
    browser.evaluate("flexureViewer.scenes.forEach(s => s.children.forEach("
                     "c => { if (c.isMesh) c.visible = true; })); flexureViewer.draw()")
    if shots:
        browser.screenshot(os.path.join(shots, "view-obstacles.png"))
    clean(browser, "obstacles.html")


def plastic_page(browser, shots):
    """A run with plasticity, --style plastic: the legend spans [0, the largest face value of its
    plastic.json] and is titled by its measure; the last frame is coloured."""
    with open(os.path.join("bent", "plastic.json")) as f:
        plastic = json.load(f)
    largest = max(max(frame) for frame in plastic["faces"])
    load(browser, "plastic.html")
    browser.evaluate("flexureViewer.setFrame(%d)" % (len(plastic["frames"]) - 1))
    hi = float(browser.evaluate("document.getElementById('legend-max').textContent"))
    title = browser.evaluate("document.getElementById('legend-title').textContent")
    check(title == plastic["measure"] and abs(hi - largest) <= 0.01 * largest,
          "plastic.html: legend '%s' up to %g ~ %g" % (title, hi, largest))
    if shots:
        browser.screenshot(os.path.join(shots, "view-plastic.png"))
    clean(browser, "plastic.html")


def tear_page(browser, shots):
    """examples/tear-strip.json's folder: a cut changes the faces (128 → 129) at frame 3, whose
    crack lips (cracks.json) are drawn magenta; the first frame has neither."""
    load(browser, "tear.html")
    check(browser.evaluate("document.body.dataset.shownFaces") == "128" and
          browser.evaluate("document.body.dataset.crackSegments") == "0" and
          browser.evaluate(MAGENTA) == 0, "tear.html: frame 0 has the uncut faces, no crack")
    browser.evaluate("flexureViewer.setFrame(6)")
    browser.wait_for("document.body.dataset.drawnFrame === '6'")
    magenta = browser.evaluate(MAGENTA)
    check(browser.evaluate("document.body.dataset.shownFaces") == "129" and
          browser.evaluate("document.body.dataset.crackSegments") == "16" and magenta > 50,
          "tear.html: frame 6 has the cut faces and its 16 lip edges drawn (%d pixels)" % magenta)
    if shots:
        browser.screenshot(os.path.join(shots, "view-tear.png"))
    clean(browser, "tear.html")


def modes_page(browser, shots):
    """A flexure modes folder: mode 1 animated, the selector and the amplitude slider change the
    drawing, the nodal lines (none for the simply supported (1,1) mode, a line for (1,2)) drawn."""
    load(browser, "modes.html")
    check(not browser.evaluate("document.getElementById('mode-controls').hidden"),
          "modes.html: the mode controls are shown")
    options = browser.evaluate("Array.from(document.getElementById('mode').options)"
                               ".map(o => o.textContent)")
    check(len(options) == 4 and options[0].startswith("mode 1: λ = ") and "ω = " in options[0],
          "modes.html: four modes in the selector %s" % options)
    # Playing: the phase moves on its own.
    a = browser.evaluate(PIXELS)["sum"]
    time.sleep(0.4)
    check(browser.evaluate(PIXELS)["sum"] != a, "modes.html: the mode plays")
    browser.evaluate("flexureViewer.pause(); flexureViewer.setPhase(Math.PI / 2)")
    first = browser.evaluate(PIXELS)
    check(first["drawn"] > 0.05 * first["total"], "modes.html: a mesh drawn %s" % first)
    check(browser.evaluate("document.body.dataset.nodalSegments") == "0",
          "modes.html: mode 1 (1,1) has no nodal line inside the plate")
    browser.evaluate("(() => { const s = document.getElementById('mode'); s.value = '1';"
                     " s.dispatchEvent(new Event('change')); })()")
    second = browser.evaluate(PIXELS)
    segments = int(browser.evaluate("document.body.dataset.nodalSegments"))
    check(browser.evaluate("document.body.dataset.mode") == "1" and second["sum"] != first["sum"],
          "modes.html: the selector changes the mode drawn")
    check(segments >= 16, "modes.html: mode 2 has a nodal line (%d segments)" % segments)
    red = browser.evaluate(RED)
    browser.evaluate("flexureViewer.scenes.forEach(s => s.children.forEach("
                     "c => { if (c.isLineSegments) c.visible = false; }))")
    unlined = browser.evaluate(RED)
    browser.evaluate("flexureViewer.scenes.forEach(s => s.children.forEach("
                     "c => { if (c.isLineSegments) c.visible = true; })); flexureViewer.draw()")
    check(red > unlined + 50, "modes.html: the nodal line drawn red (%d red pixels, %d "
          "without it)" % (red, unlined))
    browser.evaluate("(() => { const s = document.getElementById('amplitude'); s.value = '0';"
                     " s.dispatchEvent(new Event('input')); })()")
    flat = browser.evaluate(PIXELS)
    check(flat["sum"] != second["sum"] and
          browser.evaluate("document.getElementById('amplitude-text').textContent") == "0.00 × φ",
          "modes.html: the amplitude slider changes the drawing")
    browser.evaluate("flexureViewer.setAmplitude(1)")
    if shots:
        browser.screenshot(os.path.join(shots, "view-modes.png"))
    clean(browser, "modes.html")


# The sequential map's ends: its top (yellow, an equilateral face at 60°) and its bottom
# (dark purple, a sliver).
YELLOW = pixel_count("r > 200 && g > 190 && b < 90")
PURPLE = pixel_count("r < 110 && g < 70 && b > 60")


def angle_page(browser, shots):
    """--style angle on an equilateral face (60°) and a sliver (6.8°): each face is one colour,
    the top and the bottom of the map, and the legend spans [0, 60]."""
    load(browser, "angle.html")
    lo = browser.evaluate("document.getElementById('legend-min').textContent")
    hi = browser.evaluate("document.getElementById('legend-max').textContent")
    yellow, purple = browser.evaluate(YELLOW), browser.evaluate(PURPLE)
    drawn = browser.evaluate(PIXELS)["drawn"]
    check(lo == "0" and hi == "60", "angle.html: legend [%s, %s]" % (lo, hi))
    # Per vertex the two faces would blend across their shared edge; per face each is one colour
    # (the legend's own pixels are a few hundred of each).
    check(yellow > 0.5 * drawn and purple > 0.02 * drawn,
          "angle.html: the equilateral face yellow, the sliver purple (%d, %d of %d pixels)"
          % (yellow, purple, drawn))
    if shots:
        browser.screenshot(os.path.join(shots, "view-angle.png"))
    clean(browser, "angle.html")
    # A run that fractured: the per-face field follows the faces the cut changes.
    load(browser, "tear-angle.html")
    browser.evaluate("flexureViewer.setFrame(6)")
    browser.wait_for("document.body.dataset.drawnFrame === '6'")
    check(browser.evaluate("document.body.dataset.shownFaces") == "129",
          "tear-angle.html: frame 6 shows the cut faces")
    clean(browser, "tear-angle.html")


def error_page(browser, shots):
    """--style error of the bowl z = x² + y² against the flat sheet z = 0 under it: each vertex's
    error is its height, so the legend's top is the bowl's largest z."""
    load(browser, "error.html")
    top = max(p[2] for p in read_obj("bowl.obj")[0])
    hi = float(browser.evaluate("document.getElementById('legend-max').textContent"))
    title = browser.evaluate("document.getElementById('legend-title').textContent")
    check(title == "error: distance to sheet.obj" and abs(hi - top) <= 0.005 * top,
          "error.html: legend '%s' up to %g ~ %g" % (title, hi, top))
    if shots:
        browser.screenshot(os.path.join(shots, "view-error.png"))
    clean(browser, "error.html")


def main():
    binary, work = sys.argv[1], sys.argv[2]
    shots = sys.argv[sys.argv.index("--screenshots") + 1] if "--screenshots" in sys.argv else None
    os.makedirs(work, exist_ok=True)
    os.chdir(work)
    flexure(binary, "mesh", "--family", "delaunay", "--n", "24", "--height", "quadratic:1,0,1",
            "-o", "bowl.obj")
    flexure(binary, "mesh", "--family", "sphere", "--n", "32", "-o", "sphere.obj")
    flexure(binary, "mesh", "--family", "patch48", "--n", "16", "-o", "sheet.obj")
    simulation_folder("sheet.obj", "sag", 20)
    flexure(binary, "view", "bowl.obj", "sphere.obj", "-o", "side.html", "--quiet")
    flexure(binary, "view", "bowl.obj", "--style", "curvature", "-o", "curvature.html", "--quiet")
    flexure(binary, "view", "sag", "--style", "displacement", "-o", "sag.html", "--quiet")
    flexure(binary, "view", "bowl.obj", "--style", "isophote", "-o", "isophote.html", "--quiet")
    flexure(binary, "modes", "--family", "patch48", "--n", "16", "--energy", "midedge", "--count",
            "4", "--support", "simply-supported", "--write-shapes", "-o", "modes", "--quiet")
    flexure(binary, "view", "modes", "-o", "modes.html", "--quiet")
    bumpy_bowl("bowl.obj", "bumpy.obj")
    flexure(binary, "fair", "bumpy.obj", "--region", "sphere:0,0,0.05,0.28", "-o", "faired.obj",
            "--cgal-output", "cgal.obj", "--report", "fair.json", "--quiet")
    flexure(binary, "view", "fair.json", "-o", "fair.html", "--quiet")
    flexure(binary, "fair", "sphere.obj", "--region", "sphere:0.5,0,0,0.2", "-o", "cap.obj",
            "--report", "cap.json", "--quiet")
    flexure(binary, "view", "cap.json", "-o", "cap.html", "--quiet")
    simulation_folder("sheet.obj", "sag-obstacles", 3,
                      obstacles=["sphere:0,0,-0.8,0.25", "plane:0,0,1,-1.2"])
    flexure(binary, "view", "sag-obstacles", "-o", "obstacles.html", "--quiet")
    examples = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples")
    flexure(binary, "--quiet", "run", os.path.join(examples, "tear-strip.json"))
    flexure(binary, "view", "tear", "-o", "tear.html", "--quiet")
    flexure(binary, "simulate", "--rest", "sheet.obj", "--energy", "hinge", "--stiffness", "0.05",
            "--membrane", "stvk", "--young", "1000", "--pin", "box:-0.5,-0.4,-1,1,-1,1", "--pin",
            "box:0.4,0.5,-1,1,-1,1@rotate:0,-1,0,0,0,0,1.57", "--yield-curvature", "0.5",
            "--damping", "rayleigh:4,0", "--dt", "0.02", "--duration", "0.6", "--fps", "10",
            "--render-style", "none", "-o", "bent", "--quiet")
    flexure(binary, "view", "bent", "--style", "plastic", "-o", "plastic.html", "--quiet")
    # An equilateral face (60°) and a sliver under it (atan(0.06 / 0.5) = 6.8°).
    write_obj("slivers.obj", [[0, 0, 0], [1, 0, 0], [0.5, 0.8660254, 0], [0.5, -0.06, 0]],
              [[0, 1, 2], [0, 3, 1]])
    flexure(binary, "view", "slivers.obj", "--style", "angle", "-o", "angle.html", "--quiet")
    flexure(binary, "view", "tear", "--style", "angle", "-o", "tear-angle.html", "--quiet")
    flexure(binary, "view", "bowl.obj", "--style", "error", "--reference", "sheet.obj", "-o",
            "error.html", "--quiet")

    browser = Browser()
    try:
        # Two meshes side by side, reflection lines: each half drawn, both stripe colours.
        load(browser, "side.html")
        px = browser.evaluate(PIXELS)
        check(px["left"] > 0.05 * px["total"] / 2 and px["right"] > 0.05 * px["total"] / 2,
              "side.html: a mesh drawn in each view %s" % px)
        check(px["dark"] > 0.1 * px["drawn"] and px["light"] > 0.1 * px["drawn"],
              "side.html: dark and light reflection stripes")
        names = browser.evaluate("document.getElementById('names').innerText")
        check("bowl.obj" in names and "sphere.obj" in names, "side.html: both names shown")
        # Orbiting moves the camera-locked stripes: the image changes.
        before = px["sum"]
        browser.evaluate("(() => { const c = flexureViewer.camera; c.position.applyAxisAngle("
                         "new THREE.Vector3(0, 0, 1), 0.4); flexureViewer.controls.update(); })()")
        check(browser.evaluate(PIXELS)["sum"] != before, "side.html: orbiting changes the image")
        if shots:
            browser.screenshot(os.path.join(shots, "view-side.png"))
        clean(browser, "side.html")

        # A curvature field: its legend shows the symmetric range of H, the bowl is coloured.
        load(browser, "curvature.html")
        lo = float(browser.evaluate("document.getElementById('legend-min').textContent"))
        hi = float(browser.evaluate("document.getElementById('legend-max').textContent"))
        title = browser.evaluate("document.getElementById('legend-title').textContent")
        visible = browser.evaluate("!document.getElementById('legend').hidden")
        # z = x² + y²: H = 2 at the apex (the sign is the kernel's), near it over the patch.
        check(visible and "mean curvature" in title and lo == -hi and 1.0 < hi < 4.0,
              "curvature.html: legend '%s' [%g, %g]" % (title, lo, hi))
        px = browser.evaluate(PIXELS)
        check(px["drawn"] > 0.05 * px["total"], "curvature.html: mesh drawn %s" % px)
        check(browser.evaluate("document.getElementById('controls').hidden"),
              "curvature.html: no slider for one frame")
        if shots:
            browser.screenshot(os.path.join(shots, "view-curvature.png"))
        clean(browser, "curvature.html")

        # A simulation: the slider shows another frame; the legend spans 0 .. the largest sag.
        load(browser, "sag.html")
        first = browser.evaluate(PIXELS)
        check(browser.evaluate("document.getElementById('time').textContent") == "t = 0.000 s",
              "sag.html: the first frame's time")
        browser.evaluate("(() => { const s = document.getElementById('frame'); s.value = '19';"
                         " s.dispatchEvent(new Event('input')); })()")
        browser.wait_for("document.body.dataset.drawnFrame === '19'")
        last = browser.evaluate(PIXELS)
        check(browser.evaluate("document.getElementById('time').textContent") == "t = 0.950 s",
              "sag.html: the slider shows the last frame's time")
        check(last["sum"] != first["sum"] and last["drawn"] > 0.05 * last["total"],
              "sag.html: the slider changes the frame drawn")
        hi = float(browser.evaluate("document.getElementById('legend-max').textContent"))
        expected = 0.8 * 0.5 + 0.08  # the corner (±1/2, ±1/2) of the last frame
        check(abs(hi - expected) < 0.01 * expected, "sag.html: legend top %g ~ %g" % (hi, expected))
        browser.evaluate("document.getElementById('play').click()")
        time.sleep(0.3)
        browser.evaluate("document.getElementById('play').click()")
        check(browser.evaluate("document.getElementById('frame').value") != "19",
              "sag.html: play advances the frames")
        if shots:
            browser.screenshot(os.path.join(shots, "view-sag.png"))
        clean(browser, "sag.html")

        load(browser, "isophote.html")
        px = browser.evaluate(PIXELS)
        check(px["dark"] > 0.05 * px["drawn"] and px["light"] > 0.05 * px["drawn"],
              "isophote.html: dark and light bands %s" % px)
        if shots:
            browser.screenshot(os.path.join(shots, "view-isophote.png"))
        clean(browser, "isophote.html")

        modes_page(browser, shots)
        fairing_page(browser, shots)
        cap_page(browser)
        obstacles_page(browser, shots)
        tear_page(browser, shots)
        plastic_page(browser, shots)
        angle_page(browser, shots)
        error_page(browser, shots)

        # The driver does see a console error and a request when a page makes them.
        browser.evaluate("console.error('probe'); fetch('http://127.0.0.1:9/x').catch(() => 0)")
        time.sleep(0.2)
        browser.evaluate("1")
        check(any("probe" in e for e in browser.console_errors()) and
              any(u.startswith("http://127.0.0.1:9/") for u in browser.requests()),
              "the driver records console errors and requests")

    finally:
        browser.close()
    if failures:
        print("%d check(s) failed" % len(failures))
        sys.exit(1)
    print("every check passed")


if __name__ == "__main__":
    main()
