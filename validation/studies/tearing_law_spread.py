"""How much the rigid model's containment depends on which machine pushed its law through
tearing.

The law through tearing (:func:`fem.rim_law` with ``fracture``) comes from an FE push that
goes on after the rim's first tear; on another machine the same code gives the same law up to
the tear and another one after it (the torn pieces take another path: docs/fem_validation.md,
"Which stores replay today"). A validation store keeps the law it was run with. This study
pushes the law again here (in a cache folder of its own), compares the two, and runs the
rigid model's containment ladder (:func:`rigid.critical_sa`, yielding rims, the validation's
ladder: 0.01 g rungs to 1.5 g, fast search) on every record at both pressures with each law.

Run::

    python -m validation.studies.tearing_law_spread [--out docs/fem-validation-fracture] \\
        [--records 28] [--csv docs/results/tearing_law_spread.csv]
    python -m validation.studies.tearing_law_spread --out docs/fem-validation-fracture-rims80 \\
        --rim-thickness 80 --slider-edge-radius 20 --csv docs/results/tearing_law_spread_rims80.csv

(a push of about a minute and two ladders per record and pressure: about 10 min of CPU).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import tempfile
import time
from pathlib import Path
from unittest.mock import patch

import numpy as np

from rigid import DFPBearing, G, critical_sa, fema_p695
from rigid.collapse.comparison import write_csv
from rigid.rims import RimLaw
from rigid.tasks import ResultStore
from validation.stored_rim_laws import curve_gap, stored_rim_law

from . import DOCS, RESULTS

#: The validation's ladder (validation.run.Settings' defaults).
LADDER = {"step": 0.01 * G, "stop": 1.5 * G, "search": "fast"}


def stored_law(out: Path, bearing: DFPBearing, fracture: str, edge_radius,
               revision: str | None = None) -> RimLaw:
    """The law through tearing that the validation store of ``out`` holds under today's
    key (its runs key on it), or under the key of ``revision``'s code (a store not carried
    over yet); pushed by the slider with edges of ``edge_radius`` [m] if given."""
    from contextlib import nullcontext

    from rigid.tasks.rekey import code_at

    keys = nullcontext() if revision is None else code_at(revision, today=())
    with ResultStore(out / "results.sqlite") as store, keys:
        law = stored_rim_law(store, bearing, fracture=fracture, edge_radius=edge_radius)
    if law is None:
        raise SystemExit(f"{out}: no {fracture} law through tearing under the keys of "
                         f"{revision or 'today'}'s code (carry the store over first, or name "
                         "the code that stored it: --stored-under)")
    return law


def pushed_here(bearing: DFPBearing, fracture: str, edge_radius) -> RimLaw:
    """The same law pushed on this machine by today's code, in a cache of its own."""
    from fem import rim_law

    punch = {} if edge_radius is None else {"punch": "slider", "edge_radius": edge_radius}
    with tempfile.TemporaryDirectory() as cache, patch.dict(os.environ,
                                                           {"DFP_CACHE_DIR": cache}):
        return rim_law(bearing, fracture=fracture, **punch)


def law_spread(here: RimLaw, stored: RimLaw) -> dict:
    """The two laws' first tears and rim-off sets [mm], and their backbones' difference
    relative to the peak force: before the first tear at the samples both share
    (:func:`validation.stored_rim_laws.curve_gap`, with the fraction shared), after it by
    linear interpolation on the sets both cover (their samples part there)."""
    tear = min(here.tear_set, stored.tear_set)
    before, shared = curve_gap(here, stored, "plastic_set", "force", np.nextafter(tear, 0.0))
    top = min(here.plastic_set.max(), stored.plastic_set.max())
    at = np.union1d(here.plastic_set, stored.plastic_set)
    at = at[(at >= tear) & (at <= top)]
    after = np.abs(here.backbone(at) - stored.backbone(at)).max(initial=0.0)
    return {"tear_set_here_mm": here.tear_set * 1e3, "tear_set_stored_mm": stored.tear_set * 1e3,
            "off_set_here_mm": here.off_set * 1e3, "off_set_stored_mm": stored.off_set * 1e3,
            "before_tear_of_peak": float(before), "shared_before_tear": float(shared),
            "after_tear_of_peak": float(after / max(here.force.max(), stored.force.max()))}


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=DOCS / "fem-validation-fracture",
                   help="the validation folder whose store holds the law")
    p.add_argument("--fracture", default="median")
    p.add_argument("--rim-thickness", type=float, default=None, help="[mm]")
    p.add_argument("--slider-edge-radius", type=float, default=None,
                   help="[mm] the law pushed by the slider with these edges (--rim-punch "
                   "slider of the validation)")
    p.add_argument("--stored-under", metavar="REVISION", default=None,
                   help="the store's law under the keys of this commit's code (a store not "
                   "carried over yet)")
    p.add_argument("--records", type=int, default=None)
    p.add_argument("--csv", type=Path, default=RESULTS / "tearing_law_spread.csv")
    args = p.parse_args(argv)
    t0 = time.process_time()
    base = DFPBearing() if args.rim_thickness is None else DFPBearing(
        rim_thickness=args.rim_thickness * 1e-3)
    edge = None if args.slider_edge_radius is None else args.slider_edge_radius * 1e-3
    stored = stored_law(args.out, base, args.fracture, edge, args.stored_under)
    here = pushed_here(base, args.fracture, edge)
    spread = law_spread(here, stored)
    print(", ".join(f"{k} {v:.4g}" for k, v in spread.items()), flush=True)
    rows = []
    for pressure in (60e6, 10e6):
        bearing = dataclasses.replace(base, pressure=pressure)
        for motion in fema_p695("nearfield_pulse")[:args.records]:
            sa = [critical_sa(bearing, motion, rims="yielding", limit_state="containment",
                              rim_law=law, **LADDER).sa for law in (stored, here)]
            rows.append({"record": motion.name, "pressure_mpa": pressure / 1e6,
                         **{f"containment_sa_g_{k}": None if s is None else round(s / G, 4)
                            for k, s in zip(("stored_law", "law_pushed_here"), sa,
                                            strict=True)},
                         "same": sa[0] == sa[1]})
            print(rows[-1], flush=True)
    write_csv(rows, args.csv)
    both = [r for r in rows if None not in (r["containment_sa_g_stored_law"],
                                            r["containment_sa_g_law_pushed_here"])]
    ratio = [r["containment_sa_g_law_pushed_here"] / r["containment_sa_g_stored_law"]
             for r in both]
    print(f"{sum(r['same'] for r in rows)} of {len(rows)} the same critical SA; ratio "
          f"here/stored {min(ratio):.3f}-{max(ratio):.3f}, median {np.median(ratio):.3f} "
          f"({len(both)} with both); {time.process_time() - t0:.0f} s CPU; wrote {args.csv}")


if __name__ == "__main__":
    main()
