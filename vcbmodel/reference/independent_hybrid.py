"""The independent reference's event-driven hybrid integration: slip regimes, sticking, breakaway.

Holds :class:`Hybrid`, which integrates a mechanism (:mod:`.independent_lagrange`) under the
friction law (:mod:`.independent_friction`) with scipy's DOP853 on smooth segments:

- slip mode, sign s = sign(w), in one speed regime of the law; the regime boundaries are terminal
  events, so no DOP853 step sees a discontinuity;
- w reaching 0: the shaft sticks if |Tc| <= mu_s r Fn0 (Fn0: the reaction with w = 0 and
  theta'' = 0), else it slips on in the direction of Tc;
- stuck mode: theta frozen, w = 0 exactly, Tf = Tc; the spring masses (if any) keep moving, and
  the event |Tc| = mu_s r Fn0 (rising) breaks the shaft away in the direction of Tc.

A stuck shaft does not creep and friction never does positive work; the model instead catches
sticking with a widened band. Shares no code with the model.

Units: SI. Times in s, angles in rad, speeds in rad/s, torques in N m, forces in N.
"""
from __future__ import annotations

import math
from typing import Callable, Sequence

import numpy as np
from scipy.integrate import solve_ivp

from vcbmodel.errors import SimulationError

from .independent_friction import coupled_acceleration

#: Guard against Zeno behaviour (endless stick/slip or regime switching).
MAX_SEGMENTS = 200_000


def _check_solver(sol) -> None:
    if sol.status < 0:
        raise SimulationError(f"independent reference: solver failed at t = {sol.t[-1]:.6g} s: {sol.message}")


class Segment:
    """One smooth piece of the solution: mode ``stuck`` (at ``theta``) or ``slip`` (direction
    ``s``, regime index ``regime``) from t0 to t1 (s), with its dense output ``sol``."""

    __slots__ = ("t0", "t1", "mode", "s", "regime", "sol", "theta")

    def __init__(self, t0, mode, s=0, regime=0, sol=None, theta=None):
        self.t0, self.t1, self.mode, self.s, self.regime, self.sol, self.theta = t0, None, mode, s, regime, sol, theta


class Hybrid:
    """Event-driven integration of a mechanism (q[0] the shaft angle) under the friction law."""

    def __init__(self, mech, law, rtol, atol):
        self.mech, self.law, self.rtol, self.atol = mech, law, rtol, atol
        self.nq = mech.nq

    # -- accelerations ------------------------------------------------------------------------
    def slip(self, q: np.ndarray, qd: np.ndarray, s: float, regime: int) -> tuple[np.ndarray, float, float, float]:
        """(q'', Tf, Fn, Tc) in slip mode."""
        M, Minv = self.mech.mass(q)
        h = self.mech.forces(q, qd)
        a_free = -Minv @ h
        b = Minv[:, 0]
        k, v = self.law.split(regime, qd[0], s)
        R0, R1 = self.mech.reaction(q, qd)
        a = coupled_acceleration(a_free[0], b[0], k, v, R0, R1)
        fn = math.hypot(R0[0] + R1[0] * a, R0[1] + R1[1] * a)
        tf = k * fn + v
        qdd = a_free - b * tf
        return qdd, tf, fn, a_free[0] / b[0]

    def stuck(self, q: np.ndarray, qd: np.ndarray) -> tuple[np.ndarray, float, float, float]:
        """(q'' with theta'' = 0, Tf holding the shaft, Fn0, Tc); qd[0] must be 0."""
        M, _ = self.mech.mass(q)
        h = self.mech.forces(q, qd)
        qdd = np.zeros(self.nq)
        if self.nq > 1:
            qdd[1:] = np.linalg.solve(M[1:, 1:], -h[1:])
        tc = -h[0] - M[0, 1:] @ qdd[1:]
        R0, _ = self.mech.reaction(q, qd)
        return qdd, tc, math.hypot(R0[0], R0[1]), tc

    # -- right-hand sides ---------------------------------------------------------------------
    def _check(self, t, y):
        if not np.all(np.isfinite(y)):
            raise SimulationError(f"independent reference: non-finite state at t = {t:.6g} s")

    def slip_rhs(self, s: float, regime: int) -> Callable[[float, np.ndarray], np.ndarray]:
        nq = self.nq

        def rhs(t, y):
            self._check(t, y)
            qdd = self.slip(y[:nq], y[nq:], s, regime)[0]
            return np.concatenate([y[nq:], qdd])

        return rhs

    def stuck_rhs(self, theta: float) -> Callable[[float, np.ndarray], np.ndarray]:
        nq = self.nq

        def rhs(t, z):
            self._check(t, z)
            q, qd = self.full(theta, z)
            qdd = self.stuck(q, qd)[0]
            return np.concatenate([z[nq - 1:], qdd[1:]])

        return rhs

    def full(self, theta: float, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        nq = self.nq
        q = np.concatenate([[theta], z[:nq - 1]])
        qd = np.concatenate([[0.0], z[nq - 1:]])
        return q, qd

    # -- driver -------------------------------------------------------------------------------
    def _start_at_rest(self, t, y, segments, events, kind):
        """Shaft at rest at time t: stuck or break away. Returns the new mode tuple."""
        nq = self.nq
        y = y.copy()
        y[nq] = 0.0
        _, tc, fn0, _ = self.stuck(y[:nq], y[nq:])
        if self.law.holds(tc, fn0):
            events.append({"t": t, "kind": "stick" if kind != "start" else "start_stuck", "theta": y[0]})
            return ("stuck", 0, 0), y
        s = 1 if tc > 0 else -1
        events.append({"t": t, "kind": kind, "theta": y[0], "direction": s})
        self._check_entry(t, y, s, 0, outward=True)
        return ("slip", s, 0), y

    def _check_entry(self, t, y, s, regime, outward):
        """Entering a slip regime at its boundary, the speed must move into it; if it points back
        out, both sides drive the speed onto the boundary (a sliding mode the law does not define,
        e.g. mu_k > mu_s): report it instead of chattering."""
        nq = self.nq
        rate = s * self.slip(y[:nq], y[nq:], s, regime)[0][0]  # d|w|/dt in the new regime
        if (rate < 0.0) if outward else (rate > 0.0):
            law = self.law
            raise SimulationError(
                f"independent reference: friction law has no consistent motion at t = {t:.6g} s, |w| = "
                f"{abs(y[nq]):.3g} rad/s ({law.kinds[regime]} branch drives the speed back; mu_s = {law.mu_s:g}, "
                f"mu_k = {law.mu_k:g})")

    def run(self, q0: Sequence[float], qd0: Sequence[float], t_end: float) -> tuple[list[Segment], list[dict]]:
        """Integrate from t = 0 to ``t_end`` (s): (segments, events), mode by mode."""
        y = np.concatenate([np.asarray(q0, float), np.asarray(qd0, float)])
        self._check(0.0, y)
        t = 0.0
        segments, events = [], []
        mode, y = self._initial_mode(t, y, segments, events)
        opts = dict(method="DOP853", rtol=self.rtol, atol=self.atol, dense_output=True)
        done = False
        while not done:
            if len(segments) > MAX_SEGMENTS:
                raise SimulationError(f"independent reference: more than {MAX_SEGMENTS} stick/slip segments "
                                      f"before t = {t:.6g} s (Zeno behaviour)")
            step = self._stuck_segment if mode[0] == "stuck" else self._slip_segment
            done, t, y, mode = step(t, y, mode, t_end, segments, events, opts)
        segments[-1].t1 = t_end
        return segments, events

    def _initial_mode(self, t, y, segments, events):
        """The mode at t = 0: at rest, stuck or breaking away; moving, slipping in its regime."""
        if y[self.nq] == 0.0:
            return self._start_at_rest(t, y, segments, events, "start")
        s = 1 if y[self.nq] > 0 else -1
        return ("slip", s, self.law.regime_of(abs(y[self.nq]))), y

    def _stuck_segment(self, t, y, mode, t_end, segments, events, opts):
        """The shaft held by static friction from t until it breaks away (or t_end):
        (done, t, y, mode) at the segment's end."""
        nq = self.nq
        seg = Segment(t, "stuck", theta=y[0])
        segments.append(seg)
        if nq == 1 or t >= t_end:  # nothing else moves (or no time left): stuck to the end
            seg.t1 = t_end
            seg.sol = ConstantSol(np.concatenate([y[1:nq], y[nq + 1:]]))
            return True, t, y, mode
        theta = y[0]
        sol = solve_ivp(self.stuck_rhs(theta), (t, t_end), y[1:nq].tolist() + y[nq + 1:].tolist(),
                        events=[self._breakaway_event(theta)], **opts)
        _check_solver(sol)
        seg.sol, seg.t1 = sol.sol, sol.t[-1]
        if sol.status == 0:
            return True, t, y, mode
        t = float(sol.t_events[0][0])
        seg.t1 = t
        q, qd = self.full(theta, sol.y_events[0][0])
        y = np.concatenate([q, qd])
        _, tc, _, _ = self.stuck(q, qd)
        s = 1 if tc > 0 else -1
        events.append({"t": t, "kind": "breakaway", "theta": theta, "direction": s})
        self._check_entry(t, y, s, 0, outward=True)
        return False, t, y, ("slip", s, 0)

    def _breakaway_event(self, theta):
        """Terminal event |Tc| = mu_s r Fn0 (rising) of the shaft stuck at ``theta``."""
        law = self.law

        def breakaway(tt, z, theta=theta):
            q, qd = self.full(theta, z)
            _, tc, fn0, _ = self.stuck(q, qd)
            return abs(tc) - law.mu_s * law.r * fn0

        breakaway.terminal, breakaway.direction = True, 1.0
        return breakaway

    def _regime_events(self, s, lo, hi):
        """Terminal events of |w| leaving the speed regime (lo, hi) (rad/s) in direction s."""
        nq = self.nq

        def leave_low(tt, yy, s=s, lo=lo):
            return s * yy[nq] - lo

        leave_low.terminal, leave_low.direction = True, -1.0
        evs = [leave_low]
        if math.isfinite(hi):
            def leave_high(tt, yy, s=s, hi=hi):
                return s * yy[nq] - hi

            leave_high.terminal, leave_high.direction = True, 1.0
            evs.append(leave_high)
        return evs

    def _slip_segment(self, t, y, mode, t_end, segments, events, opts):
        """The shaft slipping in direction s in one speed regime from t until |w| leaves it (or
        t_end): (done, t, y, mode) at the segment's end."""
        _, s, regime = mode
        seg = Segment(t, "slip", s=s, regime=regime)
        segments.append(seg)
        if t >= t_end:
            seg.t1 = t_end
            seg.sol = ConstantSol(y)
            return True, t, y, mode
        lo, hi = self.law.bounds[regime], self.law.bounds[regime + 1]
        sol = solve_ivp(self.slip_rhs(s, regime), (t, t_end), y, events=self._regime_events(s, lo, hi), **opts)
        _check_solver(sol)
        seg.sol, seg.t1 = sol.sol, sol.t[-1]
        if sol.status == 0:
            return True, t, y, mode
        which = 0 if len(sol.t_events[0]) else 1
        t = float(sol.t_events[which][0])
        y = np.array(sol.y_events[which][0], float)
        self._check(t, y)
        seg.t1 = t
        mode, y = self._next_regime(t, y, s, regime, which, segments, events)
        return False, t, y, mode

    def _next_regime(self, t, y, s, regime, which, segments, events):
        """(mode, y) after |w| left ``regime`` upwards (which = 1) or downwards (which = 0)."""
        nq, law = self.nq, self.law
        if which == 1:
            y[nq] = s * law.bounds[regime + 1]
            self._check_entry(t, y, s, regime + 1, outward=True)
            return ("slip", s, regime + 1), y
        if regime > 0:
            y[nq] = s * law.bounds[regime]
            self._check_entry(t, y, s, regime - 1, outward=False)
            return ("slip", s, regime - 1), y
        # w reached zero: stick, or slip on in the direction of Tc
        mode, y = self._start_at_rest(t, y, segments, events, "reversal")
        if mode[0] == "slip" and mode[1] == s:
            events[-1]["kind"] = "restart"
        return mode, y

    # -- output -------------------------------------------------------------------------------
    def sample(self, segments: Sequence[Segment], t_eval: np.ndarray) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray]:
        nq = self.nq
        starts = np.array([seg.t0 for seg in segments])
        idx = np.clip(np.searchsorted(starts, t_eval, side="right") - 1, 0, len(segments) - 1)
        N = len(t_eval)
        Q, QD = np.empty((N, nq)), np.empty((N, nq))
        tf, fn, tc, acc = np.empty(N), np.empty(N), np.empty(N), np.empty(N)
        stuck = np.zeros(N, bool)
        for j in np.unique(idx):
            seg = segments[j]
            sel = np.nonzero(idx == j)[0]
            ts = np.clip(t_eval[sel], seg.t0, seg.t1)
            if seg.mode == "stuck":
                stuck[sel] = True
                Z = seg.sol(ts).T
                for i, z in zip(sel, Z):
                    q, qd = self.full(seg.theta, z)
                    Q[i], QD[i] = q, qd
                    qdd, tc_i, fn0, _ = self.stuck(q, qd)
                    tf[i], fn[i], tc[i], acc[i] = tc_i, fn0, tc_i, 0.0
            else:
                Y = seg.sol(ts).T
                for i, yy in zip(sel, Y):
                    q, qd = yy[:nq], yy[nq:]
                    Q[i], QD[i] = q, qd
                    qdd, tf[i], fn[i], tc[i] = self.slip(q, qd, seg.s, seg.regime)
                    acc[i] = qdd[0]
        out = {"t": np.asarray(t_eval, float), "theta": Q[:, 0].copy(), "omega": QD[:, 0].copy(),
               "friction_torque": tf, "stuck": stuck, "alpha": acc, "normal_force": fn, "applied_torque": tc}
        if not all(np.all(np.isfinite(v)) for v in (Q, QD, tf, fn)):
            raise SimulationError("independent reference: non-finite values in the sampled output")
        return out, Q, QD


class ConstantSol:
    """Dense output of a segment with nothing moving: the constant state ``y``."""

    def __init__(self, y):
        self.y = np.asarray(y, float)

    def __call__(self, t):
        return np.repeat(self.y[:, None], np.size(t), axis=1)
