"""The independent breaker reference's event-driven integration of the closing.

Holds the right-hand side in each mode (:func:`rhs`: the shaft stuck, or slipping in one speed
regime of the friction law) and :class:`ClosingRun`, which integrates a :class:`.Closing` from
the latch's rest with scipy's DOP853 on smooth segments. Events end each segment: the shaft's
speed leaving its friction regime, the stuck shaft breaking away (|T_c| above mu_s r F_n), the
start and end of each pole contact and (Lankarani-Nikravesh damping) of the cam-roller contact,
whose impact speed is the exact approach speed at that instant; with the rig's closing end stop
and holding latch, the start and end of the stop's contact, the latch's engagement (the cam
reaching its angle: exact, where the model keeps it as memory from the start of its step) and,
once engaged, the start and end of the latch's contact. With an elastic main shaft the free pole
levers' angles and speeds follow in the state (no events: their segments are smooth), and each
segment starts with a step of a tenth of the levers' fastest period. The model instead latches impact
speeds at the start of the RK4 step and catches sticking with a widened band; this module shares
no code with the model.

Units: SI. Times in s, angles in rad, lengths in m, speeds in rad/s or m/s, forces in N, torques in N m.
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np
from scipy.integrate import solve_ivp

from ..errors import SimulationError
from .breaker_closing import Closing

#: Guard against endless event switching.
MAX_SEGMENTS = 10_000


def rhs(mech: Closing, mode: tuple) -> Callable[[float, np.ndarray], np.ndarray]:
    """Right-hand side in a mode: ('stuck',) or ('slip', s, regime)."""
    nm, n, lev, nl = mech.nm, mech.n, mech.lev, mech.nl
    j = 2 + 4 * nm

    def f(t, y):
        Tc, R0, R1, roller = mech.cam_applied(t, y)
        if mode[0] == "stuck":
            th_acc = 0.0
        else:
            k, v = mech.regime_split(mode[2], y[1], mode[1])
            th_acc = mech.slip_acceleration(Tc, R0, R1, k, v)[0]
        acc, phi_acc, zacc, lever_acc = mech.others(t, y, roller)
        dy = np.empty_like(y)
        dy[0] = 0.0 if mode[0] == "stuck" else y[1]
        dy[1] = th_acc
        dy[2:2 + 2 * nm] = y[2 + 2 * nm:2 + 4 * nm]
        for k, (ax, ay) in enumerate(acc):
            dy[2 + 2 * nm + 2 * k], dy[3 + 2 * nm + 2 * k] = ax, ay
        dy[j] = y[j + 1 + n]
        dy[j + 1:j + 1 + n] = y[j + 2 + n:j + 2 + 2 * n]
        dy[j + 1 + n] = phi_acc
        dy[j + 2 + n:j + 2 + 2 * n] = zacc
        if nl:
            dy[lev:lev + nl] = y[lev + nl:lev + 2 * nl]
            dy[lev + nl:lev + 2 * nl] = lever_acc
        return dy

    return f


def friction_state(mech: Closing, t: float, y: np.ndarray, mode: tuple) -> tuple[float, float]:
    """(T_f N m, F_n N) at a state in a mode."""
    Tc, R0, R1, _ = mech.cam_applied(t, y)
    if mode[0] == "stuck":
        return Tc, math.hypot(*R0)
    k, v = mech.regime_split(mode[2], y[1], mode[1])
    _, fn = mech.slip_acceleration(Tc, R0, R1, k, v)
    return k * fn + v, fn


def state_scale(size: int, nm: int, n: int, atol: float, nl: int = 0) -> np.ndarray:
    """Absolute tolerance per state: ``atol`` for angles and lengths (rad, m), 1e3 ``atol`` for
    their rates (rad/s, m/s); ``nl`` free pole levers' angles and speeds at the end."""
    j = 2 + 4 * nm
    scale = np.full(size, atol)
    scale[1] = atol * 1e3  # rad/s
    scale[2 + 2 * nm:2 + 4 * nm] = atol * 1e3
    scale[j + 1 + n:j + 2 + 2 * n] = atol * 1e3
    scale[size - nl:] = atol * 1e3
    return scale


class ClosingRun:
    """One closing from the latch's rest (t = 0) to ``t_end``: segments, events and first touches.

    ``segments``: (t0, t1, mode, dense output, LN impact speeds); ``events``: (t, kind);
    ``touches``, ``touch_speeds``: per pole, its first contact (s, m/s).
    """

    def __init__(self, mech: Closing, t_end: float, rtol: float, atol: float):
        self.mech = mech
        self.phi0, self.z0, self.holding, self.levers0 = mech.rest()
        self.y = mech.initial_vector(self.phi0, self.z0, self.levers0)
        nm, n = mech.nm, mech.n
        self.j = 2 + 4 * nm
        self.t_end, self.rtol = t_end, rtol
        self.scale = state_scale(len(self.y), nm, n, atol, mech.nl)
        self.events, self.segments, self.touches, self.touch_speeds = [], [], [None] * n, [None] * n
        self.t = 0.0
        # a torque below round-off of the latch's balance (1e-12 of the holding torque) is no torque:
        # without friction the balanced cam would otherwise chatter between stuck and slipping at t = 0
        self.tiny = 1e-12 * (abs(self.holding) + 1.0)
        y, j = self.y, self.j
        self.mode = self.start_at_rest(self.t, y) if y[1] == 0.0 else ("slip", 1 if y[1] > 0 else -1, 0)
        self.closed = [mech.roller_contact(y[0], y[1], y[j], y[j + 1 + n])[0] > 0.0]
        self.closed += [y[j + 1 + i] > mech.gaps[i] for i in range(n)]
        d_stop, d_hold = mech.stop_penetrations(y[0])
        # contact states of the stop and of the latch (in contact only once engaged)
        self.stop_closed, self.hold_closed = d_stop > 0.0, False

    def start_at_rest(self, t: float, y: np.ndarray) -> tuple:
        """The mode of the shaft at rest: stuck if static friction holds T_c, else slipping its way."""
        mech = self.mech
        Tc, R0, _, _ = mech.cam_applied(t, y)
        if abs(Tc) <= mech.mu_s * mech.r * math.hypot(*R0) + self.tiny:
            return ("stuck",)
        return ("slip", 1 if Tc > 0 else -1, 0)

    # -- events -------------------------------------------------------------------------------
    def friction_events(self) -> tuple[list[Callable], list[str]]:
        """(events, kinds) ending the friction mode: breakaway when stuck; leaving the speed
        regime (``down``, ``up``) when slipping."""
        mech, mode, tiny = self.mech, self.mode, self.tiny
        if mode[0] == "stuck":
            def breakaway(tt, yy):
                Tc, R0, _, _ = mech.cam_applied(tt, yy)
                return abs(Tc) - mech.mu_s * mech.r * math.hypot(*R0) - tiny
            breakaway.terminal, breakaway.direction = True, 1.0
            return [breakaway], ["breakaway"]
        s, regime = mode[1], mode[2]
        lo, hi = mech.bounds[regime], mech.bounds[regime + 1]

        def low(tt, yy, s=s, lo=lo):
            return s * yy[1] - lo
        low.terminal, low.direction = True, -1.0
        evs, kinds = [low], ["down"]
        if math.isfinite(hi):
            def high(tt, yy, s=s, hi=hi):
                return s * yy[1] - hi
            high.terminal, high.direction = True, 1.0
            evs.append(high)
            kinds.append("up")
        return evs, kinds

    def contact_events(self) -> tuple[list[Callable], list[tuple]]:
        """(events, kinds) of the contacts: an open one waits for its start (LN: the impact
        speed), a closed one for its end (which re-arms the start); the contact's state is
        tracked, not read from a state that sits on the switching surface."""
        mech, j, n, closed = self.mech, self.j, self.mech.n, self.closed
        evs, kinds = [], []
        for i in range(n):
            def gap(tt, yy, i=i):
                return yy[j + 1 + i] - mech.gaps[i]
            gap.terminal, gap.direction = True, -1.0 if closed[i + 1] else 1.0
            evs.append(gap)
            kinds.append(("pole", i))
        if not mech.hunt_crossley:
            def land(tt, yy):
                return mech.roller_contact(yy[0], yy[1], yy[j], yy[j + 1 + n])[0]
            land.terminal, land.direction = True, -1.0 if closed[0] else 1.0
            evs.append(land)
            kinds.append(("roller", 0))
        more, more_kinds = self.stop_events()
        return evs + more, kinds + more_kinds

    def stop_events(self) -> tuple[list[Callable], list[tuple]]:
        """(events, kinds) of the end stop and the holding latch: the stop's contact begins or ends
        (its damper's force jumps there); the latch engages when the cam reaches its angle, and once
        engaged its contact begins or ends."""
        mech, evs, kinds = self.mech, [], []
        if mech.stop:
            evs.append(self._penetration_event(0, self.stop_closed))
            kinds.append(("end_stop", 0))
        if mech.hold and not mech.engaged:
            def engage(tt, yy):
                return yy[0] - mech.hold[0]
            engage.terminal, engage.direction = True, 1.0
            evs.append(engage)
            kinds.append(("engage", 0))
        elif mech.hold:
            evs.append(self._penetration_event(1, self.hold_closed))
            kinds.append(("hold_latch", 0))
        return evs, kinds

    def _penetration_event(self, k: int, closed: bool) -> Callable:
        """The event where the stop's (k = 0) or the engaged latch's (k = 1) penetration crosses
        zero: closing when it is open, opening when it is closed."""
        mech = self.mech

        def contact(tt, yy):
            return mech.stop_penetrations(yy[0])[k]
        contact.terminal, contact.direction = True, -1.0 if closed else 1.0
        return contact

    # -- integration --------------------------------------------------------------------------
    def integrate(self) -> None:
        """Segment after segment until t_end."""
        while self.t < self.t_end:
            if len(self.segments) > MAX_SEGMENTS:
                raise SimulationError("independent breaker reference: too many events (Zeno behaviour)")
            if self.segment():
                break

    def segment(self) -> bool:
        """Integrate the current mode until its first event; True when t_end came first."""
        mech, mode, t = self.mech, self.mode, self.t
        evs, kinds = self.friction_events()
        cevs, ckinds = self.contact_events()
        evs, kinds = evs + cevs, kinds + ckinds
        # with an elastic shaft, DOP853's first step from a state at rest would be blind to the
        # levers' twisting: start each segment at a tenth of its fastest period
        first = min(0.1 * mech.shaft.period(), self.t_end - t) if mech.nl else None
        sol = solve_ivp(rhs(mech, mode), (t, self.t_end), self.y, method="DOP853", rtol=self.rtol, atol=self.scale,
                        events=evs, dense_output=True, first_step=first)
        if sol.status < 0:
            raise SimulationError(f"independent breaker reference: {sol.message} at t = {sol.t[-1]:.6g} s")
        self.segments.append((t, sol.t[-1], mode, sol.sol, list(mech.impact), mech.engaged))
        if sol.status == 0:
            return True
        hit = [(sol.t_events[k][0], k) for k in range(len(evs)) if len(sol.t_events[k])]
        t_hit, k = min(hit)
        self.y = np.array(sol.y_events[k][0], float)
        self.t = float(t_hit)
        self.segments[-1] = (self.segments[-1][0], self.t, mode, sol.sol) + self.segments[-1][4:]
        self.apply(kinds[k])
        return False

    def apply(self, kind) -> None:
        """Log an event at (self.t, self.y) and switch the mode or contact it ends."""
        mech, t, y, closed, j, n = self.mech, self.t, self.y, self.closed, self.j, self.mech.n
        if not isinstance(kind, str) and kind[0] in ("end_stop", "engage", "hold_latch"):
            self.apply_stop(kind[0])
            return
        if isinstance(kind, str):
            self.events.append((t, kind))
        else:
            slot = 0 if kind[0] == "roller" else kind[1] + 1
            name = "roller" if slot == 0 else f"pole_{slot}"
            self.events.append((t, f"{name}_{'opens' if closed[slot] else 'closes'}"))  # before the toggle below
        if kind == "breakaway":
            Tc, _, _, _ = mech.cam_applied(t, y)
            self.mode = ("slip", 1 if Tc > 0 else -1, 0)
        elif kind == "up":
            self.mode = ("slip", self.mode[1], self.mode[2] + 1)
        elif kind == "down":
            if self.mode[2] > 0:
                self.mode = ("slip", self.mode[1], self.mode[2] - 1)
            else:
                y[1] = 0.0
                self.mode = self.start_at_rest(t, y)
        elif kind[0] == "roller":
            closed[0] = not closed[0]
            if closed[0]:
                mech.impact[0] = max(mech.roller_contact(y[0], y[1], y[j], y[j + 1 + n])[1], 0.0)
        else:
            i = kind[1]
            closed[i + 1] = not closed[i + 1]
            if closed[i + 1]:
                mech.impact[i + 1] = max(y[j + 2 + n + i], 0.0)
                if self.touches[i] is None:
                    self.touches[i], self.touch_speeds[i] = t, y[j + 2 + n + i]

    def apply_stop(self, what: str) -> None:
        """Log and switch an end stop or holding latch event at self.t."""
        if what == "engage":
            self.mech.engaged = True  # at its angle: the pawl drops, not yet in contact
            self.hold_closed = False
            self.events.append((self.t, "hold_latch_engages"))
        elif what == "end_stop":
            self.stop_closed = not self.stop_closed
            self.events.append((self.t, f"end_stop_{'closes' if self.stop_closed else 'opens'}"))
        else:
            self.hold_closed = not self.hold_closed
            self.events.append((self.t, f"hold_latch_{'closes' if self.hold_closed else 'opens'}"))

    # -- output -------------------------------------------------------------------------------
    def sample(self, t_eval: np.ndarray):
        """(states, roller force N, penetration m, friction torque N m, normal force N) at t_eval."""
        mech, j, n, segments = self.mech, self.j, self.mech.n, self.segments
        starts = np.array([s[0] for s in segments])
        idx = np.clip(np.searchsorted(starts, t_eval, side="right") - 1, 0, len(segments) - 1)
        Y = np.empty((len(t_eval), len(self.y)))
        force, pen, tf, fn = (np.empty(len(t_eval)) for _ in range(4))
        for q in np.unique(idx):
            t0, t1, mode, sol, impact, engaged = segments[q]
            sel = np.nonzero(idx == q)[0]
            Ys = sol(np.clip(t_eval[sel], t0, t1)).T
            mech.impact, mech.engaged = list(impact), engaged
            for r, yy in zip(sel, Ys):
                if mode[0] == "stuck":
                    yy[1] = 0.0
                Y[r] = yy
                p, rate, _, _ = mech.roller_contact(yy[0], yy[1], yy[j], yy[j + 1 + n])
                pen[r], force[r] = p, mech.roller_force(p, rate)
                tf[r], fn[r] = friction_state(mech, t_eval[r], yy, mode)
        if not np.all(np.isfinite(Y)):
            raise SimulationError("independent breaker reference: non-finite solution")
        return Y, force, pen, tf, fn

    def output(self, t_eval: np.ndarray) -> dict:
        """The sampled closing as :func:`.breaker.solve_closing` returns it."""
        mech, j, n = self.mech, self.j, self.mech.n
        Y, force, pen, tf, fn = self.sample(t_eval)
        F0y = mech.output_point(self.phi0)[1]
        out = {"t": t_eval, "cam_angle": Y[:, 0], "shaft_velocity": Y[:, 1], "follower_angle": Y[:, j],
               "follower_velocity": Y[:, j + 1 + n],
               "follower_displacement": np.array([mech.output_point(p)[1] for p in Y[:, j]]) - F0y,
               "cam_roller_force": force, "cam_roller_penetration": pen, "friction_torque": tf, "normal_force": fn,
               "touch_times": self.touches, "touch_speeds": self.touch_speeds, "events": self.events,
               "initial": {"follower_angle": self.phi0, "pole_travel": self.z0, "holding_torque": self.holding}}
        for i in range(n):
            out[f"pole_{i + 1}_travel"] = Y[:, j + 1 + i]
            out[f"pole_{i + 1}_velocity"] = Y[:, j + 2 + n + i]
        if mech.shaft is not None:
            lev, nl = mech.lev, mech.nl
            out["initial"]["lever_angle"] = dict(zip((f"pole_{i + 1}" for i in mech.shaft.free), self.levers0))
            for k, i in enumerate(mech.shaft.free):
                out[f"pole_{i + 1}_lever_angle"] = Y[:, lev + k]
                out[f"pole_{i + 1}_lever_velocity"] = Y[:, lev + nl + k]
        return out
