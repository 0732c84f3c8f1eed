"""The validation report: a self-contained HTML page (:mod:`validation.report.html`), a CSV per
table and ``report.nc`` with every table (:mod:`validation.report.netcdf`), written from a run's
results by :func:`write_report`."""

from .write import write_report

__all__ = ["write_report"]
