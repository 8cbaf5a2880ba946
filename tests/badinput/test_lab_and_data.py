"""Bad-input corpus (issue 13): laboratory data files, tracer data files, photographs, runaways.

Every case runs the real command in an empty working folder and checks the contract: exit code 2,
an ``error:`` line naming the option, file and line, plain numbers (no NumPy repr), no traceback,
and nothing written to (or changed in) the working folder. Limits exercised: 200 000 data rows
per file, 64 MB per data file, 40 megapixels per photograph (read from the header, before
decoding), the drum inside the photograph, the tracer time origin inside the data.
"""

from __future__ import annotations

import os
import struct
import uuid
import zlib
from pathlib import Path

import numpy as np
import pytest

from .conftest import assert_bad, run_cli, snapshot

TRACER_OK = "time_s,signal\n0,0\n10,1\n20,3\n30,1\n40,0.2\n50,0\n"
RIG_HEADER = "time_s,mass_kg\n"


def _rig_text(n=200, dt=0.01):
    """A plausible load-cell record: flat, then a ramp (kg)."""
    t = np.arange(n) * dt
    m = 30.0 + np.clip(t - 0.5, 0.0, None) * 4.0
    return RIG_HEADER + "".join(f"{a:.2f},{b:.4f}\n" for a, b in zip(t, m))


def _png_header(w: int, h: int) -> bytes:
    """A tiny PNG that *declares* w x h pixels (IHDR), with a token IDAT: no big image is made."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(b"\x00" * 16)) + chunk(b"IEND", b""))


@pytest.fixture(scope="module")
def photo_png(tmp_path_factory) -> bytes:
    """A synthetic 327 x 327 px photograph of Ajayi's pilot drum (radius 150 px, centre 163,163)."""
    from skimage import io

    from rotarydryer.geometry.presets import preset_drum
    from rotarydryer.lab import images as im

    d = preset_drum("ajayi_pilot")[0]
    s = im.render_cross_section(d, 46.7, reference_angle=91.0, px_per_m=400.0, mirror=True)
    p = tmp_path_factory.mktemp("photo") / "photo.png"
    io.imsave(p, s.image, check_contrast=False)
    assert s.calibration.centre == (163.0, 163.0)
    return p.read_bytes()


def _write(folder: Path, name: str, content) -> None:
    p = folder / name
    if content is None:
        return
    if content == "DIR":
        p.mkdir()
    elif content == "SPARSE":  # a 65 MB file without writing 65 MB
        with open(p, "wb") as fh:
            fh.truncate(65 * 1024 * 1024)
    elif isinstance(content, bytes):
        p.write_bytes(content)
    else:
        p.write_text(content, encoding="utf-8")


def _check(res, fragments):
    assert_bad(res, *fragments)
    assert "np.float" not in res.output and "array(" not in res.output, res.output


def _run_case(workdir, files: dict, args, fragments):
    for name, content in files.items():
        _write(workdir, name, content)
    before = snapshot(workdir)
    res = run_cli(args, cwd=workdir)
    _check(res, fragments)
    assert snapshot(workdir) == before, "the failing command changed the working folder"
    return res


# --------------------------------------------------------------------------- tracer files (rtd-fit)
BIG_TRACER = "time_s,signal\n" + "".join(f"{i},{1.0 + (i % 7)}\n" for i in range(200_001))

TRACER_CASES = [
    # id, file content, extra args, fragments in the message
    ("no-time-column", "t,signal\n0,0\n10,1\n20,3\n30,1\n40,0\n", [], ["bad.csv line 1", "missing time column"]),
    ("unknown-time-unit", "time_days,signal\n0,0\n1,1\n2,3\n3,1\n4,0\n", [], ["bad.csv", "time_days", "not a known unit"]),
    ("no-signal-column", "time_s,conc\n0,0\n10,1\n20,3\n30,1\n40,0\n", [], ["bad.csv line 1", "'signal'"]),
    ("two-time-columns", "time_s,time_min,signal\n0,0,0\n60,1,1\n120,2,3\n180,3,1\n240,4,0\n", [],
     ["bad.csv line 1", "more than one time column"]),
    ("text-in-signal", "time_s,signal\n0,0\n10,abc\n20,3\n30,1\n40,0\n", [],
     ["bad.csv line 3", "'abc' is not a number in column signal"]),
    ("text-in-time", "time_s,signal\n0,0\n1O,1\n20,3\n30,1\n40,0\n", [],
     ["bad.csv line 3", "'1o' is not a number in column time_s"]),
    ("empty-field", "time_s,signal\n0,0\n10,\n20,3\n30,1\n40,0\n", [], ["bad.csv line 3", "empty field", "signal"]),
    ("empty-file", "", [], ["bad.csv", "no header"]),
    ("header-only", "time_s,signal\n", [], ["bad.csv", "no data rows"]),
    ("comments-only", "# source: nothing\n# signal_unit: ppm\n", [], ["bad.csv", "no header"]),
    ("nan-signal", "time_s,signal\n0,0\n10,nan\n20,3\n30,1\n40,0\n", [], ["bad.csv line 3", "nan", "NaN or infinite"]),
    ("inf-time", "time_s,signal\n0,0\n10,1\ninf,3\n30,1\n40,0\n", [], ["bad.csv line 4", "inf", "NaN or infinite"]),
    ("negative-time", "time_s,signal\n0,0\n-10,1\n20,3\n30,1\n40,0\n", [], ["bad.csv line 3", "-10", "negative"]),
    ("negative-signal", "time_s,signal\n0,0\n10,-0.5\n20,3\n30,1\n40,0\n", [], ["bad.csv line 3", "negative signal -0.5"]),
    ("unsorted-time", "time_s,signal\n0,0\n20,1\n10,3\n30,1\n40,0\n", [], ["bad.csv line 4", "unsorted time 10 after 20"]),
    ("duplicate-time", "time_s,signal\n0,0\n10,1\n10,3\n30,1\n40,0\n", [], ["bad.csv line 4", "duplicate time 10"]),
    ("short-row", "time_s,signal,note\n0,0,a\n10,1\n20,3,c\n30,1,d\n40,0,e\n", [], ["bad.csv line 3", "expected 3 columns"]),
    ("too-few-points", "time_s,signal\n0,0\n10,1\n20,3\n30,1\n", [], ["bad.csv", "too few points (4)"]),
    ("all-zero-signal", "time_s,signal\n0,0\n10,0\n20,0\n30,0\n40,0\n", [], ["bad.csv", "signal is 0"]),
    ("non-utf8", b"# source: caf\xe9\ntime_s,signal\n0,0\n10,1\n20,3\n30,1\n40,0\n", [],
     ["bad.csv line 1", "not UTF-8", "0xe9"]),
    ("binary-garbage", bytes(range(256)) * 8, [], ["bad.csv line 1", "binary"]),
    ("origin-after-data", "# time_origin_s: 500\n" + TRACER_OK, [],
     ["bad.csv line 1", "time_origin_s = 500 s", "after the last sample (50 s"]),
    ("origin-after-signal", "# time_origin_s: 45\n" + TRACER_OK, [],
     ["bad.csv line 1", "time_origin_s = 45 s", "after all the tracer signal"]),
    ("origin-after-mass", "# time_origin_s: 25\n" + TRACER_OK, [], ["bad.csv", "mean residence time", "time_origin_s"]),
    ("origin-not-number", "# time_origin_s: noon\n" + TRACER_OK, [], ["bad.csv line 1", "time_origin_s", "'noon'"]),
    ("origin-nan", "# time_origin_s: nan\n" + TRACER_OK, [], ["bad.csv line 1", "time_origin_s", "not a finite number"]),
    ("bad-pulse-kind", "# pulse_kind: square\n" + TRACER_OK, [], ["bad.csv line 1", "pulse_kind = 'square'"]),
    ("pulse-without-duration", "# pulse_kind: rectangular\n" + TRACER_OK, [], ["bad.csv line 1", "pulse_duration_s"]),
    ("negative-feed-rate", "# feed_rate_kg_s: -3\n" + TRACER_OK, [], ["bad.csv line 1", "feed_rate_kg_s = -3 kg/s"]),
    ("too-many-rows", BIG_TRACER, [], ["bad.csv line 200002", "more than 200000 data rows"]),
    ("too-large-file", "SPARSE", [], ["bad.csv", "68.2 MB", "limit is 64 MB"]),
    ("directory", "DIR", [], ["bad.csv", "is a directory"]),
    ("missing-file", None, [], ["bad.csv", "does not exist"]),
    ("opt-n-starts-0", TRACER_OK, ["--n-starts", "0"], ["--n-starts = 0", "[1, 1000]"]),
    ("opt-pulse-negative", TRACER_OK, ["--pulse-s", "-3"], ["--pulse-s = -3 s", "[0, inf) s"]),
    ("opt-pulse-nan", TRACER_OK, ["--pulse-s", "nan"], ["--pulse-s = nan", "not a finite number"]),
    ("opt-pulse-longer-than-record", TRACER_OK, ["--pulse-s", "600"], ["--pulse-s = 600 s", "bad.csv"]),
    ("opt-baseline-nan", TRACER_OK, ["--baseline", "nan"], ["--baseline = nan", "not a finite number"]),
    ("opt-baseline-word", TRACER_OK, ["--baseline", "median"], ["--baseline = 'median'"]),
    ("opt-model", TRACER_OK, ["--model", "plug_flow"], ["--model = 'plug_flow'", "tanks_in_series"]),
]


@pytest.mark.parametrize("content, extra, fragments", [c[1:] for c in TRACER_CASES], ids=[c[0] for c in TRACER_CASES])
def test_rtd_fit_bad_tracer_input(workdir, content, extra, fragments):
    _run_case(workdir, {"bad.csv": content}, ["rtd-fit", "bad.csv", *extra], fragments)


MOMENTS_CASES = [
    ("origin-option-after-data", ["--time-origin-s", "1e9"], ["--time-origin-s = 1000000000 s", "after the last sample"]),
    ("origin-option-nan", ["--time-origin-s", "nan"], ["--time-origin-s = nan", "not a finite number"]),
    ("origin-option-after-mass", ["--time-origin-s", "25"], ["bad.csv", "mean residence time is"]),
    ("tail-points-1", ["--tail-points", "1"], ["--tail-points = 1", "[2, 10000]"]),
    ("tail-word", ["--tail", "linear"], ["--tail = 'linear'", "exponential"]),
]


@pytest.mark.parametrize("extra, fragments", [c[1:] for c in MOMENTS_CASES], ids=[c[0] for c in MOMENTS_CASES])
def test_rtd_moments_bad_options(workdir, extra, fragments):
    _run_case(workdir, {"bad.csv": TRACER_OK}, ["rtd-moments", "bad.csv", *extra], fragments)


def test_not_a_file_nor_a_dataset(workdir):
    _run_case(workdir, {}, ["rtd-fit", "no_such_dataset"], ["'no_such_dataset'", "lee2008_invicta"])


# --------------------------------------------------------------------------- rig files (lab rig)
RIG_ARGS = ["--rpm", "2", "--start-angle", "93.5", "--bulk-density", "1474"]
BIG_RIG = RIG_HEADER + "".join(f"{i / 100:.2f},30\n" for i in range(200_001))
_r = _rig_text().splitlines(keepends=True)

RIG_CASES = [
    ("text-in-mass", "".join(_r[:4]) + "0.03,abc\n" + "".join(_r[5:]), RIG_ARGS,
     ["rig.csv line 5", "'abc' is not a number in column mass_kg"]),
    ("text-in-time", "".join(_r[:16]) + "x0.15,30\n" + "".join(_r[17:]), RIG_ARGS,
     ["rig.csv line 17", "'x0.15' is not a number in column time_s"]),
    ("nan-mass", "".join(_r[:6]) + "0.05,nan\n" + "".join(_r[7:]), RIG_ARGS, ["rig.csv line 7", "mass_kg", "NaN"]),
    ("ragged-row", "".join(_r[:6]) + "0.05,30,1\n" + "".join(_r[7:]), RIG_ARGS, ["rig.csv line 7", "3 columns, expected 2"]),
    ("header-mismatch", "time_s,cell1,cell2\n0,1\n0.01,1\n", RIG_ARGS, ["rig.csv line 2", "header has 3"]),
    ("time-backwards", "".join(_r[:10]) + "0.05,30\n" + "".join(_r[11:]), RIG_ARGS,
     ["rig.csv line 11", "strictly increasing"]),
    ("time-not-uniform", "".join(_r[:10]) + "0.0875,30\n" + "".join(_r[11:]), RIG_ARGS,
     ["rig.csv line", "uniformly sampled"]),
    ("too-few-samples", RIG_HEADER + "0,1\n0.01,2\n", RIG_ARGS, ["rig.csv", "at least 8 samples, got 2"]),
    ("one-column", "time_s\n0\n0.01\n0.02\n", RIG_ARGS, ["rig.csv line 2", "1 column"]),
    ("empty-file", "", RIG_ARGS, ["rig.csv", "no numeric data rows"]),
    ("header-only", RIG_HEADER, RIG_ARGS, ["rig.csv", "no numeric data rows"]),
    ("two-headers", "a,b\nc,d\n0,1\n", RIG_ARGS, ["rig.csv line 2", "second header"]),
    ("non-utf8", RIG_HEADER.encode() + b"0,1\n0.01,\xff\xfe\n", RIG_ARGS, ["rig.csv line 3", "not UTF-8"]),
    ("binary-garbage", b"\x00\x01\x02" * 500, RIG_ARGS, ["rig.csv line 1", "binary"]),
    ("too-many-rows", BIG_RIG, RIG_ARGS, ["rig.csv line 200002", "more than 200000 data rows"]),
    ("too-large-file", "SPARSE", RIG_ARGS, ["rig.csv", "68.2 MB", "limit is 64 MB"]),
    ("directory", "DIR", RIG_ARGS, ["rig.csv", "is a directory"]),
    ("missing-file", None, RIG_ARGS, ["rig.csv", "does not exist"]),
    ("opt-rpm-negative", _rig_text(), ["--rpm", "-2", "--start-angle", "93.5", "--bulk-density", "1474"],
     ["--rpm = -2 rev/min", "(0, 100] rev/min"]),
    ("opt-rpm-nan", _rig_text(), ["--rpm", "nan", "--start-angle", "93.5", "--bulk-density", "1474"],
     ["--rpm = nan", "not a finite number"]),
    ("opt-bulk-density-zero", _rig_text(), ["--rpm", "2", "--start-angle", "93.5", "--bulk-density", "0"],
     ["--bulk-density = 0 kg/m^3", "(0, 20000]"]),
    ("opt-start-angle-400", _rig_text(), ["--rpm", "2", "--start-angle", "400", "--bulk-density", "1474"],
     ["--start-angle = 400 deg", "[0, 360) deg"]),
    ("opt-start-angle-past-unloading", _rig_text(), ["--rpm", "2", "--start-angle", "300", "--bulk-density", "1474"],
     ["--start-angle = 300 deg", "past the end of unloading"]),
    ("opt-cutoff-above-nyquist", _rig_text(), RIG_ARGS + ["--cutoff", "80"], ["--cutoff = 80 Hz", "rig.csv", "50 Hz"]),
    ("opt-cutoff-negative", _rig_text(), RIG_ARGS + ["--cutoff", "-1"], ["--cutoff = -1 Hz"]),
    ("opt-repose-angle-95", _rig_text(), RIG_ARGS + ["--repose-angle", "95"], ["--repose-angle = 95 deg", "(0, 90) deg"]),
    ("opt-repose-sd-negative", _rig_text(), RIG_ARGS + ["--repose-sd", "-1"], ["--repose-sd = -1 deg"]),
    ("opt-length-inf", _rig_text(), RIG_ARGS + ["--length", "inf"], ["--length = inf m", "not a finite number"]),
    ("opt-flight", _rig_text(), RIG_ARGS + ["--flight", "quarter_scale"], ["--flight = 'quarter_scale'", "alternative"]),
    ("opt-phase", _rig_text(), RIG_ARGS + ["--phase", "acausal"], ["--phase = 'acausal'", "filtfilt"]),
]


@pytest.mark.parametrize("content, args, fragments", [c[1:] for c in RIG_CASES], ids=[c[0] for c in RIG_CASES])
def test_lab_rig_bad_input(workdir, content, args, fragments):
    _run_case(workdir, {"rig.csv": content}, ["lab", "rig", "rig.csv", *args], fragments)


# --------------------------------------------------------------------------- photographs (lab image)
IMG_OK = ["--centre", "163,163", "--px-per-m", "400", "--mirror"]

IMAGE_CASES = [
    # id, photo content ("PHOTO" = the synthetic photograph), args, fragments
    ("not-an-image", "just some text, not a PNG\n", IMG_OK, ["photo.png", "not a readable image"]),
    ("truncated-png", "TRUNCATED", IMG_OK, ["photo.png", "truncated"]),
    ("empty-file", b"", IMG_OK, ["photo.png", "not a readable image"]),
    ("huge-declared-64MP", _png_header(8000, 8000), IMG_OK,
     ["photo.png", "8000 x 8000 pixels", "64.0 megapixels", "limit is 40 megapixels"]),
    ("huge-declared-10000MP", _png_header(100_000, 100_000), IMG_OK,
     ["photo.png", "10000 megapixels", "limit is 40 megapixels"]),
    ("centre-outside", "PHOTO", ["--centre", "500,163", "--px-per-m", "400"],
     ["--centre = 500,163 px", "outside photo.png", "327 x 327 px"]),
    ("centre-negative", "PHOTO", ["--centre", "-20,163", "--px-per-m", "400"], ["--centre = -20,163 px", "outside"]),
    ("drum-larger-than-image", "PHOTO", ["--centre", "163,163", "--px-per-m", "4000"],
     ["1500 px", "larger than photo.png", "--px-per-m"]),
    ("drum-off-the-edge", "PHOTO", ["--centre", "100,163", "--px-per-m", "400"],
     ["--centre = 100,163", "columns -50 .. 250", "beyond photo.png"]),
    ("drum-too-small", "PHOTO", ["--centre", "163,163", "--known-length-px", "7.5", "--known-length-m", "0.75"],
     ["3.8 px", "too small", "--known-length-px/--known-length-m"]),
    ("centre-text", "PHOTO", ["--centre", "middle", "--px-per-m", "400"], ["--centre = 'middle'", "column,row"]),
    ("centre-word", "PHOTO", ["--centre", "a,163", "--px-per-m", "400"], ["--centre", "column 'a' is not a number"]),
    ("centre-nan", "PHOTO", ["--centre", "163,nan", "--px-per-m", "400"], ["--centre row = nan", "not a finite number"]),
    ("px-per-m-negative", "PHOTO", ["--centre", "163,163", "--px-per-m", "-400"], ["--px-per-m = -400 px/m"]),
    ("known-length-m-zero", "PHOTO", ["--centre", "163,163", "--known-length-px", "300", "--known-length-m", "0"],
     ["--known-length-m = 0 m"]),
    ("no-scale", "PHOTO", ["--centre", "163,163"], ["--px-per-m", "--known-length-px"]),
    ("threshold-300", "PHOTO", IMG_OK + ["--threshold", "300"], ["--threshold = 300", "[0, 255]"]),
    ("airborne-threshold-text", "PHOTO", IMG_OK + ["--airborne-threshold", "bright"], ["--airborne-threshold = 'bright'"]),
    ("channel-3-of-rgb", "PHOTO", IMG_OK + ["--channel", "3"], ["--channel = 3", "not a channel of photo.png", "0 .. 2"]),
    ("channel-negative", "PHOTO", IMG_OK + ["--channel", "-1"], ["--channel = -1"]),
    ("smooth-sigma-negative", "PHOTO", IMG_OK + ["--smooth-sigma", "-2"], ["--smooth-sigma = -2 px"]),
    ("reference-angle-nan", "PHOTO", IMG_OK + ["--reference-angle", "nan"], ["--reference-angle = nan"]),
    ("unknown-drum", "PHOTO", IMG_OK + ["--drum", "tiny"], ["--drum", "'tiny'"]),
    ("out-unknown-type", "PHOTO", IMG_OK + ["--out", "ann.docx"], ["--out 'ann.docx'", ".docx"]),
    ("out-is-the-photo", "PHOTO", IMG_OK + ["--out", "photo.png"], ["--out 'photo.png'", "the photograph itself"]),
    ("directory", "DIR", IMG_OK, ["photo.png", "is a directory"]),
    ("missing-file", None, IMG_OK, ["photo.png", "does not exist"]),
]


@pytest.mark.parametrize("content, args, fragments", [c[1:] for c in IMAGE_CASES], ids=[c[0] for c in IMAGE_CASES])
def test_lab_image_bad_input(workdir, photo_png, content, args, fragments):
    if content == "PHOTO":
        content = photo_png
    elif content == "TRUNCATED":
        content = photo_png[: len(photo_png) // 2]
    _run_case(workdir, {"photo.png": content}, ["lab", "image", "photo.png", *args], fragments)


# --------------------------------------------------------------------------- design-load tables
TABLE_OK = "loading_kg,FUF_area_cm2\n" + "".join(f"{x},{min(x, 30) * 2:.1f}\n" for x in range(10, 60, 5))

TABLE_CASES = [
    ("text-in-loading", "loading_kg,FUF_area_cm2\n10,20\nten,30\n", [], ["t.csv line 3", "'ten' is not a number in column loading_kg"]),
    ("missing-area-column", "loading_kg,area\n10,20\n", [], ["t.csv line 1", "'FUF_area_cm2'", "--area-column"]),
    ("nan-area", "loading_kg,FUF_area_cm2\n10,nan\n", [], ["t.csv line 2", "FUF_area_cm2", "NaN"]),
    ("negative-loading", "loading_kg,FUF_area_cm2\n-10,20\n", [], ["t.csv line 2", "loading_kg = -10"]),
    ("non-utf8", b"loading_kg,FUF_area_cm2\n10,\xe920\n", [], ["t.csv line 2", "not UTF-8"]),
    ("empty", "", [], ["t.csv", "empty file"]),
    ("confidence-1.5", TABLE_OK, ["--confidence", "1.5"], ["--confidence = 1.5", "(0, 1)"]),
    ("too-few-points", "loading_kg,FUF_area_cm2\n10,20\n20,30\n", [], ["t.csv", "2 distinct values", "at least 4 distinct loadings"]),
]


@pytest.mark.parametrize("content, extra, fragments", [c[1:] for c in TABLE_CASES], ids=[c[0] for c in TABLE_CASES])
def test_lab_design_load_bad_table(workdir, content, extra, fragments):
    _run_case(workdir, {"t.csv": content}, ["lab", "design-load", "t.csv", *extra], fragments)


# --------------------------------------------------------------------------- output folders
def _commands(out_dir: str, out_file: str):
    """(name, files to create, argv) of the three writing commands; ``out_dir`` for --out DIR,
    ``out_file`` for lab image's --out FILE."""
    return {
        "rtd-fit": ({"c.csv": TRACER_OK}, ["rtd-fit", "c.csv", "--out", out_dir]),
        "lab rig": ({"rig.csv": "RIGRUN"}, ["lab", "rig", "rig.csv", *RIG_ARGS, "--repose-angle", "39.6",
                                              "--repose-sd", "1.7", "--out", out_dir]),
        "lab image": ({"photo.png": "PHOTO"}, ["lab", "image", "photo.png", *IMG_OK, "--out", out_file]),
    }


@pytest.fixture(scope="module")
def rig_run_csv(tmp_path_factory) -> str:
    from rotarydryer.lab import flight_rig as fr

    d = fr.rig_drum("alternative")
    run = fr.synthetic_run(d, 39.6, rpm=2.0, start_angle=93.5, bulk_density=1474.0, seed=1)
    p = tmp_path_factory.mktemp("rig") / "run.csv"
    fr.write_rig_csv(p, run)
    return p.read_text()


def _setup(workdir, files, photo_png, rig_run_csv):
    for name, content in files.items():
        _write(workdir, name, photo_png if content == "PHOTO" else rig_run_csv if content == "RIGRUN" else content)


def _no_temporaries(folder: Path):
    left = [p.name for p in Path(folder).rglob("*") if p.name.endswith(".tmp")]
    assert left == [], left


@pytest.fixture
def readonly_dir(workdir):
    """A folder in which nothing can be written: chmod 555 for a normal user; a read-only tmpfs as
    root (chmod does not stop root); skipped if neither is possible."""
    d = workdir / f"ro_{uuid.uuid4().hex[:6]}"
    d.mkdir()
    if os.geteuid() != 0:
        d.chmod(0o555)
        yield d
        d.chmod(0o755)
        return
    import subprocess

    r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m,ro", "tmpfs", str(d)], capture_output=True, text=True)
    if r.returncode != 0:
        pytest.skip("running as root, where chmod does not make a folder read-only, and a read-only tmpfs "
                    f"cannot be mounted here ({r.stderr.strip() or 'mount failed'}); the path-under-a-file "
                    "case below covers the unwritable output for everyone")
    yield d
    subprocess.run(["umount", "-l", str(d)], capture_output=True)


@pytest.mark.parametrize("cmd", ["rtd-fit", "lab rig", "lab image"])
def test_output_into_read_only_folder(workdir, readonly_dir, photo_png, rig_run_csv, cmd):
    files, argv = _commands(str(readonly_dir), str(readonly_dir / "ann.png"))[cmd]
    _setup(workdir, files, photo_png, rig_run_csv)
    before = snapshot(workdir)
    res = run_cli(argv, cwd=workdir)
    _check(res, ["cannot write", readonly_dir.name])
    assert list(readonly_dir.iterdir()) == []
    assert snapshot(workdir) == before


@pytest.mark.parametrize("cmd", ["rtd-fit", "lab rig", "lab image"])
def test_output_under_a_regular_file(workdir, photo_png, rig_run_csv, cmd):
    """--out some_file.txt/sub: fails for every user, root included, before any work is done."""
    files, argv = _commands("note.txt/sub", "note.txt/sub/ann.png")[cmd]
    files = {**files, "note.txt": "a regular file\n"}
    _setup(workdir, files, photo_png, rig_run_csv)
    before = snapshot(workdir)
    res = run_cli(argv, cwd=workdir)
    _check(res, ["--out 'note.txt/sub", "'note.txt' is a file"])
    assert snapshot(workdir) == before


@pytest.mark.parametrize("cmd", ["rtd-fit", "lab rig"])
def test_output_folder_is_an_existing_file(workdir, photo_png, rig_run_csv, cmd):
    files, argv = _commands("result.txt", "unused.png")[cmd]
    _setup(workdir, {**files, "result.txt": "keep me\n"}, photo_png, rig_run_csv)
    before = snapshot(workdir)
    res = run_cli(argv, cwd=workdir)
    _check(res, ["--out 'result.txt'", "existing file, not a directory"])
    assert snapshot(workdir) == before and (workdir / "result.txt").read_text() == "keep me\n"


def test_image_output_is_an_existing_folder(workdir, photo_png, rig_run_csv):
    files, argv = _commands("unused", "annotated")["lab image"]
    _setup(workdir, {**files, "annotated": "DIR"}, photo_png, rig_run_csv)
    before = snapshot(workdir)
    res = run_cli(argv, cwd=workdir)
    _check(res, ["--out 'annotated' is a directory", "give a file name"])
    assert snapshot(workdir) == before


@pytest.mark.parametrize("cmd", ["rtd-fit", "lab rig", "lab image"])
def test_full_disk_leaves_no_partial_output(workdir, photo_png, rig_run_csv, monkeypatch, cmd):
    """The early checks pass, then the disk is full when the file replaces its target: exit 2,
    ``cannot write ...: No space left on device``, no output and no temporary file left."""
    import errno

    import rotarydryer._io as io_mod

    real_replace = os.replace

    def full(src, dst, *a, **kw):
        if str(workdir) in os.path.abspath(str(dst)):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real_replace(src, dst, *a, **kw)

    monkeypatch.setattr(io_mod.os, "replace", full)
    files, argv = _commands("out", "out/ann.png")[cmd]
    _setup(workdir, files, photo_png, rig_run_csv)
    before = snapshot(workdir)
    res = run_cli(argv, cwd=workdir)
    _check(res, ["cannot write", "No space left on device"])
    _no_temporaries(workdir)
    assert snapshot(workdir) == before


def test_rig_second_output_failing_removes_the_first(workdir, rig_run_csv, monkeypatch):
    """rig.png written, then rig_aligned.csv fails: rig.png (new in this run) is removed too."""
    import rotarydryer._io as io_mod
    from rotarydryer._io import OutputError

    def broken(path, text, **kw):
        raise OutputError(f"cannot write {str(path)!r}: No space left on device")

    monkeypatch.setattr(io_mod, "write_text_atomic", broken)
    files, argv = _commands("out", "unused.png")["lab rig"]
    _setup(workdir, files, None, rig_run_csv)
    before = snapshot(workdir)
    res = run_cli(argv, cwd=workdir)
    _check(res, ["rig_aligned.csv", "No space left"])
    assert snapshot(workdir) == before


def test_good_outputs_are_written(workdir, photo_png, rig_run_csv):
    """The same three commands succeed with a writable --out (the corpus checks only failures)."""
    for cmd, (files, argv) in _commands("out", "out/ann.png").items():
        _setup(workdir, files, photo_png, rig_run_csv)
        res = run_cli(argv, cwd=workdir)
        assert res.exit_code == 0, (cmd, res.output)
    names = sorted(p.name for p in (workdir / "out").iterdir())
    assert names == ["ann.png", "rig.png", "rig_aligned.csv", "rtd_fit.png"]
    _no_temporaries(workdir)


# --------------------------------------------------------------------------- library level
def test_library_limits_and_checks(tmp_path):
    """The same checks reached without the CLI: row limit, drum in image, time origin."""
    from rotarydryer.geometry.presets import preset_drum
    from rotarydryer.lab import flight_rig as fr
    from rotarydryer.lab import images as im
    from rotarydryer.rtd import load_tracer_csv, parse_tracer_text, rtd_moments

    p = tmp_path / "r.csv"
    p.write_text(_rig_text(50))
    with pytest.raises(ValueError, match=r"line 12: more than 10 data rows"):
        fr.read_rig_csv(p, max_rows=10)
    q = tmp_path / "t.csv"
    q.write_text(TRACER_OK)
    with pytest.raises(ValueError, match=r"line 5: more than 3 data rows"):
        load_tracer_csv(q, max_rows=3)
    with pytest.raises(ValueError, match="time_origin_s = 60 s is at or after the last sample"):
        rtd_moments([0, 10, 20, 30], [0, 1, 2, 0], time_origin_s=60)
    with pytest.raises(ValueError, match="after all the tracer signal"):
        parse_tracer_text("# time_origin_s: 35\n" + TRACER_OK.replace("40,0.2", "40,0"), "x")
    d = preset_drum("ajayi_pilot")[0]
    with pytest.raises(ValueError, match="calibration.centre = 400,10 px"):
        im.measure(np.zeros((300, 300), np.uint8), d, im.ImageCalibration((400, 10), 300.0), reference_angle=90)
    h = tmp_path / "h.png"
    h.write_bytes(_png_header(3000, 3000))
    with pytest.raises(ValueError, match="limit is 1 megapixels"):
        im.load_image(h, max_pixels=1_000_000)
