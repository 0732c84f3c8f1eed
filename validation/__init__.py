"""Validation runs across ground-motion sets, the result store, reports and the ``dfp`` command."""
