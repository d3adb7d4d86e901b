"""Checks of vcbmodel.reference.independent against analytic results (not against the model).

Every expected value below is computed here from the equations (elliptic integrals, energy
balances, quadratures, hand-written Newton equations), never from vcbmodel code. The last test
is a clearly marked cross-check against the Exudyn model through its public API.
"""
import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp
from scipy.special import ellipk

from vcbmodel.reference import independent as ref
from vcbmodel.errors import SimulationError

# --- the paper's pendulum (point mass: I = M L^2) ------------------------------------------------
M, I, L, G, R = 60.0, 2.74, 0.2137, 9.81, 0.02
TH0 = math.radians(10.0)

# --- the reference cam rig (brief / spec numbers) --------------------------------------------------
CAM = {"mass": 6.0, "inertia_com": 0.05, "com_distance": 0.02, "com_angle": 0.5, "pivot": (0.4445, 0.0),
       "arm_length": 0.1032, "initial_angle": TH0, "initial_velocity": 0.0}
K0, LFREE, M0, COUNT = 24230.0, 0.30, 0.3364, 2
A = np.array(CAM["pivot"])
B0 = A + CAM["arm_length"] * np.array([math.cos(TH0), math.sin(TH0)])
MASSLESS = {"count": COUNT, "anchor": (0.0, 0.0), "stiffness": K0, "free_length": LFREE, "chain": None}
# uniform 2-mass chain: 3 equal springs 3 k0 of free length L/3, m0/3 at 1/3 and 2/3 of O->B, m0/6 on B
UNIFORM2 = dict(MASSLESS, chain={"masses": [M0 / 3, M0 / 3], "stiffnesses": [3 * K0] * 3,
                                 "free_lengths": [LFREE / 3] * 3, "positions": [B0 / 3, 2 * B0 / 3],
                                 "pin_mass": M0 / 6})
CAM_T = np.linspace(0.0, 0.035, 701)
RIG_FRICTION = {"mu_k": 0.13, "mu_s": 0.20, "stick_velocity": 1e-3, "stribeck_velocity": 0.10}


def swing(friction, t_eval, theta0=TH0, omega0=0.0):
    return ref.pendulum(M, I, L, G, R, friction, theta0, omega0, t_eval)


# ================================================================================================
# pendulum
# ================================================================================================
@pytest.fixture(scope="module")
def frictionless_swing():
    return swing({}, np.linspace(0.0, 6.0, 6001))


def test_frictionless_pendulum_period_is_the_elliptic_integral(frictionless_swing):
    r = frictionless_swing
    period = 4.0 * math.sqrt(I / (M * G * L)) * ellipk(math.sin(TH0 / 2) ** 2)
    # turning points (w = 0 events) at multiples of half the period
    reversals = [e["t"] for e in r["events"] if e["kind"] == "reversal"]
    assert len(reversals) >= 12
    k = np.arange(1, len(reversals) + 1)
    err = np.max(np.abs(np.array(reversals) - k * period / 2)) / period
    assert err < 1e-6
    # and from the samples: one Newton step on w(t) at t = j T gives the simulated period
    tj = period * np.arange(1, 7)
    out = swing({}, tj)
    alpha = -M * G * L * math.sin(TH0) / I
    t_true = tj - out["omega"] / alpha
    assert np.max(np.abs(t_true - tj)) / period < 1e-6
    assert np.max(np.abs(out["theta"] - TH0)) < 1e-9


def test_frictionless_pendulum_conserves_energy(frictionless_swing):
    r = frictionless_swing
    E = 0.5 * I * r["omega"] ** 2 - M * G * L * np.cos(r["theta"])
    scale = M * G * L * (1 - math.cos(TH0))
    assert np.max(np.abs(E - E[0])) / scale < 1e-8
    assert not r["stuck"].any() and np.all(r["friction_torque"] == 0.0)


def _coulomb_half_swings(mu, amplitude, count):
    """Amplitudes after each half swing from the energy balance written in the angle domain.

    With u = w^2/2 as a function of theta, theta'' = du/dtheta, so eq. 1 with Tf = mu r Fn s and
    eq. 5-6 (Fn = |(M g cos th + 2 M L u, M g sin th + M L u')|) becomes an ODE in theta whose
    implicit coupling is a quadratic solved in closed form (no time integration, no brentq)."""
    c, alpha = mu * R, M * L / I

    def du(theta, y, s):
        u = y[0]
        P = M * G * math.cos(theta) + 2 * M * L * u
        beta = M * G * math.sin(theta) * (1 - M * L * L / I)
        # X = I a + M g L sin th satisfies X^2 = c^2 (P^2 + (beta + alpha X)^2) with sign(X) = -s
        qa, qb, qc = 1 - (c * alpha) ** 2, -2 * c * c * alpha * beta, -c * c * (P * P + beta * beta)
        disc = math.sqrt(qb * qb - 4 * qa * qc)
        X = (-qb - s * disc) / (2 * qa)
        return [(X - M * G * L * math.sin(theta)) / I]

    amps, a, s = [], amplitude, -1
    for _ in range(count):
        stop = lambda theta, y, s=s: y[0]  # noqa: E731
        stop.terminal, stop.direction = True, -1
        start = a if s < 0 else -a
        sol = solve_ivp(du, (start, -start), [0.0], args=(s,), method="DOP853", rtol=1e-13, atol=1e-16,
                        events=stop)
        a = abs(sol.t_events[0][0])
        amps.append(a)
        s = -s
    return np.array(amps)


def test_coulomb_pendulum_amplitude_decrement_matches_energy_balance():
    mu = 0.13
    r = swing({"mu_k": mu}, np.linspace(0.0, 4.0, 401))
    simulated = np.array([abs(e["theta"]) for e in r["events"] if e["kind"] == "reversal"])
    assert len(simulated) >= 5
    expected = _coulomb_half_swings(mu, TH0, len(simulated))
    assert np.max(np.abs(simulated - expected)) < 1e-9
    # the linear (Coulomb) decay: 2 mu r / L per half swing for Fn ~ M g, a few % off for eq. 5-6
    decrement = -np.diff(np.concatenate([[TH0], simulated]))
    assert np.allclose(decrement, 2 * mu * R / L, rtol=0.05)


def test_pendulum_held_by_static_friction_never_moves():
    theta0 = 0.01  # M g L sin(0.01) = 1.26 N m < mu_s r M g = 2.35 N m
    r = swing({"mu_k": 0.13, "mu_s": 0.2, "stick_velocity": 1e-3}, np.linspace(0.0, 10.0, 101), theta0=theta0)
    assert r["stuck"].all()
    assert np.all(r["theta"] == theta0) and np.all(r["omega"] == 0.0)
    assert np.allclose(r["friction_torque"], -M * G * L * math.sin(theta0), rtol=1e-12)
    # just above the holding limit it moves at once
    r = swing({"mu_k": 0.13, "mu_s": 0.2}, [0.0, 0.1], theta0=math.asin(0.2 * R / L) * 1.001)
    assert r["events"][0]["kind"] == "start"
    assert not r["stuck"][-1] and r["theta"][-1] < r["theta"][0]


@pytest.mark.parametrize("friction", [{"mu_k": 0.13},
                                      {"mu_k": 0.13, "mu_s": 0.20, "stick_velocity": 1e-3,
                                       "stribeck_velocity": 0.10, "viscous": 0.6}],
                         ids=["coulomb", "hybrid"])
def test_swinging_pendulum_stops_and_stays_and_friction_dissipates(friction):
    t = np.linspace(0.0, 16.0, 16001)
    r = swing(friction, t)
    stops = [e["t"] for e in r["events"] if e["kind"] == "stick"]
    assert len(stops) == 1 and stops[0] < 5.0
    rest = t >= stops[0] + 1e-9
    assert r["stuck"][rest].all() and not r["stuck"][t < stops[0] - 1e-9].any()
    late = t >= stops[0] + 0.5
    assert t[late][-1] - t[late][0] >= 10.0
    assert np.ptp(r["theta"][late]) < 1e-9
    # held: the gravity torque is within static friction at rest
    mu_s = friction.get("mu_s", friction["mu_k"])
    assert abs(M * G * L * math.sin(r["theta"][-1])) <= mu_s * R * M * G * math.cos(r["theta"][-1])
    # friction never does positive work (Tf opposes w in eq. 1: its power on the shaft is -Tf w)
    assert np.all(r["friction_torque"] * r["omega"] >= 0.0)
    # energy only decreases
    E = 0.5 * I * r["omega"] ** 2 - M * G * L * np.cos(r["theta"])
    assert np.all(np.diff(E) <= 1e-9 * M * G * L)


def test_pendulum_friction_law_and_reaction_at_the_samples():
    """Tf equals the spec's law evaluated with eq. 5-6 at the sampled state and acceleration."""
    fr = {"mu_k": 0.13, "mu_s": 0.20, "stick_velocity": 1e-3, "stribeck_velocity": 0.10, "viscous": 0.6}
    r = swing(fr, np.linspace(0.0, 2.5, 2501))
    th, w, a = r["theta"], r["omega"], r["alpha"]
    Fn = np.hypot(M * G * np.cos(th) + M * L * w**2, M * G * np.sin(th) + M * L * a)
    assert np.allclose(r["normal_force"], Fn, rtol=1e-12)
    s, aw = np.where(w == 0, np.sign(r["applied_torque"]), np.sign(w)), np.abs(w)  # at w = 0: breaking away
    law = np.where(aw <= 1e-3, 0.20 * R * Fn * s,
                   np.where(aw < 0.10, (0.20 - 0.07 * aw / 0.10) * R * Fn * s, 0.13 * R * Fn * s + 0.6 * (w - 0.10 * s)))
    slip = ~r["stuck"]
    assert np.allclose(r["friction_torque"][slip], law[slip], rtol=1e-10, atol=1e-12)
    # eq. 1 holds with the coupled Tf
    assert np.allclose(I * a + M * G * L * np.sin(th) + r["friction_torque"], 0.0, atol=1e-9)


def test_non_finite_input_is_a_simulation_error():
    with pytest.raises(SimulationError, match="non-finite"):
        swing({}, [0.0, 1.0], theta0=float("nan"))


def test_kinetic_above_static_friction_is_reported_not_chattered():
    """mu_k > mu_s: once |Tc| lies between the static and kinetic limits neither sticking nor
    slipping is consistent; the reference says so instead of chattering at w = 0."""
    with pytest.raises(SimulationError, match="no consistent motion"):
        swing({"mu_k": 0.2, "mu_s": 0.1}, [0.0, 5.0], theta0=0.17)


def test_pendulum_started_moving_and_viscous_only():
    """Started with a speed; linear viscous damping only: small-angle amplitude decays like
    exp(-zeta w_n t) (checked loosely: the nonlinearity of sin at 0.05 rad is < 0.1 %)."""
    zeta = 0.05
    wn = math.sqrt(M * G * L / I)
    wd = wn * math.sqrt(1 - zeta**2)
    t = np.linspace(0.0, 3.0, 301)
    r = swing({"zeta": zeta}, t, theta0=0.0, omega0=0.05 * wd)
    linear = 0.05 * np.exp(-zeta * wn * t) * np.sin(wd * t)
    assert np.max(np.abs(r["theta"] - linear)) < 1e-3 * 0.05
    assert not r["stuck"].any() and np.all(r["friction_torque"] * r["omega"] >= 0.0)


# ================================================================================================
# cam drop
# ================================================================================================
def cam_energy(r, spring):
    """Kinetic + potential energy (J) of cam, pin mass and spring masses, written out here."""
    c, ch = spring["count"], spring.get("chain")
    th, w = r["theta"], r["omega"]
    mc, Ic, lg, psi, lab = CAM["mass"], CAM["inertia_com"], CAM["com_distance"], CAM["com_angle"], CAM["arm_length"]
    mpin = c * (ch["pin_mass"] if ch else 0.0)
    E = 0.5 * (Ic + mc * lg**2 + mpin * lab**2) * w**2 + mc * G * (A[1] + lg * np.sin(th - psi))
    B = A[None, :] + lab * np.stack([np.cos(th), np.sin(th)], axis=1)
    O = np.broadcast_to(np.array(spring["anchor"], float), B.shape)
    if ch is None:
        pts, ks, ls = [O, B], [c * spring["stiffness"]], [spring["free_length"]]
    else:
        P, V = r["mass_positions"], r["mass_velocities"]
        for i, m in enumerate(ch["masses"]):
            E = E + 0.5 * c * m * np.sum(V[:, i] ** 2, axis=1)
        pts = [O] + [P[:, i] for i in range(P.shape[1])] + [B]
        ks, ls = [c * k for k in ch["stiffnesses"]], ch["free_lengths"]
    for k, l0, p, q in zip(ks, ls, pts[:-1], pts[1:]):
        E = E + 0.5 * k * (np.linalg.norm(q - p, axis=1) - l0) ** 2
    return E


@pytest.mark.parametrize("spring", [MASSLESS, UNIFORM2], ids=["massless", "lumped2"])
def test_frictionless_cam_drop_conserves_energy(spring):
    r = ref.cam_drop(CAM, spring, G, R, {}, CAM_T)
    E = cam_energy(r, spring)
    scale = 0.5 * COUNT * K0 * (np.linalg.norm(B0) - LFREE) ** 2  # initial spring energy, ~ 1.5 kJ
    assert r["theta"][-1] > 3.0  # the cam has turned most of a revolution
    assert np.max(np.abs(E - E[0])) / scale < 1e-9
    assert not r["stuck"].any()
    if spring["chain"] is not None:
        assert r["mass_positions"].shape == (len(CAM_T), 2, 2)
        np.testing.assert_allclose(r["mass_positions"][0], [B0 / 3, 2 * B0 / 3], atol=0)


def test_frictionless_massless_cam_drop_matches_quadrature():
    """1-DOF conservative drop: t(theta) = int dtheta / w(theta), w from the energy integral."""
    mc, Ic, lg, psi, lab = CAM["mass"], CAM["inertia_com"], CAM["com_distance"], CAM["com_angle"], CAM["arm_length"]
    IA = Ic + mc * lg**2

    def V(th):
        B = A + lab * np.array([math.cos(th), math.sin(th)])
        return mc * G * lg * math.sin(th - psi) + 0.5 * COUNT * K0 * (math.hypot(*B) - LFREE) ** 2

    def dV(th):
        B = A + lab * np.array([math.cos(th), math.sin(th)])
        dB = lab * np.array([-math.sin(th), math.cos(th)])
        lb = math.hypot(*B)
        return mc * G * lg * math.cos(th - psi) + COUNT * K0 * (lb - LFREE) * (B @ dB) / lb

    def drop_per_s2(s):  # (V(TH0) - V(TH0 + s^2)) / s^2, by its midpoint slope where it would cancel
        return -dV(TH0 + s * s / 2) if s * s < 1e-6 else (V(TH0) - V(TH0 + s * s)) / (s * s)

    def t_of(theta):  # theta = TH0 + s^2 removes the start's 1/sqrt singularity
        f = lambda s: 2 / math.sqrt(2 * drop_per_s2(s) / IA)  # noqa: E731
        return quad(f, 0.0, math.sqrt(theta - TH0), epsabs=1e-14, epsrel=1e-12, limit=200)[0]

    r = ref.cam_drop(CAM, MASSLESS, G, R, {}, CAM_T)
    for i in (50, 150, 300, 500, 700):
        assert abs(t_of(r["theta"][i]) - CAM_T[i]) < 1e-10


def test_cam_drop_with_friction_obeys_newton_and_the_law():
    """Coupled Tf at the samples: I_A th'' = Tc - Tf, Fn = |F_A| by Newton on the cam body, and
    Tf = the law's value at that Fn; friction dissipates."""
    spring = UNIFORM2
    r = ref.cam_drop(CAM, spring, G, R, RIG_FRICTION, CAM_T)
    mc, Ic, lg, psi, lab = CAM["mass"], CAM["inertia_com"], CAM["com_distance"], CAM["com_angle"], CAM["arm_length"]
    mpin = COUNT * spring["chain"]["pin_mass"]
    IA = Ic + mc * lg**2 + mpin * lab**2
    th, w, a = r["theta"], r["omega"], r["alpha"]
    B = A[None, :] + lab * np.stack([np.cos(th), np.sin(th)], 1)
    d = r["mass_positions"][:, -1] - B
    length = np.linalg.norm(d, axis=1)
    F = (COUNT * 3 * K0 * (length - LFREE / 3) / length)[:, None] * d  # last segment's pull on B
    rB = B - A
    Tc = rB[:, 0] * F[:, 1] - rB[:, 1] * F[:, 0] - mc * G * lg * np.cos(th - psi)
    assert np.allclose(r["applied_torque"], Tc, rtol=1e-11, atol=1e-9)
    assert np.allclose(IA * a, Tc - r["friction_torque"], rtol=1e-11, atol=1e-8)
    phi = th - psi
    aG = lg * (a[:, None] * np.stack([-np.sin(phi), np.cos(phi)], 1) - (w**2)[:, None] * np.stack([np.cos(phi), np.sin(phi)], 1))
    aB = lab * (a[:, None] * np.stack([-np.sin(th), np.cos(th)], 1) - (w**2)[:, None] * np.stack([np.cos(th), np.sin(th)], 1))
    FA = mc * aG + mpin * aB - F - np.array([0.0, -mc * G])
    Fn = np.linalg.norm(FA, axis=1)
    assert np.allclose(r["normal_force"], Fn, rtol=1e-11)
    s, aw = np.where(w == 0, np.sign(Tc), np.sign(w)), np.abs(w)  # at w = 0: breaking away
    mu = np.where(aw <= 1e-3, 0.20, np.where(aw < 0.10, 0.20 - 0.07 * aw / 0.10, 0.13))
    assert np.allclose(r["friction_torque"], mu * R * Fn * s, rtol=1e-11)
    assert np.all(r["friction_torque"] * w >= 0.0)
    # friction slows the drop
    r0 = ref.cam_drop(CAM, spring, G, R, {}, CAM_T)
    assert r["theta"][-1] < r0["theta"][-1] - 0.1


def test_lagrange_equations_match_hand_written_newton():
    """For one random state of a 2-mass chain with weights and pin mass: Lagrange (sympy) vs
    Newton written out here: m_i a_i = sum of axial forces + weight, I_A th'' = torques - Tf."""
    rng = np.random.default_rng(7)
    ch = {"masses": [0.11, 0.07], "stiffnesses": [6e4, 9e4, 7e4], "free_lengths": [0.09, 0.11, 0.1],
          "positions": [[0.2, 0.01], [0.35, -0.02]], "pin_mass": 0.05}
    spring = {"count": 2, "anchor": (0.01, -0.02), "stiffness": K0, "free_length": LFREE, "chain": ch, "weight": True}
    mech = ref.CamMechanism(CAM, spring, G)
    q = np.concatenate([[rng.uniform(0, 2 * np.pi)], (np.array(ch["positions"]) + rng.normal(0, 0.01, (2, 2))).ravel()])
    qd = rng.normal(0, 5.0, 5)
    Tf = 3.7
    Mm, Minv = mech.mass(q)
    qdd = Minv @ (-mech.forces(q, qd) - Tf * np.eye(5)[0])

    c = 2
    mc, Ic, lg, psi, lab = CAM["mass"], CAM["inertia_com"], CAM["com_distance"], CAM["com_angle"], CAM["arm_length"]
    th = q[0]
    B = A + lab * np.array([math.cos(th), math.sin(th)])
    pts = [np.array(spring["anchor"]), q[1:3], q[3:5], B]
    tension = [c * k * (np.linalg.norm(p1 - p0) - l0) for k, l0, p0, p1 in zip(ch["stiffnesses"], ch["free_lengths"], pts[:-1], pts[1:])]
    unit = [(p1 - p0) / np.linalg.norm(p1 - p0) for p0, p1 in zip(pts[:-1], pts[1:])]
    down = np.array([0.0, -1.0])
    acc = [(-tension[i] * unit[i] + tension[i + 1] * unit[i + 1] + c * ch["masses"][i] * G * down) / (c * ch["masses"][i])
           for i in range(2)]
    mpin = c * ch["pin_mass"]
    FB = -tension[2] * unit[2] + mpin * G * down
    rB, rG = B - A, lg * np.array([math.cos(th - psi), math.sin(th - psi)])
    torque = rB[0] * FB[1] - rB[1] * FB[0] + rG[0] * (-mc * G) - Tf
    thdd = torque / (Ic + mc * lg**2 + mpin * lab**2)
    newton = np.concatenate([[thdd], acc[0], acc[1]])
    np.testing.assert_allclose(qdd, newton, rtol=1e-11, atol=1e-9)


def test_cam_stuck_while_spring_masses_swing_then_breaks_away():
    """Static friction holds the cam while the (laterally displaced) spring masses oscillate;
    the shaft angle is frozen exactly until |Tc| reaches mu_s r Fn, then it breaks away."""
    offset = 0.004 * np.array([-B0[1], B0[0]]) / np.linalg.norm(B0)
    ch = dict(UNIFORM2["chain"], positions=[B0 / 3 + offset, 2 * B0 / 3 - offset])
    spring = dict(UNIFORM2, chain=ch)
    # holding torque at t = 0, computed here: pull of the last segment on B, cam weight
    mc, lg, psi = CAM["mass"], CAM["com_distance"], CAM["com_angle"]
    d = ch["positions"][1] - B0
    F = COUNT * 3 * K0 * (np.linalg.norm(d) - LFREE / 3) * d / np.linalg.norm(d)
    Tc0 = (B0 - A)[0] * F[1] - (B0 - A)[1] * F[0] - mc * G * lg * math.cos(TH0 - psi)
    Fn0 = np.linalg.norm(-F - np.array([0.0, -mc * G]))
    mu_s = 1.03 * abs(Tc0) / (R * Fn0)
    t = np.linspace(0.0, 0.01, 2001)
    r = ref.cam_drop(CAM, spring, G, R, {"mu_k": 0.13, "mu_s": mu_s}, t)
    kinds = [e["kind"] for e in r["events"]]
    assert kinds[0] == "start_stuck" and "breakaway" in kinds
    tb = r["events"][kinds.index("breakaway")]["t"]
    held = t < tb
    assert held.sum() > 5 and r["stuck"][held].all()
    assert np.all(r["theta"][held] == TH0) and np.all(r["omega"][held] == 0.0)
    assert np.all(np.abs(r["applied_torque"][held]) <= mu_s * R * r["normal_force"][held] * (1 + 1e-12))
    # at the breakaway, |Tc| = mu_s r Fn0 (the last held sample is within one sample of it)
    just = ref.cam_drop(CAM, spring, G, R, {"mu_k": 0.13, "mu_s": mu_s}, [tb * (1 - 1e-9)])
    assert just["stuck"][0]
    assert abs(abs(just["applied_torque"][0]) / (mu_s * R * just["normal_force"][0]) - 1) < 1e-6
    # the spring chain with both ends fixed conserves its energy while the cam is held
    P, V = r["mass_positions"][held], r["mass_velocities"][held]
    pts = [np.zeros_like(P[:, 0]), P[:, 0], P[:, 1], np.broadcast_to(B0, P[:, 0].shape)]
    E = sum(0.5 * COUNT * (M0 / 3) * np.sum(V[:, i] ** 2, 1) for i in range(2))
    E = E + sum(0.5 * COUNT * 3 * K0 * (np.linalg.norm(q - p, axis=1) - LFREE / 3) ** 2 for p, q in zip(pts[:-1], pts[1:]))
    assert np.ptp(E) / E[0] < 1e-9
    # after breaking away the cam turns with the spring torque
    assert r["theta"][-1] > TH0 + 1e-3 and not r["stuck"][-1]
