"""An independent solve of the whole breaker's closing, written again from the equations.

Why this exists
---------------
:class:`vcbmodel.reference.solve.BreakerExtension` integrates the model's own
:class:`vcbmodel.laws.breaker.BreakerLaws`: agreement with Exudyn checks only the wiring. This
module shares no code with the model: it imports nothing from ``vcbmodel.laws`` (nor from the
builders, the other references or the evaluation); the geometry, the contact laws, the friction
law and the equations of motion are written here a second time. It reads the loaded rig's data
(plain attributes) and the model spec's values, and a lumped chain's numbers.

What is different on purpose
----------------------------
* **Exact roller-to-profile distance.** The model takes the penetration of the roller as the
  pitch curve's normal offset at the roller's own polar angle, (rho(u) - rho_C) cos(gamma), exact
  to first order. Here the penetration is the signed minimum distance from the roller centre to
  the cam's pitch curve (the locus of roller centres at zero penetration), found numerically
  (Newton on the stationarity condition), and the force acts along the pitch curve's normal at
  the closest point. ``distance="first_order"`` uses the model's formula instead, to measure
  what the first-order offset costs.
* **Event-driven integration** (scipy's DOP853 on smooth segments): the shaft friction's speed
  regimes, the stuck shaft held by static friction (theta frozen, w = 0, no creep) and its
  breakaway, and the start of each Lankarani-Nikravesh contact (its impact speed is the exact
  approach speed at that instant) are events; the model instead latches impact speeds at the
  start of the RK4 step and catches sticking with a widened band.
* **The friction/reaction coupling** is a root solve for theta'' (Brent), not the model's closed
  form.

Equations (SI units; angles counter-clockwise; gravity along -y)
----------------------------------------------------------------
Coordinates: cam angle theta (direction of A->B), the closing springs' chain points p_k (``count``
identical springs lumped as one chain of ``count`` times the masses and stiffnesses), follower
angle phi (direction pivot->roller centre), pole travels z_i.

* Cam (with the chain's pin mass m_pin riding on B): I_A theta'' = T_c - T_f,
  I_A = I_c + m_c l_g^2 + count m_pin l_AB^2; T_c = r_AB x F_spring + cam and pin weight torques +
  r_C x F_roller-on-cam + latch torque. Shaft reaction R = m_c a_G + count m_pin a_B - (every
  other force on the cam), a_P = theta'' e_z x r_P - theta'^2 r_P, so R = R0 + R1 theta''; the
  friction T_f (spec law with Karnopp band, Stribeck branch, viscous term) takes F_n = |R|.
* Chain point k: m_k p_k'' = (pulls of its two springs) (+ weight if ``closing_spring.weight``).
* Follower: I_f phi'' = torques of the roller force, the opening spring and the push rods.
* Pole i: m z_i'' = (rod force along F->pin)_y - contact force + bellows force - m g.
* Cam profile: pitch radius rho(u) = r_b + r_r + lift s, s the 4-5-6-7 polynomial
  35x^4 - 84x^5 + 70x^6 - 20x^7 on the rise, 1 - s on the return; the roller at polar angle beta
  (from A) sees u = theta - (beta - beta_rest).
* Contacts: Hertz point K delta^n or line K_L delta^(10/9) with Palmgren's K_L for a steel roller
  of length l: delta(mm) = 3.84e-5 Q^0.9 / l(mm)^0.8; damping Lankarani-Nikravesh
  (1 + 3 (1 - e^2)/4 delta'/max(v_impact, v_floor)) or Hunt-Crossley (1 + alpha delta'), clipped
  at zero force.
* Push rod: compression s = L_rod - |pin - F|; force k_rod s below the wipe preload, preload +
  k_wipe (s - s0) above, plus c_rod s'. Opening spring: from its anchor below F0 to F.
* Latch: torque T_h (1 - t / t_r) for 0 < t < t_r as a force T / arm perpendicular to A->L at the
  latch point L = A + arm (cos(theta + angle), sin(theta + angle)).
* Start: the static rest held by the latch (follower on the base circle, rods at their rest
  compression, latch torque balancing the cam).

Public API: :func:`solve_closing`.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from ..errors import SimulationError

TWO_PI = 2.0 * math.pi
#: Palmgren's steel-on-steel line-contact compliance, delta (mm) = C Q^0.9 / l^0.8 (N, mm).
PALMGREN = 3.84e-5
#: Guard against endless event switching.
MAX_SEGMENTS = 10_000


# ----------------------------------------------------------------------------------------------
# cam profile
# ----------------------------------------------------------------------------------------------
class _Profile:
    """Pitch radius rho(u) (m) with its first and second derivatives in u (m/rad, m/rad^2)."""

    def __init__(self, profile, roller_radius):
        self.base = profile.base_radius + roller_radius
        self.lift = profile.lift
        self.r0, self.r1 = profile.rise_start, profile.rise_end
        self.d0, self.d1 = profile.return_start, profile.return_end

    @staticmethod
    def _poly(x):
        if x <= 0.0:
            return 0.0, 0.0, 0.0
        if x >= 1.0:
            return 1.0, 0.0, 0.0
        s = 35 * x**4 - 84 * x**5 + 70 * x**6 - 20 * x**7
        ds = 140 * x**3 - 420 * x**4 + 420 * x**5 - 140 * x**6
        dds = 420 * x**2 - 1680 * x**3 + 2100 * x**4 - 840 * x**5
        return s, ds, dds

    def __call__(self, u):
        u = self.r0 + math.fmod(u - self.r0, TWO_PI)
        if u < self.r0:
            u += TWO_PI
        if u <= self.r1:
            w = self.r1 - self.r0
            s, ds, dds = self._poly((u - self.r0) / w)
            return self.base + self.lift * s, self.lift * ds / w, self.lift * dds / (w * w)
        if u < self.d0:
            return self.base + self.lift, 0.0, 0.0
        w = self.d1 - self.d0
        s, ds, dds = self._poly((u - self.d0) / w)
        return self.base + self.lift * (1.0 - s), -self.lift * ds / w, -self.lift * dds / (w * w)


# ----------------------------------------------------------------------------------------------
# the mechanism
# ----------------------------------------------------------------------------------------------
class _Closing:
    """Parameters, the rest state and the forces of the closing (module docstring)."""

    def __init__(self, rig, spec, chain, distance):
        if distance not in ("exact", "first_order"):
            raise ValueError("distance must be 'exact' or 'first_order'")
        self.distance = distance
        b, cam, spring = rig.breaker, rig.cam, rig.closing_spring
        self.g = rig.gravity
        # cam and springs
        self.A = (float(cam.pivot[0]), float(cam.pivot[1]))
        self.lab, self.mc, self.lg, self.psi = cam.arm_length, cam.mass, cam.com_distance, cam.com_angle
        c = spring.count
        self.O = (float(spring.anchor[0]), float(spring.anchor[1]))
        self.weight = bool(spring.weight)
        if chain is None:
            self.masses, self.ks, self.ls, self.mpin = [], [c * spring.stiffness], [spring.free_length], 0.0
        else:
            self.masses = [c * float(m) for m in chain.masses]
            self.ks = [c * float(k) for k in chain.stiffnesses]
            self.ls = [float(x) for x in chain.free_lengths]
            self.mpin = c * float(getattr(chain, "pin_mass", 0.0))
        self.nm = len(self.masses)
        self.IA = cam.inertia_com + self.mc * self.lg**2 + self.mpin * self.lab**2
        self.theta0 = cam.initial_angle
        # friction (spec values; without an effect its value is off in the spec already)
        self.mu_k = spec.mu_k
        self.mu_s = max(spec.mu_s, spec.mu_k)
        self.w0, self.ws, self.cv, self.r = spec.stick_velocity, spec.stribeck_velocity, spec.viscous, rig.shaft_radius
        bounds = [0.0] + ([self.w0] if self.w0 > 0 else []) + ([self.ws] if self.ws > self.w0 else []) + [math.inf]
        self.bounds = bounds
        # follower
        f = b.follower
        self.P = (float(f.pivot[0]), float(f.pivot[1]))
        self.ar, self.ao, self.alpha_o, self.If = f.roller_arm, f.output_arm, f.output_angle, f.inertia
        self.profile = _Profile(b.profile, b.roller_radius)
        # rest geometry: the roller on the base circle
        rho0 = b.profile.base_radius + b.roller_radius
        dx, dy = self.A[0] - self.P[0], self.A[1] - self.P[1]
        d = math.hypot(dx, dy)
        cos_a = (self.ar**2 + d * d - rho0**2) / (2 * self.ar * d)
        if abs(cos_a) > 1:
            raise SimulationError("independent breaker reference: the roller cannot reach the base circle")
        base, a = math.atan2(dy, dx), math.acos(cos_a)
        self.phi_geo = min((base + a, base - a), key=lambda x: abs(math.remainder(x - f.rest_angle, TWO_PI)))
        C = self.roller_centre(self.phi_geo)
        self.beta_rest = math.atan2(C[1] - self.A[1], C[0] - self.A[0])
        self.F0 = self.output_point(self.phi_geo)
        # poles, rods, opening spring
        po = b.poles
        self.n = po.count
        self.mp = po.moving_mass
        self.gaps = [po.contact_gap + o for o in po.gap_offsets]
        self.Lrod, self.krod, self.pre, self.kwipe, self.crod = (po.push_rod_length, po.rod_stiffness, po.wipe_preload,
                                                                  po.wipe_rate, po.rod_damping)
        self.s0 = self.pre / self.krod
        self.pin_x, self.pin_y0 = self.F0[0], self.F0[1] + self.Lrod
        self.pole_push = spec.bellows_force - self.mp * self.g  # N along closing
        o = b.opening_spring
        self.anchor = (self.F0[0], self.F0[1] - o.length)
        self.k_open, self.l_open = o.stiffness, o.length - o.preload / o.stiffness
        # contacts
        con = b.contact
        roller = b.cam_roller
        if roller.law == "line":
            width_mm = 1000.0 * roller.roller_width
            self.K_roller = (1000.0 * width_mm**0.8 / PALMGREN) ** (1.0 / 0.9)  # Q = (delta_mm l^0.8 / C)^(1/0.9)
            self.n_roller = 1.0 / 0.9
        else:
            self.K_roller, self.n_roller = con.cam_roller_stiffness, con.exponent
        damped = "contact_damping" in spec.effects
        self.e = spec.restitution if damped else 1.0
        self.hunt_crossley = roller.damping == "hunt_crossley"
        self.alpha = roller.damping_factor if damped else 0.0
        self.K_pole, self.n_pole, self.v_floor = con.pole_stiffness, con.exponent, con.min_impact_speed
        # latch
        lp = b.latch_point
        self.latch_arm = self.lab if lp.arm is None else lp.arm
        self.latch_angle = lp.angle
        self.t_release = b.latch_release_time
        self.holding = 0.0
        self.impact = [0.0] * (self.n + 1)  # LN impact speeds [cam-roller, poles]

    # -- kinematics ---------------------------------------------------------------------------
    def roller_centre(self, phi):
        return self.P[0] + self.ar * math.cos(phi), self.P[1] + self.ar * math.sin(phi)

    def output_point(self, phi):
        a = phi + self.alpha_o
        return self.P[0] + self.ao * math.cos(a), self.P[1] + self.ao * math.sin(a)

    def pitch_point(self, beta, theta):
        """Pitch curve at polar angle beta: (P, dP/dbeta, d2P/dbeta2, rho, drho/dbeta)."""
        rho, d1, d2 = self.profile(theta - (beta - self.beta_rest))
        rb, rbb = -d1, d2  # u = theta - beta + beta_rest
        c, s = math.cos(beta), math.sin(beta)
        P = (self.A[0] + rho * c, self.A[1] + rho * s)
        dP = (rb * c - rho * s, rb * s + rho * c)
        ddP = (rbb * c - 2 * rb * s - rho * c, rbb * s + 2 * rb * c - rho * s)
        return P, dP, ddP, rho, rb

    def roller_contact(self, theta, omega, phi, phid):
        """(penetration m, rate m/s, outward normal, roller centre C)."""
        C = self.roller_centre(phi)
        vC = (-phid * (C[1] - self.P[1]), phid * (C[0] - self.P[0]))
        beta = math.atan2(C[1] - self.A[1], C[0] - self.A[0])
        if self.distance == "exact":
            for _ in range(60):  # Newton on (P - C) . dP/dbeta = 0
                P, dP, ddP, rho, rb = self.pitch_point(beta, theta)
                dx, dy = P[0] - C[0], P[1] - C[1]
                fval = dx * dP[0] + dy * dP[1]
                fder = dP[0] ** 2 + dP[1] ** 2 + dx * ddP[0] + dy * ddP[1]
                step = max(-0.05, min(0.05, fval / fder))
                beta -= step
                if abs(step) < 1e-14:
                    break
            else:
                if abs(step) > 1e-11:
                    raise SimulationError("independent breaker reference: the closest point on the cam did not "
                                          f"converge (theta = {theta:.6g} rad, last step {step:.3g} rad)")
        P, dP, _, rho, rb = self.pitch_point(beta, theta)
        c, s = math.cos(beta), math.sin(beta)
        nx, ny = rho * c + rb * s, rho * s - rb * c  # rho e_r - rho_beta e_beta
        norm = math.hypot(nx, ny)
        nx, ny = nx / norm, ny / norm
        if self.distance == "exact":
            pen = (P[0] - C[0]) * nx + (P[1] - C[1]) * ny
        else:  # the model's first-order offset along the normal at the roller's own polar angle
            pen = (rho - math.hypot(C[0] - self.A[0], C[1] - self.A[1])) * rho / norm
        vP = (-omega * (P[1] - self.A[1]), omega * (P[0] - self.A[0]))
        rate = (vP[0] - vC[0]) * nx + (vP[1] - vC[1]) * ny
        if self.distance == "first_order":  # the rate of the first-order penetration
            rate = self._first_order_rate(theta, omega, phi, phid, C, vC)
        return pen, rate, (nx, ny), C

    def _first_order_rate(self, theta, omega, phi, phid, C, vC):
        dx, dy = C[0] - self.A[0], C[1] - self.A[1]
        rho_c = math.hypot(dx, dy)
        er = (dx / rho_c, dy / rho_c)
        eb = (-er[1], er[0])
        beta = math.atan2(dy, dx)
        rho, drho_du, _ = self.profile(theta - (beta - self.beta_rest))
        beta_dot = (eb[0] * vC[0] + eb[1] * vC[1]) / rho_c
        cos_g = 1.0 / math.sqrt(1.0 + (drho_du / rho) ** 2)
        return (drho_du * (omega - beta_dot) - (er[0] * vC[0] + er[1] * vC[1])) * cos_g

    # -- forces -------------------------------------------------------------------------------
    def roller_force(self, pen, rate):
        if pen <= 0.0:
            return 0.0
        elastic = self.K_roller * pen**self.n_roller
        if self.hunt_crossley:
            return max(0.0, elastic * (1.0 + self.alpha * rate))
        v = max(self.impact[0], self.v_floor)
        return max(0.0, elastic * (1.0 + 0.75 * (1.0 - self.e**2) * rate / v))

    def pole_force(self, i, z, zd):
        pen = z - self.gaps[i]
        if pen <= 0.0:
            return 0.0
        v = max(self.impact[i + 1], self.v_floor)
        return max(0.0, self.K_pole * pen**self.n_pole * (1.0 + 0.75 * (1.0 - self.e**2) * zd / v))

    def rod(self, phi, phid, z, zd):
        """(force on the pole along +y, torque on the follower, compression)."""
        F = self.output_point(phi)
        vF = (-phid * (F[1] - self.P[1]), phid * (F[0] - self.P[0]))
        dx, dy = self.pin_x - F[0], self.pin_y0 + z - F[1]
        L = math.hypot(dx, dy)
        ex, ey = dx / L, dy / L
        comp = self.Lrod - L
        rate = -(ex * (0.0 - vF[0]) + ey * (zd - vF[1]))
        force = self.krod * comp if comp <= self.s0 else self.pre + self.kwipe * (comp - self.s0)
        force += self.crod * rate
        # the rod pushes the pin along +e, the follower at F along -e
        torque = (F[0] - self.P[0]) * (-force * ey) - (F[1] - self.P[1]) * (-force * ex)
        return force * ey, torque, comp

    def opening_torque(self, phi):
        F = self.output_point(phi)
        dx, dy = F[0] - self.anchor[0], F[1] - self.anchor[1]
        L = math.hypot(dx, dy)
        tension = self.k_open * (L - self.l_open)
        gx, gy = -tension * dx / L, -tension * dy / L
        return (F[0] - self.P[0]) * gy - (F[1] - self.P[1]) * gx

    def latch(self, t, theta):
        """(torque, Fx, Fy) of the latch on the cam."""
        if t <= 0.0:
            torque = self.holding
        elif t >= self.t_release:
            torque = 0.0
        else:
            torque = self.holding * (1.0 - t / self.t_release)
        a = theta + self.latch_angle
        f = torque / self.latch_arm
        return torque, -f * math.sin(a), f * math.cos(a)

    def pin(self, theta):
        return self.A[0] + self.lab * math.cos(theta), self.A[1] + self.lab * math.sin(theta)

    def chain_forces(self, theta, pts):
        """(accelerations of the chain points, pull on pin B)."""
        B = self.pin(theta)
        nodes = [self.O] + pts + [B]
        pulls = []
        for k, l0, p, q in zip(self.ks, self.ls, nodes[:-1], nodes[1:]):
            dx, dy = q[0] - p[0], q[1] - p[1]
            L = math.hypot(dx, dy)
            tension = k * (L - l0)
            pulls.append((tension * dx / L, tension * dy / L))  # pulls q towards p: -this on q
        acc = []
        for i, m in enumerate(self.masses):
            fx = pulls[i + 1][0] - pulls[i][0]
            fy = pulls[i + 1][1] - pulls[i][1] - (m * self.g if self.weight else 0.0)
            acc.append((fx / m, fy / m))
        return acc, (-pulls[-1][0], -pulls[-1][1])

    def cam_applied(self, t, y):
        """Everything on the cam but friction: (T_c, R0, R1, roller state) at state y."""
        theta, omega = y[0], y[1]
        pts = [(y[2 + 2 * k], y[3 + 2 * k]) for k in range(self.nm)]
        _, (sx, sy) = self.chain_forces(theta, pts)
        j = 2 + 4 * self.nm
        phi, phid = y[j], y[j + 1 + self.n]
        pen, rate, (nx, ny), C = self.roller_contact(theta, omega, phi, phid)
        f = self.roller_force(pen, rate)
        cfx, cfy = -f * nx, -f * ny  # on the cam
        tl, lx, ly = self.latch(t, theta)
        rb = (self.lab * math.cos(theta), self.lab * math.sin(theta))
        rg = (self.lg * math.cos(theta - self.psi), self.lg * math.sin(theta - self.psi))
        rc = (C[0] - self.A[0], C[1] - self.A[1])
        pin_w = self.mpin * self.g if self.weight else 0.0
        Tc = (rb[0] * sy - rb[1] * sx) - self.mc * self.g * rg[0] - pin_w * rb[0] + (rc[0] * cfy - rc[1] * cfx) + tl
        # R = m_c a_G + m_pin a_B - (spring + roller + latch + weights)
        w2 = omega * omega
        R0 = (-self.mc * w2 * rg[0] - self.mpin * w2 * rb[0] - sx - cfx - lx,
              -self.mc * w2 * rg[1] - self.mpin * w2 * rb[1] - sy - cfy - ly + self.mc * self.g + pin_w)
        R1 = (-self.mc * rg[1] - self.mpin * rb[1], self.mc * rg[0] + self.mpin * rb[0])
        return Tc, R0, R1, (pen, rate, f, (nx, ny), C)

    def others(self, t, y, roller):
        """Rates of the chain, follower and poles at state y (roller: its contact state)."""
        theta = y[0]
        nm, n = self.nm, self.n
        pts = [(y[2 + 2 * k], y[3 + 2 * k]) for k in range(nm)]
        acc, _ = self.chain_forces(theta, pts)
        j = 2 + 4 * nm
        phi, phid = y[j], y[j + 1 + n]
        z, zd = y[j + 1:j + 1 + n], y[j + 2 + n:j + 2 + 2 * n]
        _, _, f, (nx, ny), C = roller
        t_fol = (C[0] - self.P[0]) * (f * ny) - (C[1] - self.P[1]) * (f * nx) + self.opening_torque(phi)
        zacc = []
        for i in range(n):
            push, torque, _ = self.rod(phi, phid, z[i], zd[i])
            t_fol += torque
            zacc.append((push - self.pole_force(i, z[i], zd[i]) + self.pole_push) / self.mp)
        return acc, t_fol / self.If, zacc

    # -- friction -----------------------------------------------------------------------------
    def regime_split(self, regime, w, s):
        """(k, v): T_f = k F_n + v in speed regime ``regime`` (bounds index), direction s."""
        lo, hi = self.bounds[regime], self.bounds[regime + 1]
        mid = 0.5 * (lo + hi) if math.isfinite(hi) else lo + 1.0
        if mid <= self.w0:
            return self.mu_s * self.r * s, 0.0
        if self.ws > 0.0 and mid < self.ws:
            # |w| clipped to the regime: a Runge-Kutta stage may look beyond the regime's end
            # (the event then ends the segment there), where the branch would extrapolate
            speed = min(max(abs(w), lo), hi)
            return (self.mu_s - (self.mu_s - self.mu_k) * speed / self.ws) * self.r * s, 0.0
        return self.mu_k * self.r * s, self.cv * (w - (self.ws if self.ws > 0 else 0.0) * s)

    def slip_acceleration(self, Tc, R0, R1, k, v):
        """theta'' with T_f = k |R0 + R1 theta''| + v (Brent on a monotonic function)."""
        I = self.IA
        a_c = (Tc - v) / I
        if k == 0.0:
            return a_c, math.hypot(*R0)

        def g(a):
            return a - a_c + k / I * math.hypot(R0[0] + R1[0] * a, R0[1] + R1[1] * a)

        if abs(k / I) * math.hypot(*R1) >= 1.0:
            raise SimulationError("independent breaker reference: friction/reaction coupling is ill-posed")
        D = abs(k / I) * (math.hypot(*R0) + math.hypot(*R1) * abs(a_c)) / (1.0 - abs(k / I) * math.hypot(*R1))
        D = D * (1.0 + 1e-9) + 1e-12
        lo, hi = a_c - D, a_c + D
        while g(lo) > 0.0:
            lo -= D
        while g(hi) < 0.0:
            hi += D
        a = brentq(g, lo, hi, xtol=1e-14 * (abs(a_c) + D), rtol=4 * np.finfo(float).eps, maxiter=200)
        return a, math.hypot(R0[0] + R1[0] * a, R0[1] + R1[1] * a)

    # -- rest state ---------------------------------------------------------------------------
    def rest(self):
        """Static rest held by the latch: (follower angle, pole travels, holding torque)."""
        n = self.n
        force = -self.pole_push  # the rod holds the pole's weight minus the bellows force
        comp = force / self.krod if force <= self.pre else self.s0 + (force - self.pre) / self.kwipe

        def travel(phi):
            F = self.output_point(phi)
            L = self.Lrod - comp
            return F[1] + math.sqrt(L * L - (self.pin_x - F[0]) ** 2) - self.pin_y0

        def torque(phi):
            z = travel(phi)
            pen, rate, (nx, ny), C = self.roller_contact(self.theta0, 0.0, phi, 0.0)
            f = self.roller_force(pen, 0.0)
            t = (C[0] - self.P[0]) * (f * ny) - (C[1] - self.P[1]) * (f * nx) + self.opening_torque(phi)
            return t + n * self.rod(phi, 0.0, z, 0.0)[1]

        phi = brentq(torque, self.phi_geo - 1e-3, self.phi_geo + 1e-3, xtol=1e-15)
        z = [travel(phi)] * n
        y = self.initial_vector(phi, z)
        self.holding = 0.0
        Tc, _, _, _ = self.cam_applied(-1.0, y)  # with holding = 0: the torque the latch must balance
        self.holding = -Tc
        return phi, z, -Tc

    def initial_vector(self, phi, z):
        B = self.pin(self.theta0)
        compliance = [1.0 / k for k in self.ks]
        total, acc, pts = sum(compliance), 0.0, []
        for k in range(self.nm):
            acc += compliance[k]
            f = acc / total
            pts += [self.O[0] + f * (B[0] - self.O[0]), self.O[1] + f * (B[1] - self.O[1])]
        return np.array([self.theta0, 0.0] + pts + [0.0] * (2 * self.nm) + [phi] + list(z) + [0.0] + [0.0] * self.n)


# ----------------------------------------------------------------------------------------------
# event-driven integration
# ----------------------------------------------------------------------------------------------
def _rhs(mech, mode):
    """Right-hand side in a mode: ('stuck',) or ('slip', s, regime)."""
    nm, n = mech.nm, mech.n
    j = 2 + 4 * nm

    def rhs(t, y):
        Tc, R0, R1, roller = mech.cam_applied(t, y)
        if mode[0] == "stuck":
            th_acc = 0.0
        else:
            k, v = mech.regime_split(mode[2], y[1], mode[1])
            th_acc = mech.slip_acceleration(Tc, R0, R1, k, v)[0]
        acc, phi_acc, zacc = mech.others(t, y, roller)
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
        return dy

    return rhs


def _friction_state(mech, t, y, mode):
    """(T_f, F_n) at a state in a mode."""
    Tc, R0, R1, _ = mech.cam_applied(t, y)
    if mode[0] == "stuck":
        return Tc, math.hypot(*R0)
    k, v = mech.regime_split(mode[2], y[1], mode[1])
    _, fn = mech.slip_acceleration(Tc, R0, R1, k, v)
    return k * fn + v, fn


def solve_closing(rig, spec, t_eval, chain=None, *, distance="exact", rtol=1e-10, atol=1e-13):
    """Solve a closing from the latch release (t = 0) without any of the model's code.

    Parameters
    ----------
    rig : a loaded ``vcb_closing`` rig (:func:`vcbmodel.experiments.loading.load_rig`).
    spec : the model spec (:func:`vcbmodel.experiments.simulation.model_spec`): effects, friction
        values (``mu_s``, ``mu_k``, ``stick_velocity``, ``stribeck_velocity``, ``viscous``),
        ``restitution`` and ``bellows_force``.
    t_eval : output times (s), increasing, from 0.
    chain : a lumped closing-spring chain (``masses`` kg, ``stiffnesses`` N/m, ``free_lengths`` m,
        ``pin_mass`` kg, per spring; :func:`vcbmodel.laws.springs.chain_for`), None: massless.
    distance : ``exact`` (minimum distance to the pitch curve) or ``first_order`` (the model's).
    rtol, atol : DOP853 tolerances (atol scaled per state: 1 for angles and lengths in m).

    Returns
    -------
    dict of arrays over ``t`` (s): ``cam_angle`` (rad), ``shaft_velocity`` (rad/s),
    ``follower_angle`` (rad), ``follower_velocity`` (rad/s), ``follower_displacement`` (m, F's
    travel along +y from rest), ``pole_i_travel`` (m), ``pole_i_velocity`` (m/s),
    ``cam_roller_force`` (N), ``cam_roller_penetration`` (m), ``friction_torque`` (N m),
    ``normal_force`` (N); ``touch_times`` and ``touch_speeds`` (per pole, first contact, from the
    events; s, m/s), ``events`` (list of (t, kind)), ``initial`` (follower angle rad, pole
    travels m, holding torque N m).
    """
    mech = _Closing(rig, spec, chain, distance)
    t_eval = np.asarray(t_eval, float)
    if t_eval.ndim != 1 or t_eval[0] < 0 or np.any(np.diff(t_eval) <= 0):
        raise ValueError("t_eval must be increasing times from 0")
    phi0, z0, holding = mech.rest()
    y = mech.initial_vector(phi0, z0)
    nm, n = mech.nm, mech.n
    j = 2 + 4 * nm
    t_end = float(t_eval[-1])
    scale = np.full(len(y), atol)
    scale[1] = atol * 1e3  # rad/s
    scale[2 + 2 * nm:2 + 4 * nm] = atol * 1e3
    scale[j + 1 + n:] = atol * 1e3
    events_log, segments, touches, touch_speeds = [], [], [None] * n, [None] * n
    t = 0.0

    # a torque below round-off of the latch's balance (1e-12 of the holding torque) is no torque:
    # without friction the balanced cam would otherwise chatter between stuck and slipping at t = 0
    tiny = 1e-12 * (abs(holding) + 1.0)

    def start_at_rest(t, y):
        Tc, R0, _, _ = mech.cam_applied(t, y)
        if abs(Tc) <= mech.mu_s * mech.r * math.hypot(*R0) + tiny:
            return ("stuck",)
        return ("slip", 1 if Tc > 0 else -1, 0)

    mode = start_at_rest(t, y) if y[1] == 0.0 else ("slip", 1 if y[1] > 0 else -1, 0)
    closed = [mech.roller_contact(y[0], y[1], y[j], y[j + 1 + n])[0] > 0.0]
    closed += [y[j + 1 + i] > mech.gaps[i] for i in range(n)]
    while t < t_end:
        if len(segments) > MAX_SEGMENTS:
            raise SimulationError("independent breaker reference: too many events (Zeno behaviour)")
        evs, kinds = [], []
        if mode[0] == "stuck":
            def breakaway(tt, yy):
                Tc, R0, _, _ = mech.cam_applied(tt, yy)
                return abs(Tc) - mech.mu_s * mech.r * math.hypot(*R0) - tiny
            breakaway.terminal, breakaway.direction = True, 1.0
            evs.append(breakaway)
            kinds.append("breakaway")
        else:
            s, regime = mode[1], mode[2]
            lo, hi = mech.bounds[regime], mech.bounds[regime + 1]

            def low(tt, yy, s=s, lo=lo):
                return s * yy[1] - lo
            low.terminal, low.direction = True, -1.0
            evs.append(low)
            kinds.append("down")
            if math.isfinite(hi):
                def high(tt, yy, s=s, hi=hi):
                    return s * yy[1] - hi
                high.terminal, high.direction = True, 1.0
                evs.append(high)
                kinds.append("up")
        # contacts: an open one waits for its start (LN: the impact speed), a closed one for its
        # end (which re-arms the start); the contact's state is tracked, not read from a state
        # that sits on the switching surface
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
        sol = solve_ivp(_rhs(mech, mode), (t, t_end), y, method="DOP853", rtol=rtol, atol=scale, events=evs,
                        dense_output=True)
        if sol.status < 0:
            raise SimulationError(f"independent breaker reference: {sol.message} at t = {sol.t[-1]:.6g} s")
        segments.append((t, sol.t[-1], mode, sol.sol, list(mech.impact)))
        if sol.status == 0:
            break
        hit = [(sol.t_events[k][0], k) for k in range(len(evs)) if len(sol.t_events[k])]
        t_hit, k = min(hit)
        y = np.array(sol.y_events[k][0], float)
        t = float(t_hit)
        segments[-1] = (segments[-1][0], t, mode, sol.sol, segments[-1][4])
        kind = kinds[k]
        if isinstance(kind, str):
            events_log.append((t, kind))
        else:
            slot = 0 if kind[0] == "roller" else kind[1] + 1
            name = "roller" if slot == 0 else f"pole_{slot}"
            events_log.append((t, f"{name}_{'opens' if closed[slot] else 'closes'}"))  # before the toggle below
        if kind == "breakaway":
            Tc, _, _, _ = mech.cam_applied(t, y)
            mode = ("slip", 1 if Tc > 0 else -1, 0)
        elif kind == "up":
            mode = ("slip", mode[1], mode[2] + 1)
        elif kind == "down":
            if mode[2] > 0:
                mode = ("slip", mode[1], mode[2] - 1)
            else:
                y[1] = 0.0
                mode = start_at_rest(t, y)
        elif kind[0] == "roller":
            closed[0] = not closed[0]
            if closed[0]:
                mech.impact[0] = max(mech.roller_contact(y[0], y[1], y[j], y[j + 1 + n])[1], 0.0)
        else:
            i = kind[1]
            closed[i + 1] = not closed[i + 1]
            if closed[i + 1]:
                mech.impact[i + 1] = max(y[j + 2 + n + i], 0.0)
                if touches[i] is None:
                    touches[i], touch_speeds[i] = t, y[j + 2 + n + i]
    # sample
    starts = np.array([s[0] for s in segments])
    idx = np.clip(np.searchsorted(starts, t_eval, side="right") - 1, 0, len(segments) - 1)
    Y = np.empty((len(t_eval), len(y)))
    force, pen, tf, fn = (np.empty(len(t_eval)) for _ in range(4))
    for q in np.unique(idx):
        t0, t1, mode, sol, impact = segments[q]
        sel = np.nonzero(idx == q)[0]
        Ys = sol(np.clip(t_eval[sel], t0, t1)).T
        mech.impact = list(impact)
        for r, yy in zip(sel, Ys):
            if mode[0] == "stuck":
                yy[1] = 0.0
            Y[r] = yy
            p, rate, _, _ = mech.roller_contact(yy[0], yy[1], yy[j], yy[j + 1 + n])
            pen[r], force[r] = p, mech.roller_force(p, rate)
            tf[r], fn[r] = _friction_state(mech, t_eval[r], yy, mode)
    if not np.all(np.isfinite(Y)):
        raise SimulationError("independent breaker reference: non-finite solution")
    F0y = mech.output_point(phi0)[1]
    out = {"t": t_eval, "cam_angle": Y[:, 0], "shaft_velocity": Y[:, 1], "follower_angle": Y[:, j],
           "follower_velocity": Y[:, j + 1 + n],
           "follower_displacement": np.array([mech.output_point(p)[1] for p in Y[:, j]]) - F0y,
           "cam_roller_force": force, "cam_roller_penetration": pen, "friction_torque": tf, "normal_force": fn,
           "touch_times": touches, "touch_speeds": touch_speeds, "events": events_log,
           "initial": {"follower_angle": phi0, "pole_travel": z0, "holding_torque": holding}}
    for i in range(n):
        out[f"pole_{i + 1}_travel"] = Y[:, j + 1 + i]
        out[f"pole_{i + 1}_velocity"] = Y[:, j + 2 + n + i]
    return out
