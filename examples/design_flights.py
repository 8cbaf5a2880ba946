"""Compare flight shapes on one drum: holdup, discharge per degree and where the curtain falls.

The Invicta drum (R 2.5 m, 28 flights; Lee (2008) Table 4.1) with its two-section flight, the
three-section preset and the equal-angular-distribution (EAD) preset
(``rotarydryer/geometry/profiles.toml``), at a 40 deg repose angle: a close-up of each flight
with the solids it holds when its root is at 120 deg, holdup and discharge rate per degree versus
root angle, and the share of the curtain falling across the drum. Prints design loads, final
discharge angles and the evenness of the discharge.

Run: ``python examples/design_flights.py OUT`` (writes ``OUT/design_flights.png``; the figure of
``docs/guide/design_flights.md``).
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Polygon  # noqa: E402

from rotarydryer.geometry import curtain_distribution  # noqa: E402
from rotarydryer.geometry.presets import preset_drum  # noqa: E402

PHI = 40.0
NAMES = {"invicta": "two-section (Invicta)", "invicta_three_section": "three-section",
         "invicta_ead": "EAD (designed)"}
COLOURS = {"invicta": "tab:blue", "invicta_three_section": "tab:orange", "invicta_ead": "tab:green"}


def main(out):
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    fig = plt.figure(figsize=(11, 7.5), constrained_layout=True)
    grid = fig.add_gridspec(2, 3)
    ax_h = fig.add_subplot(grid[1, 0])
    ax_r = fig.add_subplot(grid[1, 1])
    ax_c = fig.add_subplot(grid[1, 2])
    psi = np.arange(0.0, 260.0, 0.1)
    print(f"Invicta drum, repose angle {PHI:g} deg (areas per m of flight; design load for the drum section)")
    for k, (name, label) in enumerate(NAMES.items()):
        drum, entry = preset_drum(name)
        col = COLOURS[name]
        # close-up of the flight at root angle 120 deg, with its neighbours and the held solids
        ax = fig.add_subplot(grid[0, k])
        root = 120.0
        held = drum.held_polygon(root, PHI, 400)
        if len(held) >= 3:
            ax.add_patch(Polygon(held, fc="#d9a441", ec="#8a6416", lw=0.6))
        for j in (-2, -1, 0, 1, 2, 3):
            pts = drum.flight_outline(root + j * drum.flight_spacing)
            ax.plot(pts[:, 0], pts[:, 1], "-", color="k" if j == 0 else "0.4", lw=2 if j == 0 else 1.2)
        a = np.radians(np.linspace(root - 3.0 * drum.flight_spacing, root + 4.0 * drum.flight_spacing, 200))
        ax.plot(drum.radius * np.sin(a), -drum.radius * np.cos(a), "k-", lw=2.5)
        tip = drum.flight_outline(root)[-1]
        u = np.array([np.cos(np.radians(PHI)), np.sin(np.radians(PHI))])
        ax.plot(*np.array([tip, tip + 0.35 * u]).T, "r--", lw=0.8)
        c = np.vstack([drum.flight_outline(root), drum.flight_outline(root + drum.flight_spacing)]).mean(axis=0)
        ax.set_xlim(c[0] - 0.4, c[0] + 0.4)
        ax.set_ylim(c[1] - 0.4, c[1] + 0.4)
        ax.set_aspect("equal")
        ax.set_axis_off()
        segs = ", ".join(f"{a:g}/{b:g}" for a, b in drum.profile.segments)
        ax.set_title(f"{label}, root at {root:g} deg\nsections (m/deg): {segs}", fontsize=7)
        # holdup and rate per degree
        h = drum.holdup_area(psi, PHI)
        r = -drum.holdup_slope(psi, PHI)
        ax_h.plot(psi, h * 1e4, color=col, label=label)
        ax_r.plot(psi, r * 1e4, color=col, label=label)
        cd = curtain_distribution(drum, PHI, bins=30)
        x = 0.5 * (cd.x_edges_m[1:] + cd.x_edges_m[:-1])
        ax_c.step(x, cd.fraction, where="mid", color=col, label=label)
        psi5 = float(drum.final_discharge_angle(PHI))
        print(f"  {label:22s} design load {float(drum.design_load_area(PHI)):.4f} m2; holds {cd.discharged_area_m2 * 1e4:.0f} "
              f"cm2 at the first unloading flight; empty at root {psi5:.1f} deg (tip {psi5 + drum.tip_angle:.1f} deg); "
              f"discharge per degree CV {cd.cv_per_degree:.3f}; curtain from {cd.span_m[0]:+.2f} to "
              f"{cd.span_m[1]:+.2f} m")
    ax_h.set_xlabel("flight root angle psi (deg from the bottom)")
    ax_h.set_ylabel("holdup per m of flight (cm$^2$)")
    ax_h.axvline(90.0, color="k", lw=0.6, ls=":")
    ax_h.legend(fontsize=7)
    ax_r.set_xlabel("flight root angle psi (deg)")
    ax_r.set_ylabel("discharge -dH/dpsi (cm$^2$ per deg)")
    ax_r.set_xlim(90.0, 260.0)
    ax_r.set_ylim(0.0, None)
    ax_c.set_xlabel("across the drum, m from the axis (+: rising side)")
    ax_c.set_ylabel("share of the curtain per bin")
    fig.suptitle(f"Flight shapes on the Invicta drum (R 2.5 m, 28 flights), repose angle {PHI:g} deg", fontsize=10)
    path = out / "design_flights.png"
    fig.savefig(path, dpi=110)
    print(f"figure: {path}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else ".")
