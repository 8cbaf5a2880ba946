"""Schematic drawing of a dryer as inline SVG text (no Matplotlib, no external resources).

>>> from rotarydryer.cases import load_case
>>> svg = dryer_svg(load_case("lee2008_invicta").model_dump())
>>> svg.startswith("<svg") and 'data-direction="counter-current"' in svg
True

The drum is drawn to scale along its axis (length) with its diameter at the same scale,
clipped to a readable band, and tilted by its real slope.  Feed enters at the left end and the
product leaves at the right end; the gas arrows run in the gas direction of the case
(co-current: from the feed end, counter-current: from the product end), and the burner /
combustion chamber is drawn at the gas inlet end when the case has one.  Elements carry
classes (``drum``, ``section``, ``gas-arrow``, ``burner``, ``feed``, ``product``) so that the
drawing can be checked without rendering it.
"""

from __future__ import annotations

import html
import math

__all__ = ["dryer_layout", "dryer_svg"]


def dryer_layout(inputs: dict) -> dict:
    """What the drawing needs from a case (the ``inputs`` of a Results or ``case.model_dump()``):
    sections ``[(name, kind, length m, n_flights or None)]``, diameter (m), length (m), slope
    (deg), gas direction ("co-current", "counter-current" or None without gas) and burner (bool)."""
    drum = inputs.get("drum", {}) or {}
    secs = []
    if not inputs.get("sections"):
        secs.append(("dryer", "flighted", float(drum.get("length") or 0.0), drum.get("n_flights")))
    else:
        for s in inputs["sections"]:
            n = s.get("n_flights")
            if n is None and s.get("kind") == "flighted":
                n = drum.get("n_flights")
            secs.append((str(s["name"]), str(s["kind"]), float(s["length"]), n))
    gas = inputs.get("gas") or {}
    op = inputs.get("operating") or {}
    direction = gas.get("direction") or op.get("gas_flow")   # gas_flow: results saved before the one schema
    thermal = inputs.get("thermal") or {}
    burner = gas.get("burner") is not None or thermal.get("burner") is not None
    return dict(sections=secs, diameter=2.0 * float(drum["radius"]), length=sum(s[2] for s in secs),
                slope=float(drum.get("slope") or 0.0), direction=direction, burner=burner)


def _arrow(x1, y, x2, cls, colour, width=2.0) -> str:
    """A horizontal arrow from x1 to x2 (head at x2) as a path and a head polygon."""
    d = 1.0 if x2 > x1 else -1.0
    h = 7.0
    return (f'<g class="{cls}" data-from="{x1:.1f}" data-to="{x2:.1f}">'
            f'<path d="M {x1:.1f} {y:.1f} L {x2 - d * h:.1f} {y:.1f}" stroke="{colour}" stroke-width="{width}" '
            f'fill="none"/>'
            f'<polygon points="{x2:.1f},{y:.1f} {x2 - d * h:.1f},{y - 4:.1f} {x2 - d * h:.1f},{y + 4:.1f}" '
            f'fill="{colour}"/></g>')


def dryer_svg(inputs: dict, *, width: int = 820) -> str:
    """SVG text of the dryer of ``inputs`` (see `dryer_layout`): drum with its sections
    (flighted shaded with flights, unflighted plain with a bed), slope, feed inlet and product
    outlet, gas arrows in the gas direction, the burner at the gas inlet end, D and L labelled."""
    lay = dryer_layout(inputs)
    L, D, slope = lay["length"], lay["diameter"], lay["slope"]
    margin_l, margin_r = 175.0, 135.0
    scale = (width - margin_l - margin_r) / L                # px per m along the axis
    h = min(max(D * scale, 46.0), 130.0)                     # drum height, px (scale-ish)
    scaled = abs(h - D * scale) < 0.5
    top = 70.0
    drop = (width - margin_l - margin_r) * math.tan(math.radians(slope))
    height = int(top + h + drop + 115)
    x0, x1, yc = margin_l, margin_l + L * scale, top + h / 2
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" class="dryer-drawing" width="{width}" height="{height}" '
           f'viewBox="0 0 {width} {height}" role="img" font-family="sans-serif" font-size="12" '
           f'data-direction="{html.escape(str(lay["direction"]))}" data-burner="{str(lay["burner"]).lower()}">',
           f'<title>Dryer drawing: L = {L:g} m, D = {D:g} m, slope {slope:g} deg, gas '
           f'{html.escape(str(lay["direction"] or "none"))}{", burner" if lay["burner"] else ""}</title>',
           f'<g class="drum" transform="rotate({slope:g} {x0:.1f} {yc:.1f})">']
    x = x0
    for name, kind, length, nf in lay["sections"]:
        w = length * scale
        flighted = kind == "flighted"
        out.append(f'<g class="section" data-name="{html.escape(name)}" data-kind="{html.escape(kind)}">'
                   f'<rect x="{x:.1f}" y="{top:.1f}" width="{w:.1f}" height="{h:.1f}" '
                   f'fill="{"#f3e3c3" if flighted else "#ececec"}" stroke="#333" stroke-width="1.2"/>')
        if flighted:
            n_marks = max(2, int(w / 9))
            for k in range(n_marks):
                xf = x + (k + 0.5) * w / n_marks
                out.append(f'<line x1="{xf:.1f}" y1="{top:.1f}" x2="{xf:.1f}" y2="{top + 0.12 * h:.1f}" '
                           f'stroke="#8a6416" stroke-width="1"/>'
                           f'<line x1="{xf:.1f}" y1="{top + h:.1f}" x2="{xf:.1f}" y2="{top + 0.88 * h:.1f}" '
                           f'stroke="#8a6416" stroke-width="1"/>')
        else:
            out.append(f'<rect x="{x:.1f}" y="{top + 0.8 * h:.1f}" width="{w:.1f}" height="{0.2 * h:.1f}" '
                       f'fill="#d9a441" opacity="0.8"/>')
        label = name if len(lay["sections"]) > 1 else ""
        sub = f"{kind}, {length:g} m" + (f", {nf} flights" if flighted and nf else "")
        if w < 150:
            sub = f"{length:g} m" + (f", {nf} fl." if flighted and nf and w > 80 else "")
        out.append(f'<text x="{x + w / 2:.1f}" y="{top - 18:.1f}" text-anchor="middle" font-weight="bold">'
                   f'{html.escape(label)}</text><text x="{x + w / 2:.1f}" y="{top - 5:.1f}" text-anchor="middle" '
                   f'font-size="10">{html.escape(sub if w > 70 else f"{length:g} m")}</text></g>')
        x += w
    # gas arrows inside the drum, in the gas direction
    co = lay["direction"] == "co-current"
    if lay["direction"] in ("co-current", "counter-current"):
        n_arrows = 3
        seg = (x1 - x0) / n_arrows
        out.append('<g class="gas-flow">')
        for k in range(n_arrows):
            a, b = x0 + (k + 0.2) * seg, x0 + (k + 0.8) * seg
            out.append(_arrow(a, yc - 0.18 * h, b, "gas-arrow", "#b52b27") if co
                       else _arrow(b, yc - 0.18 * h, a, "gas-arrow", "#b52b27"))
        out.append('</g>')
    # solids arrow (always feed end -> product end)
    out.append(_arrow(x0 + 0.3 * (x1 - x0), yc + 0.22 * h, x0 + 0.7 * (x1 - x0), "solids-arrow", "#5b3a12", 1.5))
    # feed inlet (top left) and product outlet (bottom right)
    out.append(f'<g class="feed"><path d="M {x0 - 55:.1f} {top - 30:.1f} L {x0 - 20:.1f} {top - 30:.1f} '
               f'L {x0 - 10:.1f} {yc - 6:.1f} L {x0 + 6:.1f} {yc - 6:.1f}" stroke="#5b3a12" stroke-width="2" '
               f'fill="none"/><polygon points="{x0 + 8:.1f},{yc - 6:.1f} {x0 + 1:.1f},{yc - 10:.1f} '
               f'{x0 + 1:.1f},{yc - 2:.1f}" fill="#5b3a12"/>'
               f'<text x="{x0 - 55:.1f}" y="{top - 36:.1f}">wet feed in</text></g>')
    out.append(f'<g class="product"><path d="M {x1 - 6:.1f} {top + 0.85 * h:.1f} L {x1 + 14:.1f} '
               f'{top + 0.85 * h:.1f} L {x1 + 14:.1f} {top + h + 36:.1f}" stroke="#5b3a12" stroke-width="2" '
               f'fill="none"/><polygon points="{x1 + 14:.1f},{top + h + 42:.1f} {x1 + 10:.1f},{top + h + 35:.1f} '
               f'{x1 + 18:.1f},{top + h + 35:.1f}" fill="#5b3a12"/>'
               f'<text x="{x1 + 20:.1f}" y="{top + h + 42:.1f}">product out</text></g>')
    # gas inlet / exhaust labels and the burner at the gas inlet end
    if lay["direction"] in ("co-current", "counter-current"):
        gin, gout = (x0, x1) if co else (x1, x0)
        side = -1.0 if co else 1.0                          # outward from the gas inlet end
        if lay["burner"]:
            bx = gin - 115 if co else gin + 20
            ly = yc + 0.3 * h + 14 if co else yc - 0.3 * h - 24     # label below / above the box
            out.append(f'<g class="burner"><rect x="{bx:.1f}" y="{yc - 0.3 * h:.1f}" '
                       f'width="50" height="{0.6 * h:.1f}" fill="#f6d2b8" stroke="#333"/>'
                       f'<path d="M {bx + 12:.1f} {yc + 8:.1f} q 6 -22 13 -26 q 7 4 13 26 z" fill="#e8742a"/>'
                       f'<text x="{bx + 25:.1f}" y="{ly:.1f}" text-anchor="middle" font-size="10">'
                       f'burner /</text><text x="{bx + 25:.1f}" y="{ly + 12:.1f}" text-anchor="middle" '
                       f'font-size="10">combustion chamber</text></g>')
            a, b = (bx + 50, gin) if co else (bx, gin)
            out.append(_arrow(a, yc, b, "gas-arrow gas-inlet", "#b52b27"))
        else:
            a = gin + side * 60
            out.append(_arrow(a, yc, gin, "gas-arrow gas-inlet", "#b52b27"))
            out.append(f'<text x="{a:.1f}" y="{yc - 8:.1f}" text-anchor="{"start" if co else "end"}" '
                       f'fill="#b52b27">hot gas in</text>')
        out.append(_arrow(gout, yc - 0.3 * h, gout - side * 55, "gas-arrow gas-outlet", "#b52b27"))
        out.append(f'<text x="{gout - side * 58:.1f}" y="{yc - 0.3 * h - 8:.1f}" '
                   f'text-anchor="{"end" if co else "start"}" fill="#b52b27">exhaust</text>')
    out.append("</g>")
    # dimensions (horizontal frame): L below, D on the left
    yb = top + h + drop + 45
    out.append(f'<g class="dimensions" font-size="11"><line x1="{x0:.1f}" y1="{yb:.1f}" x2="{x1:.1f}" y2="{yb:.1f}" '
               f'stroke="#333"/><line x1="{x0:.1f}" y1="{yb - 5:.1f}" x2="{x0:.1f}" y2="{yb + 5:.1f}" stroke="#333"/>'
               f'<line x1="{x1:.1f}" y1="{yb - 5:.1f}" x2="{x1:.1f}" y2="{yb + 5:.1f}" stroke="#333"/>'
               f'<text x="{(x0 + x1) / 2:.1f}" y="{yb + 16:.1f}" text-anchor="middle">L = {L:g} m</text>'
               f'<text x="{x0:.1f}" y="{yb + 16:.1f}">D = {D:g} m</text>'
               f'<text x="{x1:.1f}" y="{yb + 16:.1f}" text-anchor="end">slope {slope:g} deg'
               f'{"" if scaled else ", diameter not to scale"}</text>'
               f'<text x="{x0:.1f}" y="{yb + 34:.1f}"><tspan fill="#b52b27">'
               f'{"&#8592;" if lay["direction"] == "counter-current" else "&#8594;"} gas'
               f'{" (" + html.escape(lay["direction"]) + ")" if lay["direction"] else ": none"}</tspan>'
               f'<tspan fill="#5b3a12" dx="14">&#8594; solids (feed to product)</tspan></text></g>')
    out.append("</svg>")
    return "".join(out)
