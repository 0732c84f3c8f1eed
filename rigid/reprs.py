"""Short representations of result objects: ``print(result)`` shows the key numbers, arrays
by their shape and long sequences by their length, never the data itself.

:func:`concise_repr` works on any dataclass; :func:`install` makes it the ``__repr__`` of the
library's result classes. It is installed from here (``rigid/__init__.py`` calls
:func:`install`) rather than written into the classes' own modules because their source
keys the stored results (:data:`rigid.tasks.cache.MODEL_CODE`): a representation must not make
every stored ladder unreachable. Other packages call :func:`install` with their own classes.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .units import G

__all__ = ["concise_repr", "install"]

#: Longest text shown for a string field [characters].
MAX_TEXT = 40
#: Most items of a dict shown in full.
MAX_ITEMS = 4


def _value(name: str, value) -> str:
    """One field: numbers with 4 significant digits (an SA [m/s²] also in g), arrays as
    ``array(shape)``, sequences as ``[n items]``, objects by their class."""
    if value is None or isinstance(value, bool):
        return repr(value)
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        value = float(value)
        text = f"{value:.4g}" if math.isfinite(value) else repr(value)
        if (name == "sa" or name.endswith("_sa")) and math.isfinite(value):
            text += f" ({value / G:.3g} g)"
        return text
    if isinstance(value, str):
        return repr(value if len(value) <= MAX_TEXT else value[: MAX_TEXT - 1] + "…")
    if isinstance(value, np.ndarray):
        return f"array{value.shape}"
    if isinstance(value, dict):
        if len(value) <= MAX_ITEMS and all(v is None or isinstance(v, (int, float, str))
                                           for v in value.values()):
            return "{" + ", ".join(f"{k!r}: {_value(str(k), v)}" for k, v in value.items()) + "}"
        return f"{{{len(value)} items}}"
    if isinstance(value, (list, tuple)):
        return f"[{len(value)} items]"
    return f"{type(value).__name__}(…)"


def concise_repr(obj) -> str:
    """``ClassName(field=value, …, arrays: n × (shape))`` of a dataclass instance, each
    field by :func:`_value`, the array fields counted by shape at the end: the key numbers
    and the shapes, not the data."""
    parts, shapes = [], {}
    for f in dataclasses.fields(obj):
        if not f.repr:
            continue
        value = getattr(obj, f.name)
        if isinstance(value, np.ndarray):
            shapes.setdefault(value.shape, []).append(f.name)
        else:
            parts.append(f"{f.name}={_value(f.name, value)}")
    for shape, names in shapes.items():
        parts.append(f"{names[0]}=array{shape}" if len(names) == 1
                     else f"{len(names)} arrays {shape} ({names[0]}, …)")
    return f"{type(obj).__name__}({', '.join(parts)})"


def install(*classes) -> None:
    """Make :func:`concise_repr` the ``__repr__`` of each dataclass in ``classes``."""
    for cls in classes:
        cls.__repr__ = concise_repr
