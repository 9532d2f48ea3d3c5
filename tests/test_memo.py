"""memo.kept: a value worked out once per object and key, kept on the object."""

from __future__ import annotations

from socnavgen.memo import kept


class Owner:
    pass


class Slotted:
    __slots__ = ()


def test_built_once_per_owner_and_key() -> None:
    calls: list[int] = []

    def build(value: int) -> list[int]:
        calls.append(value)
        return [value]

    a, b = Owner(), Owner()
    first = kept(a, "things", lambda: build(1), key=1)
    assert kept(a, "things", lambda: build(9), key=1) is first  # kept: not built again
    assert kept(a, "things", lambda: build(2), key=2) == [2]  # another key: its own value
    assert kept(b, "things", lambda: build(3), key=1) == [3]  # another owner: its own value
    assert kept(a, "other", lambda: build(4), key=1) == [4]  # another name: its own dict
    assert calls == [1, 2, 3, 4]


def test_an_owner_without_attributes_gets_a_fresh_value() -> None:
    owner = Slotted()
    first = kept(owner, "things", lambda: [1])
    second = kept(owner, "things", lambda: [1])
    assert first == second and first is not second
