#!/usr/bin/env python3
"""Writes the radiometric bounds of golden/gpu-bounds.toml from a correct GPU build's
`brdfkit golden check --device gpu` output (docs/gpu.md, "Radiometric bounds").

    brdfkit golden check --device gpu > correct.txt
    python3 scripts/gpu_bounds_from_check.py correct.txt golden/gpu-bounds.toml

Each bound is the measurement times MARGIN, and never below the floor that a real GPU's
transcendentals need (FLOORS; docs/gpu.md says why). The FLIP bounds and their `why` already
in the file are kept; the radiometric bounds and their measured values are rewritten.
"""
import math
import re
import sys
import tomllib

MARGIN = 3.0
# Floors: a real GPU's sin/cos/acos/atan2 differ from lavapipe's (WGSL allows 2^-11 absolute
# for sin/cos), which moves lookups at texel seams; the floors keep a correct build on such
# hardware passing, and stay at least 10x under a 0.5% gain's mean error.
FLOORS = {"mean_error": 3e-4, "rel_rmse": 2e-3, "rel_error": 1e-2, "coverage_mismatch": 2e-3}
FIELDS = {
    "mean_error": r"mean error ([0-9.e+-]+)",
    "rel_rmse": r"rel RMSE ([0-9.e+-]+)",
    "rel_error": r"rel error p99 ([0-9.e+-]+)",
    "coverage_mismatch": r"coverage mismatch ([0-9.e+-]+)",
}


def up2(x):
    """x rounded up to two significant digits."""
    if x <= 0:
        return 0.0
    step = 10 ** (math.floor(math.log10(x)) - 1)
    return float(f"{math.ceil(x / step - 1e-9) * step:.2g}")


def main(check, path):
    measured = {}
    adapter = ""
    for line in open(check):
        if line.startswith("golden check --device gpu"):
            adapter = line.split("(", 1)[1].rsplit("):", 1)[0]
        parts = line.split()
        if len(parts) > 2 and parts[1] == "pass":
            measured[parts[0]] = {k: float(re.search(rx, line).group(1)) for k, rx in FIELDS.items()}
        elif len(parts) > 2 and parts[1] == "FAIL":
            sys.exit(f"{check}: {parts[0]} failed: bounds come from a passing build")
    with open(path, "rb") as f:
        old = tomllib.load(f)
    out = [
        "# GPU-side bounds for `brdfkit golden check --device gpu` (src/golden/gpu_bounds.rs), each",
        "# with the measurement behind it. FLIP bounds replace an entry's manifest bounds for the",
        "# GPU check only; the radiometric bounds (mean_error, rel_rmse, rel_error at the percentile,",
        "# coverage_mismatch) are set here alone: each is a correct build's measure on lavapipe",
        f"# ({adapter}) times {MARGIN:g}, and never under the floor a real GPU's",
        "# transcendentals need (docs/gpu.md, \"Radiometric bounds\"). Written by",
        "# scripts/gpu_bounds_from_check.py; a GPU team loosens an entry by hand, with its reason in `why`.",
        "",
    ]
    for name, m in measured.items():
        o = old.get(name, {})
        out.append(f"[{name}]")
        for k in ("mean", "percentile", "at_percentile"):
            if k in o:
                out.append(f"{k} = {o[k]}")
        for k in FIELDS:
            out.append(f"{k} = {max(up2(MARGIN * m[k]), FLOORS[k]):.2g}")
        flip_why = o.get("why", "").split("Radiometric: ")[0].strip()
        meas = ", ".join(f"{k} {m[k]:.2e}" for k in FIELDS)
        why = (flip_why + " " if flip_why else "") + f"Radiometric: measured {meas}."
        out.append(f"why = {why!r}".replace("'", '"') if '"' not in why else f"why = '''{why}'''")
        out.append("")
    open(path, "w").write("\n".join(out))


if __name__ == "__main__":
    main(*sys.argv[1:])
