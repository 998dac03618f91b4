"""Python values -> TOML text for the scene parser (so Python-built scenes go through the same
parser, validator and messages as scene files)."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

_BARE = set("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-")


def key(k: str) -> str:
    """A TOML key: bare when possible, quoted otherwise."""
    return k if k and set(k) <= _BARE else json.dumps(k)


def _float(x: float) -> str:
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return repr(float(x))  # shortest repr: parses back to the same double


def value(v: Any) -> str:
    """One TOML value (inline tables and arrays for mappings and sequences)."""
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        return _float(float(v))
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, Mapping):
        return "{ " + ", ".join(f"{key(str(k))} = {value(x)}" for k, x in v.items()) + " }"
    if isinstance(v, np.ndarray):
        if v.ndim != 1:
            raise TypeError(f"expected a 1-D array, got shape {v.shape}")
        if v.dtype.kind == "f":
            return "[" + ", ".join(_float(x) for x in v.tolist()) + "]"
        return "[" + ", ".join(value(x) for x in v.tolist()) + "]"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(value(x) for x in v) + "]"
    raise TypeError(f"cannot write a {type(v).__name__} as a scene value")


def document(tables: Mapping[str, Mapping[str, Any]]) -> str:
    """A TOML document of `{table: {key: value}}` (tables with no keys are left out)."""
    out = []
    for name, items in tables.items():
        if not items:
            continue
        out.append(f"[{key(name)}]")
        out.extend(f"{key(k)} = {value(x)}" for k, x in items.items() if x is not None)
        out.append("")
    return "\n".join(out)
