"""Two people touching each other (criterion `people_apart`): the moment, the two people and the gap, and who can
fix it. Contact is sim/contact.py's, the one definition (gap <= bodies.CONTACT_MARGIN), between two people as
between the robot and a person.

Nothing a spec can say makes two people touch: group members walk side by side apart, a follower keeps its
distance, a spawn puts nobody on anybody (location/placement.py). So the criterion is judged from t = 0, and
two people starting on one spot fail it (the eyes see them jump apart).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from socnavgen.bodies import CONTACT_MARGIN
from socnavgen.run.spec import Blame
from socnavgen.sim import contact
from socnavgen.verify.signals import Signals
from socnavgen.verify.thresholds import STILL_SPEED


@dataclass(frozen=True)
class PeopleContact:
    """The first moment two people touch."""

    step: int
    time: float
    first: str
    second: str
    gap: float  # m, their gap then
    seconds: float  # s, how long any two of them (of `human`'s pairs) were in contact over the run
    worst: float  # m, the smallest gap of those pairs over the run


def _columns(s: Signals, human: str | None) -> list[int]:
    _, pairs = s.people_gaps()
    return [c for c, pair in enumerate(pairs) if human is None or s.human(human) in pair]


def first_contact(s: Signals, human: str | None = None) -> PeopleContact | None:
    """The first step on which two people (with `human`: that one and another) touch; None if they never do."""
    gaps, pairs = s.people_gaps()
    cols = _columns(s, human)
    if not cols:
        return None
    mine = gaps[:, cols]
    touching = contact.row_any(contact.in_contact(mine))
    if not touching.any():
        return None
    k = int(np.argmax(touching))
    c = cols[int(np.argmin(mine[k]))]
    names = s.trace.human_names
    return PeopleContact(step=k, time=float(s.t[k]), first=names[pairs[c][0]], second=names[pairs[c][1]],
                         gap=float(gaps[k, c]), seconds=round(int(touching.sum()) * float(s.trace.dt), 6),
                         worst=float(mine.min()))


def people_evidence(human: str | None, s: Signals) -> tuple[str, float | None, float | None]:
    """What the evidence of `people_apart` says: the first contact (who, when, how close, how long), else the
    closest two people came."""
    found = first_contact(s, human)
    if found is not None:
        text = (f"{found.first} and {found.second} touch at t={found.time:.1f} s (gap {found.gap:.2f} m <= "
                f"{CONTACT_MARGIN:g} m); people in contact {found.seconds:.1f} s in all, closest "
                f"{found.worst:.2f} m")
        return text, found.time, found.gap
    gaps, pairs = s.people_gaps()
    cols = _columns(s, human)
    if not cols:
        return "fewer than two people", None, None
    k, j = np.unravel_index(int(np.argmin(gaps[:, cols])), (gaps.shape[0], len(cols)))
    a, b = pairs[cols[j]]
    names = s.trace.human_names
    return (f"no two people touch: closest {names[a]} and {names[b]}, {gaps[k, cols[j]]:.2f} m at t={s.t[k]:.1f} s",
            float(s.t[k]), float(gaps[k, cols[j]]))


def blame_people(human: str | None, s: Signals) -> tuple[Blame, str | None, str]:
    """Who can fix two people touching: the paths when they start on one spot or both walk into the same place at
    the same moment (their routes or timing cross); the tree of the one that walked into the other standing."""
    found = first_contact(s, human)
    if found is None:  # pragma: no cover - only failing criteria are blamed
        return "paths", None, "two people touch"
    what = f"{found.first} and {found.second} touch at t={found.time:.1f} s (gap {found.gap:.2f} m)"
    if found.step == 0:
        return "paths", None, f"{what}: they start on one spot; put their first nodes apart"
    moving = {who: bool(s.speed(who)[found.step] >= STILL_SPEED) for who in (found.first, found.second)}
    if sum(moving.values()) == 1:
        walker = next(who for who, walks in moving.items() if walks)
        other = found.second if walker == found.first else found.first
        return "behaviors", walker, f"{what}: {walker} walked into {other} standing; its tree must stop or go around"
    return "paths", None, f"{what}: their paths bring them to one place at the same moment; change a route or its timing"
