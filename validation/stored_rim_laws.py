"""The rim laws a validation run uses, kept in its store with its results.

A run with yielding rims gives the rigid model a rim law (:class:`rigid.rims.RimLaw`), and a
run with ``--rim-model ring`` gives the FE rims the ring's effective depth, which comes from
two laws. Both come from FE pushes that the library caches outside the run's folder
(:func:`fem.rim_law`), so a store alone could not be replayed on another machine: the ring's
push takes minutes. Each law is therefore stored in ``results.sqlite`` under the key of
its cache file (which includes the pushing model's code), and planted in the cache from there
when the cache lacks it or holds a law pushed elsewhere. After an edit of the pushing code
(``--rekey-from``), :func:`carry_rim_laws` carries the stored laws over to today's keys once
today's push agrees with them.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from rigid import DFPBearing
from rigid.rims import RimLaw, load_rim_law, rim_law_cache_file, save_rim_law
from rigid.tasks import MissingResultsError, ResultStore

__all__ = ["carry_rim_laws", "curve_gap", "keep_rim_laws", "law_differences",
           "stored_rim_law"]

#: Tolerance of today's push against a stored law when carrying it over: relative for the
#: law's marks (first yield, hinge, rupture, first tear), and for its curves (push force,
#: backbone, corner height) relative to the curve's largest value at the samples both laws
#: share, up to the first tear. Not :data:`rigid.tasks.rekey.RTOL`: the push's adaptive
#: increments are not the same on every machine. The committed stores' laws pushed again on
#: another machine by the same code moved one increment in 131 and differed by up to 2.3e-4
#: of the peak push force at the samples they share and 5.0e-4 in the rupture set (80 mm
#: rims 45 mm high; docs/fem_validation.md, "Which stores replay today"); a change of 0.1 %
#: in the steel's yield stress, which the rim's force follows, would move the curves by
#: 1e-3. After the first tear the push is not repeatable from machine to machine (the same
#: docs: up to 12 % of the backbone's peak), so that part is not compared.
LAW_RTOL = 1e-3

#: The least fraction of each curve's samples (up to the tear) that the two laws must share
#: to be compared (:func:`law_differences`): another machine's push shared 123 of 131.
SHARED = 0.9

#: The marks reached after the first tear, not compared (:data:`LAW_RTOL`).
AFTER_TEAR = ("off_set",)

#: The law's curves: abscissa, ordinate (:class:`rigid.rims.RimLaw`).
CURVES = (("push_displacement", "push_force"), ("plastic_set", "force"),
          ("plastic_set", "corner_height"))


def _to_json(law: RimLaw) -> dict:
    return {f.name: np.asarray(getattr(law, f.name)).tolist()
            for f in dataclasses.fields(RimLaw)}


def _from_json(data: dict) -> RimLaw:
    return RimLaw(**{k: (np.asarray(v, dtype=float) if isinstance(v, list) else float(v))
                     for k, v in data.items()})


def stored_rim_law(store: ResultStore, bearing: DFPBearing, model: str = "plane-strain",
                   fracture: str | None = None, *,
                   edge_radius: float | None = None,
                   crush_jacobian: float | None = None) -> RimLaw | None:
    """The law of ``bearing``'s rims that ``store`` holds under today's key (the arguments
    of :func:`rigid.rims.rim_law_cache_file`), or None."""
    data = store.get(rim_law_cache_file(bearing, model, fracture, edge_radius=edge_radius,
                                        crush_jacobian=crush_jacobian).stem)
    return None if data is None else _from_json(data)


def _wanted(models, fracture, edge_radius, crush_jacobian=None):
    """(model, fracture set or None, the push's keywords of
    :func:`rigid.rims.rim_law_cache_file`: slider edge radius and crushing J_c, each or None)
    of each law wanted."""
    plain = {"edge_radius": None, "crush_jacobian": None}
    wanted = [(model, None, plain) for model in dict.fromkeys(models)]
    if fracture is not None:
        wanted.append(("plane-strain", fracture,
                       {"edge_radius": edge_radius, "crush_jacobian": crush_jacobian}))
    return wanted


def _push(bearing: DFPBearing, model: str, fracture, push: dict) -> RimLaw:
    """The law pushed by today's FE code (cached by :func:`fem.rim_law`); ``push`` as
    :func:`_wanted` gives it."""
    from fem import rim_law

    punch = ({} if push["edge_radius"] is None
             else {"punch": "slider", "edge_radius": push["edge_radius"]})
    if push["crush_jacobian"] is not None:
        punch["crush_jacobian"] = push["crush_jacobian"]
    return rim_law(bearing, model=model, fracture=fracture, **punch)


def keep_rim_laws(store: ResultStore, bearing: DFPBearing, models, *,
                  replay: bool = False, fracture: str | None = None,
                  edge_radius: float | None = None,
                  crush_jacobian: float | None = None) -> None:
    """Make the rim laws of ``bearing`` from each of ``models`` ("plane-strain", "ring") be
    both in ``store`` and in the library's cache, so that :func:`fem.rim_law` and
    :func:`fem.effective_rim_depth` read them; with ``fracture``, the plane-strain law
    through tearing with that set too (:func:`fem.rim_law`'s ``fracture``), pushed by the
    slider with edges of ``edge_radius`` [m] when given (``punch="slider"``), crushing the
    rim's elements below ``crush_jacobian`` when given.

    A law found in the store is written to the cache if the cache lacks it or holds another
    (the same push made on another machine rounds differently); a law in neither
    is pushed by the FE companion (cached) and stored, unless ``replay``: then
    :class:`rigid.tasks.MissingResultsError` names it. The pressure does not matter.
    """

    missing = []
    for model, torn, push in _wanted(models, fracture, edge_radius, crush_jacobian):
        path = rim_law_cache_file(bearing, model, torn, **push)
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
            store.put(key, "rim-law", _to_json(_push(bearing, model, torn, push)))
    if missing:
        from collections import Counter

        raise MissingResultsError(Counter({"rim-law": len(missing)}), store)


def carry_rim_laws(store: ResultStore, bearing: DFPBearing, models, revision: str, *,
                   fracture: str | None = None, edge_radius: float | None = None,
                   crush_jacobian: float | None = None,
                   keep_differing: bool = False) -> list[str]:
    """``--rekey-from revision``: copy the laws that ``store`` holds under the keys of
    ``revision``'s code (the arguments as :func:`keep_rim_laws`') to today's keys, each once
    a push with today's code agrees with it (:func:`law_differences`). The stored law is
    kept, not today's: a law pushed on another machine differs in its last digits, and the
    stored runs key on its numbers. ``keep_differing``: carry a law over even where today's
    push differs (``--keep-stored-laws``: the run's remaining cases then use the law its
    stored ones used).

    Returns
    -------
    list of str
        One line per law carried over, with the fields in which today's push differed;
        :class:`rigid.tasks.rekey.RekeyError` if one differs and not ``keep_differing``.
    """
    from rigid.tasks.rekey import RekeyError, code_at

    lines = []
    for model, torn, push in _wanted(models, fracture, edge_radius, crush_jacobian):
        new = rim_law_cache_file(bearing, model, torn, **push).stem
        if new in store:
            continue
        with code_at(revision, today=()):
            stored = store.get(rim_law_cache_file(bearing, model, torn, **push).stem)
        if stored is None:
            continue
        differ = law_differences(_push(bearing, model, torn, push), _from_json(stored))
        name = f"the {model} rim law{'' if torn is None else ' through tearing'}"
        if differ and not keep_differing:
            raise RekeyError(f"{name} pushed with today's code differs from the one stored "
                             f"by {revision} ({', '.join(differ)}): the physics changed, or "
                             "the push is not repeatable there; nothing was carried over "
                             "(rerun instead, or keep the stored law: --keep-stored-laws)")
        store.put(new, "rim-law", stored)
        lines.append(f"{name} carried over" + (
            f", kept although today's push differs in {', '.join(differ)}" if differ else
            ": today's push agrees"))
    return lines


def _paired(xa: np.ndarray, xb: np.ndarray):
    """Indices (i, j) of the samples of two sorted curves at the same abscissa, to 1e-5 of
    the range (the push's increments are at least 25 µm, 6e-4 of a 40 mm push; a backbone
    row's set moves with its force, F/k_el): a push that took other increments shares most
    of its samples with the other."""
    if not (xa.size and xb.size):
        return np.zeros(0, dtype=int), np.zeros(0, dtype=int)
    tol = 1e-5 * max(np.abs(xa).max(), np.abs(xb).max())
    right = np.clip(np.searchsorted(xb, xa), 0, xb.size - 1)
    left = np.maximum(right - 1, 0)
    j = np.where(np.abs(xb[left] - xa) <= np.abs(xb[right] - xa), left, right)
    i = np.flatnonzero(np.abs(xb[j] - xa) <= tol)
    return i, j[i]


def curve_gap(now: RimLaw, then: RimLaw, x: str, y: str, up_to: float = np.inf):
    """Two laws' curve ``y`` against ``x`` (:data:`CURVES`) at the samples they share up to
    the permanent set ``up_to`` [m] (for the push curve, u_p = δ − F/k_el, Eq. R56): the
    largest difference relative to the curve's largest value, and the smaller of the two
    fractions of samples shared (None, None if one law lacks the curve)."""
    xa, ya, xb, yb = (np.asarray(getattr(law, n), dtype=float)
                      for law in (now, then) for n in (x, y))
    if ya.size != xa.size or yb.size != xb.size:
        return None, None
    sa, sb = ((xa - ya / now.stiffness, xb - yb / then.stiffness) if x == "push_displacement"
              else (xa, xb))
    ka, kb = sa <= up_to, sb <= up_to
    i, j = _paired(xa[ka], xb[kb])
    gap = np.abs(ya[ka][i] - yb[kb][j]).max(initial=0.0)
    peak = max(np.abs(ya).max(initial=0.0), np.abs(yb).max(initial=0.0))
    relative = gap / peak if peak > 0.0 else (0.0 if gap == 0.0 else np.inf)
    return relative, min(i.size / max(ka.sum(), 1), j.size / max(kb.sum(), 1))


def law_differences(now: RimLaw, then: RimLaw, rtol: float = LAW_RTOL) -> list[str]:
    """The fields of two rim laws that differ by more than ``rtol`` (:data:`LAW_RTOL`): the
    scalar marks relative to their size (equal infinities agree); the curves (:data:`CURVES`)
    relative to their largest value at the samples they share, which must be at least
    :data:`SHARED` of each one's samples, up to the first tear for laws through tearing
    (:func:`curve_gap`)."""
    out = []
    for f in dataclasses.fields(RimLaw):
        a, b = getattr(now, f.name), getattr(then, f.name)
        if f.name not in AFTER_TEAR and np.ndim(a) == 0 and not (
                a == b or abs(a - b) <= rtol * max(abs(a), abs(b))):
            out.append(f.name)
    tear = min(now.tear_set, then.tear_set)  # inf without tearing
    for x, y in CURVES:
        gap, shared = curve_gap(now, then, x, y, tear)
        if gap is None:  # a curve one of the laws does not have
            if getattr(now, y).size or getattr(then, y).size:
                out.append(y)
        elif shared < SHARED or gap > rtol:
            out.append(y)
    return out
