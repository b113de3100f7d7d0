"""Dotted paths into scene and summary data (the parameters and output columns of a sweep).

A path is a string of segments joined by ``.``: ``contacts.0.friction``,
``boundary_conditions.cylinder/flat.value.1``, ``bodies.*.element_size``. Inside a dict a segment
is a key. Inside a list it is an index (negative counts from the end), ``*`` (every item) or a
name: the items whose ``name`` is the segment, or whose ``bodies`` joined by ``/`` are
(``cylinder/block`` for a contact), or whose ``body/edge`` are (``cylinder/flat`` for a boundary
condition; a condition without an edge, such as a body force, answers to its body's name).
Names that contain a dot cannot be written as a segment: use the item's index.
"""

from __future__ import annotations

import copy
from typing import Any


class PathError(ValueError):
    """A dotted path that does not lead anywhere in the data (the message says where it stops)."""


def split_path(path: str) -> list[str]:
    segments = path.split(".")
    if not path or any(s == "" for s in segments):
        raise PathError(f"{path!r} is not a dotted path (segments joined by '.', none empty)")
    return segments


def _item_names(item: Any) -> list[str]:
    if not isinstance(item, dict):
        return []
    names = []
    if isinstance(item.get("name"), str):
        names.append(item["name"])
    bodies = item.get("bodies")
    if isinstance(bodies, list) and all(isinstance(b, str) for b in bodies):
        names.append("/".join(bodies))
    if isinstance(item.get("body"), str):
        names.append(f"{item['body']}/{item['edge']}" if isinstance(item.get("edge"), str) else item["body"])
    return names


def _list_indices(items: list, seg: str, where: str) -> list[int]:
    if seg == "*":
        return list(range(len(items)))
    try:
        k = int(seg)
    except ValueError:
        found = [i for i, item in enumerate(items) if seg in _item_names(item)]
        if not found:
            known = sorted({n for item in items for n in _item_names(item)})
            raise PathError(f"{where}: no item named {seg!r} (names: {', '.join(known) or 'none'}; "
                            f"or an index 0..{len(items) - 1})") from None
        return found
    if not -len(items) <= k < len(items):
        raise PathError(f"{where}: index {k} out of range (the list has {len(items)} items)")
    return [k % len(items)]


def _children(node: Any, seg: str, where: str, create: bool) -> list[tuple[Any, Any]]:
    """(container, key) pairs the segment designates in ``node``."""
    if isinstance(node, list):
        return [(node, i) for i in _list_indices(node, seg, where)]
    if isinstance(node, dict):
        if seg not in node and not create:
            raise PathError(f"{where}: no key {seg!r} (keys: {', '.join(map(str, node)) or 'none'})")
        return [(node, seg)]
    raise PathError(f"{where}: cannot go into a {type(node).__name__} value ({node!r})")


def get_path(data: Any, path: str) -> Any:
    """The value at ``path``; a ``*`` or a name matching several items gives a list."""
    segments = split_path(path)
    nodes, many = [data], False
    for n, seg in enumerate(segments):
        where = ".".join(segments[: n + 1])
        nxt = []
        for node in nodes:
            pairs = _children(node, seg, where, create=False)
            many = many or len(pairs) > 1 or seg == "*"
            nxt += [c[k] for c, k in pairs]
        nodes = nxt
    return nodes if many else nodes[0]


def set_path(data: Any, path: str, value: Any) -> int:
    """Set ``value`` at ``path`` in place (a missing last key of a table is added); returns
    how many places were set."""
    segments = split_path(path)
    nodes = [data]
    for n, seg in enumerate(segments[:-1]):
        where = ".".join(segments[: n + 1])
        nodes = [c[k] for node in nodes for c, k in _children(node, seg, where, create=False)]
    count = 0
    for node in nodes:
        for container, key in _children(node, segments[-1], path, create=True):
            container[key] = copy.deepcopy(value)
            count += 1
    return count
