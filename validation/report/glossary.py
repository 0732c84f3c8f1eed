"""The report's glossary: every term and symbol it uses, defined once (:data:`GLOSSARY`), and
the anchors its text links them by (``[[critical SA]]`` in a paragraph of
:class:`validation.report.html.Report` becomes a link to the definition)."""

from __future__ import annotations

import re

__all__ = ["GLOSSARY", "anchor"]

#: Term → definition, in the order a reader meets them. Plain text; ``[[term]]`` links to
#: another entry.
GLOSSARY = {
    "SA(Tb)": "The 5 %-damped pseudo-spectral acceleration of a ground motion at the "
    "bearing's design period Tb (4.5 s in the paper, so also written SA(4.5 s)), in g. "
    "Records are scaled by it, and every critical SA is one.",
    "ladder": "A record scaled to SA(Tb) = 0.01 g, 0.02 g, … up to the ladder's top "
    "(Settings); each scaled record is a [[rung]]. A fast ladder search runs every 0.1 g "
    "first, then the 0.01 g rungs below the first failure.",
    "rung": "One scaling of a record on the [[ladder]] and the run of a model on it.",
    "critical SA": "The SA(Tb) of the first rung of the [[ladder]] at which the bearing "
    "fails (paper §4.2), under the model's [[limit state]]; 'no failure' if none up to the "
    "top.",
    "resurrection": "A rung above the [[critical SA]] at which the bearing survives again "
    "(the response near failure is chaotic); the critical SA stays the first failure.",
    "numerical rung": "A rung whose integration stayed unstable after three step halvings: "
    "neither a failure nor a survival.",
    "uncertain": "A critical SA that depends on a [[numerical rung]] (one just below the first "
    "failure, or any without failure); left out of Table 2, the fragility and the medians.",
    "limit state": "What counts as failure. hinge: the first rim root fully plastic across "
    "its thickness; rupture: a rim's plastic strain, averaged over a gauge of its thickness, "
    "past the steel's rupture strain; containment: the slider gets past a rim or overturns "
    "(failure under every limit state). Rigid rims can only lose containment.",
    "rigid model": "The rigid-body model of the bearing (the paper's): plates, a rigid slider "
    "that can rotate, Hertz contacts with damping, Coulomb friction, and rims that are "
    "either [[rigid rims]] or [[yielding rims]].",
    "rigid rims": "The paper's rims: they cannot yield; the bearing fails only by losing "
    "containment.",
    "yielding rims": "Rims of the [[rigid model]] that bend and take a permanent set, by a "
    "force-deflection law from static pushes of the FE model's rim; they reach the same "
    "[[limit state]]s as the FE model.",
    "FE model": "The 2-D plane-strain finite-element model: elastoplastic plates and rims, "
    "the slider as a rigid body in contact with friction. It checks the [[rigid model]].",
    "FE / rigid": "The FE model's critical SA over the rigid model's, for one record, "
    "pressure and limit state: below 1 the rigid model overstates the strength.",
    "uplift": "Failure mode: the slider climbs over a rim that holds.",
    "yielding": "Failure mode: a rim lets go (a hinge or a rupture first, or the slider "
    "passes a bent rim).",
    "predicted SA": "The critical SA predicted from a single Ricker pulse fitted to the record "
    "(paper §4.1-4.3): the first rung whose scaled pulse fails the bearing.",
    "criterion": "How the Ricker pulse is chosen from the record's wavelet transform (paper "
    "§4.1): 1 the largest coefficient; 2 the best acceleration match; 3 the best velocity "
    "match; 4 the best of both (Vassiliou & Makris 2011).",
    "Tp, Ap": "The period [s] and amplitude [g] of a Ricker pulse.",
    "error": "Predicted over actual critical SA minus 1 [%]; within 20 % counts as a good "
    "prediction (paper Table 2).",
    "Table 2": "How many predictions are within 20 % of the actual critical SA, for records "
    "whose pulse is long (Tp > 0.5 s), as in the paper's Table 2.",
    "fragility": "The probability of failure against SA(Tb): a lognormal distribution "
    "fitted to the critical SAs (records without failure count as above the ladder's top); "
    "its median and its dispersion β (the standard deviation of ln SA). Fewer than 10 "
    "records give two significant digits at most.",
    "S_MT": "The MCE spectral acceleration at Tb of FEMA P695 for the design category.",
    "CMR": "Collapse margin ratio: the median critical SA over [[S_MT]] (FEMA P695 §7.2); "
    "Ŝ_CT is the same median by FEMA P695's scaling of the whole set.",
    "ACMR": "Adjusted CMR, SSF × CMR, with SSF the spectral shape factor (FEMA P695 App. B). "
    "It passes when it reaches ACMR10 (10 % probability of collapse at the MCE, Table 7-3, "
    "for β_TOT, the total uncertainty); ACMR20 is the 20 % limit for a single archetype.",
    "heavy, light bearing": "The paper's bearings at 60 MPa (heavy) and 10 MPa (light) "
    "slider pressure.",
}


def anchor(term: str) -> str:
    """The id of a term's definition: ``g-critical-sa``."""
    return "g-" + re.sub(r"[^a-z0-9]+", "-", term.lower()).strip("-")
