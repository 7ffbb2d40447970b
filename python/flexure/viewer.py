"""flexure.view: the interactive HTML page ``flexure view`` writes (three.js embedded, works
offline), of meshes and frame sequences given as arrays or files; shown inline in a notebook."""

import html
import os
import tempfile

import numpy as np

from . import _checks
from . import _flexure

_STYLES = tuple(_flexure.view_style_names().split(" | "))


class View:
    """A page of ``flexure.view``: ``html`` (str), ``save(path)``, and ``_repr_html_`` (an
    iframe holding the page, so that a notebook shows it inline)."""

    def __init__(self, page, height=480):
        self.html = page
        self.height = height

    def _repr_html_(self):
        return ('<iframe srcdoc="%s" style="width:100%%;height:%dpx;border:0" '
                'sandbox="allow-scripts"></iframe>' % (html.escape(self.html, quote=True),
                                                       self.height))

    def save(self, path):
        """Writes the page to ``path`` (a temporary file renamed over it: never half written)."""
        path = os.fspath(path)
        directory = os.path.dirname(os.path.abspath(path))
        fd, temporary = tempfile.mkstemp(dir=directory, prefix=".flexure-view-")
        try:
            with os.fdopen(fd, "w", encoding="utf-8") as f:
                f.write(self.html)
            os.replace(temporary, path)
        except BaseException:
            if os.path.exists(temporary):
                os.remove(temporary)
            raise


def _item(item, k):
    """(name, F, frames, times, folder or report) of one argument of view."""
    if isinstance(item, (str, os.PathLike)):
        path = os.fspath(item)
        name = os.path.basename(os.path.normpath(path))
        if os.path.isdir(path) or path.lower().endswith(".json"):  # read by the library
            return name, np.zeros((0, 3), dtype=np.int32), [], [], path
        from . import read_mesh
        V, F = read_mesh(path)
        return name, F, [V], [], ""
    try:
        V, F = item
    except (TypeError, ValueError):
        raise ValueError(f"meshes[{k}]: expected (V, F), (frames, F), a mesh file or a "
                         "simulation folder") from None
    V = np.asarray(V, dtype=float)
    frames = list(V) if V.ndim == 3 else [V]
    frames = [_checks.positions(X, f"meshes[{k}] V") for X in frames]
    F = _checks.faces(F, frames[0].shape[0], f"meshes[{k}] F")
    return f"mesh {k + 1}", F, frames, [], ""


def view(*meshes, style="reflection", rest=None, reference=None, stripes=12, stripe_width=0.5,
         overlay=False, multisample=False, names=None, times=None, height=480):
    """An interactive page of ``meshes``, as ``flexure view`` writes it: a ``View`` (``.html``,
    ``.save(path)``, shown inline in a notebook).

    Each of ``meshes``: (V, F) with V #V×3; (frames, F) with frames #T×#V×3 (a time slider);
    a mesh file; a ``flexure simulate`` folder; or a ``flexure modes`` folder written with
    ``--write-shapes`` (a view per energy: its modes animated about the rest, a mode selector, an
    amplitude slider, the nodal lines drawn); or a ``flexure fair --report`` JSON file (the input,
    CGAL's fair when written with ``--cgal-output``, and the result side by side, the region
    outlined). Each mesh has its own view with one linked
    camera, or all one view with ``overlay``. style: "reflection" | "isophote" | "shaded" |
    "curvature" (mean curvature H, the default curvature energy) | "displacement" (|x − rest|,
    ``rest`` #V×3, else each mesh's first frame) | "plastic" (a ``flexure simulate`` folder's
    plastic strain per face, from its ``plastic.json``) | "angle" (each face's smallest angle, per face,
    0°–60°) | "error" (each vertex's distance to the surface ``reference``: (V, F) or a mesh
    file, any mesh); stripes, stripe_width as in ``flexure render``; multisample: draw 4×
    multisampled (smoother silhouettes, slower on software rendering);
    names: a label per mesh; times: the frames' times (of every mesh with frames); height: the
    notebook iframe's pixels.
    """
    if style not in _STYLES:
        raise ValueError(f"style: {style!r}, expected one of {', '.join(_STYLES)}")
    if not meshes:
        raise ValueError("meshes: give at least one mesh")
    items = [_item(m, k) for k, m in enumerate(meshes)]
    if names is not None:
        names = [str(n) for n in names]
        if len(names) != len(items):
            raise ValueError(f"names: {len(names)} names for {len(items)} meshes")
        items = [(n,) + it[1:] for n, it in zip(names, items)]
    if times is not None:
        times = [_checks.number(t, "times") for t in times]
        items = [it[:3] + (times if len(it[2]) > 1 or os.path.isdir(it[4]) else [],) + it[4:]
                 for it in items]
    a = _flexure.ViewerArguments()
    a.style = style
    a.stripes = _checks.number(stripes, "stripes", positive=True, integer=True)
    a.stripe_width = _checks.number(stripe_width, "stripe_width", positive=True)
    a.overlay = bool(overlay)
    a.multisample = bool(multisample)
    if rest is not None:
        if style != "displacement":
            raise ValueError("rest: applies to style='displacement' only")
        a.rest = _checks.positions(rest, "rest")
    if (reference is None) != (style != "error"):
        raise ValueError("reference: needed by style='error', and only by it")
    if reference is not None:
        name = "the reference"
        if isinstance(reference, (str, os.PathLike)):
            from . import read_mesh
            name = os.path.basename(os.fspath(reference))
            reference = read_mesh(os.fspath(reference))
        try:
            V, F = reference
        except (TypeError, ValueError):
            raise ValueError("reference: expected (V, F) or a mesh file") from None
        V = _checks.positions(V, "reference V")
        a.reference = (V, _checks.faces(F, V.shape[0], "reference F"))
        a.reference_name = name
    page = bytes(_flexure.viewer_page(items, a)).decode("utf-8")
    return View(page, height=int(height))
