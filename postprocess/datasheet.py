"""The figures of a manufacturer's data sheet from a case folder (issue #40): a tensile case's
strength per metre of width and its elongation at the peak and at failure, a punch case's punch
resistance (the platter's peak force) and the platter's travel at it; and the nominal values of
the standards and catalogues beside them, each with its source. No markdown here (report.py,
runner/datasheet.py)."""

import numpy as np

UNVERIFIED = "unverified: "

# Nominal values of a mesh type: (net, figure) -> (value, unit, the mesh it is for, source). A
# source starting with "unverified:" names a standard or catalogue whose table was not read in
# the original (a value recalled or read in a reproduction). Figures: strength_along (kN/m,
# tensile strength along the twists, the standard's longitudinal strength), strength_across,
# elongation_at_peak (-), punch_resistance (kN), punch_displacement (m).
NOMINAL = {
    ("hex", "strength_along"): (
        50.0, "kN/m", "double-twist 8x10, wire 2.7 mm",
        UNVERIFIED + "EN 10223-3:2013, its table of the mesh types' nominal tensile strength "
        "(table number not confirmed); the same 50 kN/m is the minimum of a manufacturer's data "
        "sheet (Maccaferri Terramesh 8x10/2.7 TDS 2017, ASTM A975 13.1.1), read in a "
        "reproduction"),
    ("hex", "punch_resistance"): (
        23.6, "kN", "double-twist 8x10, wire 2.7 mm",
        UNVERIFIED + "Maccaferri Terramesh 8x10/2.7 TDS 2017, ASTM A975 13.1.4 (5300 lb), read "
        "in a reproduction; ASTM A975's punch test is not UNI 11437's (another frame and "
        "platter): an order of magnitude, not the same test"),
    ("square", "strength_along"): (
        230.0, "kN/m", "rope panel, rope 10 mm, mesh 300 x 300 mm",
        UNVERIFIED + "a tender specification citing Maccaferri HEA rope panels (knotted "
        "crossings, rhomboidal mesh), read in a reproduction; one value for the panel"),
    ("square", "strength_across"): (
        230.0, "kN/m", "rope panel, rope 10 mm, mesh 300 x 300 mm",
        UNVERIFIED + "the same specification's single panel strength (a square mesh has no "
        "twist direction)"),
    ("square", "punch_resistance"): (
        370.0, "kN", "rope panel, rope 10 mm, mesh 300 x 300 mm",
        UNVERIFIED + "the same tender specification (HEA panels)"),
    ("square", "punch_displacement"): (
        0.33, "m", "rope panel, rope 10 mm, mesh 300 x 300 mm",
        UNVERIFIED + "the same tender specification (HEA panels: 33 cm)"),
}
NOT_FOUND = ("none: no nominal value found for this figure of this mesh type (EN 10223-3's "
             "tables and UNI 11437's nominal punch values were not read; the data sheets read "
             "give the longitudinal strength and an ASTM punch value only)")


def nominal(net, figure):
    """(value, unit, mesh, source) of a mesh type's nominal figure, or None."""
    return NOMINAL.get((net, figure))


def punch_figures(displacement, force):
    """Punch resistance [N] (the platter's peak force) and the platter travel at it [m]."""
    force = np.asarray(force, dtype=float)
    if not force.size:
        return None
    k = int(np.argmax(force))
    return {"punch_resistance": float(force[k]),
            "punch_displacement": float(np.asarray(displacement, dtype=float)[k])}


def tensile_figures(meta):
    """Strength per metre [N/m], elongation at the peak and at failure [-] of a tensile
    case.json; None for a wire or rope (no width)."""
    strength = meta.get("strength_per_metre")
    if strength is None:
        return None
    direction = meta.get("direction", "along")
    failure = meta.get("failure") or {}
    return {f"strength_{direction}": float(strength), "direction": direction,
            "peak_force": meta.get("peak_force"),
            "displacement_at_peak": meta.get("displacement_at_peak"),
            "elongation_at_peak": meta.get("elongation_at_peak"),
            "elongation_at_failure": failure.get("elongation"),
            "width": meta.get("width"), "clamp_distance": meta.get("clamp_distance")}


def of_case(case):
    """The data-sheet figures of a case folder (casefolders.Case), or None for other kinds."""
    if case.kind == "punch" and "platter" in case.tables:
        table = case.tables["platter"]
        return punch_figures(table["displacement"], table["force"])
    if case.kind == "tensile":
        return tensile_figures(case.meta)
    return None


def rows(net, figures):
    """[(figure label, model value text, nominal text, source)] of one case's figures."""
    out = []

    def add(label, figure, value, scale, unit, digits):
        n = nominal(net, figure)
        text = "n/a" if value is None else f"{value / scale:.{digits}f} {unit}"
        if n is None:
            out.append((label, text, "-", NOT_FOUND))
        else:
            out.append((label, text, f"{n[0]:g} {n[1]} ({n[2]})", n[3]))
    if figures is None:
        return out
    if "punch_resistance" in figures:
        add("punch resistance", "punch_resistance", figures["punch_resistance"], 1e3, "kN", 1)
        add("platter travel at it", "punch_displacement", figures["punch_displacement"], 1.0,
            "m", 3)
        return out
    d = figures["direction"]
    add(f"tensile strength {d} the twists", f"strength_{d}", figures[f"strength_{d}"], 1e3,
        "kN/m", 1)
    for key, label in (("elongation_at_peak", "elongation at the peak"),
                       ("elongation_at_failure", "elongation at failure")):
        v = figures.get(key)
        out.append((f"{label} ({d})", "n/a (held)" if v is None else f"{100 * v:.1f} %", "-",
                     NOT_FOUND))
    return out
