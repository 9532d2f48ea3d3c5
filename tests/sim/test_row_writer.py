"""records.RowWriter writes a Python policy's answer into the ACTION record in one store: every field must land
where the compiled step reads it by name (aligned padding, a bool between floats, a complex as two floats), and a
table of a kind it cannot pack is refused rather than written wrong."""

from __future__ import annotations

import pytest

from socnavgen.sim.engine.state import ACTION, singleton
from socnavgen.sim.records import RowWriter, layout, table


def test_every_action_field_lands_where_it_is_read_by_name() -> None:
    action = singleton(ACTION, gesture=-1)
    RowWriter(action).write(0.25, -1.5, 3, True, 0.6, -0.8, True, 0.4, -0.9)
    row = action[0]
    assert (row.vx, row.vy, row.gesture) == (0.25, -1.5, 3)
    assert bool(row.has_heading) and row.heading == complex(0.6, -0.8)
    assert bool(row.unicycle) and (row.forward, row.turn) == (0.4, -0.9)
    RowWriter(action).write(0.0, 0.0, -1, False, 1.0, 0.0, False, 0.0, 0.0)
    assert not action[0].has_heading and not action[0].unicycle and action[0].gesture == -1


def test_only_its_row_is_written() -> None:
    rows = table(layout([("a", "f8"), ("flag", "?"), ("b", "i8")]), 3)
    RowWriter(rows, row=1).write(2.5, True, 7)
    assert list(rows.a) == [0.0, 2.5, 0.0] and list(rows.b) == [0, 7, 0] and list(rows.flag) == [False, True, False]


def test_a_field_it_cannot_pack_is_refused() -> None:
    with pytest.raises(ValueError, match="field n of type int32"):
        RowWriter(table(layout([("n", "i4")]), 1))
