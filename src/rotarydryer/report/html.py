"""Self-contained HTML report of a result, a case or a drum.

>>> from rotarydryer.report.html import write_report
>>> write_report("lee2008_invicta", "report.html")          # runs the case    # doctest: +SKIP
>>> write_report("invicta.nc", "report.html")               # a saved Results  # doctest: +SKIP
>>> write_report("invicta", "report.html", repose_angle=50)  # drum preset only # doctest: +SKIP

One HTML file, no external resources: pictures are base64 PNG ``<img>`` elements, the
style sheet is inline.  Sections (each when its data exist):

* summary in sentences, then the operating conditions with an SVG drawing of the dryer
  (`rotarydryer.report.drawing`; gas direction, burner);
* model against measured with the error wherever data exist (`rotarydryer.report.manager`),
  in captions that state each figure's key numbers;
* the heat duties, kW (heat input, evaporation, heating of solids, shell loss, exhaust; `heat_duties`);
* flight cross-section and unloading profile of each flighted section (Lee (2008) ch. 4);
* design-load table (Lee (2008) Eq. 4.19-4.21; Ajayi (2011) Eq. 2.2-2.4, 4.19) next to the
  transport model's design load;
* key results, holdup profile, RTD against data, loading state per cell and per section;
* the inputs and model choices (JSON), the case's data sources and the full references
  (`rotarydryer.report.references`).

A view only: geometry pictures are computed by the geometry package, everything else
is read from the `rotarydryer.results.Results`.
"""

from __future__ import annotations

import base64
import functools
import html
import io
import json
from pathlib import Path

import numpy as np

from .. import __version__
from .._display import _finite, fmt, fmt_angle, fmt_error, output_cells, show, show_delta, show_output, unit_of
from .._io import write_text_atomic

__all__ = ["figure_to_data_uri", "render_report", "build_report", "write_report", "write_html", "resolve_source",
           "case_validation", "validation_section",
           "sensitivity_section", "load_sensitivity", "heat_duties"]

_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:0;color:#222;background:#fafafa}
header{background:#5b3a12;color:#fff;padding:18px 32px}
header h1{margin:0;font-size:1.5em} header p{margin:4px 0 0;opacity:.85;font-size:.9em}
figure{margin:12px 0} figcaption{font-size:.9em;color:#444;margin-top:4px}
main{max-width:1100px;margin:0 auto;padding:8px 32px 40px}
section{background:#fff;border:1px solid #e3e3e3;border-radius:6px;padding:12px 20px;margin:18px 0}
h2{font-size:1.15em;border-bottom:2px solid #d9a441;padding-bottom:4px}
table{border-collapse:collapse;font-size:.88em;margin:8px 0}
th,td{border:1px solid #ddd;padding:3px 9px;text-align:right} th{background:#f3ead9}
td.l,th.l{text-align:left}
img{max-width:100%;height:auto;display:block;margin:6px auto}
.row{display:flex;flex-wrap:wrap;gap:12px;align-items:flex-start} .row>div{flex:1 1 420px}
.note{color:#666;font-size:.85em} pre{font-size:.78em;background:#f6f6f6;padding:8px;overflow:auto}
.mvm{background:#f4f8fb;border-left:3px solid #2468b4;padding:4px 10px;font-size:.9em}
figure.drawing svg{max-width:100%;height:auto;display:block;margin:6px auto}
ol.refs li{margin:3px 0;font-size:.9em}
.state-over{color:#b52b27;font-weight:600} .state-under{color:#2468b4} .state-design{color:#2a7a3b}
"""



def _is_number(v) -> bool:
    """A finite number (not None, NaN, inf or a string, even a numeric one): a scalar the report can print."""
    return not isinstance(v, (str, bool)) and _finite(v)[0] is not None

def figure_to_data_uri(fig, dpi: int = 96) -> str:
    """PNG ``data:`` URI of a Matplotlib figure; closes the figure."""
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    plt.close(fig)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


_FIG_MARK = "@@FIGURE-NUMBER@@"


def _img(fig, alt: str, caption: str | None = None) -> str:
    """A figure with a numbered caption (numbers are assigned in reading order by
    `_number_figures` once the report is assembled).  ``caption``: plain text stating
    what the figure shows and its key numbers (default: ``alt``)."""
    if fig is None:
        return ""
    text = caption or alt
    text = html.escape(text[:1].upper() + text[1:]).rstrip(".")
    return (f'<figure><img alt="{html.escape(alt)}" src="{figure_to_data_uri(fig)}">'
            f'<figcaption><b>Figure {_FIG_MARK}.</b> {text}.</figcaption></figure>')


def _svg_figure(svg: str, caption: str) -> str:
    """An inline SVG drawing as a numbered figure."""
    text = html.escape(caption[:1].upper() + caption[1:]).rstrip(".")
    return (f'<figure class="drawing">{svg}'
            f'<figcaption><b>Figure {_FIG_MARK}.</b> {text}.</figcaption></figure>')


def _number_figures(text: str) -> str:
    """Replace the figure-number marks by 1, 2, ... in reading order."""
    parts = text.split(_FIG_MARK)
    return "".join(p + (str(i + 1) if i < len(parts) - 1 else "") for i, p in enumerate(parts))


def _table(header, rows, left_cols=1, cls="") -> str:
    h = "".join(f'<th class="{"l" if i < left_cols else ""}">{html.escape(str(c))}</th>' for i, c in enumerate(header))
    body = []
    for r in rows:
        cells = []
        for i, c in enumerate(r):
            klass = "l" if i < left_cols else ""
            text = c if isinstance(c, _Raw) else html.escape(str(c))
            cells.append(f'<td class="{klass}">{text}</td>')
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f'<table class="{cls}"><thead><tr>{h}</tr></thead><tbody>{"".join(body)}</tbody></table>'


class _Raw(str):
    """Trusted HTML fragment for a table cell."""


def _signed(v, quantity: str) -> str:
    """A signed difference of an SI ``quantity`` in its display unit (``+1,234 kg``, ``-0.52 min``)."""
    text = show_delta(v, quantity, 4)
    return text if text.startswith("-") or not text[:1].isdigit() else "+" + text


def _fmt(v, digits=4) -> str:
    """The report's number format: `rotarydryer._display.fmt` (engineering rounding)."""
    if isinstance(v, str):
        return v
    return fmt(v, digits)


def _geometry_sections(drums, results) -> str:
    from ..geometry import DESIGN_LOAD_METHODS
    from .plots import draw_cross_section, plot_unloading_profile

    parts = []
    for d in drums:
        drum, phi = d["drum"], float(d["repose_angle"])
        fig1 = draw_cross_section(drum, phi, angle=90.0)
        fig1.set_size_inches(5.0, 5.0)
        fig2 = plot_unloading_profile(drum, phi, float(d["rpm"]))
        tr = drum.transition_angles(phi)
        cs = drum.cascade(phi, 1.0, rpm=float(d["rpm"]), slope=float(d["slope"]))
        geo_rows = [
            ("drum radius R", f"{drum.radius:g} m"),
            ("flights N_F", f"{drum.n_flights}"),
            *([("flight s1 / s2", f"{drum.flight.s1:g} m / {drum.flight.s2:g} m"),
               ("alpha1 / alpha2", f"{drum.flight.alpha1:g} / {drum.flight.alpha2:g} deg")]
              if hasattr(drum.flight, "s2") else
              [("flight sections (length, angle)", ", ".join(f"{a:g} m / {b:g} deg" for a, b in drum.profile.segments))]),
            ("flight-tip radius R_F (Lee (2008) Eq. 4.6)", f"{_fmt(drum.tip_radius)} m"),
            ("full-flight holdup (Eq. 4.8)", f"{_fmt(drum.full_holdup_area * 1e4)} cm2 per m"),
            ("repose angle used", f"{fmt_angle(phi)} deg"),
            ("transition angles psi1-psi5 (Eq. 4.9-4.13)", ", ".join(f"{float(a):.1f}" for a in tr) + " deg"),
            ("mean fall height (design loading)", f"{_fmt(float(cs.mean_fall_height), 3)} m"),
            ("passive / active time", f"{_fmt(float(cs.passive_time), 3)} s / {_fmt(float(cs.mean_fall_time), 3)} s"),
        ]
        rho, length = float(d["bulk_density"]), float(d["length"])
        where = "the dryer" if d["name"] == "dryer" else f"section {d['name']}"
        cap1 = (f"flight cross-section of {where}: {drum.n_flights} flights in a drum of radius "
                f"{drum.radius:g} m, solids at a repose angle of {phi:.1f} deg; a full flight holds "
                f"{drum.full_holdup_area * 1e4:.0f} cm2 per m of flight")
        cap2 = (f"unloading profile of {where} at {float(d['rpm']):g} rev/min: the flights empty "
                f"with transition angles psi1-psi5 at {', '.join(f'{float(a):.0f}' for a in tr)} deg; mean fall height "
                f"{float(cs.mean_fall_height):.2f} m")
        dl_rows = []
        for m in DESIGN_LOAD_METHODS:
            a = float(drum.design_load_area(phi, method=m))
            dl_rows.append((m, f"{a:.4g}", f"{a * rho * length:,.0f}"))
        model_des = ""
        if results is not None and results.flighted_cells is not None:
            sel = results.flighted_cells.section.values == d["name"]
            if np.any(sel):
                tot = float(np.nansum(results.flighted_cells.design_load.values[sel]))
                model_des = (f'<p class="note">Transport model ({html.escape(str(results.model_choices.get("model")))})'
                             f" design load in this section: <b>{tot:,.0f} kg</b> "
                             f"(sum over {int(sel.sum())} cells, moisture-dependent repose angle).</p>")
        parts.append(f"""
<section id="flight-{html.escape(d['name'])}"><h2>Flights: section {html.escape(d['name'])}</h2>
<div class="row"><div>{_img(fig1, 'flight cross-section', cap1)}</div>
<div>{_table(('quantity', 'value'), geo_rows, left_cols=1)}
<h3>Design load</h3>
{_table(('method', 'area (m2)', f'mass (kg), rho_b {rho:g} kg/m3, L {length:g} m'), dl_rows)}
<p class="note">Lee (2008) Eq. 4.20-4.21 (= Baker (1988)), Porter (1963) (Lee (2008) Eq. 4.19), Kelly &amp;
O'Donnell (1977) and Ajayi (2011) Eq. 4.19 (1.24 x Baker); first unloading flight root at 90 deg.
No measured design load for this section is in the case data.</p>{model_des}</div></div>
{_img(fig2, 'unloading profile', cap2)}
</section>""")
    return "".join(parts)


def _transport_sections(results) -> str:
    from .figures import plot_holdup_profile, plot_loading_state, plot_rtd

    s = results.scalars
    key = [
        ("feed rate", "feed_rate_kg_s"),
        ("outlet flow", "outlet_flow_kg_s"),
        ("total holdup", "total_holdup_kg"),
        ("airborne (active) holdup", "active_holdup_kg"),
        ("passive holdup (on the flights and the kilning bed)", "passive_holdup_kg"),
        ("of which the kilning bed", "kiln_bed_holdup_kg"),
        ("unflighted bed", "bed_holdup_kg"),
        ("mean residence time H/F", "mean_residence_time_s"),
        ("RTD standard deviation", "rtd_std_s"),
    ]
    key_rows = [(label, *output_cells(name, float(s[name]))) for label, name in key if s.get(name) is not None]
    if s.get("mass_balance_error") is not None:
        key_rows.append(("mass balance error", fmt_error(s["mass_balance_error"]), "relative"))
    note = ""
    if results.model_choices.get("datasets") == "coupled heat-and-mass steady state":
        note = ('<p class="note">Key results, the holdup profile, RTD and loading-state figures and tables are '
                'those of the coupled transport, heat and mass steady state (the names and values of '
                '<code>rotarydryer simulate --json</code>): one state, one number per quantity.</p>')
    from .manager import holdup_comparison, rtd_comparison

    mass = functools.partial(show, quantity="mass")
    tot = s.get("total_holdup_kg", np.nan)
    cap_hold = (f"holdup along the dryer: {mass(tot)} in total (airborne {mass(s.get('active_holdup_kg', np.nan))}, "
                f"passive, on the flights and the kilning bed, {mass(s.get('passive_holdup_kg', np.nan))}), "
                f"mean residence time H/F "
                f"{show(s.get('mean_residence_time_s', np.nan), 'time')}")
    hc = holdup_comparison(results)
    if hc is not None:
        cap_hold += (f"; measured {mass(hc['measured_kg'])} in Test {hc['test']} (error {_signed(hc['error_kg'], 'mass')}, "
                     f"{hc['error_pct']:+.1f} %)")
        hold_mvm = (f'<p class="mvm"><b>Model against measured:</b> total holdup {mass(hc["model_kg"])} against '
                    f'{mass(hc["measured_kg"])} measured in Test {hc["test"]} (feed x measured mean residence time, '
                    f'Ajayi (2011) Table 3.14): error {_signed(hc["error_kg"], "mass")} ({hc["error_pct"]:+.1f} %).</p>')
    else:
        hold_mvm = ('<p class="mvm">No measured holdup is available for this run, so the holdup profile is a model '
                    'prediction only.</p>')
    parts = [f"""<section id="summary"><h2>Key results</h2>
{_table(('quantity', 'value', 'unit'), key_rows)}{note}</section>"""]
    parts.append(f'<section id="holdup"><h2>Holdup profile</h2>'
                 f'{_img(plot_holdup_profile(results), "holdup profile", cap_hold)}{hold_mvm}</section>')
    if results.rtd is not None:
        meas = "" if results.rtd_measured is None else " against the measured tracer curve"
        rc = rtd_comparison(results)
        m_mean = s.get("tracer_mean_s", s.get("simulated_mean_s", np.nan))
        m_std = s.get("tracer_std_s", s.get("simulated_std_s", np.nan))
        t = functools.partial(show, quantity="time")
        if rc is not None:
            d_mean, d_std = rc["model_mean_s"] - rc["measured_mean_s"], rc["model_std_s"] - rc["measured_std_s"]
            cap_rtd = (f"tracer curves: the model's (its RTD through the injection pulse) mean {t(m_mean)}, SD {t(m_std)} "
                       f"against the measured mean {t(rc['measured_mean_s'])}, SD {t(rc['measured_std_s'])} "
                       f"(mean error {_signed(d_mean, 'time')}, R2 {rc['r_squared']:.2f})")
            rtd_mvm = (f'<p class="mvm"><b>Model against measured:</b> tracer curve mean {t(m_mean)} against '
                       f'{t(rc["measured_mean_s"])} measured, error {_signed(d_mean, "time")} '
                       f'({100 * d_mean / rc["measured_mean_s"]:+.1f} %); spread (standard deviation) '
                       f'{t(m_std)} against {t(rc["measured_std_s"])}, error {_signed(d_std, "time")} '
                       f'({100 * d_std / rc["measured_std_s"]:+.1f} %); R2 of the model E(t) against the '
                       f'{rc["n_points"]} measured points {rc["r_squared"]:.3f}.</p>')
        else:
            cap_rtd = (f"the model's tracer curve (its RTD through the injection pulse): mean {t(m_mean)}, SD {t(m_std)}; "
                       f"the RTD itself: mean {t(s.get('rtd_mean_residence_time_s', np.nan))}, SD "
                       f"{t(s.get('rtd_std_s', np.nan))}")
            rtd_mvm = ('<p class="mvm">No measured tracer curve is available for this run, so the RTD is a model '
                       'prediction only.</p>')
        parts.append(f'<section id="rtd"><h2>Residence-time distribution{meas}</h2>'
                     f'{_img(plot_rtd(results), "RTD", cap_rtd)}{rtd_mvm}{_fit_table(results)}</section>')
    if results.flighted_cells is not None:
        c = results.flighted_cells
        rows = []
        for name in dict.fromkeys(c.section.values.tolist()):
            sel = c.section.values == name
            st = c.state.values[sel]
            counts = {k: int(np.sum(st == k)) for k in ("under", "design", "over")}
            dominant = max(counts, key=counts.get)
            rows.append((name, int(sel.sum()), counts["under"], counts["design"], counts["over"],
                         f"{float(np.min(c.dryer_loading.values[sel])):.3f} - {float(np.max(c.dryer_loading.values[sel])):.3f}",
                         show(float(np.sum(c.kiln_bed.values[sel])), "mass", with_unit=False),
                         _Raw(f'<span class="state-{dominant}">{dominant}-loaded</span>')))
        sec = results.sections
        # engineering rounding in the display unit (whole kg showed Song's 0.58 kg airborne as 1)
        hold_rows = [(str(n), k, f"{float(L):g}", int(nc), *(show(float(v), "mass", with_unit=False) for v in (a, p, b, t)))
                     for n, k, L, nc, a, p, b, t in zip(sec.section.values, sec.kind.values, sec.length.values,
                                                        sec.n_cells.values, sec.active_holdup.values,
                                                        sec.passive_holdup.values, sec.bed_holdup.values,
                                                        sec.total_holdup.values)]
        n_state = {k: int(np.sum(c.state.values == k)) for k in ("under", "design", "over")}
        dl = c.dryer_loading.values
        cap_load = (f"loading state per cell: {n_state['under']} under-, {n_state['design']} design- and "
                    f"{n_state['over']} over-loaded of {dl.size} flighted cells; dryer loading "
                    f"{float(np.min(dl)):.2f} to {float(np.max(dl)):.2f} (1 = design load)")
        parts.append(f"""<section id="loading"><h2>Loading state per section</h2>
{_img(plot_loading_state(results), 'loading state', cap_load)}
{_table(('section', 'cells', 'under', 'design', 'over', 'dryer loading range (-)', f'kilning bed ({unit_of("mass")})', 'state'), rows)}
<h3>Holdup per section ({unit_of("mass")})</h3>
{_table(('section', 'kind', 'length (m)', 'cells', 'airborne', 'passive (flights + kilning bed)', 'unflighted bed', 'total'), hold_rows, left_cols=2)}
<p class="note">Dryer loading = passive holdup / design load (Lee (2008) Section 4.4.2): under &lt; 1,
design = 1, over &gt; 1 (the surplus forms the kilning bed).</p>
<p class="mvm">The loading state is not measured in the plant; these figures are model predictions only.</p></section>""")
    return "".join(parts)


def _fit_table(results) -> str:
    f = results.datasets.get("rtd_fits")
    if f is None:
        return ""
    rows = []
    for i, m in enumerate(f.model.values):
        first = True
        for j, p in enumerate(f.parameter.values):
            v = float(f.value.values[i, j])
            if not np.isfinite(v):
                continue
            rows.append((str(m), str(p), _fmt(v), _fmt(float(f.std_error.values[i, j]), 3),
                         f"{_fmt(float(f.ci_low.values[i, j]))} - {_fmt(float(f.ci_high.values[i, j]))}",
                         f"{float(f.r_squared.values[i]):.3f}" if first else "",
                         _fmt(float(f.outlet_mean.values[i]) / 60) if first else ""))
            first = False
    return ("<h3>Classical RTD models fitted to the measured curve</h3>"
            + _table(("model", "parameter", "value", "std. error", "95 % interval", "R2", "outlet mean (min)"),
                     rows, left_cols=2)
            + f'<p class="note">rotarydryer.rtd.fit_rtd_model; tracer input {html.escape(str(f.attrs.get("pulse")))}, '
              f'scale {html.escape(str(f.attrs.get("scale")))}; units: the suffix of the parameter name.</p>')


def _size_section(results) -> str:
    """Feed, product and dust size distributions and a row per size class (a case with
    ``[particle_size]``: `rotarydryer.results.add_thermal`'s ``size_classes`` dataset)."""
    from ..thermal.plots import plot_size_classes

    ds = results.datasets["size_classes"]
    sc = results.scalars
    feed, prod, dust = (np.asarray(ds[k].values, float) for k in ("feed_fraction", "product_fraction", "dust_fraction"))
    moist = [None if not np.isfinite(v) else float(v) for v in ds["product_moisture"].values]
    lost = np.asarray(ds["lost_as_dust"].values, float)
    dia = np.asarray(ds["diameter"].values, float)
    dust_rate = float(sc.get("dust_rate_kg_s", 0.0))
    cap = (f"particle sizes: {dia.size} classes; product d50 {show_output('product_d50_m', sc.get('product_d50_m'))}, "
           f"dust to the exhaust {show_output('dust_rate_kg_s', dust_rate)} wet ({float(np.sum(lost * feed)):.1%} of the "
           "feed's dry solids)")
    fig = plot_size_classes(np.asarray(ds["edge"].values, float), dia, feed, prod, dust if dust.sum() > 0 else dust,
                            moist, lost)
    rows = [(show(d, "particle_size", with_unit=False), _fmt(f, 3), _fmt(p, 3), _fmt(100 * lo, 3), "-" if m is None else show(m, "moisture"),
             show(t, "time")) for d, f, p, lo, m, t in zip(dia, feed, prod, lost, moist, ds["mean_residence_time"].values)]
    table = _table((f"class diameter ({unit_of('particle_size')})", "feed fraction", "product fraction", "lost as dust (%)", "product moisture",
                    "mean residence time"), rows)
    note = ('<p class="note">Classes of equal feed mass (rotarydryer.properties.psd); each class dries with its own '
            'area and moves with its own forward step where the transport law is the trajectory step; the gas carries '
            'a curtain\'s fines away where it is faster than their terminal velocity.</p>')
    return (f'<section id="particle-sizes"><h2>Particle sizes</h2>{_img(fig, "size distributions", cap)}'
            f'{table}{note}</section>')


def _section_lengths(results):
    sec = results.datasets.get("sections")
    return [] if sec is None else list(zip(sec.section.values, sec.length.values))


def _thermal_section(results, audit: dict | None = None) -> str:
    """Key thermal results, the energy audit (heat duties: waterfall and table in the display unit of
    power; the exhaust's dew-point margin; the shell against its limit; with ``audit``, the what-if
    savings of ``rotarydryer audit``) and the axial profiles, from the thermal datasets of a
    `rotarydryer.results.Results` (cases with a heat and mass transfer model; see
    `rotarydryer.results.add_thermal`)."""
    from .plots import plot_thermal_profiles, thermal_profiles_from_results

    sc = results.scalars
    labels = (("product_moisture_kg_kg", "product moisture (wet basis)"),
              ("product_temperature_degC", "product temperature"),
              ("gas_outlet_temperature_degC", "gas outlet temperature"),
              ("evaporation_kg_s", "evaporation"),
              ("fuel_rate_kg_s", "fuel rate (burner, App. A)"),
              ("shell_heat_loss_W", "shell heat loss"),
              ("heat_input_W", "heat put into the gas"),
              ("specific_energy_kJ_kg_water", "specific energy (per kg of water evaporated)"))
    rows = [("model", str(results.model_choices.get("thermal_mode", "")), "-")]
    rows += [(label, *output_cells(key, sc[key])) for key, label in labels if key in sc]
    if _is_number(sc.get("thermal_efficiency")):
        rows.append(("thermal efficiency (evaporation heat / heat input)", _fmt(100.0 * sc["thermal_efficiency"], 3), "%"))
    rows += [(label, fmt_error(sc[key]), "relative") for key, label in
             (("energy_balance_error", "energy balance error"), ("water_balance_error", "water balance error"))
             if key in sc]
    if results.model_choices.get("fuel_rate_error") and "fuel_rate_kg_s" not in sc:
        rows.append(("fuel rate (burner, App. A)", "n/a: " + str(results.model_choices["fuel_rate_error"]),
                     unit_of("fuel_flow")))
    cap_t, t_mvm = _thermal_comparison_html(results)
    return (f'<section id="energy"><h2>Heat and mass transfer</h2>'
            f'{_table(("quantity", "value", "unit"), rows)}'
            f'{_energy_audit_html(results, audit)}'
            f'<h3>Temperature and moisture along the dryer</h3>{_img(plot_thermal_profiles(thermal_profiles_from_results(results), sections=_section_lengths(results)), "thermal profiles", cap_t)}'
            f'{t_mvm}</section>')


_DUTIES_NOTE = (
    "Heat duties (rotarydryer.thermal.audit), relative to the ambient air and the feed: heat release = fuel x "
    "lower heating value where the case has a burner, else the heat put into the gas; burner loss = release - "
    "heat put into the gas (the chamber's wall loss and the combustion products' enthalpy beyond the model's "
    "humid-air gas); evaporation = each stage's evaporation x the latent heat at its solids temperature; "
    "solids heating = the dry solids from feed to product temperature; water heating = the water kept, from feed "
    "to product temperature, and the water evaporated, from feed to evaporation temperature; shell loss = heat "
    "lost through the shell; exhaust (sensible) = the exhaust leaving the plant (with recycle, its unrecycled "
    "part) above ambient, the evaporated vapour from its evaporation temperature; air leaks = leak air heated "
    "from ambient to the exhaust temperature; balance closure = release - the others (the balance residual). "
    "They add up to the release. The exhaust's latent heat (the evaporated water's at ambient temperature, at "
    "most what a condenser would recover) is part of the evaporation's heat, not added.")


def heat_duties(results) -> dict | None:
    """``{name: W}``: the energy audit's heat duties of a thermal result (``results.datasets["heat_duties"]``,
    [`rotarydryer.thermal.audit.heat_duties`][rotarydryer.thermal.audit.heat_duties]): ``heat_release_W``, the duties that add
    up to it (`rotarydryer.thermal.audit.HEAT_DUTY_PARTS`) and ``heat_duty_exhaust_latent_W``; None for
    a result saved before the energy audit (no such dataset)."""
    ds = results.datasets.get("heat_duties")
    if ds is None:
        return None
    return {str(n): float(w) for n, w in zip(ds.duty.values, ds.power.values)}


def _energy_audit_html(results, audit: dict | None = None) -> str:
    """The report's "Energy audit": heat-duty waterfall and table, dew-point margin, shell per section
    against the limit, and (``audit``: `rotarydryer.studies.energy.EnergyAudit.to_dict`) the what-ifs."""
    from ..thermal.audit import HEAT_DUTY_LABELS, HEAT_DUTY_PARTS
    from .plots import plot_heat_duties

    duties = heat_duties(results)
    if duties is None:
        return ('<h3>Energy audit</h3><p class="note">These results were saved before the energy audit (no heat '
                'duties): rerun the case for them.</p>')
    sc = results.scalars
    power = unit_of("power")
    release = duties["heat_release_W"]
    t_rows = [(HEAT_DUTY_LABELS["heat_release_W"], show(release, "power", with_unit=False), "100")]
    t_rows += [(f"  {HEAT_DUTY_LABELS[k]}", show(duties[k], "power", with_unit=False),
                f"{100 * duties[k] / release:.1f}" if release else "") for k in HEAT_DUTY_PARTS]
    t_rows.append((HEAT_DUTY_LABELS["heat_duty_exhaust_latent_W"],
                   show(duties["heat_duty_exhaust_latent_W"], "power", with_unit=False), ""))
    big = sorted(((duties[k], HEAT_DUTY_LABELS[k]) for k in HEAT_DUTY_PARTS), reverse=True)[:3]
    cap_e = (f"heat duties: a heat release of {show(release, 'power')}"
             + (" (fuel x lower heating value)" if "fuel_rate_kg_s" in sc else " (the heat put into the gas)")
             + "; the largest: " + ", ".join(f"{name} {show(w, 'power')}" for w, name in big))
    if "specific_energy_kJ_kg_water" in sc:
        cap_e += (f"; {show_output('specific_energy_kJ_kg_water', sc['specific_energy_kJ_kg_water'])} of water "
                  "evaporated" + (f", thermal efficiency {100 * sc['thermal_efficiency']:.1f} %"
                                  if _is_number(sc.get("thermal_efficiency")) else ""))
    parts = [f'<h3>Energy audit</h3>'
             f'{_img(plot_heat_duties(duties, unit=power), "energy audit waterfall", cap_e)}'
             f'{_table(("heat duty", power, "% of release"), t_rows)}'
             f'<p class="note">{html.escape(_DUTIES_NOTE)}</p>'
             '<p class="mvm">The heat release, the fuel rate and the shell loss were not measured; the heat duties '
             'are model results only.</p>']
    dew, margin = sc.get("gas_outlet_dew_point_degC"), sc.get("gas_outlet_dew_point_margin_K")
    if dew is not None and margin is not None:
        p_kpa = sc.get("gas_pressure_Pa", 101325.0) / 1e3
        parts.append(f'<p><b>Exhaust dew point:</b> {show(dew, "temperature")} at {_fmt(p_kpa)} kPa; the exhaust, '
                     f'at {show(sc["gas_outlet_temperature_degC"], "temperature")}, is {show_delta(abs(margin), "temperature")} '
                     + ("above it." if margin > 0 else "below it: water condenses in the ducts and the bag filter.")
                     + "</p>")
    parts.append(_shell_html(results))
    if audit is not None:
        parts.append(_savings_html(audit))
    return "".join(parts)


def _shell_html(results) -> str:
    """The shell per section (loss, hottest surface and steel) against ``shell.max_temperature``."""
    ds = results.datasets.get("shell_sections")
    if ds is None:
        return ""
    sc = results.scalars
    limit = sc.get("shell_temperature_limit_degC")
    exceeded = results.model_choices.get("shell_temperature_limit_exceeded")
    rows = [(str(sec), show(float(q), "power", with_unit=False), show(float(ts), "temperature", with_unit=False),
             show(float(tw), "temperature", with_unit=False))
            for sec, q, ts, tw in zip(ds.section.values, ds.shell_loss.values, ds.max_surface_temperature.values,
                                      ds.max_wall_temperature.values)]
    t_unit = unit_of("temperature")
    verdict = ("no limit set (shell.max_temperature; e.g. 593 degC, the mild-steel limit Ajayi (2011) Ch. 7 "
               "quotes from API 521)" if limit is None else
               f"limit shell.max_temperature = {show(limit, 'temperature')}: "
               + ("<b>exceeded</b>" if exceeded else "met"))
    return ("<h4>Shell</h4>"
            + _table(("section", f"shell loss ({unit_of('power')})", f"hottest outer surface ({t_unit})",
                      f"hottest steel ({t_unit})"), rows)
            + f'<p class="note">Hottest steel {show(sc.get("shell_max_wall_temperature_degC", np.nan), "temperature")} '
              f"(its inside face), hottest outer surface {show(sc.get('shell_max_surface_temperature_degC', np.nan), 'temperature')}; "
              f"{verdict}. Lagging cools the outside and heats the steel.</p>")


def _savings_html(audit: dict) -> str:
    """The what-ifs of a saved energy audit (``rotarydryer audit --out DIR``: DIR/audit.json)."""
    rows = []
    for w in audit.get("savings", []):
        if w.get("error"):
            rows.append((w["label"], "no steady state", "", "", "", ""))
            continue
        if w.get("infeasible"):     # the case's burner cannot make its gas: no saving
            rows.append((w["label"], "not feasible: the burner cannot make this gas", "", "", "", ""))
            continue
        held = w.get("held") or {}
        fuel = w.get("fuel_saved_kg_s")
        rows.append((w["label"], show(w["heat_saved_W"], "power", with_unit=False),
                     "" if fuel is None else show(fuel, "fuel_flow", with_unit=False),
                     show_delta(w["product_moisture_change_kg_kg"], "moisture", with_unit=False),
                     show(held["heat_saved_W"], "power", with_unit=False) if held else "",
                     show(held["gas_inlet_temperature_degC"], "temperature", with_unit=False) if held else ""))
    if not rows:
        return ""
    note = ("Each what-if is a coupled steady state of the case with one change (rotarydryer audit). At the same gas "
            "inlet temperature a measure also dries the product further (the change of product moisture); the held "
            "columns give the saving at the base product moisture, the gas inlet temperature found by the target "
            "solver. Feed preheating takes its own heat (from waste heat) outside the dryer.")
    return ("<h4>What-if savings</h4>"
            + _table(("measure", f"heat saved ({unit_of('power')})", f"fuel saved ({unit_of('fuel_flow')})",
                      "product moisture change" + (" (pp)" if unit_of("moisture") == "%" else f" ({unit_of('moisture')})"),
                      f"heat saved, held moisture ({unit_of('power')})", f"gas inlet, held ({unit_of('temperature')})"),
                     rows)
            + f'<p class="note">{html.escape(note)}</p>')


def _load_saved(path, option: str, kind: str, key: str, key_type, what: str, hint: str) -> dict:
    """A saved result of another command (JSON with ``kind`` = ``kind`` and a ``key`` of ``key_type``),
    or ``ValueError`` naming ``option``, the file and what is wrong (``hint``: how to make one)."""
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"{option} {str(p)!r}: not a file ({hint})")
    try:
        data = json.loads(p.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"{option} {str(p)!r}: not a JSON file ({exc})") from None
    if not isinstance(data, dict) or data.get("kind") != kind or not isinstance(data.get(key), key_type):
        raise ValueError(f"{option} {str(p)!r}: not {what} (no kind = {kind})")
    return data


def load_audit(path) -> dict:
    """A saved energy audit (``rotarydryer audit --out DIR``: DIR/audit.json)."""
    return _load_saved(path, "--audit", "energy_audit", "savings", list, "an energy audit",
                       "give DIR/audit.json of rotarydryer audit --out DIR")


def check_saved_audit(audit: dict, results, path) -> None:
    """Refuse (``ValueError``) a saved energy audit that is not of the report's run: each of its heat duties (the
    release, evaporation, solids and water heating, shell, exhaust, leaks, ...) must be the run's to 1e-6 of the
    release (another case's audit.json was shown as this dryer's savings; with a burner, the release alone does not
    see a changed feed)."""
    from ..thermal.audit import HEAT_DUTY_LABELS

    sc = results.scalars if results is not None else {}
    mine = sc.get("heat_release_W")
    duties = audit.get("heat_duties") or {}
    theirs = duties.get("heat_release_W")
    where = f"its case {audit.get('case', '?')}" + (f" with {audit['overrides']}" if audit.get("overrides") else "")
    if not _is_number(mine):
        raise ValueError(f"--audit {str(path)!r}: this report's source has no heat and mass transfer to compare the "
                         f"audit ({where}) with")
    scale = 1e-6 * max(abs(float(mine)), 1.0)
    differ = [k for k, v in duties.items() if _is_number(v) and _is_number(sc.get(k))
              and abs(float(v) - float(sc[k])) > scale]
    if not _is_number(theirs) or abs(float(theirs) - float(mine)) > scale or differ:
        k = "heat_release_W" if not _is_number(theirs) or abs(float(theirs) - float(mine)) > scale else differ[0]
        label = HEAT_DUTY_LABELS.get(k, k)
        raise ValueError(f"--audit {str(path)!r} is of another dryer or operating point ({where}: {label} "
                         f"{fmt(float(duties[k]) / 1e3) if _is_number(duties.get(k)) else 'n/a'} kW; this report's "
                         f"{fmt(float(sc[k]) / 1e3)} kW): give the audit.json of `rotarydryer audit` on this case with "
                         "the same --set")


def _same_value(a, b) -> bool:
    try:
        return float(a) == float(b)
    except (TypeError, ValueError):
        return str(a).strip().lower() == str(b).strip().lower()


def check_saved_sensitivity(study: dict, source: str, sets: dict, path) -> None:
    """Refuse (``ValueError``) a saved sensitivity study of another case or base point than the report's: its case
    (by file or case name) must be the report's source, and every key it did not vary must have the report's value
    (its ``base_overrides`` against the report's ``--set``). A study of another dryer was shown without a word."""
    theirs = str(study.get("case", ""))
    if Path(theirs).stem != Path(str(source)).stem:
        raise ValueError(f"--sensitivity {str(path)!r} is a study of case {theirs!r}, this report is of {source!r}: "
                         "give the sensitivity.json of `rotarydryer sensitivity` on this case")
    varied = set(study.get("params") or {})
    base = {k: v for k, v in (study.get("base_overrides") or {}).items() if k not in varied}
    mine = {k: v for k, v in (sets or {}).items() if k not in varied}
    differ = sorted(k for k in set(base) | set(mine) if k not in base or k not in mine or not _same_value(base[k], mine[k]))
    if differ:
        k = differ[0]
        raise ValueError(f"--sensitivity {str(path)!r} was run at another point of {theirs!r}: {k} = "
                         f"{base.get(k, 'the case value')!s} in the study, {mine.get(k, 'the case value')!s} in this "
                         "report (--set): give the same --set to both, or rerun the study")


def _thermal_comparison_html(results) -> tuple[str, str]:
    """Caption of the thermal-profile figure and the model-versus-measured statement (with a
    table of the measured points) from `rotarydryer.report.manager.thermal_comparison`."""
    from .manager import thermal_comparison

    sc = results.scalars
    cap = (f"temperature and moisture along the dryer: product {show(sc.get('product_moisture_kg_kg', np.nan), 'moisture')} "
           f"moisture (wet basis) at {show(sc.get('product_temperature_degC', np.nan), 'temperature')}, exhaust gas "
           f"{show(sc.get('gas_outlet_temperature_degC', np.nan), 'temperature')}")
    tc = thermal_comparison(results)
    if not tc["points"]:
        return cap + "; no measured values for this run", f'<p class="mvm">{html.escape(tc["reason"])}</p>'
    pts = {p["quantity"]: p for p in tc["points"]}
    if "product moisture" in pts:
        p = pts["product moisture"]
        cap += (f"; measured product moisture {p['measured']:.2f} % (error {p['error']:+.2f} points)")
    if "gas outlet temperature" in pts:
        p = pts["gas outlet temperature"]
        cap += f", measured exhaust {p['measured']:.0f} degC (error {p['error']:+.1f} degC)"
    sentences = []
    for unit, word in (("degC", "temperatures"), ("% points", "moistures")):
        m = tc["summary"].get(unit)
        if m:
            u = "degC" if unit == "degC" else "percentage points"
            sentences.append(f"{word} at {m['n']} measured point(s): mean absolute error {m['mae']:.2f} {u}, "
                             f"maximum error {m['max']:.2f} {u} ({m['max_at']})")
    note = ""
    if tc.get("tuned"):
        note = (f" Test {tc['test']} is the test the case's gas flow and heat-transfer area were tuned on (case file), "
                "so its product moisture and exhaust temperature are fitted, not predicted.")
    rows = [(p["quantity"], p["where"], f"{p['measured']:.2f}", f"{p['model']:.2f}", f"{p['error']:+.2f}",
             p["unit"], p["source"]) for p in tc["points"]]
    if any("Table 3.3" in p["source"] for p in tc["points"]):
        note += (" The axial moistures were sampled along the dryer before a shutdown (Ajayi (2011) Table 3.3), "
                 "not during the test.")
    text = (f'<p class="mvm"><b>Model against measured:</b> {"; ".join(sentences)}.{note}</p>'
            + _table(("quantity", "where", "measured", "model", "error (model - measured)", "unit", "source"), rows,
                     left_cols=2))
    return cap, text


def load_sensitivity(path) -> dict:
    """A saved sensitivity study (``rotarydryer sensitivity --out DIR``: DIR/sensitivity.json)."""
    return _load_saved(path, "--sensitivity", "sobol_sensitivity", "indices", dict, "a sensitivity result",
                       "give DIR/sensitivity.json of rotarydryer sensitivity")


def sensitivity_section(data: dict) -> str:
    """HTML section of a sensitivity study (``SensitivityResult.to_dict()``): indices table with
    confidence intervals, output distributions, the figure, failed runs and notes."""
    from ..studies.sensitivity import plot_sensitivity

    rows = [[o, p, _fmt(v.get("S1")), _fmt(v.get("S1_conf")), _fmt(v.get("ST")), _fmt(v.get("ST_conf"))]
            for o, per in data.get("indices", {}).items() for p, v in per.items()]
    keys = ["n", "mean", "sd", "p5", "p50", "p95"]
    drows = [[o] + [_fmt(d.get(k)) for k in keys] for o, d in data.get("distributions", {}).items()]
    ranges = ", ".join(f"{k} in [{_fmt(float(a))}, {_fmt(float(b))}]" for k, (a, b) in data.get("params", {}).items())
    notes = "".join(f"<li>{html.escape(str(n))}</li>" for n in data.get("notes", []))
    conf = 100 * float(data.get("conf_level") or 0.95)
    return (f'<section id="sensitivity"><h2>Global sensitivity (Sobol) and uncertainty</h2>'
            f'<p class="note">Case {html.escape(str(data.get("case", "")))}; uniform inputs {html.escape(ranges)}; '
            f'{data.get("samples")} base samples, {data.get("n_runs")} runs, {data.get("n_failed")} failed '
            f'(blocks with a failed run left out). &plusmn;: half-width of the {conf:.0f} % bootstrap interval.</p>'
            + _table(["output", "input", "S1", "\u00b1", "ST", "\u00b1"], rows, left_cols=2)
            + _table(["output"] + keys, drows)
            + _img(plot_sensitivity(data), "Sobol indices and output distributions",
                   f"Sobol indices and output distributions of {data.get('n_runs')} runs "
                   f"({data.get('samples')} base samples, {data.get('n_failed')} failed)")
            + (f"<ul class='note'>{notes}</ul>" if notes else "") + "</section>")


def _executive_summary(results) -> str:
    """What was run and what the key numbers mean, in sentences (the report's first section)."""
    s, inp = results.scalars, results.inputs
    op = inp.get("operating", {}) or {}
    gas = inp.get("gas") or {}
    facts = []
    feed = s.get("feed_rate_kg_s", op.get("feed_rate"))
    if feed is not None:
        facts.append(f"feed {show(float(feed), 'mass_flow')} of wet solids")
    from .manager import MODEL_SOURCES, _test_row, run_gas_inlet_temperature

    rpm = (results.model_choices.get("parameters") or {}).get("rpm", op.get("rpm"))
    if rpm is None:
        rpm = (_test_row(inp) or {}).get("rpm")         # the selected [[tests]] row's, as the case builder takes it
    if rpm is not None:
        facts.append(f"{_fmt(float(rpm))} rev/min")

    t_gas = run_gas_inlet_temperature(inp)      # the run's: a [[tests]] row's where it gives one
    g_flow = s.get("gas_flow_kg_s", gas.get("flow"))
    if t_gas is not None:
        facts.append(f"{gas.get('direction', '')} gas at {show(float(t_gas), 'temperature')}"
                     + (f", {show(float(g_flow), 'mass_flow')}" if g_flow is not None else ""))

    model = str(results.model_choices.get("model", ""))
    src = MODEL_SOURCES.get(model)
    thermal = (", heat and mass transfer after Ajayi (2011) ch. 6" if "energy_balance" in results.datasets else "")
    lines = [f"<p>Case <b>{html.escape(results.case_name or results.kind)}</b> ({html.escape(str(results.kind))}, "
             f"solids transport model {html.escape(model)}{' after ' + html.escape(src) if src else ''}"
             f"{thermal}), operating point: "
             f"{html.escape(', '.join(facts) or 'as in the case file')}.</p><ul>"]
    if "mean_residence_time_s" in s:
        dusty = (s.get("dust_rate_kg_s") or 0.0) > 0 and s.get("rtd_mean_residence_time_s") is not None
        lines.append(f"<li>The solids stay <b>{show(s['mean_residence_time_s'], 'time')}</b> on average"
                     + (f" (the product {show(s['rtd_mean_residence_time_s'], 'time')}, the dust the gas carries off "
                        "less)" if dusty else "")
                     + f"; the drum holds {show(s.get('total_holdup_kg', float('nan')), 'mass')}.</li>")
    if "measured_mean_s" in s and "tracer_mean_s" in s and s["measured_mean_s"]:
        err = 100 * (s["tracer_mean_s"] / s["measured_mean_s"] - 1)
        lines.append(f"<li>Model against the measured tracer curve: mean {show(s['tracer_mean_s'], 'time')} against "
                     f"{show(s['measured_mean_s'], 'time')} ({err:+.1f} %), the curves' means from the injection start "
                     "(the model's on this report's state; the validation table's tracer items run the transport "
                     "model alone, as its calibration).</li>")
    if "product_moisture_kg_kg" in s:
        lines.append(f"<li>Product moisture <b>{html.escape(show(s['product_moisture_kg_kg'], 'moisture'))}</b> (wet basis) at "
                     f"{show(s.get('product_temperature_degC', float('nan')), 'temperature')}; exhaust gas "
                     f"{show(s.get('gas_outlet_temperature_degC', float('nan')), 'temperature')}.</li>")
    if "specific_energy_kJ_kg_water" in s:
        lines.append(f"<li>Evaporating the water costs <b>{show_output('specific_energy_kJ_kg_water', s['specific_energy_kJ_kg_water'])}</b> of heat "
                     "in the gas (" + (f"thermal efficiency {_fmt(100 * s['thermal_efficiency'], 3)} %; "
                                       if _is_number(s.get("thermal_efficiency")) else "")
                     + "direct dryers typically run at 3 000-6 000 kJ/kg).</li>")
    if s.get("fuel_rate_kg_s") is not None:
        lines.append(f"<li>The burner needs {show_output('fuel_rate_kg_s', s['fuel_rate_kg_s'])} of fuel.</li>")
    elif results.model_choices.get("fuel_rate_error"):
        from ..thermal.states import fuel_rate_note

        note = fuel_rate_note({"fuel_rate_error": results.model_choices["fuel_rate_error"]})
        lines.append(f'<li class="warning"><b>Warning:</b> {html.escape(note)}.</li>')
    lines.append("</ul>")
    return f'<section id="executive-summary"><h2>Summary</h2>{"".join(lines)}</section>'


def _operating_section(results) -> str:
    """Operating conditions of the run (table) and the drawing of the dryer (inline SVG)."""
    from .drawing import dryer_layout, dryer_svg
    from .manager import operating_conditions

    rows = operating_conditions(results)
    lay = dryer_layout(results.inputs)
    where = {"co-current": "enters at the feed end", "counter-current": "enters at the product end"}
    cap = (f"the dryer: {lay['length']:g} m long, {lay['diameter']:g} m diameter, slope {lay['slope']:g} deg, "
           f"{len(lay['sections'])} section(s); the gas ({lay['direction'] or 'none'}) "
           f"{where.get(lay['direction'], 'is not modelled')}"
           + ("; burner / combustion chamber at the gas inlet end" if lay["burner"] else ""))
    return (f'<section id="operating"><h2>Operating conditions</h2>'
            f'{_svg_figure(dryer_svg(results.inputs), cap)}'
            f'{_table(("condition", "value", "unit / source"), rows, left_cols=3)}</section>')


def _references_section(body: str) -> str:
    """Full references of every source cited (author-year) in ``body`` (HTML), from the
    project's bibliography (`rotarydryer.report.references`)."""
    from .references import cited_keys, format_reference

    keys = cited_keys(html.unescape(body))
    if not keys:
        return ""
    items = "".join(f'<li id="ref-{k}">{format_reference(k)}</li>' for k in keys)
    return f'<section id="references"><h2>References</h2><ol class="refs">{items}</ol></section>'


def validation_section(report) -> str:
    """The "Validation" section: every item of the case's validation (rotarydryer.validate) with its
    measured and model value, error, tolerance and status; known misses with their reasons."""
    from ..validate import display_cells

    s = report.summary()
    rows, misses = [], []
    for it in report.items:
        status = it.status + (" (known miss)" if it.known_miss and it.status == "pass" else "")
        if "balance error" in (it.description or it.id):      # a relative balance error: its own format
            cells = [_fmt(it.measured) if it.measured is not None else "-",
                     fmt_error(it.model) if it.model is not None else "-", "-", f"{it.kind} {_fmt(it.tolerance)}"]
        else:       # in the display units (--units), as the report's other tables; each cell with its unit
            cells = list(display_cells(it))
        rows.append([html.escape(it.description or it.id), *(html.escape(c) for c in cells), html.escape(status)])
        if it.status != "pass" and (it.known_miss or it.message):
            misses.append(f"<li><b>{html.escape(it.id)}</b>: {html.escape(it.known_miss or it.message)}</li>")
    head = (f"<p>{s['n_items']} items of the case as its file gives it (the run's --set overrides not applied): "
            f"{s['n_pass']} pass, {s['n_fail']} fail, {s['n_known_miss']} known misses. Tolerances and their reasons: "
            f"<code>rotarydryer/data/validation.toml</code>; the whole suite: <code>rotarydryer validate</code>.</p>")
    if not report.items:
        head = "<p>The case has no measured or published numbers to compare with.</p>"
    table = _table(["item", "measured", "model", "error", "tolerance", "status"], rows) if rows else ""
    known = f"<ul>{''.join(misses)}</ul>" if misses else ""
    return f'<section id="validation"><h2>Validation against the plant data</h2>{head}{table}{known}</section>'


def render_report(results=None, *, drums=None, title: str | None = None, subtitle: str = "",
                  sensitivity: dict | None = None, validation=None, audit: dict | None = None) -> str:
    """HTML text of the report.

    Parameters
    ----------
    results : rotarydryer.results.Results, optional
        Transport results (their inputs also give the flight geometry).
    drums : list of dict, optional
        Flighted sections to draw (see `rotarydryer.report.figures.case_drums`);
        default: those of ``results.inputs``.
    title, subtitle : str
    validation : rotarydryer.validate.ValidationReport, optional
        The case's validation (`validation_section`).
    audit : dict, optional
        A saved energy audit (`load_audit`): its what-if savings join the energy audit.
    """
    from .figures import case_drums

    if results is None and not drums:
        raise ValueError("render_report needs results or drums")
    if drums is None:
        drums = case_drums(results.inputs, results)
    if title is None:
        title = (results.inputs.get("meta", {}).get("title") or results.case_name) if results is not None else "Flight geometry"
    body = []
    if results is not None:
        body.append(_executive_summary(results))
        body.append(_operating_section(results))
        body.append(_transport_sections(results))
    if results is not None and "energy_balance" in results.datasets:
        body.append(_thermal_section(results, audit))
    if results is not None and "size_classes" in results.datasets:
        body.append(_size_section(results))
    body.append(_geometry_sections(drums, results))
    if sensitivity is not None:
        body.append(sensitivity_section(sensitivity))
    if validation is not None:
        body.append(validation_section(validation))
    if results is not None:
        body.append(f"""<section id="inputs"><h2>Inputs and model choices</h2>
<details><summary>model choices</summary><pre>{html.escape(json.dumps(results.model_choices, indent=1))}</pre></details>
<details><summary>case (SI units, angles in deg)</summary><pre>{html.escape(json.dumps(results.inputs, indent=1))}</pre></details>
</section>""")
        from .references import strip_line_numbers

        cites = results.inputs.get("meta", {}).get("citations", [])
        if cites:
            body.append('<section id="sources"><h2>Where the case data come from</h2><ul>' +
                        "".join(f"<li>{html.escape(strip_line_numbers(c))}</li>" for c in cites) + "</ul></section>")
    body.append(_references_section("".join(body)))
    version = results.version if results is not None else __version__
    created = results.created if results is not None else ""
    sub = subtitle or (f"case {results.case_name}, model {results.model_choices.get('model')}" if results else "")
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{html.escape(title)}</title>
<meta name="generator" content="rotarydryer {html.escape(version)}">
<style>{_CSS}</style></head>
<body><header><h1>{html.escape(title)}</h1>
<p>{html.escape(sub)} &middot; rotarydryer {html.escape(version)} {html.escape(created)}</p></header>
<main>{_number_figures(''.join(body))}</main></body></html>
"""


def resolve_source(source: str, overrides: dict | None = None, *, repose_angle: float | None = None):
    """``(results, drums, title)`` for a report source: a saved results file (``.nc``), a
    case name or ``.toml`` file (run), or a built-in drum preset (geometry only).

    ``repose_angle`` (deg, in (0, 90); checked before a case is run) is the repose angle of
    the flight pictures of every section; default: the case's mean per section
    (``drums`` is then None, see `render_report`), a drum preset's design repose angle (else 45 deg).
    """
    from .._validation import check_range
    from ..cases import list_cases
    from ..geometry.presets import DEFAULT_REPOSE_ANGLE, builtin_drums, preset_drum
    from ..results import Results
    from ..simulation import run_case

    if repose_angle is not None:
        repose_angle = float(check_range("repose_angle", repose_angle, 0.0, 90.0, unit="deg"))
    p = Path(source)
    if p.suffix in (".nc", ".h5") and p.exists():
        if overrides:
            raise ValueError(f"--set cannot be applied to a saved result ({source})")
        results = Results.load(p)
        return results, _case_drums_at(results, repose_angle), None
    if source in list_cases() or (p.suffix == ".toml" and p.exists()):
        results = run_case(source, overrides, fit_rtd=True)
        return results, _case_drums_at(results, repose_angle), None
    if source in builtin_drums():
        if overrides:       # a drum has no case keys: they were ignored, an unknown one too (found by fuzzing)
            raise ValueError(f"--set cannot be applied to a drum preset ({source}): it has no case keys; give a case "
                             "name or file")
        drum, e = preset_drum(source)
        phi = float(e.get("repose_angle", DEFAULT_REPOSE_ANGLE)) if repose_angle is None else repose_angle
        d = dict(name=source, drum=drum, length=e["length"], slope=e["slope"], rpm=e["rpm"],
                 bulk_density=e["bulk_density"], repose_angle=phi)
        return None, [d], f"Flight geometry: {e['description']}"
    raise ValueError(f"source = {source!r} is not a results file (.nc), a case ({', '.join(list_cases())}), "
                     f"a .toml case file nor a drum preset ({', '.join(builtin_drums())})")


def _case_drums_at(results, repose_angle):
    """The flighted sections of ``results`` drawn at ``repose_angle`` deg (None: None, i.e.
    the default of `render_report`)."""
    if repose_angle is None:
        return None
    from .figures import case_drums

    drums = case_drums(results.inputs, results)
    for d in drums:
        d["repose_angle"] = repose_angle
    return drums


def build_report(source: str, overrides: dict | None = None, *, repose_angle: float | None = None) -> str:
    """HTML text of the report of ``source`` (see `resolve_source`)."""
    results, drums, title = resolve_source(source, overrides, repose_angle=repose_angle)
    return render_report(results, drums=drums, title=title, validation=case_validation(source, results))


def case_validation(source: str, results):
    """The validation (`rotarydryer.validate.run_validation`) of the case a report shows: the
    case ``source`` names, or a saved result's case when it is a packaged case or a case file; None
    for a drum preset or a result of an unknown case."""
    if results is None:
        return None
    from ..cases import list_cases
    from ..validate import run_validation

    case = results.case_name if Path(source).suffix in (".nc", ".h5") else source
    if case in list_cases() or (Path(case).suffix == ".toml" and Path(case).is_file()):
        try:
            return run_validation([case])
        except ValueError:      # the case as its file gives it does not run (a report of a --set run that does:
            return None         # refused for the file's own point, which the report does not show)
    return None


def write_report(source, out, overrides: dict | None = None, *, repose_angle: float | None = None) -> Path:
    """Write the report of ``source`` (results file, case, drum preset or a Results object)
    to ``out`` atomically; returns the path."""
    from ..results import Results

    text = render_report(source) if isinstance(source, Results) else build_report(
        str(source), overrides, repose_angle=repose_angle)
    return write_html(text, out)


def write_html(text: str, out) -> Path:
    """Write ``text`` to ``out`` atomically (temporary file beside it + os.replace)."""
    return write_text_atomic(out, text)
