"""The names of the limit states by which a bearing's failure is judged: the first rim hinge,
the rupture of a rim, the loss of containment (definitions: docs/theory/finite-elements.md,
"Limit states"). Kept here, free of heavy imports, so that the FE model, its searches and the
``dfp`` command share one list."""

#: The limit states, in the order a rim usually reaches them.
LIMIT_STATES = ("hinge", "rupture", "containment")
