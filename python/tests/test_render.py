"""flexure.render against `flexure render`'s PNG pixels; PNG round trip; errors."""

import numpy as np
import pytest

import flexure
from conftest import bent


@pytest.mark.parametrize("style, options, cli_options", [
    ("reflection", {"azimuth": 25.0, "elevation": 30.0},
     ["--azimuth", "25", "--elevation", "30"]),
    ("shaded", {"edges": True, "background": "#203040"}, ["--edges", "--background", "#203040"]),
    ("curvature", {}, []),
    ("error", {"surface": "quadratic:0.3,-0.1,0.1"}, ["--surface", "quadratic:0.3,-0.1,0.1"]),
])
def test_pixels_equal_the_cli_png(cli, plate, tmp_path, style, options, cli_options):
    V, F = plate
    W = bent(V, 5)
    flexure.write_mesh(tmp_path / "m.obj", W, F)
    cli("-q", "render", tmp_path / "m.obj", "-o", tmp_path / "m.png", "--style", style,
        "--width", "260", "--height", "120", *cli_options)
    expected = flexure.read_png(tmp_path / "m.png")
    image = flexure.render(W, F, style=style, size=(260, 120), **options)
    assert image.shape == (120, 260, 3) and image.dtype == np.uint8
    np.testing.assert_array_equal(image, expected)
    assert len(np.unique(image.reshape(-1, 3), axis=0)) > 10  # not a blank image


def test_context_is_reused_and_renders_repeat(plate):
    V, F = plate
    first = flexure.render(bent(V, 1), F, size=64)
    flexure.render(bent(V, 2), F, size=96, style="isophote")
    np.testing.assert_array_equal(flexure.render(bent(V, 1), F, size=64), first)


def test_png_round_trip(plate, tmp_path):
    V, F = plate
    image = flexure.render(bent(V, 1), F, size=(70, 50))
    flexure.write_png(tmp_path / "x.png", image)
    np.testing.assert_array_equal(flexure.read_png(tmp_path / "x.png"), image)


@pytest.mark.parametrize("arguments, name", [
    ({"style": "cartoon"}, "style"),
    ({"size": 0}, "size"),
    ({"size": (10, 20, 30)}, "size"),
    ({"size": 8}, "^size x size = 8 x 8 is outside"),
    ({"style": "error"}, "surface"),
    ({"background": "blue"}, "background"),
    ({"light": [1, 0]}, "light"),
    ({"stripe_width": 1.5}, "^stripe_width"),
])
def test_bad_arguments_name_themselves(plate, arguments, name):
    V, F = plate
    with pytest.raises(ValueError, match=name):
        flexure.render(V, F, **arguments)
