"""Named state: the simulator keeps its state in numpy structured arrays, one record per person, tree node,
cue..., and single records for the robot and the clock, so that compiled code reads like the domain
(`people[i].pos`, `robot.heading`, `clock.t`) and a call passes one pointer per table.

Tables are record arrays: numba compiles them like any structured array, and plain Python (numba off)
reads and writes their fields by name too."""

from __future__ import annotations

import functools
import struct
from typing import TYPE_CHECKING, Any

import numpy as np

_RESERVED = set(dir(np.record))  # attribute names a field would hide behind in plain Python


def layout(fields: list[tuple[str, str]]) -> np.dtype:
    """The dtype of a table (aligned, as numba prefers); field names must not shadow a record's methods."""
    clash = [name for name, _ in fields if name in _RESERVED]
    if clash:
        raise ValueError(f"field names {clash} hide numpy record attributes: rename them")
    return np.dtype(fields, align=True)


def table(dtype: np.dtype, rows: int, **columns: Any) -> np.recarray:
    """`rows` zeroed records, with the given columns filled."""
    out = np.zeros(rows, dtype=dtype).view(np.recarray)
    for name, value in columns.items():
        out[name] = value
    return out


def record(dtype: np.dtype, **fields: Any) -> np.record:
    """One record (a view into a one-row table: writes from compiled code land in it)."""
    return table(dtype, 1, **fields)[0]


class Columns:
    """Every field of a table as a numpy view (`columns.pos[i]`): reading one value this way costs ~50 ns
    from Python, where a record's attribute costs ~1.5 us."""

    def __init__(self, rows: np.ndarray) -> None:
        base = rows.view(np.ndarray)
        for name in base.dtype.names or ():
            setattr(self, name, base[name])

    if TYPE_CHECKING:  # the fields are set per table; each is an array
        def __getattr__(self, name: str) -> np.ndarray: ...


_PACK = {"f8": "d", "i8": "q", "b1": "?", "c16": "dd"}  # a field's numpy kind -> struct codes (complex: re, im)


class RowWriter:
    """Writes every field of one record of a table in a single call (`write(*values)`, fields in order, a complex
    one as two floats re, im): one struct.pack_into instead of a numpy store per field (~1 us -> ~0.2 us from
    Python, the cost that counts when a Python robot policy answers every step)."""

    def __init__(self, rows: np.ndarray, row: int = 0) -> None:
        base = rows.view(np.ndarray)
        dtype, codes, at = base.dtype, ["<"], 0
        for name in dtype.names or ():
            field, offset = dtype.fields[name][:2]
            code = _PACK.get(f"{field.kind}{field.itemsize}")
            if code is None:
                raise ValueError(f"RowWriter: field {name} of type {field} is not supported")
            codes += ["x" * (offset - at), code]
            at = offset + field.itemsize
        codes.append("x" * (dtype.itemsize - at))
        self._struct = struct.Struct("".join(codes))
        self._buffer = base[row:row + 1].view(np.uint8).data
        self.write = functools.partial(self._struct.pack_into, self._buffer, 0)
