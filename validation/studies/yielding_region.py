"""Impact region spectrum of the heavy bearing (60 MPa, symmetric Ricker pulses) with the
paper's rigid rims beside the same spectrum with yielding rims under the hinge and the
containment limit states: where the failure region moves (docs/fe-companion.md, "Yielding
rims in the rigid model").

Run: ``python -m validation.studies.yielding_region [--periods 30] [--amplitudes 30]``;
writes ``docs/images/impact_region_yielding.png``. Cells are cached (the sweep cache).
"""

from __future__ import annotations

import argparse

import numpy as np

from fem import rim_law
from rigid import DFPBearing, G, SweepSettings, impact_region_spectrum
from rigid.impact import default_periods

from . import IMAGES

PANELS = (("rigid rims (the paper's model)", {}),
          ("yielding rims, failure = hinge", {"rims": "yielding",
                                              "limit_state": "hinge"}),
          ("yielding rims, failure = containment", {"rims": "yielding",
                                                    "limit_state": "containment"}))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--periods", type=int, default=30)
    parser.add_argument("--amplitudes", type=int, default=30)
    parser.add_argument("--workers", type=int, default=None)
    args = parser.parse_args()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap

    bearing = DFPBearing(pressure=60e6)
    periods = default_periods(bearing, args.periods)
    amplitudes = np.linspace(1.0 / args.amplitudes, 1.0, args.amplitudes) * G
    cmap = ListedColormap(["0.6", "white", "tab:blue", "tab:red"])  # numerical, 0, 1, 2
    fig, axes = plt.subplots(1, len(PANELS), figsize=(4.2 * len(PANELS), 4.0), sharey=True)
    for ax, (title, options) in zip(axes, PANELS, strict=True):
        if options.get("rims") == "yielding":
            options = {**options, "rim_law": rim_law(bearing)}
        ds = impact_region_spectrum(bearing, "symmetric", periods, amplitudes,
                                    settings=SweepSettings(**options), workers=args.workers)
        region = ds["region"].values  # (amplitude, period)
        ratio = ds["frequency_ratio"].values
        order = np.argsort(ratio)
        ax.pcolormesh(ratio[order], amplitudes / G, region[:, order], cmap=cmap, vmin=-1.5,
                      vmax=2.5, shading="nearest")
        share = float((region == 2).mean())
        ax.set_title(f"{title}\nfailure in {100 * share:.0f} % of the cells", fontsize=9)
        ax.set_xlabel("Tb / Tp [-]")
        print(f"{title}: failure in {100 * share:.1f} % of {region.size} cells, numerical "
              f"{int((region == -1).sum())}", flush=True)
    axes[0].set_ylabel("Ap [g]")
    handles = [plt.Rectangle((0, 0), 1, 1, fc=c, ec="k", lw=0.5)
               for c in ("white", "tab:blue", "tab:red", "0.6")]
    fig.legend(handles, ["no impact", "impact", "failure", "numerical"], loc="lower center",
               ncol=4, fontsize=8)
    fig.suptitle("Heavy bearing (60 MPa), symmetric Ricker pulses: impact region spectra",
                 fontsize=10)
    fig.tight_layout(rect=(0, 0.06, 1, 0.95))
    path = IMAGES / "impact_region_yielding.png"
    fig.savefig(path, dpi=120)
    print(path)


if __name__ == "__main__":
    main()
