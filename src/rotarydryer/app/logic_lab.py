"""Logic of the web app's "Lab data" page (``rotarydryer lab``): flight-unloading rig runs,
drum photographs, design-load series and Song's step tests.

Plain functions (no Streamlit).  Each analysis takes either the visitor's upload (text or bytes,
kept in memory and parsed by the library's in-memory readers: nothing is written to disk;
size-limited, docs/app_threat_model.md) or a built-in example made by the library (a synthetic
rig run, a rendered photograph, series mimicking Ajayi's Table 4.11, a simulated step test of
Song's pilot dryer).  Options are checked by the same functions as the command line
(`rotarydryer.services.lab`), so a bad value gives the CLI's message.
"""

from __future__ import annotations

import functools

from ..services.lab import (
    check_rig_options,
    check_steps_options,
    design_load_fits,
    image_options,
    measure_image,
    rig_analysis,
    steps_analysis,
)
from .logic import MAX_UPLOAD_MB, check_upload_text, png

__all__ = ["MAX_LAB_UPLOAD_BYTES", "MAX_LAB_ROWS", "MAX_LAB_IMAGE_PIXELS", "rig_example", "rig_view",
           "image_example", "image_view", "design_load_example", "design_load_view", "steps_example",
           "steps_view", "RIG_EXAMPLE", "IMAGE_EXAMPLE"]

#: bytes of an uploaded CSV (rig run, design-load table, step record) or photograph
MAX_LAB_UPLOAD_BYTES = MAX_UPLOAD_MB * 1_000_000
#: data rows of an uploaded CSV (a rig run at 100 Hz: 500 s)
MAX_LAB_ROWS = 50_000
#: pixels of an uploaded photograph (Ajayi's are 1927 x 1927 = 3.7 MP), checked from the header
#: before decoding
MAX_LAB_IMAGE_PIXELS = 4_000_000

#: the example rig run: Lee (2008) Table 5.5 experiment 6 (Alternative flight, filter sand, 2 rpm)
RIG_EXAMPLE = dict(flight="alternative", repose_angle=39.6, rpm=2.0, start_angle=93.5, bulk_density=1474.0,
                   noise_sd=0.1, noise_correlation=0.5, seed=6)
#: the example photograph: Ajayi's pilot drum (0.75 m, 24 flights) at a repose angle of 46.7 deg
IMAGE_EXAMPLE = dict(drum="ajayi_pilot", repose_angle=46.7, reference_angle=91.0, px_per_m=800.0, mirror=True,
                     flight_thickness=0.002, noise_sd=10.0, seed=1)


def _check_text(text: str, what: str) -> str:
    if not isinstance(text, str):
        raise ValueError(f"the {what} must be text")
    return check_upload_text(text, what, MAX_LAB_UPLOAD_BYTES, MAX_LAB_ROWS)


def decode_upload(content: bytes, what: str = "uploaded file") -> str:
    """UTF-8 text of an uploaded CSV (``ValueError`` when too large or not UTF-8)."""
    content = bytes(content)
    if len(content) > MAX_LAB_UPLOAD_BYTES:
        raise ValueError(f"the {what} has {len(content)} bytes; the limit is {MAX_LAB_UPLOAD_BYTES} bytes")
    try:
        return content.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(f"the {what} is not UTF-8 text (byte 0x{content[exc.start]:02x} at offset {exc.start}); "
                         "save it as UTF-8 CSV") from None


# ---------------------------------------------------------------------------------------------- rig
@functools.lru_cache(maxsize=1)
def rig_example() -> str:
    """CSV text (``time_s,mass_kg``) of a synthetic rig run (`RIG_EXAMPLE`,
    `rotarydryer.lab.flight_rig.synthetic_run`, as ``examples/lab_rig.py``)."""
    from ..lab import flight_rig as fr

    e = RIG_EXAMPLE
    run = fr.synthetic_run(fr.rig_drum(e["flight"]), e["repose_angle"], rpm=e["rpm"], start_angle=e["start_angle"],
                           bulk_density=e["bulk_density"], noise_sd=e["noise_sd"],
                           noise_correlation=e["noise_correlation"], seed=e["seed"])
    lines = [f"# synthetic rig run: {e['flight']} flight, {e['rpm']:g} rpm, repose angle {e['repose_angle']:g} deg "
             "(rotarydryer.lab.flight_rig.synthetic_run)", "time_s,mass_kg"]
    lines += [f"{t:.6f},{m:.6f}" for t, m in zip(run.time, run.mass)]
    return "\n".join(lines) + "\n"


def rig_view(text: str | None = None, name: str = "example rig run", *, flight="alternative", rpm=2.0,
             start_angle=93.5, bulk_density=1474.0, length=1.0, repose_angle=None, repose_sd=0.0, cutoff=1.5,
             phase="zero", fit_bulk_density=False, images=True) -> dict:
    """``rotarydryer lab rig`` on a load-cell CSV (``text``; None: `rig_example`): start of
    unloading, fitted repose angle with its CI, Lee's band and the fraction of samples inside it."""
    from ..lab import flight_rig as fr

    check_rig_options(flight, rpm, start_angle, bulk_density, length, repose_angle, repose_sd, cutoff, phase)
    text = _check_text(rig_example() if text is None else text, "rig CSV")
    run = fr.parse_rig_text(text, name, max_rows=MAX_LAB_ROWS)
    f, a = rig_analysis(run, name, flight, rpm, start_angle, bulk_density, length, repose_angle, repose_sd,
                        cutoff, phase, fit_bulk_density)
    out = {"samples": int(run.time.size), "sample_rate_hz": run.sample_rate, "unloading_start_s": a.start_time,
           "repose_angle_deg": f.repose_angle, "repose_angle_ci_deg": tuple(f.repose_angle_ci),
           "confidence": f.confidence, "bulk_density_kg_m3": f.params["bulk_density"],
           "residual_sd_kg": f.residual_sd, "residual_ar1": f.ar1,
           "band_repose_deg": (a.band.repose_low, a.band.repose_high),
           "fraction_inside_band_mass": a.inside_mass, "fraction_inside_band_rate": a.inside_rate}
    if images:
        fig = fr.plot_analysis(a)
        fig.set_size_inches(10, 4.2)
        out["plot"] = png(fig)
    return out


# ---------------------------------------------------------------------------------------------- photographs
@functools.lru_cache(maxsize=1)
def image_example() -> tuple[bytes, dict]:
    """PNG bytes of a synthetic photograph (`IMAGE_EXAMPLE`,
    `rotarydryer.lab.images.render_cross_section`) and its settings: ``centre`` (column,
    row px), ``px_per_m``, ``mirror``, ``reference_angle``, ``true_fuf_cm2``, ``true_tp_cm2``."""
    import io

    from PIL import Image

    from ..geometry.presets import preset_drum
    from ..lab import images as im

    e = IMAGE_EXAMPLE
    drum, _ = preset_drum(e["drum"])
    syn = im.render_cross_section(drum, e["repose_angle"], reference_angle=e["reference_angle"],
                                  px_per_m=e["px_per_m"], flight_thickness=e["flight_thickness"],
                                  noise_sd=e["noise_sd"], seed=e["seed"], mirror=e["mirror"])
    buf = io.BytesIO()
    Image.fromarray(syn.image).save(buf, format="PNG")
    k = im.first_unloading_flight(drum, syn.root_angles)
    return buf.getvalue(), {"centre": tuple(float(c) for c in syn.calibration.centre), "px_per_m": e["px_per_m"],
                            "mirror": e["mirror"], "reference_angle": e["reference_angle"], "drum": e["drum"],
                            "true_fuf_cm2": float(syn.flight_areas[k]) * 1e4,
                            "true_tp_cm2": float(syn.flight_areas.sum()) * 1e4}


def image_view(content: bytes | None = None, name: str = "example photograph", *, drum="ajayi_pilot",
               centre=(None, None), px_per_m=None, known_length_px=None, known_length_m=None, mirror=False,
               reference_angle=90.0, channel=0, threshold="168,177", airborne_threshold="104,120",
               smooth_sigma=0.0, images=True) -> dict:
    """``rotarydryer lab image`` on a photograph (``content``: image file bytes; None:
    `image_example`): areas per flight, FUF, UHD, LHD, TP and airborne (cm^2), and the
    annotated picture.  Needs the ``lab`` extra (scikit-image, shapely): without it the error names
    the extra to install."""
    from ..lab import images as im

    col, row = centre
    d, cal, scale_name, thr, athr = image_options(f"{col},{row}", drum, px_per_m, known_length_px, known_length_m,
                                                  mirror, reference_angle, channel, threshold, airborne_threshold,
                                                  smooth_sigma)
    if content is None:
        content = image_example()[0]
    content = bytes(content)
    if len(content) > MAX_LAB_UPLOAD_BYTES:
        raise ValueError(f"{name}: {len(content)} bytes; the limit is {MAX_LAB_UPLOAD_BYTES} bytes")
    img = im.load_image_bytes(content, name, max_pixels=MAX_LAB_IMAGE_PIXELS)
    m = measure_image(img, name, d, cal, scale_name, reference_angle, channel, thr, athr, smooth_sigma)
    out = {"size_px": (int(img.shape[1]), int(img.shape[0])), **m.as_dict()}
    if images:
        out["annotated"] = png(im.annotate(img, m), dpi=80)
    return out


# ---------------------------------------------------------------------------------------------- design load
@functools.lru_cache(maxsize=1)
def design_load_example() -> str:
    """CSV text (``condition,loading_kg,FUF_area_cm2``) of series mimicking each row of Ajayi's
    (2011) Table 4.11 (`rotarydryer.lab.design_load_fit.mimic_ajayi_series`, seeded): 11
    loadings x 5 photographs per condition."""
    from ..lab import design_load_fit as dl

    lines = ["# series mimicking Ajayi (2011) Table 4.11 (rotarydryer.lab.design_load_fit.mimic_ajayi_series)",
             "condition,loading_kg,FUF_area_cm2"]
    for k, r in enumerate(dl.ajayi_table_4_11()):
        x, y, _ = dl.mimic_ajayi_series(r["design_load_kg"], r["design_load_ci_kg"], r["FUF_area_cm2"],
                                        r["FUF_area_ci_cm2"], seed=k)
        cond = f"{r['rpm']:g} rpm {r['fluid_wt_pct']:g} %"
        lines += [f"{cond},{a:.4f},{b:.4f}" for a, b in zip(x, y)]
    return "\n".join(lines) + "\n"


def design_load_view(text: str | None = None, name: str = "example series", *, loading_column="loading_kg",
                     area_column="FUF_area_cm2", group_column: str | None = "condition", confidence=0.95,
                     images=True) -> dict:
    """``rotarydryer lab design-load`` on a table (``text``; None: `design_load_example`):
    design load = break point of FUF area against loading per group, with its intervals."""
    from ..lab import design_load_fit as dl
    from ..rtd._datafile import text_lines

    example = text is None
    text = _check_text(design_load_example() if example else text, "design-load table")
    if group_column is not None and not str(group_column).strip():
        group_column = None
    groups = dl.read_design_rows(text_lines(text), name, loading_column, area_column, group_column)
    fits = design_load_fits(groups, name, group_column is not None, confidence)
    rows = [dict(group=g, design_load=f.break_point, profile_ci=tuple(f.ci["profile"]), delta_ci=tuple(f.ci["delta"]),
                 plateau=f.plateau, slope=f.slope, n=f.n, residual_sd=f.residual_sd) for g, f in fits.items()]
    if example:   # the published values the example series mimic
        pub = {f"{r['rpm']:g} rpm {r['fluid_wt_pct']:g} %": f"{r['design_load_kg']:g} +/- {r['design_load_ci_kg']:g}"
               for r in dl.ajayi_table_4_11()}
        for row in rows:
            row["published"] = pub.get(row["group"], "")
    out = {"fits": rows, "confidence": confidence}
    if images:
        import numpy as np

        from .._plotting import pyplot

        plt = pyplot()
        fig, ax = plt.subplots(figsize=(9, 4), constrained_layout=True)
        for (g, f), color in zip(fits.items(), plt.rcParams["axes.prop_cycle"].by_key()["color"] * 10):
            ax.plot(f.loading, f.area, "o", ms=3, color=color, alpha=0.6)
            xx = np.linspace(float(np.min(f.loading)), float(np.max(f.loading)), 200)
            ax.plot(xx, f.predict(xx), color=color, label=f"{g}: {f.break_point:.1f}")
            ax.axvline(f.break_point, color=color, lw=0.6, ls=":")
        ax.set_xlabel(loading_column)
        ax.set_ylabel(area_column)
        ax.legend(fontsize=7, ncol=2, title="design load (break point)", title_fontsize=7)
        out["plot"] = png(fig)
    return out


# ---------------------------------------------------------------------------------------------- step tests
@functools.lru_cache(maxsize=1)
def steps_example() -> str:
    """CSV text of Song's up/down feed step test (Table 4.1 run 2, Appendix A line 1551) simulated
    on the transport dynamics of his pilot dryer (`rotarydryer.studies.song_pilot.step_test`,
    5 s samples): ``time_s,feed_kg_min,discharged_kg``."""
    import numpy as np

    from ..studies import song_pilot as sp

    model = sp.PilotModel(sp.pilot_runs())
    i = int(np.nonzero(model.runs.src_line == 1551)[0][0])
    res = sp.step_test(model, i, sp.Coefficients(*sp.SONG_PILOT_FITS["all"]), dt=5.0)
    return sp.step_record_csv(res["record"], "Song (2003) Table 4.1 run 2, up/down feed step, 5 s samples")


def steps_view(text: str | None = None, name: str = "example step test", *, step_times: str | None = None,
               threshold=0.1, plateau=0.2, tolerance=0.05, initial_holdup=0.0, images=True) -> dict:
    """``rotarydryer lab steps`` on a feed/discharge record (``text``; None: `steps_example`):
    holdup after each step, tau = H/F, H1 vs H2 and the closure (Song 2003, Eq. 4.1, Table 4.2)."""
    from ..lab import steps as sm

    check_steps_options(threshold, plateau, tolerance, initial_holdup)
    text = _check_text(steps_example() if text is None else text, "step record")
    rec = sm.parse_step_text(text, name)
    if step_times is not None and not step_times.strip():
        step_times = None
    a = steps_analysis(rec, name, step_times, threshold, plateau, tolerance, initial_holdup)
    out = {"columns": dict(rec.columns), "samples": int(rec.time.size), **a.as_dict()}
    out.pop("file", None)
    if images:
        fig = sm.plot_steps(rec, a)
        fig.set_size_inches(10, 4.2)
        out["plot"] = png(fig)
    return out
