"""The numbers of one case folder as the report and the figures use them: its record's facts and
the peaks of its CSVs (case_summary). No markdown and no figures here."""

import numpy as np

from . import casefolders, datasheet


def _peak_abs(values):
    values = np.abs(np.asarray(values, dtype=float))
    return float(values.max()) if values.size else None


def _peak_where(values, times, displacements):
    if not len(values):
        return None, None, None
    index = int(np.argmax(values))
    return float(values[index]), float(times[index]), float(displacements[index])


def zone_peaks(case, table=None):
    """{family: peak total / max tension, their times and displacements} of a case's
    zone_forces.csv (or of another zone's table, read as casefolders reads that one)."""
    result = {}
    for family, data in (case.zone() if table is None else casefolders.zone_families(table)).items():
        total, total_time, total_at = _peak_where(data["total"], data["time"],
                                                      data["displacement"])
        largest, largest_time, largest_at = _peak_where(data["max"], data["time"],
                                                            data["displacement"])
        result[family] = {"peak_total_tension": total, "time_of_peak_total": total_time,
                          "displacement_of_peak_total": total_at,
                          "peak_max_tension": largest, "time_of_peak_max": largest_time,
                          "displacement_of_peak_max": largest_at}
    return result


def case_mode(case):
    """'quick' or 'full' as case.json records it ('unknown' for folders without it)."""
    if "quick" not in case.meta:
        return "unknown"
    return "quick" if case.meta["quick"] is True else "full"


def case_summary(case):
    """The numbers of one case (None where the file or the value is absent)."""
    summary = {"kind": case.kind, "status": case.status, "mode": case_mode(case),
               "errors": list(case.errors),
               "files": sorted(casefolders.TABLES[k][0] for k in case.tables)}
    tables = case.tables
    summary["peak_platter_force"] = _peak_abs(tables["platter"]["force"]) \
        if "platter" in tables else None
    summary["peak_block_force"] = _peak_abs(tables["block"]["force"]) \
        if "block" in tables else None
    summary["zone"] = zone_peaks(case)
    # the zones after the first (output.zones: zone_forces_NAME.csv), by name
    summary["other_zones"] = {name: zone_peaks(case, table)
                              for name, table in casefolders.other_zones(case).items()}
    if "beam" in tables:
        beam = tables["beam"]
        summary["beam"] = [dict(zip(casefolders.TABLES["beam"][1], map(float, row)))
                           for row in zip(*(beam[c] for c in casefolders.TABLES["beam"][1]))]
        summary["beam_max_nrmse"] = _peak_abs(beam["nrmse"])
    for key in ("first_rupture", "edge_force_peak", "wall_time", "cpu_time", "started", "finished", "ended_by",
                "first_rope_rupture", "ended_at_drop", "bending", "bending_source", "panel",
                "platter", "block", "verdict", "error", "unsourced"):
        summary[key] = case.meta.get(key)
    if case.kind == "impact":
        energy = case.meta.get("energy") or {}
        momentum = case.meta.get("momentum") or {}
        summary["energy_at_lowest_point"] = energy.get("at_lowest_point")
        summary["initial_energy"] = energy.get("initial_energy")
        summary["mechanisms"] = energy.get("mechanisms")
        summary["dissipation"] = case.meta.get("dissipation", "local")
        summary["impact"] = {"closure_error": energy.get("closure_error"),
                             "momentum_error": momentum.get("error"),
                             "broken_bonds": case.meta.get("broken_bonds"),
                             "max_displacement": case.meta.get("max_displacement"),
                             "rebound_time": case.meta.get("rebound_time"),
                             "edge_force_peak": case.meta.get("edge_force_peak"),
                             "side_force_peak": case.meta.get("side_force_peak"),
                             "support_peaks": case.meta.get("support_peaks"),
                             "peak_block_force": case.meta.get("peak_block_force"),
                             "peak_block_force_raw": case.meta.get("peak_block_force_raw"),
                             "peak_block_force_windowed":
                                 case.meta.get("peak_block_force_windowed"),
                             "force_window": case.meta.get("force_window")}
    if case.kind == "fence":
        summary["fence"] = fence_summary(case.meta)
    if case.kind == "drapery":
        summary["drapery"] = drapery_summary(case.meta)
    if isinstance(case.meta.get("quasi_static"), dict):
        summary["quasi_static"] = quasi_static_summary(case.meta["quasi_static"])
    figures = datasheet.of_case(case)
    if figures is not None:
        summary["datasheet"] = figures
    return summary


def fence_summary(meta):
    """The facts of a fence impact (runner/fence.py) the report shows."""
    peaks = meta.get("support_peaks") or {}
    anchors = {k: v for k, v in peaks.items() if not k.startswith("post_base")}
    bases = {k: v for k, v in peaks.items() if k.startswith("post_base")}

    def top(group):
        if not group:
            return None, None
        name = max(group, key=lambda k: group[k].get("peak") or 0.0)
        return name, group[name].get("peak")
    anchor, anchor_peak = top(anchors)
    base, base_peak = top(bases)
    fence = meta.get("fence") or {}
    energy = meta.get("energy") or {}
    second = meta.get("second_impact")
    return {"net": fence.get("net"), "block_energy": (meta.get("block") or {}).get("energy"),
            "braking_distance": meta.get("braking_distance"),
            "block_stopped": meta.get("block_stopped"),
            "residual_height_ratio": meta.get("residual_height_ratio"),
            "residual_height_at": meta.get("residual_height_at", "end of impact"),
            "rest_settled": _rest_settled(meta.get("rest")),
            "rest_skipped": bool(meta.get("rest_skipped", False)),
            "second": dict(fence_summary(second), net=fence.get("net"),
                           block_energy=(meta.get("block") or {}).get("energy"))
            if isinstance(second, dict) else None,
            "final_block_speed": meta.get("final_block_speed"),
            "anchor": anchor, "anchor_peak": anchor_peak, "post_base": base,
            "post_base_peak": base_peak, "rope_peaks": meta.get("rope_peaks"),
            "brake_elongation_peak": meta.get("brake_elongation_peak"),
            "closure_error": energy.get("closure_error"),
            "momentum_error": (meta.get("momentum") or {}).get("error"),
            "broken_bonds": meta.get("broken_bonds"),
            "weight_carried": (meta.get("settled") or {}).get("weight_carried"),
            "weight_carried_rest": (meta.get("rest") or {}).get("weight_carried"),
            "energy_final": energy.get("final"), "initial_energy": energy.get("initial_energy"),
            "mechanisms": energy.get("mechanisms"), "dissipation": meta.get("dissipation"),
            "components": energy.get("components")}


def drapery_summary(meta):
    """The facts of a drapery case (runner/kinds/drapery.py) the report shows."""
    energy = meta.get("energy") or {}
    end = meta.get("block_end") or {}
    return {"net": meta.get("panel"), "slope": meta.get("slope"),
            "block_energy": energy.get("reference_energy", energy.get("initial_energy")),
            "block_verdict": meta.get("block_verdict"), "travel": end.get("travel"),
            "final_speed": end.get("final_speed"), "bulge": meta.get("bulge_peak"),
            "bulge_before_contact": (meta.get("before_contact") or {}).get("bulge"),
            "top_anchor_peak": (meta.get("top_anchor_peak") or {}).get("force"),
            "grid_anchor_peak": (meta.get("grid_anchor_peak") or {}).get("force"),
            "top_row_force_peak": meta.get("top_row_force_peak"),
            "closure_error": energy.get("closure_error"), "mechanisms": energy.get("mechanisms"),
            "broken_bonds": meta.get("broken_bonds")}


def _rest_settled(rest):
    """Whether the rest before the residual height ended settled (below its energy limit, or
    the ropes still: runner/fence.py), False at its time limit, None without a rest."""
    if not isinstance(rest, dict):
        return None
    return bool(rest.get("reached") or rest.get("still"))


QUASI_STATIC_KEYS = ("slow_factor", "curve_difference", "compared_up_to",
                     "kinetic_energy_fraction", "equilibrium_error",
                     "equilibrium_error_of_current", "equilibrium_holds_from", "passed")


def quasi_static_summary(evidence):
    """The punch's quasi-static evidence of case.json (runner.punch), None where absent."""
    summary = {key: evidence.get(key) for key in QUASI_STATIC_KEYS}
    summary["snap_events"] = len(evidence.get("snap_events") or [])
    return summary
