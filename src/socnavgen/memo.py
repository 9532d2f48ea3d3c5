"""Values kept on the object they were worked out from: one Location's World, one World's fields, one
formula's node count. A campaign's worker asks for them thousands of times on the same few objects; kept on
the object (not in a module-level dict), they go when it goes."""

from __future__ import annotations

from collections.abc import Callable, Hashable
from typing import Any, TypeVar

T = TypeVar("T")


def kept(owner: Any, name: str, build: Callable[[], T], key: Hashable = None) -> T:
    """`build()`, worked out once per `owner` object and `key` and kept on it (attribute `_socnavgen_<name>`,
    a dict by key). An owner that takes no new attribute (a slotted or frozen stand-in) gets a fresh value
    on every call."""
    attr = f"_socnavgen_{name}"
    found: dict[Hashable, Any] | None = getattr(owner, attr, None)
    if found is None:
        found = {}
        try:
            setattr(owner, attr, found)
        except AttributeError:
            return build()
    if key not in found:
        found[key] = build()
    return found[key]
