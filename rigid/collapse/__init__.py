"""Critical SA and collapse (paper §4): the critical SA(Tb) of a record by the scaling ladder of
time histories, its prediction from the record's Ricker pulse and the impact region, trimming
of scaled records, fragility and collapse margin, and the comparison tables of the paper
(Table 2). The definitions are in ``docs/theory/collapse.md``."""

from .comparison import comparison_rows, ladder_rows, table2, write_csv
from .fragility import (
    CollapseMargin,
    LognormalFit,
    collapse_margin,
    fit_lognormal,
    set_collapse_intensity,
)
from .ladder import CriticalSA, Rung, critical_sa
from .limit_state_ladder import critical_sa_by_limit_state
from .predict import PredictedSA, PredictionRung, predict_critical_sa, pulse_region
from .record_set import critical_sas
from .trimming import critical_sa_trimmed, trimmed_outcome, trimmed_window

__all__ = [
    "CollapseMargin",
    "CriticalSA",
    "LognormalFit",
    "PredictedSA",
    "PredictionRung",
    "Rung",
    "collapse_margin",
    "comparison_rows",
    "critical_sa",
    "critical_sa_by_limit_state",
    "critical_sa_trimmed",
    "critical_sas",
    "fit_lognormal",
    "ladder_rows",
    "predict_critical_sa",
    "pulse_region",
    "set_collapse_intensity",
    "table2",
    "trimmed_outcome",
    "trimmed_window",
    "write_csv",
]
