#!/usr/bin/env python3
"""How fast `flexure view` pages are: a 10 000-vertex simulation of 100 frames written, opened,
scrubbed and orbited in headless Chromium (WebGL on SwiftShader, the CPU: no GPU).

Run by ``scripts/bench view [ARGS]`` (not a test; the page's checks are tests/viewer's). Needs the
flexure command (``--flexure``, default build/cli/flexure) and Debian's chromium.

The simulation folder holds a patch48 sheet (n = 99: 10 000 vertices) sagging over ``--frames``
frames, as `flexure simulate` writes one. Measured:

- ``flexure view FOLDER --style displacement``: seconds and page size;
- load: navigation to the first frame drawn (the page parsed, meshes decoded, drawn once);
- a slider step: setting a frame to the frame drawn, the mean over ``--steps`` frames;
- orbit: frames per second of a drag turning the camera, drawn by the page once per animation
  frame as a user's drag is (a drag slower than 30 frames/s goes on at half resolution), over
  ``--seconds``; and the same with every frame at the full pixel ratio, the baseline (two
  alternating trials of each, the fastest kept);
- a draw: one frame's GL work alone (drawn, then a pixel read back so that it has finished);
- the orbit and the draw again on the same page written with ``--multisample`` (4× samples),
  the two pages alternating.

A table on stderr, JSON on stdout.
"""

import argparse
import json
import os
import pathlib
import random
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "viewer"))
from cdp import Browser  # noqa: E402
from test_viewer_pages import simulation_folder  # noqa: E402

# One draw, forced to finish (a pixel read back), timed: the GL work of a frame alone, the mean
# over the given count.
DRAW = """(() => {
  const v = flexureViewer, gl = v.renderer.getContext(), pixel = new Uint8Array(4);
  const axis = new THREE.Vector3(0, 0, 1);
  const start = performance.now();
  for (let k = 0; k < %d; ++k) {
    v.camera.position.applyAxisAngle(axis, 0.02);
    v.controls.update();
    v.draw();
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
  }
  return (performance.now() - start) / %d / 1000;
})()"""

# A drag as OrbitControls makes one: its start event, then per animation frame the camera turned
# about the up axis by a small angle and the controls updated (their change event has the page
# draw in the next frame), then its end event; the frames counted over the given seconds.
ORBIT = """new Promise(done => {
  const v = flexureViewer, axis = new THREE.Vector3(0, 0, 1);
  v.slowDragsAtHalfRatio = %s;
  let frames = 0;
  v.controls.dispatchEvent({type: 'start'});
  const start = performance.now();
  function tick(now) {
    v.camera.position.applyAxisAngle(axis, 0.02);
    v.controls.update();
    frames += 1;
    if (now - start < %f) {
      requestAnimationFrame(tick);
    } else {
      const rate = frames / ((performance.now() - start) / 1000);
      v.controls.dispatchEvent({type: 'end'});
      done(rate);
    }
  }
  requestAnimationFrame(tick);
})"""


def open_page(browser, page):
    browser.load("file://" + os.path.abspath(page), timeout=300)
    browser.wait_for("document.body.dataset.drawnFrame === '0'", timeout=300)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--flexure", default=str(ROOT / "build" / "cli" / "flexure"))
    parser.add_argument("--n", type=int, default=99, help="patch48 cells per side (99: 10 000 "
                        "vertices)")
    parser.add_argument("--frames", type=int, default=100)
    parser.add_argument("--steps", type=int, default=10, help="slider steps timed")
    parser.add_argument("--seconds", type=float, default=3.0, help="orbit time")
    parser.add_argument("--size", default="1000x700", help="the window, WIDTHxHEIGHT")
    args = parser.parse_args()
    flexure = os.path.abspath(args.flexure)
    width, height = (int(v) for v in args.size.split("x"))
    results = {"window": args.size}
    with tempfile.TemporaryDirectory(prefix="viewer-bench-") as work:
        os.chdir(work)
        subprocess.run([flexure, "--quiet", "mesh", "--family", "patch48", "-n",
                        str(args.n), "-o", "sheet.obj"], check=True)
        simulation_folder("sheet.obj", "sim", args.frames)
        start = time.perf_counter()
        subprocess.run([flexure, "--quiet", "view", "sim", "--style", "displacement", "-o",
                        "page.html"], check=True)
        results["write_seconds"] = time.perf_counter() - start
        subprocess.run([flexure, "--quiet", "view", "sim", "--style", "displacement",
                        "--multisample", "-o", "multisampled.html"], check=True)
        results["page_megabytes"] = os.path.getsize("page.html") / 1e6
        results["vertices"] = (args.n + 1) ** 2
        results["frames"] = args.frames
        browser = Browser(width, height)
        try:
            start = time.perf_counter()
            open_page(browser, "page.html")
            results["load_seconds"] = time.perf_counter() - start
            frames = random.Random(1).sample(range(1, args.frames), args.steps)
            start = time.perf_counter()
            for k in frames:
                browser.evaluate("flexureViewer.setFrame(%d)" % k)
                browser.wait_for("document.body.dataset.drawnFrame === '%d'" % k)
            results["slider_step_seconds"] = (time.perf_counter() - start) / len(frames)
            for trial in range(2):  # the pages alternating, the fastest of each kept
                for page, key in (("page.html", ""), ("multisampled.html", "multisampled_")):
                    if trial or key:
                        open_page(browser, page)
                    for adaptive, name in (("true", "orbit_fps"), ("false", "orbit_fps_full_ratio")):
                        fps = browser.evaluate(ORBIT % (adaptive, 1000 * args.seconds),
                                               timeout=60 + args.seconds)
                        results[key + name] = max(results.get(key + name, 0.0), fps)
                    draw = browser.evaluate(DRAW % (20, 20), timeout=120)
                    results[key + "draw_seconds"] = min(results.get(key + "draw_seconds", 1e9), draw)
        finally:
            browser.close()
    print("flexure view of %d vertices x %d frames: written in %.2f s (%.1f MB); opened in "
          "%.2f s; a slider step %.3f s; orbit %.1f frames/s (%.1f with every frame at the full "
          "pixel ratio); a draw alone %.3f s; with --multisample: orbit %.1f (%.1f), a draw "
          "%.3f s (headless Chromium, SwiftShader, %d cores, %s window)" % (
              results["vertices"], results["frames"], results["write_seconds"],
              results["page_megabytes"], results["load_seconds"], results["slider_step_seconds"],
              results["orbit_fps"], results["orbit_fps_full_ratio"], results["draw_seconds"],
              results["multisampled_orbit_fps"], results["multisampled_orbit_fps_full_ratio"],
              results["multisampled_draw_seconds"], os.cpu_count(), args.size),
          file=sys.stderr)
    json.dump(results, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
