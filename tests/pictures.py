"""Helpers for the picture tests: where data points land in a rendered picture, and whether the
ink there has the colour the data should have been drawn in.

A picture is an (H, W, 3) array of 0-255 integers, rows top-down.  Points are mapped through an
axes' ``transData`` (display units: pixels at the figure's DPI, origin at the bottom left) and
then scaled to the picture's DPI and flipped, so a figure drawn at 100 dpi can locate points in
a PNG it wrote at 110 dpi.  Colours are compared with a tolerance (Agg's anti-aliasing) and
within a few pixels (the line's width, Agg's snapping); spots that other artists may cover are
left out by the callers with :func:`near_segments`, :func:`near_points` and
:func:`in_boxes`.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

import numpy as np
from matplotlib.colors import to_rgba
from PIL import Image


def read_png(path: Path) -> np.ndarray:
    with Image.open(path) as im:
        assert im.format == "PNG"
        return np.asarray(im.convert("RGB"), dtype=np.int64)


def rgb255(colour) -> np.ndarray:
    """A matplotlib colour as 0-255 floats, composited over white if it is translucent."""
    r, g, b, a = to_rgba(colour)
    return 255.0 * (a * np.array([r, g, b]) + (1.0 - a))


class Mapper:
    """Data coordinates of a figure's axes -> (column, row) pixel coordinates of a picture of
    ``shape`` written from that figure (at any DPI: the scale comes from the picture's size)."""

    def __init__(self, fig, shape):
        self.fig = fig
        self.height, self.width = shape[:2]
        w, h = fig.bbox.width, fig.bbox.height  # display units at the figure's own DPI
        self.scale = self.height / h
        assert abs(self.width / w - self.scale) < 0.01 * self.scale, (shape, w, h)

    def display(self, xy) -> np.ndarray:
        """Display coordinates (figure's DPI, y up) -> (column, row) pixels of the picture."""
        d = np.asarray(xy, dtype=float).reshape(-1, 2) * self.scale
        return np.c_[d[:, 0], self.height - d[:, 1]]

    def data(self, ax, xy) -> np.ndarray:
        return self.display(ax.transData.transform(np.asarray(xy, dtype=float).reshape(-1, 2)))

    def data3d(self, ax, xyz) -> np.ndarray:
        """For a 3-d axes that has been drawn (its projection ``ax.M`` is the drawn one)."""
        from mpl_toolkits.mplot3d import proj3d

        p = np.asarray(xyz, dtype=float).reshape(-1, 3)
        x, y, _ = proj3d.proj_transform(p[:, 0], p[:, 1], p[:, 2], ax.M)
        return self.data(ax, np.c_[x, y])

    def boxes(self, artists, renderer, pad_px: float = 3.0) -> np.ndarray:
        """(n, 4) column/row boxes (c0, r0, c1, r1) of the artists' window extents, padded.
        A 3-d text projects its position only while it is drawn: its extent is moved to the
        projected position."""
        out = []
        for a in artists:
            ext = [a.get_window_extent(renderer)]
            if hasattr(a, "get_position_3d"):
                ax = a.axes
                from mpl_toolkits.mplot3d import proj3d

                x, y, z = a.get_position_3d()
                px, py, _ = proj3d.proj_transform(np.array([x]), np.array([y]), np.array([z]),
                                                  ax.M)
                shift = (ax.transData.transform([[px[0], py[0]]])
                         - a.get_transform().transform([a.get_position()]))[0]
                ext = [ext[0].translated(*shift)]
            for part in (getattr(a, "arrow_patch", None),  # an annotation's arrow
                         getattr(a, "get_bbox_patch", lambda: None)()):  # a text's box
                if part is not None:
                    ext.append(part.get_window_extent(renderer))
            for e in ext:
                if e.width == 0 and e.height == 0:
                    continue
                (c0, r1), (c1, r0) = self.display([[e.x0, e.y0], [e.x1, e.y1]])
                out.append((c0 - pad_px, r0 - pad_px, c1 + pad_px, r1 + pad_px))
        return np.array(out, dtype=float).reshape(-1, 4)


def axes_box(mapper: Mapper, ax, inset_px: float = 4.0) -> np.ndarray:
    """The axes' box in picture pixels, shrunk by ``inset_px`` (the spines)."""
    b = ax.bbox
    (c0, r1), (c1, r0) = mapper.display([[b.x0, b.y0], [b.x1, b.y1]])
    return np.array([c0 + inset_px, r0 + inset_px, c1 - inset_px, r1 - inset_px])


def in_boxes(spots: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    if not len(boxes) or not len(spots):
        return np.zeros(len(spots), dtype=bool)
    c, r = spots[:, 0:1], spots[:, 1:2]
    inside = (c >= boxes[:, 0]) & (c <= boxes[:, 2]) & (r >= boxes[:, 1]) & (r <= boxes[:, 3])
    return inside.any(axis=1)


def inside_box(spots: np.ndarray, box: np.ndarray) -> np.ndarray:
    return in_boxes(spots, box.reshape(1, 4))


def segments_of(polyline: np.ndarray) -> np.ndarray:
    """(k, 2) pixel points -> (k - 1, 2, 2) segments."""
    p = np.asarray(polyline, dtype=float)
    return np.stack([p[:-1], p[1:]], axis=1) if len(p) > 1 else np.zeros((0, 2, 2))


def near_segments(spots: np.ndarray, segments: np.ndarray, within_px: float) -> np.ndarray:
    """Whether each spot lies within ``within_px`` of any of the segments."""
    if not len(segments) or not len(spots):
        return np.zeros(len(spots), dtype=bool)
    a, b = segments[:, 0], segments[:, 1]  # (m, 2)
    ab = b - a
    L2 = np.maximum((ab**2).sum(axis=1), 1e-12)
    ap = spots[:, None, :] - a[None, :, :]  # (n, m, 2)
    s = np.clip((ap * ab[None]).sum(axis=2) / L2[None], 0.0, 1.0)
    d = np.hypot(*np.moveaxis(ap - s[..., None] * ab[None], 2, 0))
    return (d <= within_px).any(axis=1)


def near_points(spots: np.ndarray, points: np.ndarray, within_px: float) -> np.ndarray:
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    if not len(points) or not len(spots):
        return np.zeros(len(spots), dtype=bool)
    d = np.hypot(*np.moveaxis(spots[:, None, :] - points[None, :, :], 2, 0))
    return (d <= within_px).any(axis=1)


def spots_along(p0, p1, step_px: float = 3.0, end_px: float = 6.0) -> np.ndarray:
    """Points every ``step_px`` along the pixel segment p0-p1, none within ``end_px`` of its
    ends (the markers and joints there)."""
    p0, p1 = np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)
    length = float(np.hypot(*(p1 - p0)))
    if length <= 2 * end_px:
        return np.zeros((0, 2))
    s = np.arange(end_px, length - end_px + 1e-9, step_px) / length
    return p0 + s[:, None] * (p1 - p0)


def _windows(img: np.ndarray, spots: np.ndarray, radius: int) -> np.ndarray:
    """(n, (2r+1)**2, 3) pixels around each spot (spots are column/row floats)."""
    c = np.floor(spots[:, 0]).astype(int)
    r = np.floor(spots[:, 1]).astype(int)
    d = np.arange(-radius, radius + 1)
    dr, dc = np.meshgrid(d, d, indexing="ij")
    rr = np.clip(r[:, None] + dr.ravel()[None], 0, img.shape[0] - 1)
    cc = np.clip(c[:, None] + dc.ravel()[None], 0, img.shape[1] - 1)
    return img[rr, cc]


def colour_near(img, spots, colour, radius: int = 2, tol: float = 6.0,
                least: int = 1) -> np.ndarray:
    """Whether at least ``least`` pixels within ``radius`` of each spot have ``colour``
    (every channel within ``tol`` of 0-255).  One is the inside of a line or marker at least
    two pixels wide; most of the (2 radius + 1)**2 a filled marker, which a line crossing the
    window cannot give (a 1.6 pt line at 110 dpi wholly covers at most 10 of 25)."""
    if not len(spots):
        return np.zeros(0, dtype=bool)
    w = _windows(img, np.asarray(spots, dtype=float), radius)
    return (np.abs(w - rgb255(colour)).max(axis=2) <= tol).sum(axis=1) >= least


def ink_near(img, spots, colour, radius: int = 2, min_alpha: float = 0.6,
             tol: float = 25.0) -> np.ndarray:
    """Whether a pixel within ``radius`` of each spot is ``colour`` laid over white with a
    coverage of at least ``min_alpha`` (a thin anti-aliased line covers no pixel wholly)."""
    if not len(spots):
        return np.zeros(0, dtype=bool)
    w = _windows(img, np.asarray(spots, dtype=float), radius).astype(float)
    e, white = rgb255(colour), np.full(3, 255.0)
    u = white - e
    a = ((white - w) @ u) / (u @ u)  # the coverage that best explains each pixel
    resid = np.linalg.norm(w - (white - a[..., None] * u), axis=2)
    return ((a >= min_alpha) & (resid <= tol)).any(axis=1)


def in_polygons(spots: np.ndarray, polygons: list[np.ndarray], pad_px: float = 3.0) -> np.ndarray:
    """Whether each spot is inside, or within ``pad_px`` of the edge of, any of the pixel
    polygons."""
    from matplotlib.path import Path as MplPath

    out = np.zeros(len(spots), dtype=bool)
    for poly in polygons:
        if len(poly) < 3 or not len(spots):
            continue
        out |= MplPath(poly).contains_points(spots)
        out |= near_segments(spots, segments_of(np.vstack([poly, poly[:1]])), pad_px)
    return out


@contextlib.contextmanager
def saved_figures():
    """Within the block, every ``Figure.savefig`` still writes its file and also records the
    figure: yields {file name: Figure}.  For pictures a module draws and writes in one go, so
    that a test can map data into the very file written and compare the figure's artists
    with the data."""
    import pytest
    from matplotlib.figure import Figure

    saved: dict = {}
    original = Figure.savefig

    def spy(self, fname, *args, **kwargs):
        saved[Path(fname).name] = self
        return original(self, fname, *args, **kwargs)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(Figure, "savefig", spy)
        yield saved
