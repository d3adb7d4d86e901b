"""Every number the paper does not publish, chosen once, here, with its reasoning.

The paper's rig geometry and raw measurements are unpublished (summary.md, "Known gaps").
Reference rigs below are consistent with everything the paper does state; anything a
study plots as "measured" is synthetic, generated from these values plus sensor noise.
"""

# --- friction law -----------------------------------------------------------------------
#: Karnopp stick band w0 (rad/s) when a rig gives none. The paper fits it but does not print
#: it; 1e-3 rad/s is 0.1 % of the pendulum's peak speed (~0.5 rad/s) and is the value the
#: example rigs state.
DEFAULT_STICK_VELOCITY = 1e-3
#: Time constant tau (s) of the passive stuck state (vcbmodel/laws/friction.py): a shaft caught in
#: the stick band comes to rest as exp(-t/tau) and moves by at most w0 tau = 2 urad. 2 ms lets the
#: pendulum's explicit RK4 step grow to 2 ms (stable below 2.8 tau) and is far shorter than any
#: swing (0.9 s period) or the 30 ms closing.
STICK_TIME = 2e-3

# --- spring models ----------------------------------------------------------------------
#: Mass model chosen when the diagnosis adds ``spring_mass`` to a massless model: three
#: lumped masses reproduce the first three fixed-fixed modes (paper Fig. 9(b): two masses
#: capture the behaviour, three are not much better, so three is the safe choice).
DEFAULT_SPRING_MASS_MODEL = "lumped-3"

#: Coil geometry for the ANCF spring's bending stiffness when a rig gives none: derived from k0
#: and m0 (vcbmodel/laws/coil.py) with spring index C = D/d = 4, the smallest commonly coiled
#: (Shigley, Mechanical Engineering Design, ch. 10), steel (G 79.3 GPa, E 206 GPa, 7850 kg/m^3).
#: k0 = 24230 N/m, m0 = 0.3364 kg give d = 5.1 mm, D = 20.4 mm, 32.6 active coils (0.17 m of
#: wire side by side in the 0.30 m free length). Finding: no steel spring with this k0 and m0
#: carries 6000 N: the Wahl-corrected shear stress, K_W F sqrt(2 rho G / (k0 m0)) at any
#: geometry but the Wahl factor, is 3.3 GPa at C = 4 (1.9 GPa for m0 = 1 kg) against an
#: allowable of about 0.85 GPa (45 % of 1.9 GPa tensile strength, Shigley Table 10-7). The
#: paper's 6000 N, k0 and m0 cannot all hold for one steel spring (6000 N for both springs, or
#: m0 = 0.3364 kg read as a third of a 1 kg spring, would fit better); we keep the paper's k0,
#: m0 and forces and state the bending stiffness's geometry as an assumption.
SPRING_INDEX = 4.0
STEEL_DENSITY = 7850.0
DEFAULT_SHEAR_MODULUS = 79.3e9
DEFAULT_YOUNGS_MODULUS = 206e9

# --- integration ------------------------------------------------------------------------
#: Fixed RK4 step for the pendulum (s), sized for accuracy alone (the passive stuck state catches
#: a reversing shaft whatever the step): against the independent event-driven reference, a 6 s
#: hybrid-friction swing is within 0.03 mrad at 5e-4 s (0.14 mrad at 1e-3 s; noise 0.5 mrad).
#: The old 2e-4 s, sized to the stick band, is no longer needed. Step refinement is tested.
PENDULUM_STEP = 5e-4
#: Fixed RK4 step for the cam drop (s): over 200 steps per period of the highest lumped-3
#: mode (403 Hz for m0 = 0.3364 kg), and 1/8 of the 12 kHz camera period.
CAM_STEP = 1e-5
#: Default simulated duration (s) when neither a measurement nor --t-end gives one.
PENDULUM_T_END = 6.0
CAM_T_END = 0.035

# --- reference rigs (studies) -----------------------------------------------------------
#: Pendulum of the paper's section 2: M = 60 kg and I = 2.74 kg m^2 are the paper's; L is
#: not printed: L = sqrt(I/M) = 0.2137 m treats the 60 kg weight as the whole inertia (a
#: point mass on a light link; small-angle period 0.93 s); journal radius 20 mm (a 40 mm
#: cam shaft). These are the spec's example values.
REFERENCE_PENDULUM = {
    "format": "vcb-rig/1", "name": "reference pendulum (paper section 2)",
    "experiment": "pendulum", "gravity": 9.81, "shaft": {"radius": 0.02},
    "pendulum": {"mass": 60.0, "inertia": 2.74, "com_distance": 0.2137,
                 "initial_angle": 0.17453292519943295, "initial_velocity": 0.0},
    "friction": {},
    "model": {"effects": ["coulomb_friction", "stribeck", "viscous_friction"], "spring_model": "massless"},
}
#: The paper's second test: "a shorter link and 15 deg" to reach higher speeds. The link
#: length is not printed; 0.15 m (point mass again, I = M L^2) gives 30 % higher speeds.
REFERENCE_PENDULUM_15 = dict(REFERENCE_PENDULUM, name="reference pendulum, short link, 15 deg",
                             pendulum={"mass": 60.0, "inertia": 1.35, "com_distance": 0.15,
                                       "initial_angle": 0.2617993877991494, "initial_velocity": 0.0})
#: The truth used for the synthetic pendulum "measurements" (documented stand-ins): the
#: ranges of the example data (mu_k 0.09-0.16, mu_s about 2 mu_k, ws ~0.1 rad/s, Cv ~0.6).
REFERENCE_PENDULUM_TRUTH = {"mu_s": 0.20, "mu_k": 0.13, "stick_velocity": 1e-3,
                            "stribeck_velocity": 0.10, "viscous": 0.6}

#: Cam drop of the paper's section 3: k0 and m0 are the paper's; the anchor, pivot and arm
#: are chosen so that each spring pulls 5970 N at the start (theta = 10 deg) and 1000 N at
#: theta = 180 deg, the paper's 6000 -> 1000 N over the closing stroke; cam mass and inertia
#: are those of a 6 kg steel cam of about 0.13 m radius.
REFERENCE_CAM = {
    "format": "vcb-rig/1", "name": "reference cam drop (paper section 3)",
    "experiment": "cam_drop", "gravity": 9.81, "shaft": {"radius": 0.02},
    "cam": {"mass": 6.0, "inertia_com": 0.05, "com_distance": 0.02, "com_angle": 0.5,
            "pivot": [0.4445, 0.0], "arm_length": 0.1032,
            "initial_angle": 0.17453292519943295, "initial_velocity": 0.0},
    "closing_spring": {"count": 2, "stiffness": 24230.0, "mass": 0.3364, "free_length": 0.30,
                       "anchor": [0.0, 0.0]},
    "friction": {"mu_k": 0.13, "mu_s": 0.20, "stick_velocity": 1e-3, "stribeck_velocity": 0.10},
    "model": {"effects": ["coulomb_friction", "stribeck", "spring_mass"], "spring_model": "lumped-2",
              "lumped_convention": "exact"},
}
#: The text's "each spring is heavy (about 1 kg)": the variant with the whole coil mass.
HEAVY_SPRING_MASS = 1.0

# --- ANCF spring (vcbmodel/ancf_spring.py) ----------------------------------------------------
#: Elements of the ANCF closing spring by default (axial modes within 0.1 % at 8, exudyn-notes).
ANCF_ELEMENTS = 8
#: Penalty springs tie the cable's ends to the anchor and to the cam pin (N/m per spring); no
#: constraints, so the explicit RK4 solver stays exact (exudyn-notes: constraint elimination is
#: wrong for mass-coupled ANCF coordinates). 1e8 N/m moves an end by 0.06 mm under 6000 N; the
#: penalty springs are critically damped against their end-node mass so their own fast mode dies.
ANCF_PENALTY_STIFFNESS = 1e8
#: RK4 step for the ANCF cam drop (s) up to ANCF_ELEMENTS elements: halving it changes the
#: 35 ms cam angle by about 1e-5 rad (5e-6 s: 3e-4 rad; 1e-5 s diverges at 4 elements).
ANCF_STEP = 2.5e-6
#: The RK4 step's stability limit is set by the ties' damped fast mode: h < C sqrt(m_end / k_tie),
#: m_end = m0 / (2 N) the end element's half mass per spring, k_tie the tie stiffness per spring.
#: Measured by bisection on the step (cam drop with Coulomb friction, m0 0.1-3 kg, N 4-16,
#: 1e8 N/m): C = 0.208-0.236. Steps are capped at this factor (0.84 of the lowest limit): before,
#: a spring under 0.3 kg diverged at the default step. Fits run at the cap (0.001-0.006 mrad from a
#: step half as long in a 1 kg cam drop; the default ANCF_STEP is kept for studies).
ANCF_STEP_FACTOR = 0.175

# --- whole breaker (paper section 4; vcbmodel/laws/breaker.py) --------------------------------
#: A 12 kV, 40 kA class three-pole vacuum breaker around the reference cam (the closing springs
#: and the cam are REFERENCE_CAM's, unchanged; the paper gives only the rating, the closing time
#: of about 30 ms and the spring forces). Values and reasons:
#: - contact gap 11 mm (12 kV interrupters open 8-12 mm), wipe about 4 mm (contact-spring travel
#:   of 3-4 mm is usual); pole gaps spread by +-0.3 mm (assembly tolerance: shows pole scatter);
#: - moving mass 1.5 kg per pole (moving contact and stem, terminal, share of the push rod);
#: - wipe spring 2500 N preload, 250 kN/m (about 3500 N contact force closed: 40 kA interrupters
#:   need 3-4 kN against electrodynamic repulsion); push rod and stop 2e7 N/m, 500 N s/m;
#: - bellows: 150 N per pole (0.1 MPa on a 15 cm^2 mean bellows area);
#: - follower: pivot 0.1 m from the roller, output arm 0.16 m (F travels 1.6 x the roller),
#:   0.08 kg m^2 with main shaft and pole levers; roller radius 20 mm, 20 mm wide, on a 45 mm
#:   base circle;
#: - cam profile: 9.4 mm roller lift (F travel 15 mm = gap + wipe) with a 4-5-6-7 polynomial rise
#:   over cam angles 12-285 deg (dwell to 325 deg, return 325-368 deg). The closing springs turn
#:   the cam to about 150 deg in 30 ms at about 215 rad/s, and the F travel per cam angle sets the
#:   touch speed: the former 40-220 deg rise touched at 2.0 m/s, above the 0.6-1.5 m/s of 12 kV
#:   vacuum breakers. Spreading the rise over 273 deg brings the touch to 1.27 m/s (target
#:   1.0-1.3 m/s) at the cost of the closing time: 32.5 ms instead of 30 ms (with these springs a
#:   30 ms closing touches at 1.5 m/s). The cam turns back at about 294 deg (the springs
#:   recharge), 9 deg past the rise's end; without shaft friction and spring mass it turns on to
#:   323 deg in the 45 ms simulated, still short of the return (the holding latch that keeps a
#:   real breaker closed is not modelled). Pressure angle: at most 5 deg while the roller rises,
#:   24 deg on the return (limit for roller followers about 30 deg);
#: - opening spring 2000 N at open, 60 kN/m (37 J stored in the 15 mm stroke of F): it keeps the
#:   roller on the cam through the rise's deceleration with 1.5 kN to spare (the smallest roller
#:   force before the touch). At the former 1200 N the margin is about 0.2 kN, and with the
#:   former 180 deg rise the roller jumped 0.4 ms before the touch;
#: - cam-roller contact: a 20 mm wide cylindrical roller on the cam is a line contact: Palmgren's
#:   steel law (K_L delta^(10/9), 0.02 mm at 15 kN; Johnson's cylinder formula within 15 %);
#:   Hunt-Crossley damping with alpha = 0.2 s/m (Hunt & Crossley's range for steel 0.08-0.32 s/m)
#:   because the contact is preloaded for the whole closing (Lankarani-Nikravesh needs an impact
#:   speed; its 0.05 m/s floor gave an arbitrary dashpot of several kN). cam_roller_stiffness
#:   1e11 N/m^1.5 is the Hertz point-contact alternative (cam_roller_law "hertz_point");
#: - pole contacts: Hertz point contact 1e10 N/m^1.5 (Cu-Cr butt contacts with the stems'
#:   compliance, 0.05 mm at 3.5 kN), impacts with Lankarani-Nikravesh damping, restitution 0.8
#:   (bounces of 1-2 ms as seen on breakers), impact-speed floor 0.05 m/s;
#: - closing latch: holds the cam at its spring pin B (arm l_AB, angle 0; the force enters the
#:   shaft reaction), released linearly over 2 ms (a solenoid-tripped latch).
REFERENCE_BREAKER_SECTION = {
    "cam_profile": {"base_radius": 0.045, "lift": 0.0094, "rise_start": 0.20944, "rise_end": 4.97419,
                    "return_start": 5.67232, "return_end": 6.42281},
    "roller_radius": 0.02,
    "follower": {"pivot": [0.3445, 0.065], "inertia": 0.08, "roller_arm": 0.10, "output_arm": 0.16,
                 "output_angle": 0.0, "rest_angle": 0.0},
    "poles": {"count": 3, "moving_mass": 1.5, "contact_gap": 0.011, "gap_offsets": [0.0, 0.0003, -0.0003],
              "push_rod_length": 0.25, "wipe_preload": 2500.0, "wipe_rate": 2.5e5, "rod_stiffness": 2e7,
              "rod_damping": 500.0, "bellows_force": 150.0},
    "opening_spring": {"stiffness": 6e4, "preload": 2000.0, "length": 0.2},
    "contact": {"cam_roller_law": "line", "roller_width": 0.02, "cam_roller_damping": "hunt_crossley",
                "cam_roller_damping_factor": 0.2, "cam_roller_stiffness": 1e11, "pole_stiffness": 1e10,
                "exponent": 1.5, "restitution": 0.8, "min_impact_speed": 0.05},
    "latch": {"release_time": 0.002, "arm": 0.1032, "angle": 0.0},
}
REFERENCE_BREAKER = dict(
    REFERENCE_CAM, name="reference 12 kV / 40 kA breaker closing (paper section 4)", experiment="vcb_closing",
    breaker=REFERENCE_BREAKER_SECTION,
    model={"effects": ["coulomb_friction", "stribeck", "spring_mass", "contact_damping", "bellows_force"],
           "spring_model": "lumped-2", "lumped_convention": "paper"})
#: Simulated closing (s): latch release to contacts settled.
BREAKER_T_END = 0.045
#: Fixed RK4 step of the whole breaker (s): the cam drop's step; the stiffest contact (cam-roller
#: at 20 kN, about 1.7 kHz) then gets 60 steps per period. Step refinement is tested; against
#: the independent solve (vcbmodel/reference/breaker.py) the touch times agree to 10 ns.
BREAKER_STEP = 1e-5

# --- friction truths outside the fitted family (vcbmodel/reference/truth_friction.py) -----------
#: The realism study's records may take their shaft friction from laws the diagnosis does not fit
#: (issue 20). Their mu_s, mu_k, Stribeck (Tustin: decay) velocity and viscous coefficient are
#: drawn as for the hybrid truth (analysis/realistic.py); the numbers below are what those laws add.
#: LuGre bristle stiffness per unit normal force sigma0 (1/m): a steady bristle deflection of
#: mu/sigma0 = 1.5-2.7 um for mu 0.09-0.16, the 1-5 um pre-sliding displacements of steel
#: junctions in Armstrong-Helouvry et al.'s survey (Automatica 30, 1994); Canudas de Wit et al.'s
#: example (IEEE TAC 40, 1995: 1e5 N/m for 1 N of Coulomb friction) gives 10 um.
LUGRE_SIGMA0 = 6e4
#: LuGre bristle damping per unit normal force sigma1 (s/m): Canudas de Wit et al.'s example takes
#: sigma1 = sqrt(sigma0) for a unit mass (316 N s/m on 9.81 N, i.e. 32 s/m per unit normal force at
#: sigma0 1e4 /m); scaled as sqrt(sigma0) to ours: 32 sqrt(6) ~ 80 s/m. It fades with speed as
#: exp(-(w/w_s)^2) (Olsson et al., Eur. J. Control 4, 1998), so it damps pre-sliding only.
LUGRE_SIGMA1 = 80.0
#: Dahl rest stiffness per unit normal force sigma0 (1/m), exponent 1: a softer junction than
#: LuGre's, 3-5 um of pre-sliding at mu_k 0.09-0.16 (Dahl 1968 fits ball bearings with
#: micrometre-scale rest slopes).
DAHL_SIGMA0 = 3e4
#: A cogging or defect torque a sin(k theta + p) on the shaft: amplitude a as a fraction of the
#: kinetic friction torque at the rig's static load (pendulum M g; cam drop the springs' initial
#: pull), drawn in this range: a defect felt but not dominant (the friction still decides the
#: decay). Wavenumber k in 1/rad (integer: a defect repeats each revolution), 20-40: 9-18 deg
#: between bumps, one to two bumps per swing of a 10-15 deg pendulum.
POSITION_TORQUE_FRACTION = (0.2, 0.4)
POSITION_TORQUE_WAVENUMBER = (20, 40)
