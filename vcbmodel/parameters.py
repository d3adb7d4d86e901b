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
#: Datasheet plausibility of a closing spring (vcbmodel/rig/datasheet.py): the thickest wire a
#: breaker mechanism's spring is wound from is about 20 mm (hot-wound above about 16 mm); 50 mm is
#: beyond any, so a larger value is millimetres. Mean coil diameters likewise stay well under 0.5 m.
SPRING_WIRE_LARGEST = 0.05
SPRING_COIL_LARGEST = 0.5
#: Shear modulus of spring wire (Pa): phosphor bronze 41 GPa, titanium alloys 42-45 GPa, steels and
#: stainless 69-81 GPa (Shigley Table 10-5); 10-100 GPa holds them all, a value like 79.3 is GPa.
SPRING_SHEAR_MODULUS_RANGE = (10e9, 100e9)
#: Density of spring wire (kg/m^3): titanium 4430 to phosphor bronze 8860; 7.85 is g/cm^3.
SPRING_DENSITY_RANGE = (2000.0, 20000.0)
#: Spring index D/d that springs are wound with: 4-12 preferred, about 3 the least that can be coiled
#: and above about 20 a spring tangles and buckles (Shigley sec. 10-2); 3-25 allows the rare ones.
SPRING_INDEX_RANGE = (3.0, 25.0)
STEEL_DENSITY = 7850.0
DEFAULT_SHEAR_MODULUS = 79.3e9
DEFAULT_YOUNGS_MODULUS = 206e9

# --- records ------------------------------------------------------------------------------
#: Largest relative error of a record's clock the diagnosis's time-scale nuisance may take (its
#: bounds): a camera's frame rate or a logger's crystal is off by a fraction of a percent (crystals
#: 20-100 ppm; cheap cameras' nominal rates up to about 0.5 %); beyond 1 % the record is not what
#: its file says and the user should fix its time stamps. A rig's ``uncertain.record.time_base``
#: may be at most half of it (a prior wider than the bounds would be cut silently).
TIME_SCALE_SPAN = 0.01
#: Plausible relative error (1 sigma) of a sensor's gain that the rig does not mark uncertain: a
#: potentiometer's or an encoder's scale from its data sheet or a one-point calibration is good to
#: about 1 % (conductive-plastic potentiometers: independent linearity 0.5-2 %; a camera's scale
#: from a marker of known length, about 1 % of the field of view). The diagnosis does not fit such a
#: gain (in a cam drop it would stand in for shaft friction); it says when this much error would move
#: a fitted parameter beyond its stated 95 % interval (analysis/diagnosis/pinned.py).
PINNED_GAIN_ERROR = 0.01

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
#: Kept as it is after issue 19 settled the spring reading (0.83 kg, 3000 N each): it is the section-3
#: test on which the spring models are compared (Fig. 9-10, studies/spring_models.py), its two
#: masses (0.3364 kg and HEAVY_SPRING_MASS) bracket the settled 0.83 kg, and changing it would move
#: every spring-fidelity number without changing what the study shows (which chain follows the
#: continuum). Its 6000 N per spring is the overturned reading (no steel coil carries it): read it
#: as a test of the spring models, not as a spring. The breaker has its own springs and cam.
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

# --- effects outside the paper: air drag, the closing spring's internal damping -----------------
#: Density of air (kg/m^3) at about 20 degC and sea level (ISO 2533 standard atmosphere: 1.225 at
#: 15 degC; 1.20 at 20 degC): the air a pendulum's paddle swings through.
AIR_DENSITY = 1.2
#: Drag coefficient of a square flat plate broadside to the flow, Cd = 1.17 (Hoerner, Fluid-Dynamic
#: Drag, 1965, ch. 3; White, Fluid Mechanics, Table 7.3: 1.18 above Re 1e4). A paddle of area A
#: (m^2) at radius R (m) on a shaft turning at w (rad/s) meets the air at R w: its torque is
#: 0.5 rho Cd A R^3 w|w| (vcbmodel.laws.mechanics.paddle_drag_coefficient; the speed's spread across
#: the paddle is neglected, R is the paddle's centre).
FLAT_PLATE_DRAG_COEFFICIENT = 1.17
#: Plausible damping ratio of a closing spring's first surge mode (the ``spring_damping`` effect,
#: Kelvin-Voigt: vcbmodel.laws.springs.kelvin_voigt_time). Low end: the material hysteresis of
#: quenched and tempered spring steel alone, a loss factor of order 1e-4 to 1e-3 (Lazan, Damping of
#: Materials and Members in Structural Mechanics, 1968), i.e. zeta = eta / 2 ~ 5e-5 to 5e-4; high
#: end: a few percent, the surge damping valvetrain models use, where coil contact and the end
#: coils' rubbing add to the material's. An assumption, not a measured range.
SPRING_DAMPING_RATIO_RANGE = (5e-5, 0.05)

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
#: The paper's closing spring under the settled reading (studies/spring_reading.py,
#: results/spring_reading.md; issue 19): m0 = 0.3364 kg is eq. 8's chain parameter, so the spring's
#: active mass is pi^2/4 m0 = 0.830 kg (the text's "about 1 kg"; its fixed-fixed fundamental is the
#: paper's f0), and "6000 N -> 1000 N" is the pair's pull: 3000 N -> 500 N on each spring.
PAPER_SPRING_MASS = 0.25 * 3.141592653589793**2 * 0.3364
#: Pull of each closing spring (N) charged (cam at 10 deg) and at the springs' dead centre (180 deg).
REFERENCE_SPRING_CHARGED = 3000.0
REFERENCE_SPRING_DISCHARGED = 500.0
#: The main shaft that carries the pole levers (rig section breaker.main_shaft; its twist modelled
#: by laws.breaker.segment_torque, estimated statically by laws.mechanics.main_shaft_twist):
#: - solid steel, 60 mm, G 79.3 GPa; pole centres 210 mm apart (12 kV panels space poles
#:   150-275 mm; 210 mm is the middle choice); driven at the first pole's side (drive_pole 1, the
#:   worst case: the segment next to the drive carries two poles' torque). Each segment:
#:   G pi d^4 / 32 / pitch = 480 kN m/rad;
#: - why 60 mm: SIZED WITH THE MODEL against the assumed limits (studies/design_tolerance.py: bounce
#:   <= 2 ms; 40 kA interrupters need 3-4 kN of contact force). The review's estimate, 40 mm
#:   (MAIN_SHAFT_FIRST_ESTIMATE_DIAMETER), fails both: its far levers ring at the shaft's torsional
#:   modes and pole 2 bounces for 5.1 ms; closed, the wipe springs twist the far levers back 2.4 mm at
#:   the pole and pole 3 keeps 2.94 kN. 50 mm still bounces 2.2 ms; 60 mm bounces at most 1.93 ms
#:   and keeps every pole above 3.29 kN (the closing study's pole-spread table);
#: - lever_inertia 0.010 kg m^2: a forged steel pole lever as long as the follower's output arm
#:   (L = 0.16 m), a 40 x 15 mm bar (0.754 kg; m L^2 / 3 = 0.0064 kg m^2 about the shaft; it carries
#:   the 3.5 kN closed rod force at 0.16 m at 160 MPa of bending stress), its hub 90 mm across on
#:   the 60 mm shaft, 40 mm wide (1.11 kg; m (R^2 + r^2) / 2 = 0.0016 kg m^2), and a pitch of the
#:   shaft (4.66 kg; m r^2 / 2 = 0.0021 kg m^2): 0.010 kg m^2 of follower.inertia's 0.08;
#: - damping 6.1 N m s/rad per segment: 2 % of the critical damping 2 sqrt(k J) of one segment with
#:   a lever and its pole's mass reflected through the rod (J = 0.010 + 1.5 kg x 0.16^2 m^2 =
#:   0.048 kg m^2: 2 x 0.02 x sqrt(480e3 x 0.048) = 6.1). A judgement: the steel's own damping is
#:   well below 1 %; keyed or clamped joints add to it; US NRC Regulatory Guide 1.61 (rev. 1, 2007)
#:   takes 2-4 % for welded and 4-7 % for bolted steel structures; we take the low end, 2 % (on the
#:   40 mm shaft even 10 % left 3.8 ms of bounce: the stiffness, not the damping, is the remedy).
#: Torsional modes (laws.breaker.torsional_frequencies, the drive lever held, the poles' mass
#: reflected): 310 and 811 Hz; a free lever against its stiff rod rings at about 1.9 kHz: 52 steps
#: per period at BREAKER_STEP (1e-5 s), as the cam-roller contact's 1.7 kHz gets 60.
MAIN_SHAFT_SECTION = {"pole_pitch": 0.21, "diameter": 0.06, "bore": 0.0, "shear_modulus": 79.3e9, "damping": 6.1,
                      "lever_inertia": 0.010, "drive_pole": 1}
#: The main shaft's diameter first estimated by the issue-19 review (m): kept for the closing
#: study's comparison (it fails the bounce and contact-force limits, above).
MAIN_SHAFT_FIRST_ESTIMATE_DIAMETER = 0.04
#: A 12 kV, 40 kA class three-pole vacuum breaker driven by the paper's springs read as above (the
#: paper gives the rating, the closing time of about 30 ms and the spring forces, not the breaker).
#: Every value below with its reason; published sources are cited by the short names at the end.
#:
#: Closing springs and the cam (the breaker's own, not REFERENCE_CAM's):
#: - springs: k0 = 24230 N/m (paper), 0.830 kg each (PAPER_SPRING_MASS), two of them. The lightest
#:   steel coil of this rate and mass at spring index 6 has 7.84 mm wire on a 47.0 mm mean diameter
#:   (14.9 active coils; laws/coil.py): at 3000 N its Wahl-corrected shear stress is 0.93 GPa, below
#:   the 1.04 GPa (0.65 S_ut, chromium-silicon wire, Shigley Table 10-6) of a compression spring with
#:   set removed. VCB closing springs are compression springs charged by the motor [Machines 2023],
#:   worked here through a pull rod, so the compression allowable applies (an extension spring's body,
#:   0.45 S_ut = 0.72 GPa, would not carry it). The pair stores 371 J and releases 361 J from 3000 N
#:   to 500 N (the springs' dead centre);
#: - anchor O at the origin, free length 0.30 m (as the cam drop's); crank (arm l_AB) 51.9 mm and cam
#:   axis A at 0.3726 m from O: solved so that each spring pulls 3000 N at the start angle, 10 deg
#:   (the paper's, just past the springs' dead centre, so the latch holds a small torque: 54 N m), and
#:   500 N at 180 deg, the paper's ratio over the closing stroke;
#: - cam shaft assembly 9.5 kg, 0.020 kg m^2 about its axis, centre of mass 2 mm off the axis: a
#:   bill of the parts that turn with the cam: a 40 mm steel cam shaft 0.45 m long (4.4 kg,
#:   0.0009 kg m^2), the cam disc (its pitch curve is 45-54 mm for a 20 mm roller: 0.6 kg,
#:   0.0003 kg m^2), two spring cranks (0.6 kg), and the charging ratchet wheel that turns with the
#:   shaft in the closing, 180 mm across and 20 mm thick (4.0 kg, 0.016 kg m^2); the cranks and the
#:   cam lobe put the centre of mass about 2 mm off the axis. We found no published cam-shaft inertia
#:   of a 12 kV mechanism. The inertia was then chosen with the cam profile for the closing speed
#:   (below): with these springs and cam law the product of closing speed and closing time is set
#:   by the shapes (spring pull against angle, profile, gap), not by the inertia or the energy, so
#:   the inertia picks a point on that line: 0.020 kg m^2 gives 1.28 m/s over the closing-speed zone
#:   (1.15 m/s at touch) and 39.1 ms; 0.012 kg m^2 would close in about 32 ms at 1.58 m/s.
#: The rest:
#: - contact gap 11 mm (12 kV interrupters open 8-12 mm, [Shonevac]), wipe about 4 mm (contact
#:   overtravel 2-4 mm, [Shonevac]); pole gaps spread by +-0.3 mm (assembly tolerance: shows pole
#:   scatter);
#: - moving mass 1.5 kg per pole (moving contact and stem, terminal, share of the push rod);
#: - wipe spring 2500 N preload, 250 kN/m (about 3500 N contact force closed: 40 kA interrupters
#:   need 3-4 kN against electrodynamic repulsion); push rod and stop 2e7 N/m, 500 N s/m;
#: - bellows: 150 N per pole (0.1 MPa on a 15 cm^2 mean bellows area);
#: - follower: pivot 0.1 m from the cam axis along the springs' line and 65 mm above, 0.1 m from the
#:   roller, output arm 0.16 m (F travels 1.6 x the roller), 0.08 kg m^2 with main shaft and pole
#:   levers; roller radius 20 mm, 20 mm wide, on a 45 mm base circle;
#: - cam profile: 9.4 mm roller lift (F travel 15 mm = gap + wipe) with a 4-5-6-7 polynomial rise
#:   over cam angles 12-240 deg, dwell to 330 deg, return 330-368 deg. The contacts touch at about
#:   149 deg, the rise ends at about 50 ms; unstopped, the cam would turn on to about 267 deg (the
#:   springs recharge past their dead centre at 180 deg), so the rise ends well before. Pressure
#:   angle at most about 5 deg while the roller rises (limit for roller followers about 30 deg);
#: - closing speed: 1.0-1.3 m/s (12 kV vacuum breakers close at about 0.6-1.5 m/s; contacts must
#:   move at 1.0-1.5 m/s [VCB blog]) over the analyser's zone (breaker.speed_zone, default the last
#:   4 mm before touch); the closing time is then about 39 ms from the latch release, against the
#:   paper's "about 30 ms": at these shapes a 30 ms closing needs about 1.6 m/s. Spring mechanisms
#:   close 40-80 ms after the command (coil and latch included), so 39 ms from the release is a
#:   breaker that exists; we keep the speed in its window and say the time is longer;
#: - opening spring 2000 N at open, 60 kN/m (37 J in the 15 mm stroke of F; with the wipe springs'
#:   35 J about 70 J drive the opening): keeps the roller on the cam through the rise's deceleration
#:   with about 2.2 kN to spare (the smallest roller force before the touch);
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
#:   shaft reaction), released linearly over 2 ms (a solenoid-tripped latch);
#: - closing end stop (breaker.end_stop): a buffer (a stop with a shock absorber, the "damper for
#:   closing" of [Siemens 3AP]) met by a stop lever on the cam shaft at 250 deg, 10 deg past the
#:   rise's end, so the roller sits on the dwell and the contacts keep their full stroke while the
#:   cam is stopped; lever arm 60 mm; 2e6 N/m and 6e3 N s/m: about 0.9 of the critical damping of the
#:   cam shaft's inertia seen at the lever (0.0215 kg m^2 / 0.06^2 m^2 = 6 kg). The cam meets it at
#:   52 ms at 4.8 m/s (at the lever), runs 2.7 deg (2.8 mm) into it and is pushed back with at most
#:   29 kN; the cam brings 65 J to it;
#: - holding latch (breaker.hold_latch): a pawl that drops behind the cam's latch face at 248 deg
#:   (2 deg before the stop) and keeps the recharging springs from turning the cam back, as the roller
#:   that "jumps behind the cam to prevent backward swinging of the charging shaft" [Siemens 3AP];
#:   60 mm arm, 5e7 N/m (a hardened steel pawl and its seat: 0.04 mm under the springs' 2.2 kN),
#:   5e3 N s/m. The cam comes to rest on it at about 66 ms (BREAKER_REST_T_END);
#: - spring model: lumped-2 in the `exact` convention (the continuum's frequencies and Rayleigh's
#:   mass at the pin; the spring study shows the paper's convention diverging with n).
#: Where the energy goes: of the 371 J the pair stores, 346 J are released by the first touch; the
#: cam shaft holds 282 J of it (82 %, the springs' pin mass included) (a closing damper or stop must take that, as in real
#: mechanisms: the cam "transfers its residual kinetic energy to the damper for closing"
#: [Siemens 3AP], or the crank's energy is returned to the closing spring [Alstom FK]).
#: Sources: [Machines 2023] Optimal design and dynamic analysis of a spring-actuated cam-linkage
#: mechanism in a vacuum circuit breaker (12 kV, 25 kA), Machines 11(2) 150, 2023,
#: doi:10.3390/machines11020150 (closing springs compressed by a motor drive the cam; they charge the
#: opening spring; contact (wipe) springs per pole). [Shonevac] vacuum interrupter maker's notes,
#: shonevac.com, "Vacuum interrupter for MV VCB": contact stroke 8-12 mm at 10-15 kV, overtravel
#: 2-3 mm. [VCB blog] "Why does a vacuum circuit breaker need energy storage" (a commissioning
#: engineer's notes): contact speeds of 1.0-1.5 m/s. [Siemens 3AP] Siemens 3AP2-FI operating manual,
#: sec. 3 (closing damper). [Alstom FK] Alstom FK 3-12 spring operating mechanism manual (the main
#: shaft's low-impact stop against the trip latch; crank energy returned to the closing spring).
REFERENCE_BREAKER_SECTION = {
    "cam_profile": {"base_radius": 0.045, "lift": 0.0094, "rise_start": 0.20944, "rise_end": 4.18879,
                    "return_start": 5.75959, "return_end": 6.42281},
    "roller_radius": 0.02,
    "follower": {"pivot": [0.27257, 0.065], "inertia": 0.08, "roller_arm": 0.10, "output_arm": 0.16,
                 "output_angle": 0.0, "rest_angle": 0.0},
    "poles": {"count": 3, "moving_mass": 1.5, "contact_gap": 0.011, "gap_offsets": [0.0, 0.0003, -0.0003],
              "push_rod_length": 0.25, "wipe_preload": 2500.0, "wipe_rate": 2.5e5, "rod_stiffness": 2e7,
              "rod_damping": 500.0, "bellows_force": 150.0},
    "opening_spring": {"stiffness": 6e4, "preload": 2000.0, "length": 0.2},
    "contact": {"cam_roller_law": "line", "roller_width": 0.02, "cam_roller_damping": "hunt_crossley",
                "cam_roller_damping_factor": 0.2, "cam_roller_stiffness": 1e11, "pole_stiffness": 1e10,
                "exponent": 1.5, "restitution": 0.8, "min_impact_speed": 0.05},
    "latch": {"release_time": 0.002, "arm": 0.051935, "angle": 0.0},
    "end_stop": {"angle": 4.36332, "arm": 0.06, "stiffness": 2e6, "damping": 6e3},
    "hold_latch": {"angle": 4.32842, "arm": 0.06, "stiffness": 5e7, "damping": 5e3},
    "main_shaft": MAIN_SHAFT_SECTION,
}
REFERENCE_BREAKER = dict(
    REFERENCE_CAM, name="reference 12 kV / 40 kA breaker closing (paper section 4)", experiment="vcb_closing",
    cam={"mass": 9.5, "inertia_com": 0.020, "com_distance": 0.002, "com_angle": 0.5,
         "pivot": [0.37257, 0.0], "arm_length": 0.051935,
         "initial_angle": 0.17453292519943295, "initial_velocity": 0.0},
    closing_spring={"count": 2, "stiffness": 24230.0, "mass": round(PAPER_SPRING_MASS, 4), "free_length": 0.30,
                    "anchor": [0.0, 0.0], "wire_diameter": 0.00784, "coil_diameter": 0.0470},
    breaker=REFERENCE_BREAKER_SECTION,
    model={"effects": ["coulomb_friction", "stribeck", "spring_mass", "contact_damping", "bellows_force"],
           "spring_model": "lumped-2", "lumped_convention": "exact"})
#: The reference breaker before issue 19, kept for the closing study's before/after table
#: (studies/vcb_closing.py): REFERENCE_CAM's cam and springs (2 x 6000 N springs of 0.3364 kg on a
#: 6 kg, 0.05 kg m^2 cam: a flywheel holding 1234 of the 1354 J released at the first touch), a
#: 12-285 deg rise, lumped-2 in the paper's convention, no end stop, holding latch or main shaft. Not a breaker
#: anyone could build.
FORMER_REFERENCE_BREAKER = dict(
    REFERENCE_CAM, name="reference breaker before issue 19 (springs read as 2 x 6000 N, 0.3364 kg)",
    experiment="vcb_closing",
    breaker=dict({k: v for k, v in REFERENCE_BREAKER_SECTION.items() if k not in ("end_stop", "hold_latch", "main_shaft")},
                 cam_profile=dict(REFERENCE_BREAKER_SECTION["cam_profile"], rise_end=4.97419, return_start=5.67232),
                 follower=dict(REFERENCE_BREAKER_SECTION["follower"], pivot=[0.3445, 0.065]),
                 latch=dict(REFERENCE_BREAKER_SECTION["latch"], arm=0.1032)),
    model=dict(REFERENCE_BREAKER["model"], lumped_convention="paper"))
#: MAIN_SHAFT_SECTION for the static twist table (studies/vcb_closing.py), with each pole lever's
#: arm: the follower's output arm.
MAIN_SHAFT = dict(MAIN_SHAFT_SECTION, lever_arm=REFERENCE_BREAKER_SECTION["follower"]["output_arm"])
#: Simulated closing (s): latch release to contacts settled and the rise's end (about 50 ms: the
#: full wipe, so the overtravel is the profile's).
BREAKER_T_END = 0.055
#: Largest lift or pitch radius of a cam given by points (m): a vacuum breaker's closing cam is a
#: few centimetres across (the reference cam: 45 mm base circle, 9.4 mm lift); a value above half a
#: metre is a table in millimetres read as metres, refused with that hint.
CAM_POINT_LARGEST = 0.5
#: How closely (m) a cam export's last point, one turn after its first (0 and 360 deg), must repeat
#: the first's value to be dropped as the same point: 1 um, a CMM's resolution.
CAM_POINT_CLOSURE = 1e-6
#: Largest scatter (m) of a cam's points about a smooth curve that a spline may be fitted through
#: without ``smoothing``: a CAD export rounded to 0.1 um scatters by 0.03 um; on the docs' example
#: cam (docs/examples/cam_lift.csv, 2 deg steps) a scatter of 1 um already raises the peak
#: cam-roller force by 17 % (3 um: 32 %, touch speed -6 %; 10 um: 2.5x, +24 %), measured.
CAM_POINT_SCATTER = 0.5e-6
#: How far the lift under the roller may fall back from its peak, as a fraction of the cam's lift,
#: before a closing's summary says the cam runs back (turns back down its rise, or on into its
#: return): a cam that rebounds off its end stop onto a holding latch a few degrees behind it loses
#: up to 3.0 % of the lift on a rise (tests/models/test_end_stop.py's rig: latch 5 deg behind a stop
#: at 210 deg on the rise, measured); the reference breaker without its stop, turned back by its
#: springs, loses 53 % by 100 ms and its contacts reopen.
CAM_FALL_BACK_FRACTION = 0.05
#: Shaft speed at the end of a run, as a fraction of the run's peak, above which a closing's summary
#: says the run ended with the cam still turning (not at rest: a longer ``--t-end`` shows the rest).
MOVING_AT_END_FRACTION = 0.01
#: Simulated closing (s) to the cam's rest on the holding latch (about 66 ms): the closing study's
#: energy split at rest.
BREAKER_REST_T_END = 0.075
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

# --- plausible ranges of fitted values (vcbmodel/analysis/plausibility.py) ----------------------
#: A fitted value outside its range, or one that breaks its law's constraint, is reported as
#: implausible (never a clean fit). Ranges are wide on purpose: they catch a law absorbing what it
#: does not describe (mu_k 24 times too low), not a rig that is merely unusual.
#: Kinetic friction coefficient of a steel shaft in its journal: from a greased bronze or steel
#: bushing's boundary friction (0.02-0.1; Rabinowicz, Friction and Wear of Materials, 2nd ed. 1995,
#: ch. 4) to dry steel on steel (0.42-0.57; Marks' Standard Handbook for Mechanical Engineers,
#: 11th ed., Table 3.2.1).
PLAUSIBLE_MU_K = (0.01, 0.6)
#: Static coefficient: up to dry steel on steel's static 0.74-0.8 (Marks', Table 3.2.1).
PLAUSIBLE_MU_S = (0.01, 0.8)
#: Stribeck velocity as the journal's sliding speed r w_s (m/s): 1e-5 to 0.1 m/s for lubricated
#: metal contacts (Armstrong-Helouvry, Dupont & Canudas de Wit, Automatica 30, 1994, sec. 2.1).
PLAUSIBLE_STRIBECK_SLIDING_SPEED = (1e-5, 0.1)
#: Petroff's viscous torque of a full film in a journal, T = 2 pi mu_oil r^3 L w / c, i.e.
#: C_v = 2 pi mu_oil r^3 L / c (N m s/rad) with the rig's journal radius r and:
#: the lubricant's (apparent) viscosity mu_oil (Pa s), from a light oil at 40 degC (ISO VG 10,
#: 0.009 Pa s) to an NLGI 2 grease's apparent viscosity at the film's shear rates r w / c ~
#: 1e2-1e3 1/s (shear-thinning greases: about 1-20 Pa s there, far above their base oil's 0.1);
PETROFF_VISCOSITY = (0.009, 20.0)
#: the bearing's length over its diameter L / 2r (plain journal bearings: 0.5-2; Shigley's
#: Mechanical Engineering Design, 10th ed., ch. 12);
PETROFF_LENGTH_RATIO = (0.5, 2.0)
#: the radial clearance over the radius c / r (0.0005-0.003; Shigley: c / r about 0.001).
PETROFF_CLEARANCE_RATIO = (5e-4, 3e-3)
#: The range's low end is 0 (a dry journal carries no film): its high end is Petroff's with the
#: most viscous grease, the longest bearing and the smallest clearance (8 N m s/rad at r = 20 mm).
#: Air drag on a pendulum, c_d = 0.5 rho Cd A R^3 (N m s^2/rad^2): air (AIR_DENSITY), a bluff
#: body's Cd of at most 2.0 (a cupped plate; a flat plate 1.17: Hoerner, Fluid-Dynamic Drag, 1965,
#: ch. 3), a paddle of at most 0.1 m^2 at a radius of at most twice the rig's centre-of-mass distance.
DRAG_MAX_CD = 2.0
DRAG_MAX_AREA = 0.1
DRAG_MAX_RADIUS_OVER_COM = 2.0
#: Drift of the friction levels in time (1/s): a bearing warming by a few kelvin during a test moves
#: a boundary film's friction by at most about half a typical mu_k (0.05) over a 10-20 s record.
PLAUSIBLE_MU_K_DRIFT = (-0.005, 0.005)
#: Coefficient of restitution of the breaker's steel contacts at 0.1-1 m/s: 0.3-1 (Goldsmith,
#: Impact, 1960: 0.5-0.95 for hardened steels; lower with the interrupter's copper contacts).
PLAUSIBLE_RESTITUTION = (0.3, 1.0)
#: Atmospheric force on a medium-voltage vacuum interrupter's bellows (N): 0-600 (100-400 N for
#: the usual 12-40 kV interrupters; the registry's description).
PLAUSIBLE_BELLOWS_FORCE = (0.0, 600.0)
#: A stated error this many times the plausible range's width (or a non-finite one) says the record
#: does not determine the value at all (a fit stopped on a flat direction: mu_s +- 2.9e12).
IMPLAUSIBLE_STDERR_OVER_RANGE = 1.0

# --- air drag and a drifting Coulomb level as truths (vcbmodel/analysis/realistic.py) -----------
#: A realism record's paddle: area A (m^2) and radius R (m) drawn in these ranges, a flat plate
#: (FLAT_PLATE_DRAG_COEFFICIENT) in air (AIR_DENSITY): c = 0.5 rho Cd A R^3 = 3.8e-4 to 5.3e-3 N m
#: s^2/rad^2 (a 0.02-0.06 m^2 paddle at 0.3-0.5 m: a paddle a pendulum might carry to be damped).
DRAG_TRUTH_AREA = (0.02, 0.06)
DRAG_TRUTH_RADIUS = (0.3, 0.5)
#: A realism record's drift of the Coulomb level (1/s, either sign): 0.01-0.04 over a 20 s record,
#: 7-40 % of mu_k 0.09-0.16 (a bearing warming through a test; within PLAUSIBLE_MU_K_DRIFT).
DRIFT_TRUTH_RATE = (5e-4, 2e-3)
