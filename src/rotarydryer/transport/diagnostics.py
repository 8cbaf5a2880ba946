"""Per-cell flows and holdup decomposition of a steady state (what makes a trend).

[`cell_flows`][rotarydryer.transport.diagnostics.cell_flows] lists, for every cell of the flighted sections, the flows of Lee (2008)
Ch. 3 (flight discharge, forward step, return, backmix, kilning; kg/s) and the net axial
transport of the curtain across the cell's downstream boundary, forward_i - backmix_{i+1}
(negative: the flights carry solids net *backwards*, Lee (2008) Table 7.5: backmix >
forward in the first cell for every N). [`holdup_parts`][rotarydryer.transport.diagnostics.holdup_parts] splits the holdup into the
solids borne by the flights (min(M_P, M_des)), the kilning bed (M_P - M_des > 0), the
curtains and the unflighted beds (kg).
"""

from __future__ import annotations

import numpy as np

__all__ = ["cell_flows", "holdup_parts"]

_FAMILIES = ("discharge", "forward", "return", "backmix", "kiln", "passive_forward")


def _family_per_cell(ss, name, section, passive):
    """Flow (kg/s) of family ``name`` out of each cell of ``section`` (by source node), zeros if absent."""
    out = np.zeros(passive.size)
    for fam, flow in zip(ss.model.network.families, ss.flows):
        if fam.name == name and fam.section == section:
            np.add.at(out, np.asarray(ss.cell[np.asarray(fam.src)], dtype=int), np.asarray(flow, float))
    return out


def cell_flows(ss, section=None) -> dict:
    """Per-cell flows of a flighted section of a [`SteadyState`][rotarydryer.transport.results.SteadyState].

    Returns a dict of arrays (one value per cell, kg/s unless stated): ``discharge_kg_s``
    (P -> A), ``forward_kg_s`` (A_i -> P_{i+1}), ``return_kg_s``, ``backmix_kg_s`` (A_i -> cell
    i-1), ``kiln_kg_s`` (P_i -> P_{i+1}; Model 1 also ``passive_forward``), ``net_curtain_kg_s``
    (forward_i - backmix_{i+1}: the curtain's net transport across the boundary to the next cell;
    the last cell's forward flow leaves the dryer), ``passive_kg``, ``active_kg``,
    ``design_load_kg``, ``kiln_bed_kg`` and ``passive_time_s`` (M_P / discharge where the flights
    are not over their design load, else M_des / discharge).
    """
    sections = [s["name"] for s in ss.model.sections if s["kind"] == "flighted"]
    if not sections:
        raise ValueError("the model has no flighted section")
    section = sections[0] if section is None else section
    if section not in sections:
        raise ValueError(f"section = {section!r} is not a flighted section ({', '.join(sections)})")
    sel = ss.section == section
    passive = np.flatnonzero(sel & (ss.phase == "passive"))
    active = np.flatnonzero(sel & (ss.phase == "active"))
    passive = passive[np.argsort(ss.cell[passive])]
    active = active[np.argsort(ss.cell[active])]
    out = {f"{name}_kg_s": _family_per_cell(ss, name, section, passive) for name in _FAMILIES}
    out["kiln_kg_s"] = out["kiln_kg_s"] + out.pop("passive_forward_kg_s")
    back_next = np.r_[out["backmix_kg_s"][1:], 0.0]
    out["net_curtain_kg_s"] = out["forward_kg_s"] - back_next
    mp, des = ss.masses[passive], ss.design_load[passive]
    out.update(passive_kg=mp, active_kg=ss.masses[active], design_load_kg=des,
               kiln_bed_kg=np.maximum(mp - des, 0.0),
               passive_time_s=np.minimum(mp, des) / np.maximum(out["discharge_kg_s"], 1e-300))
    return out


def holdup_parts(ss) -> dict:
    """Holdup split (kg): ``flights_kg`` (sum of min(M_P, M_des) over flighted cells),
    ``kiln_bed_kg`` (sum of the excess over the design load), ``curtain_kg`` (active phases),
    ``bed_kg`` (unflighted sections) and ``total_kg``."""
    p = ss.phase == "passive"
    mp, des = ss.masses[p], np.nan_to_num(ss.design_load[p], nan=np.inf)
    return dict(flights_kg=float(np.sum(np.minimum(mp, des))), kiln_bed_kg=float(np.sum(np.maximum(mp - des, 0.0))),
                curtain_kg=ss.active_holdup, bed_kg=ss.bed_holdup, total_kg=ss.total_holdup)
