"""Photographs of a drum cross-section: solids segmentation and per-flight areas (Ajayi (2011) ch. 4).

Ajayi (2011) section 4.3 photographed the end of his pilot drum through a Perspex plate
(black background, spotlights), enhanced the images in ImageJ (brightness/contrast,
sigma filter, threshold 168 upper / 177 lower half for flight-borne solids, 104 / 120 for
airborne solids; Table 4.7, l.1228) and counted the non-zero pixels of channel 1 inside
hand-placed rectangles and circles (Appendix C), with the scale from the 75 cm drum
diameter (950 px radius, 25.33 px/cm).

This module does the same with scikit-image, but places the regions from the flight
geometry instead of hard-coded pixel rectangles:

* [`ImageCalibration`][rotarydryer.lab.images.ImageCalibration] - drum centre (px), pixel scale (px/m) from a known length,
  and the viewing side (``mirror=True`` when the drum turns clockwise in the picture,
  as Ajayi's did; the geometry's convention is anticlockwise).
* [`region_labels`][rotarydryer.lab.images.region_labels] - a label image from the flight geometry: pixel -> the pocket of
  flight k (between flight k, flight k+1, the wall and the tip-tip chord, Lee (2008)
  Eq. 4.8), the airborne region inside the tip polygon (Ajayi's "AP", inside the
  flight-tip circle), or outside the drum. Each solids pixel is assigned to the flight
  whose pocket contains it.
* [`segment`][rotarydryer.lab.images.segment] - threshold one channel (Ajayi used channel 1, red) with a fixed
  threshold (Ajayi's 168/177, upper/lower half) or Otsu's; separate thresholds for
  flight-borne and airborne solids; optional Gaussian smoothing (a stand-in for
  ImageJ's sigma filter) and removal of specks smaller than ``min_size`` pixels.
* [`measure`][rotarydryer.lab.images.measure] - areas (m^2, per m of drum length: a cross-section area) per flight,
  first unloading flight (FUF), upper and lower half (UHD, LHD; split by the horizontal
  through the centre, Ajayi's Fig. 4.3), total passive TP = UHD + LHD, and airborne.
* [`annotate`][rotarydryer.lab.images.annotate] - a PNG with the segmentation and the per-flight areas drawn over
  the photograph, for the user to check.
* [`render_cross_section`][rotarydryer.lab.images.render_cross_section] - a synthetic photograph from the exact geometry (held
  polygons of every flight, Lee (2008) Eq. 4.14-4.17, plus vertical curtains from the
  discharging tips) with the true visible areas computed exactly with shapely: the
  test bed for the measurement.

Areas are in m^2 (multiply by 1e4 for Ajayi's cm^2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .._validation import check_choice, check_finite, check_positive, check_range
from ..geometry import FlightedDrum

__all__ = [
    "AJAYI_THRESHOLDS",
    "ImageCalibration",
    "SyntheticImage",
    "ImageMeasurement",
    "render_cross_section",
    "region_labels",
    "segment",
    "measure",
    "first_unloading_flight",
    "annotate",
    "load_image",
    "load_image_bytes",
    "check_drum_in_image",
    "MAX_IMAGE_PIXELS",
]

AJAYI_THRESHOLDS = {"flight_borne": (168, 177), "airborne": (104, 120)}
"""Ajayi (2011) Table 4.7 and l.1228: (upper half, lower half) grey-level thresholds."""

_OUTSIDE = -1
_AIRBORNE = 0


@dataclass(frozen=True)
class ImageCalibration:
    """Where the drum is in the image.

    ``centre`` = (column, row) of the drum axis, px; ``px_per_m`` the scale, px/m;
    ``mirror`` = True when the drum turns clockwise as photographed (the geometry
    turns anticlockwise); ``angle_offset`` (deg) rotates the geometry's angles if the
    camera is not level.
    """

    centre: tuple
    px_per_m: float
    mirror: bool = False
    angle_offset: float = 0.0

    def __post_init__(self):
        c = check_finite("centre", self.centre).ravel()
        if c.size != 2:
            raise ValueError(f"centre must be (column, row) in pixels, got {self.centre!r}")
        object.__setattr__(self, "centre", (float(c[0]), float(c[1])))
        object.__setattr__(self, "px_per_m", float(check_positive("px_per_m", self.px_per_m, "px/m")))
        object.__setattr__(self, "angle_offset", float(check_finite("angle_offset", self.angle_offset)))

    @classmethod
    def from_known_length(cls, centre, length_px: float, length_m: float, **kw) -> ImageCalibration:
        """Scale from a known length: ``length_px`` pixels measure ``length_m`` metres
        (Ajayi: the 0.75 m drum diameter = 1900 px)."""
        lp = float(check_positive("length_px", length_px, "px"))
        lm = float(check_positive("length_m", length_m, "m"))
        return cls(centre, lp / lm, **kw)

    def to_pixels(self, xy) -> np.ndarray:
        """Geometry coordinates (m, centre origin, y up) -> (column, row) pixel coordinates."""
        xy = np.asarray(xy, dtype=float)
        a = math.radians(self.angle_offset)
        x = xy[..., 0] * math.cos(a) - xy[..., 1] * math.sin(a)
        y = xy[..., 0] * math.sin(a) + xy[..., 1] * math.cos(a)
        if self.mirror:
            x = -x
        return np.stack([self.centre[0] + x * self.px_per_m, self.centre[1] - y * self.px_per_m], axis=-1)

    def to_metres(self, colrow) -> np.ndarray:
        """Inverse of [`to_pixels`][rotarydryer.lab.images.ImageCalibration.to_pixels]."""
        cr = np.asarray(colrow, dtype=float)
        x = (cr[..., 0] - self.centre[0]) / self.px_per_m
        y = -(cr[..., 1] - self.centre[1]) / self.px_per_m
        if self.mirror:
            x = -x
        a = -math.radians(self.angle_offset)
        return np.stack([x * math.cos(a) - y * math.sin(a), x * math.sin(a) + y * math.cos(a)], axis=-1)



def _require_lab(module, package):
    """Image analysis needs the ``lab`` extra (scikit-image, shapely)."""
    from .._extras import require

    require(module, "lab", "flight-loading image analysis (lab image)", package)

def _root_angles(drum: FlightedDrum, reference_angle: float) -> np.ndarray:
    ref = float(check_finite("reference_angle", reference_angle))
    return np.mod(ref + drum.flight_spacing * np.arange(drum.n_flights), 360.0)


def _fill(mask_shape, poly_px, value, out):
    """Set ``out`` to ``value`` at the pixels whose centres lie inside the polygon (px coords)."""
    from matplotlib.path import Path as MplPath

    poly_px = np.asarray(poly_px, dtype=float)
    if len(poly_px) < 3:
        return
    h, w = int(mask_shape[0]), int(mask_shape[1])
    c0 = max(int(math.floor(poly_px[:, 0].min())), 0)
    c1 = min(int(math.ceil(poly_px[:, 0].max())), w - 1)
    r0 = max(int(math.floor(poly_px[:, 1].min())), 0)
    r1 = min(int(math.ceil(poly_px[:, 1].max())), h - 1)
    if c1 < c0 or r1 < r0:
        return
    rr, cc = np.mgrid[r0: r1 + 1, c0: c1 + 1]
    inside = MplPath(poly_px).contains_points(np.column_stack([cc.ravel(), rr.ravel()])).reshape(rr.shape)
    out[r0: r1 + 1, c0: c1 + 1][inside] = value


def region_labels(drum: FlightedDrum, calibration: ImageCalibration, shape, reference_angle: float,
                  n_arc: int = 128) -> np.ndarray:
    """Label image (int32, ``shape[:2]``): ``k + 1`` in the pocket of flight k (root at
    ``reference_angle + k * 360/N_F`` deg), 0 in the airborne region inside the drum,
    -1 outside the drum. Pixels are tested at their centres."""
    if not isinstance(drum, FlightedDrum):
        raise ValueError(f"drum must be a FlightedDrum, got {type(drum).__name__}")
    h, w = int(shape[0]), int(shape[1])
    lab = np.full((h, w), _OUTSIDE, dtype=np.int32)
    rows, cols = np.ogrid[0:h, 0:w]
    r2 = (cols - calibration.centre[0]) ** 2 + (rows - calibration.centre[1]) ** 2
    lab[r2 < (drum.radius * calibration.px_per_m) ** 2] = _AIRBORNE
    del r2
    for k, psi in enumerate(_root_angles(drum, reference_angle)):
        _fill((h, w), calibration.to_pixels(drum.pocket_polygon(psi, n_arc)), k + 1, lab)
    return lab


# ---------------------------------------------------------------------------- synthetic images
@dataclass(frozen=True)
class SyntheticImage:
    """A rendered cross-section: ``image`` (uint8, rows x columns x 3), its ``calibration``,
    the ``reference_angle`` (deg) and the exact visible areas (m^2): ``flight_areas``
    (per flight, in flight order), ``airborne_area``; ``model_areas`` are the geometric
    holdups ([`FlightedDrum.holdup_area`][rotarydryer.geometry.drum.FlightedDrum.holdup_area]) of the same flights."""

    image: np.ndarray = field(repr=False)
    calibration: ImageCalibration
    reference_angle: float
    flight_areas: np.ndarray
    model_areas: np.ndarray
    airborne_area: float
    root_angles: np.ndarray


def render_cross_section(drum: FlightedDrum, repose_angle: float, *, reference_angle: float = 90.0,
                         px_per_m: float = 1000.0, margin: int = 10, flight_thickness: float = 0.0,
                         curtain_width: float = 0.006, curtains: bool = True, mirror: bool = False,
                         levels: Optional[dict] = None, noise_sd: float = 0.0, blur_sigma: float = 0.0,
                         seed=None, n_arc: int = 128) -> SyntheticImage:
    """Render a synthetic photograph of a drum cross-section from the flight geometry.

    Parameters
    ----------
    drum : FlightedDrum
    repose_angle : float
        Dynamic angle of repose, deg (the surface of every flight's held solids).
    reference_angle : float
        Root angle (deg, geometry convention) of flight 0; the others follow at 360/N_F.
    px_per_m : float
        Scale, px/m (Ajayi's photographs: 2533 px/m).
    flight_thickness : float
        Drawn flight plate thickness, m (Ajayi's flights: 0.002 m); the plate hides the
        solids under it and the true areas account for that.
    curtain_width : float
        Width of the vertical curtain falling from each discharging tip, m (Ajayi's CFD
        discharge width 0.006 m, Table 4.12); clipped to the airborne region.
    levels : dict, optional
        Grey levels: ``background`` 15, ``wall`` 70, ``flight`` 50, ``solids`` 230,
        ``curtain`` 165 (bright flight-borne solids, dimmer curtains, as Ajayi's
        thresholds 168/104 imply).
    noise_sd, blur_sigma : float
        Gaussian grey-level noise (levels) and Gaussian blur (px); seeded by ``seed``.
    """
    _require_lab("shapely", "shapely")
    from shapely.geometry import LineString, Polygon, box
    from shapely.ops import unary_union

    if not isinstance(drum, FlightedDrum):
        raise ValueError(f"drum must be a FlightedDrum, got {type(drum).__name__}")
    phi = float(check_range("repose_angle", repose_angle, 0.0, 90.0, unit="deg"))
    s = float(check_positive("px_per_m", px_per_m, "px/m"))
    th = float(check_range("flight_thickness", flight_thickness, 0.0, drum.radius, low_inclusive=True, unit="m"))
    cw = float(check_range("curtain_width", curtain_width, 0.0, drum.radius, low_inclusive=True, unit="m"))
    check_range("noise_sd", noise_sd, 0.0, 255.0, low_inclusive=True)
    check_range("blur_sigma", blur_sigma, 0.0, 100.0, low_inclusive=True, unit="px")
    lv = {"background": 15, "wall": 70, "flight": 50, "solids": 230, "curtain": 165}
    if levels:
        for k, v in levels.items():
            check_choice("levels key", k, lv)
            lv[k] = float(check_range(f"levels[{k!r}]", v, 0.0, 255.0, low_inclusive=True, high_inclusive=True))
    R = drum.radius
    half = int(math.ceil(R * s)) + int(margin) + 3
    size = 2 * half + 1
    cal = ImageCalibration((half, half), s, mirror=mirror)
    roots = _root_angles(drum, reference_angle)
    img = np.full((size, size), lv["background"], dtype=float)
    # drum wall ring (outside the shell radius, 1.5 % of R thick) and the inside
    yy, xx = np.mgrid[0:size, 0:size]
    rr = np.hypot(xx - half, yy - half) / s
    img[(rr >= R) & (rr < R * 1.04)] = lv["wall"]
    # geometry as shapely objects (m)
    held = [drum.held_polygon(p, phi, n_arc) for p in roots]
    held_sh = [Polygon(h).buffer(0) if len(h) >= 3 else Polygon() for h in held]
    outlines = [drum.flight_outline(p) for p in roots]
    plates = unary_union([LineString(o).buffer(th / 2.0, cap_style=2, join_style=2) for o in outlines]) if th > 0 else Polygon()
    tips = np.array([o[-1] for o in outlines])
    inner = Polygon(tips)  # airborne region: inside the tip-tip chord polygon
    curt = []
    if curtains and cw > 0:
        slopes = drum.holdup_slope(roots, phi)
        for k, p in enumerate(roots):
            tip = tips[k]
            discharging = slopes[k] < 0 and held_sh[k].area > 0
            # solids fall into the curtain once the tip has passed the horizontal (Lee l.4789)
            tip_angle = (p + drum.tip_angle) % 360.0
            if discharging and 90.0 <= tip_angle <= 270.0 + 1e-9:
                band = box(tip[0] - cw / 2.0, -R, tip[0] + cw / 2.0, tip[1]).intersection(inner)
                if not band.is_empty:
                    curt.append(band)
    curtain_sh = unary_union(curt) if curt else Polygon()
    solids_all = unary_union(held_sh) if held_sh else Polygon()
    curtain_vis = curtain_sh.difference(solids_all).difference(plates)
    areas = np.array([hs.difference(plates).area for hs in held_sh])
    model = np.asarray(drum.holdup_area(roots, phi), dtype=float)

    def fill_geom(geom, value):
        if geom.is_empty:
            return
        polys = [geom] if geom.geom_type == "Polygon" else [g for g in getattr(geom, "geoms", []) if g.geom_type == "Polygon"]
        for pg in polys:
            mask = np.zeros((size, size), dtype=bool)
            _fill((size, size), cal.to_pixels(np.asarray(pg.exterior.coords)), True, mask)
            for hole in pg.interiors:
                hm = np.zeros((size, size), dtype=bool)
                _fill((size, size), cal.to_pixels(np.asarray(hole.coords)), True, hm)
                mask &= ~hm
            img[mask] = value

    fill_geom(curtain_sh, lv["curtain"])
    for hs in held_sh:
        fill_geom(hs, lv["solids"])
    fill_geom(plates, lv["flight"])
    rng = np.random.default_rng(seed)
    if blur_sigma > 0:
        _require_lab("skimage", "scikit-image")
        from skimage.filters import gaussian

        img = gaussian(img, sigma=float(blur_sigma), preserve_range=True)
    if noise_sd > 0:
        img = img + float(noise_sd) * rng.standard_normal(img.shape)
    img8 = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    rgb = np.stack([img8, img8, img8], axis=-1)
    return SyntheticImage(rgb, cal, float(reference_angle), areas, model, float(curtain_vis.area), roots)


# ---------------------------------------------------------------------------- loading and checks
MAX_IMAGE_PIXELS = 40_000_000
"""Largest photograph read, pixels (40 megapixels, e.g. 7300 x 5500; Ajayi's were about 4 MP).
Checked from the file header before the image is decoded; measuring and annotating an image of
this size takes about 2.5 GB of memory and half a minute."""
MAX_IMAGE_FILE_BYTES = 512_000_000
"""Largest image file read, bytes (512 MB)."""
MIN_DRUM_RADIUS_PX = 20.0
"""Smallest drum radius in the image, px: below it the flight pockets are a few pixels wide."""
ANNOTATE_MAX_PIXELS = 12_000_000
"""Largest annotated picture drawn by [`annotate`][rotarydryer.lab.images.annotate], pixels; a larger photograph is drawn at a
reduced resolution (every k-th pixel)."""
DRUM_EDGE_TOLERANCE = 0.05
"""The drum circle may extend beyond the image edge by this fraction of its radius (a photo
cropped at the shell); beyond that the centre or the scale is wrong."""


def _fmt(x) -> str:
    from ..rtd._datafile import fmt

    return fmt(x)


def load_image(path, *, max_pixels: Optional[int] = None) -> np.ndarray:
    """Read an image file (PNG, JPEG, TIFF, ...) as a uint8 array (rows x columns [x channels]).

    The pixel count is read from the file header and checked against ``max_pixels`` (default
    [`MAX_IMAGE_PIXELS`][rotarydryer.lab.images.MAX_IMAGE_PIXELS]) *before* the image is decoded. Only the first frame of a multi-frame
    file is read. 16-bit images are scaled to 8 bits; palette, bilevel and CMYK images are
    converted to grey or RGB. Errors are ``ValueError`` naming the file.
    """
    from ..rtd._datafile import check_input_file

    limit = MAX_IMAGE_PIXELS if max_pixels is None else int(max_pixels)
    p = check_input_file(path, "image file", MAX_IMAGE_FILE_BYTES)
    return _decode_image(p, str(p), limit)


def load_image_bytes(data: bytes, name: str = "<image>", *, max_pixels: Optional[int] = None) -> np.ndarray:
    """[`load_image`][rotarydryer.lab.images.load_image] of the bytes of an image file held in memory (e.g. an upload to the web
    app; nothing is written to disk), with the same checks (pixel count from the header before
    decoding); messages name ``name`` as they name the file."""
    import io

    limit = MAX_IMAGE_PIXELS if max_pixels is None else int(max_pixels)
    data = bytes(data)
    if len(data) > MAX_IMAGE_FILE_BYTES:
        raise ValueError(f"{name}: {len(data) / 1e6:.1f} MB; the limit is {MAX_IMAGE_FILE_BYTES / 1e6:.0f} MB")
    return _decode_image(io.BytesIO(data), name, limit)


def _decode_image(source, name: str, limit: int) -> np.ndarray:
    import warnings

    from PIL import Image, UnidentifiedImageError

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            pil = Image.open(source)  # lazy: reads the header only
    except Image.DecompressionBombError as exc:
        import re

        m = re.search(r"\((\d+) pixels\)", str(exc))
        size = f"{int(m.group(1)) / 1e6:.0f} megapixels" if m else "too many pixels"
        raise ValueError(f"{name}: the image declares {size}; the limit is {limit / 1e6:g} megapixels "
                         "(reduce the resolution)") from None
    except UnidentifiedImageError:
        raise ValueError(f"{name}: not a readable image file (PNG, JPEG, TIFF, BMP...)") from None
    except OSError as exc:
        raise ValueError(f"cannot read image file {name!r}: {exc.strerror or exc}") from None
    with pil:
        w, h = pil.size
        if w <= 0 or h <= 0:
            raise ValueError(f"{name}: the image header declares {w} x {h} pixels")
        if w * h > limit:
            raise ValueError(f"{name}: the image is {w} x {h} pixels ({w * h / 1e6:.1f} megapixels); the limit is "
                             f"{limit / 1e6:g} megapixels (reduce the resolution or crop to the drum)")
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", Image.DecompressionBombWarning)
                pil.seek(0)
                pil.load()
        except MemoryError:
            raise
        except Exception as exc:  # noqa: BLE001 - PIL raises OSError, SyntaxError, ValueError, zlib.error...
            raise ValueError(f"{name}: cannot decode the image ({str(exc) or type(exc).__name__}); the file may be "
                             "truncated or corrupt") from None
        try:
            img = _to_uint8(pil)
        except ValueError as exc:
            raise ValueError(f"{name}: {exc}") from None
    if img.shape[0] != h or img.shape[1] != w:
        raise ValueError(f"{name}: the decoded image is {img.shape[1]} x {img.shape[0]} px, the header says {w} x {h}")
    return img


def _to_uint8(pil) -> np.ndarray:
    """A decoded PIL image as uint8 (rows x columns [x 3 or 4])."""
    mode = pil.mode
    if mode in ("L", "RGB", "RGBA"):
        return np.array(pil, dtype=np.uint8)
    if mode == "1":
        return np.array(pil.convert("L"), dtype=np.uint8)
    if mode in ("LA", "La"):
        return np.array(pil.convert("L"), dtype=np.uint8)
    if mode in ("P", "PA"):
        return np.array(pil.convert("RGBA" if "transparency" in pil.info or mode == "PA" else "RGB"), dtype=np.uint8)
    if mode.startswith("I;16") or mode == "I":
        a = np.array(pil)
        if a.size and (a.min() < 0 or a.max() > 65535):
            raise ValueError(f"32-bit integer pixels ({int(a.min())} .. {int(a.max())}) are not supported")
        return (a.astype(np.uint32) >> 8).astype(np.uint8)  # 16 -> 8 bits, as skimage's img_as_ubyte
    if mode == "F":
        raise ValueError("32-bit floating-point images are not supported; save it as 8- or 16-bit")
    return np.array(pil.convert("RGB"), dtype=np.uint8)


def check_drum_in_image(shape, drum: FlightedDrum, calibration: ImageCalibration, *, image_name: str = "the image",
                        centre_name: str = "centre", scale_name: str = "px_per_m") -> None:
    """Raise ``ValueError`` unless the drum (centre and radius, px) lies in an image of ``shape``.

    The centre must be a pixel of the image; the drum circle must fit within the image up to
    [`DRUM_EDGE_TOLERANCE`][rotarydryer.lab.images.DRUM_EDGE_TOLERANCE] of its radius, and its radius must be at least
    [`MIN_DRUM_RADIUS_PX`][rotarydryer.lab.images.MIN_DRUM_RADIUS_PX]. ``centre_name``/``scale_name`` name what the user set (the
    command-line options) in the messages.
    """
    h, w = int(shape[0]), int(shape[1])
    cx, cy = calibration.centre
    r = float(drum.radius) * calibration.px_per_m
    size = f"{image_name} ({w} x {h} px: columns 0 .. {w - 1}, rows 0 .. {h - 1})"
    if not (0 <= cx <= w - 1 and 0 <= cy <= h - 1):
        raise ValueError(f"{centre_name} = {_fmt(cx)},{_fmt(cy)} px (column,row) is outside {size}")
    how = (f"the drum radius {_fmt(drum.radius)} m x {_fmt(calibration.px_per_m)} px/m = {_fmt(round(r, 1))} px")
    if r < MIN_DRUM_RADIUS_PX:
        raise ValueError(f"{how} is below {_fmt(MIN_DRUM_RADIUS_PX)} px, too small to measure; check {scale_name}")
    if 2 * r > (1 + DRUM_EDGE_TOLERANCE) * max(w, h) + 2:
        raise ValueError(f"{how}: the drum ({_fmt(round(2 * r))} px across) is larger than {size}; check {scale_name}")
    tol = DRUM_EDGE_TOLERANCE * r + 1.0
    if cx - r < -tol or cy - r < -tol or cx + r > w - 1 + tol or cy + r > h - 1 + tol:
        raise ValueError(
            f"the drum circle around {centre_name} = {_fmt(cx)},{_fmt(cy)} px with {how} spans columns "
            f"{_fmt(round(cx - r))} .. {_fmt(round(cx + r))} and rows {_fmt(round(cy - r))} .. {_fmt(round(cy + r))}, "
            f"beyond {size}; check {centre_name} and {scale_name}"
        )


# ---------------------------------------------------------------------------- segmentation
def _channel(image, channel: int) -> np.ndarray:
    img = np.asarray(image)
    if img.ndim == 2:
        return img.astype(float)
    if img.ndim != 3:
        raise ValueError(f"image must be 2-D (grey) or 3-D (rows x columns x channels), got {img.ndim}-D")
    check_range("channel", channel, 0, img.shape[2], low_inclusive=True)
    return img[..., int(channel)].astype(float)


def _halves(threshold):
    if isinstance(threshold, str):
        return threshold
    t = np.atleast_1d(check_finite("threshold", threshold)).ravel()
    if t.size == 1:
        return float(t[0]), float(t[0])
    if t.size == 2:
        return float(t[0]), float(t[1])
    raise ValueError(f"threshold must be a number, an (upper, lower) pair or 'otsu', got {threshold!r}")


def segment(image, labels: np.ndarray, calibration: ImageCalibration, *, channel: int = 0,
            threshold=AJAYI_THRESHOLDS["flight_borne"], airborne_threshold=AJAYI_THRESHOLDS["airborne"],
            smooth_sigma: float = 0.0, min_size: int = 4):
    """Boolean masks ``(flight_borne, airborne)`` of the solids in a photograph.

    A pixel in a flight pocket is flight-borne solids if its ``channel`` value exceeds
    ``threshold``; a pixel in the airborne region is airborne solids if it exceeds
    ``airborne_threshold`` (Ajayi (2011) Table 4.7: 168 / 177 and 104 / 120 for the
    upper / lower half of the drum; a number applies to both halves). ``"otsu"``
    uses Otsu's threshold (skimage ``threshold_otsu``) of the pixels of that region
    type: all pocket pixels for flight-borne solids, the airborne-region pixels for
    the curtain. Fixed thresholds suit Ajayi's enhanced images; on blurred edges an
    area is unbiased only for a threshold midway between the solids and background
    levels, which Otsu's method approximates. ``smooth_sigma`` (px): Gaussian
    smoothing first. Connected specks smaller than ``min_size`` pixels are dropped.
    """
    _require_lab("skimage", "scikit-image")
    from skimage.filters import gaussian, threshold_otsu
    g = _channel(image, channel)
    labels = np.asarray(labels)
    if labels.shape != g.shape:
        raise ValueError(f"labels shape {labels.shape} does not match the image {g.shape}")
    check_range("smooth_sigma", smooth_sigma, 0.0, 100.0, low_inclusive=True, unit="px")
    if smooth_sigma > 0:
        g = gaussian(g, sigma=float(smooth_sigma), preserve_range=True)
    for name, val in (("threshold", threshold), ("airborne_threshold", airborne_threshold)):
        if isinstance(val, str):
            check_choice(name, val, ("otsu",))
    if isinstance(threshold, str):
        px = g[labels > 0]
        t = float(threshold_otsu(px)) if px.size and np.ptp(px) > 0 else 0.0
        tf = (t, t)
    else:
        tf = _halves(threshold)
    if isinstance(airborne_threshold, str):
        px = g[labels == _AIRBORNE]
        t = float(threshold_otsu(px)) if px.size and np.ptp(px) > 0 else 0.0
        ta = (t, t)
    else:
        ta = _halves(airborne_threshold)
    upper_rows = np.arange(g.shape[0])[:, None] < calibration.centre[1]  # (rows, 1): no full-size arrays
    thr_f = np.where(upper_rows, tf[0], tf[1])
    thr_a = np.where(upper_rows, ta[0], ta[1])
    fb = (labels > 0) & (g > thr_f)
    ab = (labels == _AIRBORNE) & (g > thr_a)
    if min_size and min_size > 1:
        fb = _drop_specks(fb, int(min_size))
        ab = _drop_specks(ab, int(min_size))
    return fb, ab


def _drop_specks(mask: np.ndarray, min_size: int) -> np.ndarray:
    """Remove connected objects with fewer than ``min_size`` pixels (any scikit-image version)."""
    _require_lab("skimage", "scikit-image")
    from skimage.morphology import remove_small_objects

    try:  # scikit-image >= 0.26: max_size removes objects <= max_size
        return remove_small_objects(mask, max_size=min_size - 1)
    except TypeError:
        return remove_small_objects(mask, min_size=min_size)


@dataclass(frozen=True)
class ImageMeasurement:
    """Areas measured in one photograph, m^2 (cross-section; x1e4 for cm^2).

    ``flight_areas``: per flight (flight k has its root at ``root_angles[k]`` deg);
    ``fuf_index``/``fuf_area``: the first unloading flight; ``upper_half`` (UHD),
    ``lower_half`` (LHD), ``total_passive`` (TP = UHD + LHD), ``airborne`` (AP);
    ``airborne_fraction``: airborne area / area of the airborne region (Ajayi (2011)
    Eq. 4.1, as a fraction). ``labels``, ``flight_borne``, ``airborne_mask``: the pixel maps.
    """

    flight_areas: np.ndarray
    root_angles: np.ndarray
    fuf_index: int
    fuf_area: float
    upper_half: float
    lower_half: float
    total_passive: float
    airborne: float
    airborne_fraction: float
    px_per_m: float
    labels: np.ndarray = field(repr=False)
    flight_borne: np.ndarray = field(repr=False)
    airborne_mask: np.ndarray = field(repr=False)

    def as_dict(self) -> dict:
        """Summary in cm^2 (Ajayi's unit), JSON-friendly."""
        c = 1e4
        return {
            "flight_areas_cm2": [round(float(a) * c, 4) for a in self.flight_areas],
            "root_angles_deg": [round(float(a), 4) for a in self.root_angles],
            "fuf_index": int(self.fuf_index),
            "FUF_cm2": float(self.fuf_area) * c,
            "UHD_cm2": float(self.upper_half) * c,
            "LHD_cm2": float(self.lower_half) * c,
            "TP_cm2": float(self.total_passive) * c,
            "airborne_cm2": float(self.airborne) * c,
            "airborne_percent": 100.0 * float(self.airborne_fraction),
            "px_per_m": float(self.px_per_m),
        }


def first_unloading_flight(drum: FlightedDrum, root_angles, convention: str = "root") -> int:
    """Index of the first unloading flight: the flight whose root (``convention="root"``,
    the geometry package's default) or tip (``"tip"``) is nearest the 90 deg position
    (Ajayi's 9 o'clock; Lee (2008) section 4.4)."""
    check_choice("convention", convention, ("root", "tip"))
    a = np.asarray(root_angles, dtype=float) + (drum.tip_angle if convention == "tip" else 0.0)
    d = np.abs((a - 90.0 + 180.0) % 360.0 - 180.0)
    return int(np.argmin(d))


def measure(image, drum: FlightedDrum, calibration: ImageCalibration, *, reference_angle: float,
            channel: int = 0, threshold=AJAYI_THRESHOLDS["flight_borne"],
            airborne_threshold=AJAYI_THRESHOLDS["airborne"], smooth_sigma: float = 0.0, min_size: int = 4,
            fuf_convention: str = "root") -> ImageMeasurement:
    """Measure the solids areas in a photograph of a drum cross-section (Ajayi (2011) section 4.3).

    ``reference_angle``: root angle (deg, geometry convention: from the drum bottom in
    the direction of rotation) of one flight, called flight 0; read it off the photograph.
    Pixel areas are converted with ``calibration.px_per_m``. See [`segment`][rotarydryer.lab.images.segment] for the
    thresholds and [`region_labels`][rotarydryer.lab.images.region_labels] for the assignment of pixels to flights.
    """
    img = np.asarray(image)
    if img.ndim not in (2, 3):
        raise ValueError(f"image must be 2-D or 3-D, got shape {img.shape}")
    if not isinstance(drum, FlightedDrum):
        raise ValueError(f"drum must be a FlightedDrum, got {type(drum).__name__}")
    check_drum_in_image(img.shape, drum, calibration, centre_name="calibration.centre",
                        scale_name="calibration.px_per_m")
    labels = region_labels(drum, calibration, img.shape[:2], reference_angle)
    fb, ab = segment(img, labels, calibration, channel=channel, threshold=threshold,
                     airborne_threshold=airborne_threshold, smooth_sigma=smooth_sigma, min_size=min_size)
    px_area = 1.0 / calibration.px_per_m**2
    counts = np.bincount(labels[fb].ravel(), minlength=drum.n_flights + 1)[1: drum.n_flights + 1]
    areas = counts * px_area
    rows = np.arange(img.shape[0])[:, None]
    upper = rows < calibration.centre[1]
    uhd = float(np.count_nonzero(fb & upper)) * px_area
    lhd = float(np.count_nonzero(fb & ~upper)) * px_area
    air = float(np.count_nonzero(ab)) * px_area
    region = float(np.count_nonzero(labels == _AIRBORNE)) * px_area
    roots = _root_angles(drum, reference_angle)
    k = first_unloading_flight(drum, roots, fuf_convention)
    return ImageMeasurement(areas, roots, k, float(areas[k]), uhd, lhd, uhd + lhd, air,
                            air / region if region > 0 else 0.0, calibration.px_per_m, labels, fb, ab)


def annotate(image, measurement: ImageMeasurement, path=None, *, dpi: int = 100, title: str = ""):
    """Draw the segmentation and the per-flight areas (cm^2) over the photograph.

    Flight-borne solids are tinted orange (the first unloading flight red), airborne
    solids cyan, pocket boundaries thin white. Returns the Matplotlib figure; saves it
    to ``path`` if given (atomically; the format from the suffix, PNG by default). A photograph
    larger than [`ANNOTATE_MAX_PIXELS`][rotarydryer.lab.images.ANNOTATE_MAX_PIXELS] is drawn at a reduced resolution.
    """
    from .._plotting import pyplot

    plt = pyplot()
    _require_lab("skimage", "scikit-image")
    from skimage.segmentation import find_boundaries

    img = np.asarray(image)
    base = img if img.ndim == 3 else np.stack([img] * 3, axis=-1)
    base = base[..., :3].astype(np.float32) / np.float32(255.0)  # float32: half the memory of a 40 MP photo
    over = base.copy()
    m = measurement
    fuf = m.labels == m.fuf_index + 1
    tint = np.array([1.0, 0.55, 0.0])
    over[m.flight_borne] = 0.45 * over[m.flight_borne] + 0.55 * tint
    over[m.flight_borne & fuf] = 0.45 * base[m.flight_borne & fuf] + 0.55 * np.array([1.0, 0.0, 0.0])
    over[m.airborne_mask] = 0.45 * over[m.airborne_mask] + 0.55 * np.array([0.0, 0.9, 1.0])
    bnd = find_boundaries(m.labels, mode="inner")
    over[bnd] = 0.6 * over[bnd] + 0.4
    del base, fuf, bnd
    over8 = np.clip(np.rint(over * 255.0), 0, 255).astype(np.uint8)  # uint8 RGB: Matplotlib keeps it compact
    del over
    h, w = img.shape[:2]
    # above ANNOTATE_MAX_PIXELS the picture is shown every k-th pixel (rendering a 40 MP image
    # in Matplotlib takes several GB); the areas are those measured at full resolution
    k = max(1, int(math.ceil(math.sqrt(h * w / ANNOTATE_MAX_PIXELS))))
    shown = over8[::k, ::k]
    hs, ws = shown.shape[:2]
    fig, ax = plt.subplots(figsize=(ws / dpi, hs / dpi), dpi=dpi)
    ax.imshow(shown, interpolation="nearest", extent=(-0.5, w - 0.5, h - 0.5, -0.5))
    ax.set_axis_off()
    h = hs  # font sizes follow the drawn size
    from scipy import ndimage

    n = m.flight_areas.size
    counts = np.bincount(np.clip(m.labels, 0, None).ravel(), minlength=n + 1)
    present = [k for k in range(n) if counts[k + 1] > 0]
    centres = ndimage.center_of_mass(m.labels > 0, m.labels, [k + 1 for k in present]) if present else []
    for k, (rc, cc) in zip(present, centres):
        ax.text(cc, rc, f"{m.flight_areas[k] * 1e4:.1f}", color="red" if k == m.fuf_index else "white",
                fontsize=max(6, int(h / 120)), ha="center", va="center")
    d = m.as_dict()
    ax.set_title(title or (f"FUF {d['FUF_cm2']:.2f} cm2  UHD {d['UHD_cm2']:.1f}  LHD {d['LHD_cm2']:.1f}  "
                           f"TP {d['TP_cm2']:.1f}  airborne {d['airborne_cm2']:.1f} cm2"),
                 fontsize=max(7, int(h / 90)))
    fig.tight_layout()
    if path is not None:
        from pathlib import Path

        from .._io import atomic_output

        fmt = Path(path).suffix.lstrip(".").lower() or "png"
        try:
            with atomic_output(path) as tmp:  # a failed or interrupted write leaves no partial file
                fig.savefig(tmp, dpi=dpi, format=fmt)
        except BaseException:
            plt.close(fig)
            raise
    return fig
