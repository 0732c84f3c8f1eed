"""Which push the 40 mm rim's law through tearing should come from (issue #31): the rigid
model's containment SA with the law from the slider's pushes (``fem.rim_law(bearing,
fracture="median", punch="slider")``, Eq. F71) beside the one with the face push's law that
the 40 mm validation with tearing used, both against that validation's FE answers
(``docs/fem-validation-fracture/fem_comparison.csv``, nothing rerun in FE), with the first
touch beside them (``docs/results/containment_tearing.csv``).

The ladder is the validation's: 0.01 g rungs to 1.5 g, the fast search. Writes
``docs/results/slider_law_40mm.csv`` (a row per case) and prints the statistics of
:func:`validation.studies.rim_design_fem.statistics_rows` for both laws.

Run (a few minutes of CPU): ``python -m validation.studies.slider_law_40mm``.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import statistics
import time
from pathlib import Path

from rigid.collapse.comparison import write_csv

from . import RESULTS, number, read_csv

#: The ladder of the validation runs: its step and top [g] (``dfp validate``'s defaults).
STEP_G, STOP_G = 0.01, 1.5


def _share(ratios, band):
    return sum(abs(x - 1) <= band + 1e-9 for x in ratios) / len(ratios)


def main(argv=None) -> None:
    import fem
    import rigid

    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", type=Path, default=RESULTS)
    args = p.parse_args(argv)
    cases = [r for r in read_csv(RESULTS / "containment_tearing.csv")
             if r["rim_thickness_mm"] in ("40", "40.0") and not r.get("crush_jacobian")]
    motions = {m.name: m for m in rigid.fema_p695("nearfield_pulse")}
    bearing = rigid.DFPBearing()
    law = fem.rim_law(bearing, fracture="median", punch="slider")
    rows = []
    for r in cases:
        b = dataclasses.replace(bearing, pressure=float(r["pressure_mpa"]) * 1e6)
        t0 = time.process_time()
        crit = rigid.critical_sa(b, motions[r["record"]], STEP_G * rigid.G,
                                 stop=STOP_G * rigid.G, search="fast", rims="yielding",
                                 rim_law=law, limit_state="containment")
        slider = math.nan if crit.sa is None else round(crit.sa / rigid.G, 2)
        fe = number(r["fem_sa_g"])
        rows.append({
            "record": r["record"], "pressure_mpa": r["pressure_mpa"], "fem_sa_g": fe,
            "face_law_sa_g": number(r["yielding_sa_g"]), "slider_law_sa_g": slider,
            "first_touch_sa_g": number(r["first_touch_sa_g"]),
            "fem_over_face_law": fe / number(r["yielding_sa_g"]),
            "fem_over_slider_law": fe / slider,
            "fem_over_first_touch": number(r["fem_over_first_touch"]),
            "slider_numerical_rungs": sum(bool(x.numerical_failure) for x in crit.rungs),
            "cpu_s": round(time.process_time() - t0, 1)})
        print(rows[-1], flush=True)
    write_csv(rows, args.out / "slider_law_40mm.csv")
    for name in ("face_law", "slider_law", "first_touch"):
        ratios = [x[f"fem_over_{name}"] for x in rows if math.isfinite(x[f"fem_over_{name}"])]
        print(f"{name}: {len(ratios)} of {len(rows)} cases, median FE/{name} "
              f"{statistics.median(ratios):.3f}, within 20 % {_share(ratios, 0.2):.0%}, "
              f"within 35 % {_share(ratios, 0.35):.0%}")


if __name__ == "__main__":
    main()
