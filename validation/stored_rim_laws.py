"""The rim laws a validation run uses, kept in its store with its results.

A run with yielding rims gives the rigid model a rim law (:class:`rigid.rims.RimLaw`), and a
run with ``--rim-model ring`` gives the FE rims the ring's effective depth, which comes from
two laws. Both come from FE pushes that the library caches outside the run's folder
(:func:`fem.rim_law`), so a store alone could not be replayed on another machine: the ring's
push takes minutes. Each law is therefore stored in ``results.sqlite`` under the key of
its cache file (which includes the pushing model's code), and planted in the cache from there
when the cache lacks it or holds a law pushed elsewhere.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from rigid import DFPBearing
from rigid.rims import RimLaw, load_rim_law, rim_law_cache_file, save_rim_law
from rigid.tasks import MissingResultsError, ResultStore

__all__ = ["keep_rim_laws"]


def _to_json(law: RimLaw) -> dict:
    return {f.name: np.asarray(getattr(law, f.name)).tolist()
            for f in dataclasses.fields(RimLaw)}


def _from_json(data: dict) -> RimLaw:
    return RimLaw(**{k: (np.asarray(v, dtype=float) if isinstance(v, list) else float(v))
                     for k, v in data.items()})


def keep_rim_laws(store: ResultStore, bearing: DFPBearing, models, *,
                  replay: bool = False, fracture: str | None = None,
                  edge_radius: float | None = None) -> None:
    """Make the rim laws of ``bearing`` from each of ``models`` ("plane-strain", "ring") be
    both in ``store`` and in the library's cache, so that :func:`fem.rim_law` and
    :func:`fem.effective_rim_depth` read them; with ``fracture``, the plane-strain law
    through tearing with that set too (:func:`fem.rim_law`'s ``fracture``), pushed by the
    slider with edges of ``edge_radius`` [m] when given (``punch="slider"``).

    A law found in the store is written to the cache if the cache lacks it or holds another
    (the same push made on another machine rounds differently); a law in neither
    is pushed by the FE companion (cached) and stored, unless ``replay``: then
    :class:`rigid.tasks.MissingResultsError` names it. The pressure does not matter.
    """
    from fem import rim_law

    missing = []
    wanted = [(model, None) for model in dict.fromkeys(models)]
    if fracture is not None:
        wanted.append(("plane-strain", fracture))
    for model, torn in wanted:
        slider = edge_radius if torn is not None else None
        path = rim_law_cache_file(bearing, model, torn, edge_radius=slider)
        key = path.stem
        stored = store.get(key)
        if stored is not None:
            # the store's law wins over a cached one pushed elsewhere (its last digits differ
            # from machine to machine, and the stored runs key on its numbers)
            if not path.exists() or _to_json(load_rim_law(path)) != stored:
                save_rim_law(_from_json(stored), path)
            continue
        if path.exists():
            store.put(key, "rim-law", _to_json(load_rim_law(path)))
        elif replay:
            missing.append(model)
        else:
            punch = {} if slider is None else {"punch": "slider", "edge_radius": slider}
            store.put(key, "rim-law", _to_json(rim_law(bearing, model=model, fracture=torn,
                                                       **punch)))
    if missing:
        from collections import Counter

        raise MissingResultsError(Counter({"rim-law": len(missing)}), store)
