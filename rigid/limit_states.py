"""The names of the limit states by which a bearing's failure is judged: the first rim hinge,
the rupture of a rim, the loss of containment (definitions: docs/theory/finite-elements.md,
"Limit states"), and the one function that checks a limit state's name. Kept here, free of
heavy imports, so that both models, the FE searches and the ``dfp`` command share one list and
one check (docs/architecture.md: a module of the neutral base).

Every signature names a limit state ``limit_state`` (as the command line's ``--limit-state``);
the older keyword names ``failure_criterion`` and ``criterion`` are accepted for one release
with a :class:`DeprecationWarning` (:func:`renamed_limit_state`).
"""

from __future__ import annotations

import functools
import warnings

__all__ = ["DEPRECATED_NAMES", "LIMIT_STATES", "RIM_MODELS", "check_limit_state",
           "check_limit_states", "renamed_limit_state"]

#: The limit states, in the order a rim usually reaches them.
LIMIT_STATES = ("hinge", "rupture", "containment")

#: The rim models of both models' ``rims`` argument: rims that cannot yield (the paper's) or
#: elastoplastic rims (docs/theory/rigid-body.md, "Yielding rims").
RIM_MODELS = ("rigid", "yielding")

#: Keyword names a limit state had before it was ``limit_state`` everywhere (accepted with a
#: DeprecationWarning for one release).
DEPRECATED_NAMES = ("failure_criterion", "criterion")


def check_limit_state(limit_state: str | None, *, rims: str | None = None) -> str:
    """The limit state a run is judged by, checked: the one validating function of the names.

    Parameters
    ----------
    limit_state : {"hinge", "rupture", "containment"} or None
        The limit state that defines failure. None: the rim model's default ("hinge" with
        yielding rims, "containment" with rigid ones); None without ``rims`` is an error.
    rims : {"rigid", "yielding"}, optional
        The rim model, when the limit state must be one it can reach: rigid rims cannot
        hinge or rupture, so they have only "containment".

    Returns
    -------
    str
        The limit state's name.

    Raises
    ------
    ValueError
        For an unknown rim model or limit state, or one the rim model cannot reach.
    """
    if rims is not None and rims not in RIM_MODELS:
        raise ValueError(f"rims must be one of {', '.join(RIM_MODELS)}, got {rims!r}")
    if limit_state is None and rims is not None:
        return "hinge" if rims == "yielding" else "containment"
    if limit_state not in LIMIT_STATES:
        raise ValueError(f"limit_state must be one of {', '.join(LIMIT_STATES)}, got "
                         f"{limit_state!r}")
    if rims == "rigid" and limit_state != "containment":
        raise ValueError(f"rims='rigid' cannot yield, so limit_state {limit_state!r} cannot be "
                         "reached; use rims='yielding'")
    return limit_state


def check_limit_states(limit_states) -> tuple[str, ...]:
    """Several limit states (e.g. those an FE search decides, the command line's repeated
    ``--limit-state``), each checked by :func:`check_limit_state`, duplicates dropped, in the
    order given; ValueError for none."""
    names = tuple(dict.fromkeys(check_limit_state(s) for s in limit_states))
    if not names:
        raise ValueError(f"limit_states must be some of {', '.join(LIMIT_STATES)}, got none")
    return names


def renamed_limit_state(*old_names: str):
    """Decorator factory: the decorated function accepts the deprecated keyword names of
    ``limit_state`` (default ``failure_criterion``; e.g. ``renamed_limit_state("criterion")``
    where a signature called it ``criterion``) with a :class:`DeprecationWarning`, passing the
    value on as ``limit_state``. A TypeError if both an old and the new name are given.

    Usage: ``@renamed_limit_state()`` above ``def simulate(..., limit_state=None)``."""
    names = old_names or ("failure_criterion",)
    unknown = [n for n in names if n not in DEPRECATED_NAMES]
    if unknown:
        raise ValueError(f"not a former name of limit_state: {unknown}")

    def decorate(function):
        @functools.wraps(function)
        def call(*args, **kwargs):
            for old in names:
                if old in kwargs:
                    if "limit_state" in kwargs:
                        raise TypeError(f"{function.__qualname__}() got both limit_state and "
                                        f"its deprecated name {old}")
                    warnings.warn(f"{function.__qualname__}(): {old}= is deprecated, use "
                                  "limit_state=", DeprecationWarning, stacklevel=2)
                    kwargs["limit_state"] = kwargs.pop(old)
            return function(*args, **kwargs)

        return call

    return decorate


def deprecated_attribute(old: str, new: str = "limit_state"):
    """A read-only property ``old`` that returns ``self.new`` with a DeprecationWarning (the
    results' former ``failure_criterion`` attribute)."""

    def get(self):
        warnings.warn(f"{type(self).__name__}.{old} is deprecated, use .{new}",
                      DeprecationWarning, stacklevel=2)
        return getattr(self, new)

    return property(get, doc=f"Deprecated alias of :attr:`{new}`.")
