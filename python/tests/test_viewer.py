"""flexure.view: the same page as `flexure view`; _repr_html_ and save; refusals by keyword."""

import base64
import html
import json
import pathlib
import re

import numpy as np
import pytest

import flexure
from conftest import bent


def page_data(page):
    """The page's data object (its meshes' arrays decoded)."""
    data = json.loads(re.search(r"const flexureData = (\{.*?\});\n", page, re.S).group(1))
    for m in data["meshes"]:
        m["positions"] = np.frombuffer(base64.b64decode(m["positions"]), "<f4")
        m["triangles"] = np.frombuffer(base64.b64decode(m["triangles"]), "<u4")
        if m["fields"]:
            m["fields"] = np.frombuffer(base64.b64decode(m["fields"]), "<f4")
    return data


def test_same_page_as_the_cli(cli, plate, tmp_path):
    V, F = plate
    W = bent(V, 3)
    flexure.write_mesh(tmp_path / "a.obj", W, F)
    cli("-q", "view", tmp_path / "a.obj", "-o", tmp_path / "a.html", "--style", "curvature")
    python = flexure.view(tmp_path / "a.obj", style="curvature").html
    expected = (tmp_path / "a.html").read_text()
    # The title names the input as given; everything else is the same bytes.
    strip = lambda p: re.sub(r"<title>.*?</title>", "", p)
    assert strip(python) == strip(expected)


def test_modes_folder_same_page_as_the_cli(cli, tmp_path):
    modes = tmp_path / "modes"
    cli("-q", "modes", "--family", "patch48", "--n", "8", "--energy", "midedge", "--count", "3",
        "--support", "simply-supported", "--write-shapes", "-o", modes)
    cli("-q", "view", modes, "-o", tmp_path / "modes.html")
    python = flexure.view(modes).html
    strip = lambda p: re.sub(r"<title>.*?</title>", "", p)
    assert strip(python) == strip((tmp_path / "modes.html").read_text())
    (mesh,) = page_data(python)["meshes"]
    assert mesh["name"] == "midedge" and mesh["frameCount"] == 1
    assert [m["label"].split(":")[0] for m in mesh["modes"]] == ["mode 1", "mode 2", "mode 3"]
    # φ_k = shape − rest: its largest displacement is --scale × L = 0.1.
    rest, _ = flexure.read_mesh(modes / "rest.obj")
    shape, _ = flexure.read_mesh(modes / "mode-midedge-2.obj")
    phi = np.frombuffer(base64.b64decode(mesh["modes"][1]["shape"]), "<f4").reshape(-1, 3)
    np.testing.assert_allclose(phi, shape - rest, atol=1e-6)
    assert abs(np.linalg.norm(phi, axis=1).max() - 0.1) < 1e-6
    # Mode 1 (1,1) has no nodal line inside the held boundary; mode 2 one across the plate.
    assert mesh["modes"][0]["lineT"] == "" and len(mesh["modes"][1]["lineT"]) > 0
    with pytest.raises(ValueError, match="modes"):
        flexure.view(modes, style="curvature")
    (modes / "rest.obj").unlink()
    with pytest.raises(ValueError, match="rest.obj"):
        flexure.view(modes)


def test_fairing_report_same_page_as_the_cli(cli, tmp_path):
    cli("-q", "mesh", "--family", "patch48", "--n", "8", "--height", "quadratic:1,0,1", "-o",
        tmp_path / "bowl.obj")
    cli("-q", "fair", tmp_path / "bowl.obj", "--region", "rings:40,1", "-o", tmp_path / "f.obj",
        "--cgal-output", tmp_path / "c.obj", "--report", tmp_path / "fair.json")
    cli("-q", "view", tmp_path / "fair.json", "-o", tmp_path / "fair.html")
    python = flexure.view(tmp_path / "fair.json").html
    strip = lambda p: re.sub(r"<title>.*?</title>", "", p)
    assert strip(python) == strip((tmp_path / "fair.html").read_text())
    meshes = page_data(python)["meshes"]
    assert [m["name"].split(":")[0] for m in meshes] == ["input", "CGAL fair", "flexure midedge"]
    # The outline: the boundary edges of the region's faces, the same on each mesh, each end a
    # vertex (t = 0), none in the region.
    ends = [np.frombuffer(base64.b64decode(m["outline"]["lineEnds"]), "<u4") for m in meshes]
    assert len(ends[0]) > 0 and all(np.array_equal(e, ends[0]) for e in ends)
    t = np.frombuffer(base64.b64decode(meshes[0]["outline"]["lineT"]), "<f4")
    assert np.all(t == 0) and np.array_equal(ends[0][0::2], ends[0][1::2])
    report = json.loads((tmp_path / "fair.json").read_text())
    region = set(report["region"]["indices"])
    assert len(region) == report["region"]["vertices"] and not region & set(ends[0].tolist())


def test_simulation_obstacles(cli, plate, tmp_path):
    V, F = plate
    folder = tmp_path / "sim"
    folder.mkdir()
    for k in range(2):
        flexure.write_mesh(folder / ("frame-%05d.obj" % k), V + [0, 0, -0.1 * k], F)
    (folder / "report.json").write_text(json.dumps(
        {"frame_times": [0, 0.1], "obstacles": ["sphere:0,0,-1,0.5", "plane:0,0,2,-3"]}))
    cli("-q", "view", folder, "-o", tmp_path / "sim.html")
    python = flexure.view(folder).html
    strip = lambda p: re.sub(r"<title>.*?</title>", "", p)
    assert strip(python) == strip((tmp_path / "sim.html").read_text())
    (mesh,) = page_data(python)["meshes"]
    # The plane 2z = −3 as its unit normal and offset: z = −1.5.
    assert mesh["spheres"] == [[0, 0, -1, 0.5]] and mesh["planes"] == [[0, 0, 1, -1.5]]
    (folder / "report.json").write_text(json.dumps({"obstacles": ["cone:1,2,3"]}))
    with pytest.raises(ValueError, match="report.json"):
        flexure.view(folder)


def test_fractured_simulation_same_page_as_the_cli(cli, tmp_path, monkeypatch):
    """A run that fractured (examples/tear-strip.json): the faces change at the cut's frame, the
    frames are padded to the cut mesh's vertex count, and each frame has its crack lips."""
    monkeypatch.chdir(tmp_path)
    cli("-q", "run", pathlib.Path(__file__).parents[2] / "examples" / "tear-strip.json")
    cli("-q", "view", "tear", "-o", "tear.html")
    python = flexure.view("tear").html
    strip = lambda p: re.sub(r"<title>.*?</title>", "", p)
    assert strip(python) == strip((tmp_path / "tear.html").read_text())
    (mesh,) = page_data(python)["meshes"]
    lips = json.loads((tmp_path / "tear" / "cracks.json").read_text())["lips"]
    cut_frame = next(f for f, frame in enumerate(lips) if frame)
    assert [c["frame"] for c in mesh["faceChanges"]] == [cut_frame]
    last, _ = flexure.read_mesh(tmp_path / "tear" / ("frame-%05d.obj" % (len(lips) - 1)))
    assert mesh["vertexCount"] == len(last)
    assert len(mesh["positions"]) == 3 * len(last) * len(lips)
    assert mesh["cracks"]["starts"] == [0] + list(np.cumsum([len(f) for f in lips]))


def test_plastic_style_same_page_as_the_cli(cli, tmp_path, monkeypatch):
    """A run with a yield value: its plastic.json on the page as the field of every frame."""
    monkeypatch.chdir(tmp_path)
    cli("-q", "mesh", "--family", "patch48", "--n", "8", "-o", "plate8.obj")
    cli("-q", "simulate", "--rest", "plate8.obj", "--energy", "hinge", "--stiffness", "0.05",
        "--membrane", "stvk", "--young", "1000", "--pin", "box:-0.5,-0.4,-1,1,-1,1", "--pin",
        "box:0.4,0.5,-1,1,-1,1@rotate:0,-1,0,0,0,0,1.57", "--yield-curvature", "0.5",
        "--damping", "rayleigh:4,0", "--dt", "0.02", "--duration", "0.6", "--fps", "10",
        "--render-style", "none", "-o", "bent")
    cli("-q", "view", "bent", "--style", "plastic", "-o", "bent.html")
    python = flexure.view("bent", style="plastic").html
    strip = lambda p: re.sub(r"<title>.*?</title>", "", p)
    assert strip(python) == strip((tmp_path / "bent.html").read_text())
    data = page_data(python)
    plastic = json.loads((tmp_path / "bent" / "plastic.json").read_text())
    expected = np.concatenate([np.asarray(f, dtype=np.float32) for f in plastic["faces"]])
    assert data["fieldTitle"] == plastic["measure"] and data["fieldOnFaces"] and expected.max() > 0
    np.testing.assert_array_equal(data["meshes"][0]["fields"], expected)
    # The per-vertex values (the PNG frames') are the largest of each vertex's faces'.
    _, F = flexure.read_mesh(tmp_path / "bent" / "frame-00000.obj")
    for faces, vertices in zip(plastic["faces"], plastic["frames"]):
        largest = np.zeros(len(vertices))
        np.maximum.at(largest, F.ravel(), np.repeat(faces, 3))
        np.testing.assert_array_equal(largest, vertices)
    with pytest.raises(ValueError, match="plastic"):
        flexure.view("plate8.obj", style="plastic")


def test_angle_and_error_styles_same_page_as_the_cli(cli, plate, tmp_path, monkeypatch):
    """Each face's smallest angle (per face) and each vertex's distance to a reference surface,
    given as a file or as arrays: the command's page."""
    monkeypatch.chdir(tmp_path)
    V, F = plate
    flexure.write_mesh("plate.obj", V, F)
    flexure.write_mesh("bent.obj", bent(V, 3), F)
    strip = lambda p: re.sub(r"<title>.*?</title>", "", p)
    cli("-q", "view", "bent.obj", "--style", "angle", "-o", "angle.html")
    python = flexure.view("bent.obj", style="angle").html
    assert strip(python) == strip((tmp_path / "angle.html").read_text())
    data = page_data(python)
    assert data["fieldOnFaces"] and len(data["meshes"][0]["fields"]) == len(F)
    cli("-q", "view", "bent.obj", "--style", "error", "--reference", "plate.obj", "-o", "e.html")
    python = flexure.view("bent.obj", style="error", reference="plate.obj").html
    assert strip(python) == strip((tmp_path / "e.html").read_text())
    arrays = page_data(flexure.view("bent.obj", style="error", reference=(V, F)).html)
    assert arrays["fieldTitle"] == "error: distance to the reference"
    np.testing.assert_array_equal(arrays["meshes"][0]["fields"], page_data(python)["meshes"][0]["fields"])
    with pytest.raises(ValueError, match="reference"):
        flexure.view("bent.obj", style="error")
    with pytest.raises(ValueError, match="reference"):
        flexure.view("bent.obj", style="angle", reference=(V, F))
    with pytest.raises(ValueError, match="reference F"):
        flexure.view("bent.obj", style="error", reference=(V, F + len(V)))


def test_arrays_frames_and_fields(plate):
    V, F = plate
    frames = np.stack([V + [0, 0, 0.1 * k] for k in range(4)])
    view = flexure.view((frames, F), (V, F), style="displacement", names=["moving", "still"],
                        times=[0, 0.5, 1.0, 1.5])
    data = page_data(view.html)
    moving, still = data["meshes"]
    assert moving["name"] == "moving" and moving["frameCount"] == 4 and still["frameCount"] == 1
    assert moving["times"] == [0, 0.5, 1.0, 1.5] and still["times"] == []
    np.testing.assert_allclose(moving["positions"].reshape(4, -1, 3), frames, atol=1e-6)
    np.testing.assert_array_equal(moving["triangles"].reshape(-1, 3), F)
    # |x − first frame|: 0.1 k at every vertex of frame k; the legend spans [0, 0.3].
    np.testing.assert_allclose(moving["fields"].reshape(4, -1), np.repeat(
        0.1 * np.arange(4)[:, None], V.shape[0], axis=1), atol=1e-6)
    assert data["rangeText"] == ["0", "0.3"] and data["style"] == 4
    assert not data["multisample"]
    assert page_data(flexure.view((V, F), multisample=True).html)["multisample"]


def test_repr_html_and_save(plate, tmp_path):
    V, F = plate
    view = flexure.view((V, F))
    shown = view._repr_html_()
    assert shown.startswith("<iframe srcdoc=") and "<script>" not in shown
    assert html.unescape(re.search(r'srcdoc="(.*?)"', shown, re.S).group(1)) == view.html
    view.save(tmp_path / "v.html")
    assert (tmp_path / "v.html").read_text() == view.html
    assert [p.name for p in tmp_path.iterdir()] == ["v.html"]  # no temporary left


@pytest.mark.parametrize("args, kwargs, words", [
    ((), {}, "meshes"),
    (("plate",), {"style": "wavy"}, "style"),
    (("plate",), {"stripe_width": 1.5}, "stripe_width"),
    (("plate",), {"stripes": 0}, "stripes"),
    (("plate",), {"rest": np.zeros((3, 3))}, "rest"),
    (("plate",), {"style": "displacement", "rest": np.zeros((3, 3))}, "rest"),
    (("plate",), {"names": ["a", "b"]}, "names"),
])
def test_refusals_name_the_keyword(plate, args, kwargs, words):
    meshes = [plate if a == "plate" else a for a in args]
    with pytest.raises(ValueError, match=words):
        flexure.view(*meshes, **kwargs)


def test_repr_html_draws_inside_a_host_page(plate, tmp_path):
    """The iframe of _repr_html_, in a page as a notebook holds it, loaded in headless Chromium:
    the mesh is drawn in the displacement map's colours, with no console error or request."""
    import pathlib
    import sys
    import time
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "tests" / "viewer"))
    from cdp import Browser
    V, F = plate
    frames = np.stack([V + [0, 0, 0.1 * k] for k in range(3)])
    host = tmp_path / "host.html"
    host.write_text("<!DOCTYPE html><html><body><p>cell</p>" +
                    flexure.view((frames, F), style="displacement")._repr_html_() +
                    "</body></html>")
    browser = Browser(width=800, height=600)
    try:
        browser.load(host.as_uri())
        deadline = time.time() + 60
        while True:
            browser.screenshot(tmp_path / "host.png")
            image = flexure.read_png(tmp_path / "host.png").astype(int)
            # viridis' first stop (0.267, 0.005, 0.329): frame 0 is at rest, |x − rest| = 0.
            violet = np.all(np.abs(image - [68, 1, 84]) <= 12, axis=2).sum()
            if violet > 0.05 * image.shape[0] * image.shape[1] or time.time() > deadline:
                break
            time.sleep(0.2)
        assert violet > 0.05 * image.shape[0] * image.shape[1]
        assert browser.console_errors() == []
        assert browser.requests() == [host.as_uri()]
    finally:
        browser.close()
