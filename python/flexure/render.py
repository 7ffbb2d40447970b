"""flexure.render: offscreen images of a mesh (OSMesa), as ``flexure render`` draws them."""

import numbers
import struct
import zlib

import numpy as np

from . import _checks
from . import _flexure

_STYLES = ("reflection", "isophote", "highlight", "shaded", "error", "curvature")


def render(V, F, style="reflection", size=1024, azimuth=0.0, elevation=90.0, perspective=False,
           background="#ffffff", flat=False, edges=False, stripes=12, stripe_width=0.5,
           stripe_direction=90.0, light=None, surface=None, error_max=None, curvature_max=None,
           framing_points=None):
    """An image of the mesh (V #V×3 float64, F #F×3 int) as an H×W×3 uint8 array (rows top to
    bottom), the pixels ``flexure render`` writes to its PNG for the same options.

    style: "reflection" | "isophote" | "highlight" | "shaded" | "error" (needs ``surface``,
    e.g. "quadratic:1,0,1"; ``error_max`` the top of the colour map) | "curvature" (cotan mean
    curvature; ``curvature_max`` its range); size: pixels, an int (square) or (width, height),
    each in [32, 8192]; azimuth: degrees about +z, 0 = seen from −y; elevation: degrees above
    the xy plane (90 = from above); perspective: else orthographic; background: "#rrggbb";
    flat: face normals; edges: draw the triangle edges; stripes, stripe_width (dark fraction in
    (0, 1)), stripe_direction (degrees); light: a 3-vector towards the light in camera
    coordinates; framing_points: #P×3 points framed in place of V (one framing for several
    renders). One OSMesa context is made at the first call and reused; call from one thread.
    """
    V = _checks.positions(V, "V")
    F = _checks.faces(F, V.shape[0], "F")
    if style not in _STYLES:
        raise ValueError(f"style: {style!r}, expected one of {', '.join(_STYLES)}")
    a = _flexure.RenderArguments()
    a.style = style
    if isinstance(size, numbers.Integral):
        width = height = size
    else:
        try:
            width, height = size
        except (TypeError, ValueError):
            raise ValueError(f"size: {size!r}, expected an int or (width, height)") from None
    a.width = _checks.number(width, "size", positive=True, integer=True)
    a.height = _checks.number(height, "size", positive=True, integer=True)
    a.azimuth = _checks.number(azimuth, "azimuth")
    a.elevation = _checks.number(elevation, "elevation")
    a.perspective, a.flat, a.edges = bool(perspective), bool(flat), bool(edges)
    a.background = str(background)
    a.stripes = _checks.number(stripes, "stripes", positive=True, integer=True)
    a.stripe_width = _checks.number(stripe_width, "stripe_width", positive=True)
    a.stripe_direction = _checks.number(stripe_direction, "stripe_direction")
    if light is not None:
        a.light = [float(x) for x in _checks.vector(light, 3, "light")]
    if surface is not None:
        a.surface = str(surface)
    if error_max is not None:
        a.error_max = _checks.number(error_max, "error_max", positive=True)
    if curvature_max is not None:
        a.curvature_max = _checks.number(curvature_max, "curvature_max", positive=True)
    if framing_points is not None:
        a.framing_points = _checks.positions(framing_points, "framing_points")
    return _flexure.render(V, F, a)


def png_bytes(image):
    """The PNG file bytes of an H×W×3 uint8 image (the renderer's own encoder)."""
    image = np.asarray(image)
    if image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
        raise ValueError(f"image: shape {image.shape} dtype {image.dtype}, expected H×W×3 uint8")
    return bytes(_flexure.encode_png(np.ascontiguousarray(image)))


def write_png(path, image):
    """Writes an H×W×3 uint8 image to ``path`` as PNG."""
    data = png_bytes(image)
    with open(path, "wb") as f:
        f.write(data)


def read_png(path):
    """An 8-bit RGB or RGBA, non-interlaced PNG (what flexure writes) as H×W×3 uint8."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG file")
    pos, idat = 8, b""
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            w, h, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body[:13])
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    if depth != 8 or colour not in (2, 6) or interlace:
        raise ValueError(f"{path}: only 8-bit RGB/RGBA non-interlaced PNGs are read")
    bpp = 3 if colour == 2 else 4
    stride = w * bpp
    raw = np.frombuffer(zlib.decompress(idat), dtype=np.uint8).reshape(h, stride + 1)
    out = np.zeros((h, stride), dtype=np.int32)
    prev = np.zeros(stride, dtype=np.int32)
    for y in range(h):
        f, line = raw[y, 0], raw[y, 1:].astype(np.int32)
        if f == 0:
            cur = line
        elif f == 2:
            cur = (line + prev) & 255
        else:  # filters with a left neighbour: byte by byte (PNG spec, section 9)
            cur = line.copy()
            for i in range(stride):
                a = cur[i - bpp] if i >= bpp else 0
                b, c = prev[i], (prev[i - bpp] if i >= bpp else 0)
                if f == 1:
                    p = a
                elif f == 3:
                    p = (a + b) // 2
                else:
                    q = a + b - c
                    pa, pb, pc = abs(q - a), abs(q - b), abs(q - c)
                    p = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                cur[i] = (cur[i] + p) & 255
        out[y] = cur
        prev = cur
    return out.reshape(h, w, bpp)[:, :, :3].astype(np.uint8)
