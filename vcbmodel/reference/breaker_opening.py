"""An independent solve of the breaker's opening (an O from the closed rest on the trip latch),
written from the rig file's numbers with scipy, for verification of the model's opening.

The mechanism as the rig file describes it (docs/rig-format.md): the follower (with the drive
pole's lever) and the other pole levers on the elastic main shaft, each lever's output point
pushing its pole's pin through a push rod with its wipe spring; the poles pressed on their fixed
contacts; the opening spring pulling the follower's output point F down; the trip latch's pawl
holding F at its travel from the open rest and letting go linearly over its release time from
t = 0; the opening dashpot and the open stop under F. The cam stays at its start angle (held by
its closing latch): the roller is off it from the closed rest until F is back near open, so the
solve runs up to F's entry into the last ``reset_travel`` (the window the tests compare).

Shares no code with the model: it reads the rig file with ``json`` and states every force here.
It shares the reading of the rig's fields (the layout: the rods' pins straight above the output
point at the roller's geometric rest on the base circle, the opening spring's anchor straight below
it, F's travel measured from the static open rest; the rod law stiff to the wipe preload, then the
wipe rate, with structural damping; Hertz contacts with Lankarani-Nikravesh damping whose impact
speed is the floor ``min_impact_speed`` for contacts closed from the start; Palmgren's line
contact for the roller at the open rest; the main shaft's segments G J / pitch with the drive
lever rigid with the follower and the inertia split I_f - (n-1) I_l; the bellows force and the
poles' weight along the travel; the pawl, dashpot and stop laws as docs/rig-format.md states them).

Units: SI (m, kg, kg m^2, rad counter-clockwise, N, N m, s).
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, root

#: Palmgren's steel line contact: delta (mm) = 3.84e-5 Q^0.9 / l^0.8 (Q in N, l in mm)
PALMGREN = 3.84e-5


class Opening:
    """The opening's parameters from a rig file's JSON object and its forces at a state."""

    def __init__(self, data: dict) -> None:
        b, cam = data["breaker"], data["cam"]
        f, p = b["follower"], b["poles"]
        self.g = data.get("gravity", 9.81)
        self.pivot = np.array(f["pivot"], float)
        self.r_out, self.alpha, self.r_roll = f["output_arm"], f.get("output_angle", 0.0), f["roller_arm"]
        self.n, self.m = int(p["count"]), p["moving_mass"]
        self.gaps = [p["contact_gap"] + o for o in p.get("gap_offsets", [0.0] * self.n)]
        self.rod = (p["push_rod_length"], p["wipe_preload"], p["wipe_rate"], p["rod_stiffness"], p["rod_damping"])
        self.pole_load = p["bellows_force"] - self.m * self.g
        c = b["contact"]
        self.k_pole, self.exp_pole, self.e = c["pole_stiffness"], c.get("exponent", 1.5), c["restitution"]
        self.v_floor = c.get("min_impact_speed", 0.05)
        length_mm = 1000.0 * c["roller_width"]
        self.k_roller = (1000.0 * length_mm ** 0.8 / PALMGREN) ** (1.0 / 0.9)  # N/m^(10/9)
        self.cam_axis = np.array(cam["pivot"], float)
        self.rho0 = b["cam_profile"]["base_radius"] + b["roller_radius"]
        s = b["main_shaft"]
        k = 79.3e9 if "shear_modulus" not in s else s["shear_modulus"]
        self.k_seg = k * math.pi * (s["diameter"] ** 4 - s["bore"] ** 4) / 32.0 / s["pole_pitch"]
        self.c_seg, self.i_lever, self.drive = s["damping"], s["lever_inertia"], s["drive_pole"] - 1
        self.i_follower = f["inertia"] - (self.n - 1) * s["lever_inertia"]
        self.latch, self.dashpot = b["trip_latch"], b["opening_dashpot"]
        # the roller on the base circle: the geometric rest, where the rods' pins and the spring's anchor sit
        phi_g = brentq(lambda a: np.linalg.norm(self.roller(a) - self.cam_axis) - self.rho0,
                       f["rest_angle"] - 0.5, f["rest_angle"] + 0.5)
        f0 = self.output(phi_g)
        self.pin_x, self.pin_y0 = f0[0], f0[1] + self.rod[0]
        o = b["opening_spring"]
        self.anchor = np.array([f0[0], f0[1] - o["length"]])
        self.k_open, self.l_open = o["stiffness"], o["length"] - o["preload"] / o["stiffness"]
        self.y_open = 0.0
        self.y_open = self.output(self.open_rest())[1]

    # -- kinematics
    def output(self, a: float) -> np.ndarray:
        return self.pivot + self.r_out * np.array([math.cos(a + self.alpha), math.sin(a + self.alpha)])

    def roller(self, a: float) -> np.ndarray:
        return self.pivot + self.r_roll * np.array([math.cos(a), math.sin(a)])

    @staticmethod
    def moment(arm: np.ndarray, force: np.ndarray) -> float:
        return float(arm[0] * force[1] - arm[1] * force[0])

    # -- forces
    def rod_force(self, s: float, rate: float) -> float:
        length, preload, wipe, stiff, damping = self.rod
        s0 = preload / stiff
        spring = stiff * s if s <= s0 else preload + wipe * (s - s0)
        return spring + damping * rate

    def contact(self, i: int, z: float, zd: float) -> float:
        d = z - self.gaps[i]
        if d <= 0.0:
            return 0.0
        return max(0.0, self.k_pole * d ** self.exp_pole * (1.0 + 0.75 * (1.0 - self.e ** 2) * zd / self.v_floor))

    def f_forces(self, t: float, a: float, ad: float, roller: bool) -> float:
        """Torque (N m) on the follower of the opening spring, the pawl, the dashpot and stop and (at
        the open rest) the roller on the base circle."""
        f = self.output(a)
        arm = f - self.pivot
        vy = ad * arm[0]
        d = f - self.anchor
        torque = self.moment(arm, -self.k_open * (np.linalg.norm(d) - self.l_open) * d / np.linalg.norm(d))
        u = f[1] - self.y_open
        up = 0.0
        lt = self.latch
        holding = 1.0 if t < 0.0 else max(0.0, 1.0 - t / lt["release_time"])
        if u < lt["travel"]:
            up += holding * max(0.0, lt["stiffness"] * (lt["travel"] - u) - lt["damping"] * vy)
        dp = self.dashpot
        up += dp["damping"] * min(1.0, max(0.0, (dp["stroke"] - u) / dp["ramp"])) * max(0.0, -vy)
        if u < 0.0:
            up += max(0.0, dp["stop_stiffness"] * (-u) - dp["stop_damping"] * vy)
        torque += self.moment(arm, np.array([0.0, up]))
        if roller:
            c = self.roller(a) - self.cam_axis
            dist = np.linalg.norm(c)
            pen = self.rho0 - dist
            if pen > 0.0:
                torque += self.moment(self.roller(a) - self.pivot, self.k_roller * pen ** (10.0 / 9.0) * c / dist)
        return torque

    def accelerations(self, t: float, x: np.ndarray, roller: bool = False) -> np.ndarray:
        """[follower, other levers, poles] accelerations at state x = [positions, speeds]."""
        n = self.n
        q, v = x[:n + n], x[n + n:]
        levers, lever_v = list(q[1:n]), list(v[1:n])
        levers.insert(self.drive, q[0])
        lever_v.insert(self.drive, v[0])
        torque = [0.0] * n
        pole_acc = []
        for i in range(n):
            f = self.output(levers[i])
            arm = f - self.pivot
            vf = lever_v[i] * np.array([-arm[1], arm[0]])
            pin = np.array([self.pin_x, self.pin_y0 + q[n + i]])
            d = pin - f
            length = np.linalg.norm(d)
            e = d / length
            rate = -float(e @ (np.array([0.0, v[n + i]]) - vf))
            force = self.rod_force(self.rod[0] - length, rate)
            torque[i] += self.moment(arm, -force * e)
            pole_acc.append((force * e[1] - self.contact(i, q[n + i], v[n + i]) + self.pole_load) / self.m)
        for j in range(n - 1):
            seg = self.k_seg * (levers[j] - levers[j + 1]) + self.c_seg * (lever_v[j] - lever_v[j + 1])
            torque[j] -= seg
            torque[j + 1] += seg
        torque[self.drive] += self.f_forces(t, levers[self.drive], lever_v[self.drive], roller)
        acc = [torque[self.drive] / self.i_follower] + [torque[j] / self.i_lever for j in range(n) if j != self.drive]
        return np.array(acc + pole_acc)

    def rest(self, x0: np.ndarray, t: float, roller: bool) -> np.ndarray:
        """The positions where every acceleration vanishes at rest (time t: before the trip, t < 0)."""
        n = self.n

        def residual(dq):  # solved for the offsets from x0: finite differences of 1.5e-8 (rad, m) each
            a = self.accelerations(t, np.concatenate([x0 + dq, np.zeros(2 * n)]), roller)
            return a * np.array([self.i_follower] + [self.i_lever] * (n - 1) + [self.m] * n)

        sol = root(residual, np.zeros_like(x0), method="lm", options={"xtol": 1e-15, "ftol": 1e-15})
        if np.max(np.abs(residual(sol.x))) > 1e-6:
            raise ValueError(f"no rest found: {sol.message}")
        return x0 + sol.x

    def open_rest(self) -> float:
        """The follower's static open rest angle (rad): the roller pressed on the base circle, the
        poles hanging on their rods (pawl and stop inactive: F at its open position)."""
        phi_g = brentq(lambda a: np.linalg.norm(self.roller(a) - self.cam_axis) - self.rho0, -1.0, 1.0)
        self.latch, saved = dict(self.latch, travel=-1.0), self.latch
        self.dashpot, saved_d = dict(self.dashpot, stop_stiffness=0.0, damping=0.0, stop_damping=0.0), self.dashpot
        self.y_open = -1.0  # u far above every stop
        q = self.rest(np.array([phi_g] * self.n + [0.0] * self.n), -1.0, True)
        self.latch, self.dashpot = saved, saved_d
        return float(q[0])


def solve_opening(path: str | Path, t_end: float, step: float = 1e-5) -> dict[str, np.ndarray]:
    """The O from the closed rest (the pawl lets go from t = 0): {t, follower_angle, lever angles
    ``pole_j_lever_angle`` (the free levers), ``pole_i_travel``, ``f_travel``} sampled every
    ``step`` s; DOP853 with rtol 1e-10, its steps capped at ``step``."""
    o = Opening(json.loads(Path(path).read_text()))
    n = o.n
    a0 = math.asin((o.latch["travel"] + o.y_open - o.pivot[1]) / o.r_out) - o.alpha
    q0 = o.rest(np.array([a0] * n + [g + 2e-5 for g in o.gaps]), -1.0, False)
    t = np.arange(0.0, t_end + 0.5 * step, step)
    sol = solve_ivp(lambda tt, x: np.concatenate([x[2 * n:], o.accelerations(tt, x)]), (0.0, t[-1]),
                    np.concatenate([q0, np.zeros(2 * n)]), method="DOP853", rtol=1e-10, atol=1e-13, max_step=step, t_eval=t)
    out = {"t": sol.t, "follower_angle": sol.y[0]}
    free = [j for j in range(n) if j != o.drive]
    for k, j in enumerate(free):
        out[f"pole_{j + 1}_lever_angle"] = sol.y[1 + k]
    for i in range(n):
        out[f"pole_{i + 1}_travel"] = sol.y[n + i]
    out["f_travel"] = np.array([o.output(a)[1] for a in sol.y[0]]) - o.y_open
    return out
