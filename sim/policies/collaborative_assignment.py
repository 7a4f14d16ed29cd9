"""The coalition rules of the collaborative levels: who goes to which task, in what order,
and whom a knower fetches (:class:`CoalitionRules`, the part of
:class:`~epistemica.sim.policies.collaborative_levels.CollaborativePolicy` that assigns).

The methods read the policy's state (``self.s``, ``self.parameters``, ``self.style``,
``self.predicted``, ``self.meet``, ``self.on_sweep`` and the per-robot arrays set by
:meth:`CollaborativePolicy.start`): they are a concept of that class kept in a module of its
own, not a class to use alone.
"""

from __future__ import annotations

import numpy as np

from epistemica.sim.engine.joint import JointView as View

__all__ = ["EXPLORING", "FETCHING", "WAIT", "CoalitionRules"]

#: ``steer_to`` of a robot exploring, fetching a teammate, waiting for helpers.
EXPLORING, FETCHING, WAIT = -1, -2, -3


class CoalitionRules:
    """The assignment of robots to tasks and the choice of whom to fetch (a mixin of
    :class:`~epistemica.sim.policies.collaborative_levels.CollaborativePolicy`)."""

    def _assign(self, view: View, i: int, tasks: np.ndarray, aware) -> tuple:
        """Robot ``i``'s view of who does what, task by task: the coalition that assembles
        soonest first (``soonest``; else in index order)."""
        n, s = self.s.n_robots, self.s
        where = np.array([self.predicted(view, i, j) for j in range(n)])
        taken = np.zeros(n, dtype=bool)
        sent_to = np.full(n, -1)  # the task i expects each teammate at
        if aware is not None and self.parameters.complete_first:
            # tasks enough robots know of first (i among them): the teammates that know only
            # those expect i there (they cannot know of its other tasks)
            short = aware[i][:, tasks].sum(axis=0) < np.asarray(s.needs)[tasks]
            tasks = tasks[np.argsort(short, kind="stable")]
        if self.parameters.soonest:
            tasks = self._soonest_first(i, tasks, aware, where)
        for t in tasks:
            if aware is None:  # rules-shared: everyone knows what i knows
                knowers = np.ones(n, dtype=bool)
            else:
                knowers = aware[i, :, t].copy()
                knowers[i] = True
            free = np.flatnonzero(knowers & ~taken)
            gap = np.hypot(*(where[free] - s.tasks[t]).T)
            order = free[np.argsort(gap, kind="stable")]
            need = s.needs[t]
            if order.size >= need or aware is None:
                chosen = order[:need]
                if self.parameters.stand_in and aware is not None and i not in chosen:
                    chosen = self._stand_ins(view, i, order, need)
                taken[chosen] = True
                sent_to[chosen] = t
                if i in chosen:
                    return ("task", int(t))
                continue
            taken[order] = True  # too few know: they wait, or fetch those who do not
            fetch = self._recruit(view, i, t, knowers | taken, where)
            if i in order:
                if fetch == WAIT or (
                    order.size > 1
                    and i == order[0]
                    and self._watched(t, fetch, knowers | taken, where)
                ):
                    self.backed[i] = order.size > 1  # another knower fetches or seeks
                    return ("task", int(t))
                if fetch is None and self.parameters.join_busy and (sent_to >= 0).any():
                    return ("task", self._nearest(view, i, sent_to[sent_to >= 0]))
                if fetch is None:  # nobody it knows where to find: look for helpers
                    return ("explore",) if self._seeks(view.step, i, t) else ("task", int(t))
                return ("fetch", int(t), fetch)
            if fetch is not None and fetch != WAIT:
                taken[fetch] = True
        return ("explore",)

    def _soonest_first(self, i: int, tasks: np.ndarray, aware, where) -> np.ndarray:
        """``tasks`` reordered (``soonest``): repeatedly the task whose ``needs`` nearest
        free knowers (by ``where``) assemble soonest, those knowers then taken; then the
        tasks too few free robots know of, in the order given."""
        n, s = self.s.n_robots, self.s
        # a fresh array either way (indexing by the array ``tasks`` copies)
        knowers = np.ones((n, len(tasks)), dtype=bool) if aware is None else aware[i][:, tasks]
        knowers[i] = True
        gaps = np.hypot(*(where[:, None, :] - s.tasks[tasks][None]).transpose(2, 0, 1))
        needs = np.asarray(s.needs)[tasks]
        free, left, order = np.ones(n, dtype=bool), list(range(len(tasks))), []
        while left:
            best, cost = None, np.inf
            for c in left:
                ok = knowers[:, c] & free
                if ok.sum() >= needs[c]:
                    far = np.sort(gaps[ok, c])[needs[c] - 1]
                    if far < cost:
                        best, cost = c, far
            if best is None:
                break
            ok = np.flatnonzero(knowers[:, best] & free)
            free[ok[np.argsort(gaps[ok, best], kind="stable")[: needs[best]]]] = False
            order.append(best)
            left.remove(best)
        return tasks[order + left]

    def _nearest(self, view: View, i: int, tasks: np.ndarray) -> int:
        """The task of ``tasks`` nearest robot ``i``."""
        gaps = np.hypot(*(self.s.tasks[tasks] - view.poses[i, :2]).T)
        return int(tasks[np.argmin(gaps)])

    def _watched(self, t: int, fetch: int | None, busy: np.ndarray, where) -> bool:
        """Whether a knower waiting at task ``t`` may be seen there by a teammate that does
        not know of it: one neither busy (a knower, or sent to another task) nor the
        teammate being fetched, predicted (``where``) within ``watch_range`` sensing ranges
        of the task (else nobody is near to see it wait: it fetches too)."""
        p = self.parameters
        if not p.fetch_together or fetch is None or fetch == WAIT:
            return True
        near = np.hypot(*(where - self.s.tasks[t]).T) <= p.watch_range * self.s.sensing_range
        near[fetch] = False
        return bool((near & ~busy).any())

    def _hail(self, i: int, j: int) -> float:
        """How near robot ``i`` comes to a teammate ``j`` it fetches before it heads for the
        task: near enough that ``j`` still sees it after both move a step apart (turning
        back at the edge of sight, ``i`` would be out of sight when the heading event
        fires; ``j`` may be turning away to fetch ``i`` for another task)."""
        s = self.s
        return s.sensing_range - (s.max_speed[i] + s.max_speed[j]) * s.dt

    def _seeks(self, step: int, i: int, t: int) -> bool:
        """Whether robot ``i`` looks for helpers for task ``t`` rather than waiting there
        (``seek``, for at most ``seek_limit`` steps until its patience there runs out)."""
        p = self.parameters
        if not p.seek:
            return False
        if self.seeking_since[i, t] < 0:
            self.seeking_since[i, t] = step
        return not p.seek_limit or step - self.seeking_since[i, t] < p.seek_limit

    def _stand_ins(self, view: View, i: int, order: np.ndarray, need: int) -> np.ndarray:
        """The knowers robot ``i`` sends to a task (nearest first, ``order``): the
        ``need`` nearest, and one more for each of those whose place it does not know."""
        recent = view.last_seen[i] >= view.step - self.parameters.fetch_memory
        recent[i] = True
        unsure = int((~recent[order[:need]]).sum())
        return order[: need + unsure]

    def _recruit(self, view: View, i: int, t: int, excluded: np.ndarray, where) -> int | None:
        """The teammate robot ``i`` would fetch for task ``t`` (:data:`WAIT`: its sweep
        brings it by; None: no teammate it knows where to find)."""
        p, step = self.parameters, view.step
        recent = view.last_seen[i] >= step - p.fetch_memory
        allowed = ~excluded & ~self.gave_up[i, t]
        known = recent.copy()
        if p.sweep_memory:  # teammates it knows are sweeping: it knows where they are
            longer = allowed & ~recent & (view.last_seen[i] >= step - p.sweep_memory)
            for j in np.flatnonzero(longer):
                known[j] = self.on_sweep(view, i, j, self.open_now[i])
        candidates = np.flatnonzero(allowed & known)
        if candidates.size == 0:
            return None
        gap = np.hypot(*(where[candidates] - self.s.tasks[t]).T)
        if p.meet_ahead:  # steps to meet it, then metres from there to the task
            for c, j in enumerate(candidates):
                met = self.meet(view, i, j)
                if met is not None:
                    gap[c] = met[0] + np.hypot(*(met[1] - self.s.tasks[t]))
        j = int(candidates[np.argmin(gap)])
        if not recent[j]:  # a task it does not know of may have drawn j away: go and see
            return j
        horizon, sight = p.wait_horizon, p.sight_fraction * self.s.sensing_range
        for ahead in range(0, horizon + 1, p.horizon_step):
            if np.hypot(*(self.predicted(view, i, j, ahead) - self.s.tasks[t])) <= sight:
                return WAIT  # its sweep brings it by: wait at the task
        return j
