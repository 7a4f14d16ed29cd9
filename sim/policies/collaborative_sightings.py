"""What a planning robot reads from seeing its teammates (a mixin of
:class:`~epistemica.sim.policies.collaborative_planning.PlanningCollaborativePolicy`): who
has a task in sight (``plan_sighted``), who stands waiting at one (``plan_waiters``), who
is not where it was predicted (``plan_missed``), and what a fetch shows a teammate where no
``heads to`` event tells it (``plan_told``).

Examples
--------
>>> from epistemica.sim.policies.collaborative_planning import PlanningCollaborativePolicy
>>> issubclass(PlanningCollaborativePolicy, Sightings)
True
"""

from __future__ import annotations

import numpy as np

from epistemica.sim.engine.joint import JointView as View

__all__ = ["Sightings"]


class Sightings:
    """Methods over the policy's scenario ``s``, ``parameters``, ``teammates``,
    ``open_now`` and ``waiting_now``, and the rules' :meth:`standing` and
    :meth:`predicted`."""

    def sighted(self, view: View) -> np.ndarray:
        """``(n, n, m)``: robot ``i`` sees teammate ``j`` now with task ``t`` in ``j``'s
        sight (within the sensing range of where ``i`` sees it), so ``j`` has seen ``t``:
        what ``i`` may learn of ``j``'s knowledge beyond the ledger's shared events
        (``plan_sighted``)."""
        s = self.s
        now = view.last_seen == view.step
        gap = np.hypot(*(view.estimates[..., None, :] - s.tasks).transpose(3, 0, 1, 2))
        return now[..., None] & (gap <= s.sensing_range)

    def standing_still(self, view: View) -> np.ndarray:
        """``(n, n)``: robot ``i`` sees teammate ``j`` now and saw it last step, and it
        moved less than ``still_fraction`` of its top speed in between (it stands)."""
        model, s = self.teammates, self.s
        seen = (view.last_seen == view.step) & (model.prev_seen == view.step - 1)
        moved = np.hypot(*(view.estimates - model.prev_estimates).transpose(2, 0, 1))
        return seen & (moved < self.parameters.still_fraction * np.asarray(s.max_speed) * s.dt)

    def waiters(self, view: View, i: int) -> dict[int, int]:
        """Teammate -> the open task (of those robot ``i`` knows) it stands still at,
        within two completion radii, as ``i`` sees it now (``plan_waiters``: it waits
        there, and a fetch of it for another task is charged what that task loses;
        nearest task if several)."""
        if not (self.parameters.plan_waiters and self.model == "nested"):
            return {}
        at = self.standing(view, i) & self.still[i][:, None] & self.open_now[i][None]
        gap = np.hypot(*(view.estimates[i][:, None, :] - self.s.tasks[None]).transpose(2, 0, 1))
        return {j: int(np.argmin(np.where(at[j], gap[j], np.inf)))
                for j in np.flatnonzero(at.any(axis=1)) if j != i}  # fmt: skip

    def presuming(self, view: View, i: int) -> np.ndarray:
        """``(n, m)`` the tasks robot ``i`` takes each teammate to presume done
        (``plan_presumed``): those ``i`` presumed done itself (``stale_after``) and then
        found open, for every teammate ``i`` does not see standing at them now. Such a
        teammate is not predicted to come back, and may be fetched."""
        if not self.doubted[i].any():  # always so with plan_presumed off: no sighting to read
            return np.zeros((self.s.n_robots, self.s.n_tasks), dtype=bool)
        gone = self.doubted[i][None] & ~self.standing(view, i)
        gone[i] = False
        return gone

    def staying(self) -> dict[int, int]:
        """The waiters the planner predicts at their tasks: all with ``plan_waiters`` 1;
        none with 2 (they are taken to know of them and met where they stand, but their
        choice is predicted as any teammate's)."""
        return self.waiting_now if self.parameters.plan_waiters == 1 else {}

    def missed(self, view: View) -> None:
        """Give up robot ``i``'s fetches of teammate ``j`` for every task (``gave_up``) when
        ``j``'s predicted place (:meth:`predicted`) lies within ``lost_range`` sensing ranges
        of ``i`` and ``i``, having seen ``j`` before, does not see it (a never-seen one's
        starts are ruled out by :class:`TeammateModel`): sight is certain within its range,
        so ``j`` left its predicted sweep (``plan_missed``; mission 1635: a fetcher stood at
        the empty place, its intercept met in 0 steps). Seeing ``j`` lifts it
        (``plan_retry``); at 2 so do ``fetch_memory`` steps (it may be back on its sweep)."""
        p, n = self.parameters, self.s.n_robots
        if not p.plan_missed:
            return
        out = np.zeros((n, n), dtype=bool)
        near = p.lost_range * self.s.sensing_range
        for i, j in np.argwhere((view.last_seen >= 0) & (view.last_seen < view.step)):
            if i != j:  # seen before, not now: is it where i predicts it, in i's sight?
                out[i, j] = np.hypot(*(self.predicted(view, i, j) - view.poses[i, :2])) <= near
        self.missed_at[view.last_seen == view.step] = -1
        if p.plan_missed == 2:  # the miss is as old as fetch_memory: forget it
            old = (self.missed_at >= 0) & (view.step - self.missed_at >= p.fetch_memory) & ~out
            self.gave_up &= ~old[:, None, :]
            self.missed_at[old] = -1
        self.missed_at[out] = view.step
        self.gave_up |= out[:, None, :]

    def told(self, view: View, i: int, j: int, met: tuple, stays: bool = False) -> np.ndarray:
        """``(m,)`` for each task, whether robot ``i``, meeting teammate ``j`` as ``met``
        (steps, place) and then going to the task, is in ``j``'s sight (``j`` where
        :meth:`predicted` puts it) when it comes within the found event's reach of the
        task or stands at it: where no ``heads to`` event tells a teammate what a robot
        heads for, that is how a fetch tells it (``plan_told``). With ``stays``, ``j``
        waits where it is seen (``plan_waiters``)."""
        s = self.s
        speed, place = float(s.max_speed[i] * s.dt), np.asarray(met[1], dtype=float)
        gap = np.hypot(*(place - s.tasks).T)  # (m,) from the meeting
        out = np.zeros(s.n_tasks, dtype=bool)
        for t in range(s.n_tasks):
            moments = []  # (steps ahead, where i is)
            if self.reach is not None and gap[t] > self.reach:
                cut = (gap[t] - self.reach) / gap[t]
                moments.append((met[0] + (gap[t] - self.reach) / speed,
                                place + cut * (s.tasks[t] - place)))  # fmt: skip
            if self.settle:
                moments.append((met[0] + gap[t] / speed, s.tasks[t]))
            for ahead, there in moments:
                later = int(np.rint(ahead))
                seen = view.estimates[i, j] if stays else self.predicted(view, i, j, later)
                out[t] |= bool(np.hypot(*(seen - there)) <= s.sensing_range)
        return out
