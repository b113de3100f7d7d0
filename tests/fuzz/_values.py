"""Hypothesis strategies of the fuzz campaign: JSON values a new user (or a damaged
file) might put anywhere, and mutations of a parsed document at a random key path."""

from __future__ import annotations

import copy
from typing import Any

from hypothesis import strategies as st

#: words that mean something somewhere in a scene or an Onshape response
WORDS = ["yes", "no", "true", "free", "contact", "", " ", "steel", "upper", "lower", "flat", "arc", "band",
         "ellipse", "tied", "frictionless", "frictional", "polygon", "profile", "disk", "line", "PLANE", "CYLINDER",
         "BCURVE", "SOLID", "NaN", "1e300", "0.04", "\u00e9", "\x00", "a" * 200]
SPECIAL_NUMBERS = [0, -1, 1, 2, 3, 12, 13, 10_001, 2**31, 2**63, 10**30, 10**300, 0.0, -0.0, 1e-300, 5e-324,
                   -1e-12, 1e-9, 0.5, 0.999, 1.0 + 1e-15, 1e20, 1e21, 1e300, -1e300, 1e308, float("inf"),
                   float("-inf"), float("nan")]
FACTORS = [0.0, -1.0, 1e-6, 1e-3, 0.1, 0.5, 0.999, 1.001, 2.0, 10.0, 1e3, 1e6, 1e300]

scalars = st.one_of(
    st.none(), st.booleans(), st.sampled_from(SPECIAL_NUMBERS), st.integers(-1000, 1000),
    st.floats(allow_nan=True, allow_infinity=True), st.sampled_from(WORDS), st.text(max_size=6),
)
json_values = st.recursive(
    scalars,
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.sampled_from(WORDS[:12]) | st.text(max_size=5),
                                                                 inner, max_size=3),
    max_leaves=8,
)


def paths(doc: Any, prefix: tuple = (), limit: int = 4000) -> list[tuple]:
    """Every key path of a parsed JSON document (the root is ()), at most ``limit``."""
    out: list[tuple] = [prefix]
    stack = [(doc, prefix)]
    while stack and len(out) < limit:
        node, loc = stack.pop()
        items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
        for k, v in items:
            out.append(loc + (k,))
            if isinstance(v, (dict, list)):
                stack.append((v, loc + (k,)))
    return out


def _parent(doc: Any, loc: tuple) -> Any:
    for k in loc[:-1]:
        doc = doc[k]
    return doc


def mutate(doc: Any, draw) -> tuple[Any, str]:
    """One random change of ``doc`` (a deep copy is changed): replace a value, delete a key or
    item, add an unknown key, duplicate an item, scale a number, or turn a value into a list /
    a string of itself. Returns (document, description)."""
    doc = copy.deepcopy(doc)
    all_paths = paths(doc)
    leaves = [p for p in all_paths if p and not isinstance(_parent(doc, p)[p[-1]], (dict, list))]
    pool = leaves if leaves and draw(st.integers(0, 4)) else all_paths  # mostly values, sometimes tables
    loc = pool[draw(st.integers(0, len(pool) - 1))]
    op = draw(st.sampled_from(["scale", "scale", "scale", "replace", "replace", "delete", "add_key", "duplicate",
                               "wrap", "stringify"]))
    if not loc:
        if op == "replace" or not isinstance(doc, dict):
            return draw(json_values), "root replaced"
        op = "add_key"
    parent = _parent(doc, loc) if loc else None
    key = loc[-1] if loc else None
    current = parent[key] if loc else doc
    if op == "replace":
        parent[key] = draw(json_values)
    elif op == "delete":
        del parent[key]
    elif op == "add_key" and isinstance(current, dict):
        current[draw(st.sampled_from(WORDS[:12]) | st.text(max_size=5))] = draw(json_values)
    elif op == "duplicate" and isinstance(parent, list):
        parent.insert(key, copy.deepcopy(current))
    elif op == "scale" and isinstance(current, (int, float)) and not isinstance(current, bool):
        try:
            parent[key] = current * draw(st.sampled_from(FACTORS))
        except OverflowError:
            parent[key] = float("inf")
    elif op == "wrap":
        parent[key] = [current]
    elif op == "stringify" and not isinstance(current, (dict, list)):
        parent[key] = str(current)
    else:
        parent[key] = draw(json_values)
        op = "replace"
    return doc, f"{op} at {'/'.join(map(str, loc))}"
