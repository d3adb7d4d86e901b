"""The whole breaker's closing (paper section 4, Fig. 11-12): laws and geometry.

Planar model with separate pole bodies (see README "The whole breaker"): the cam of the
cam-drop test (eq. 9-13, closing springs and shaft friction unchanged) drives an oscillating
roller follower pivoted on the frame at ``follower.pivot``; the follower's output point F
pushes ``poles.count`` insulating push rods, each through its wipe (contact-pressure) spring,
into a moving contact that slides on a straight vertical guide (the translational joint) and
closes on its fixed contact after ``contact_gap``. An opening spring pulls F down (it is
charged by the closing). The closing latch holds the cam at rest until it is released.

Everything here is a pure function of numbers (units in each docstring), testable without
Exudyn, in rooms of one job each: :mod:`.forces` (every force at a state), :mod:`.rest` (the rest
before the release), :mod:`.poles`, :mod:`.main_shaft`, :mod:`.latch`, :mod:`.stops`; this face
hands their names on. The breaker's data (:class:`vcbmodel.rig.data.Breaker` and its parts) come
in as arguments.

The cam profile, the follower's kinematics and the cam-roller contact's geometry and law are in
:mod:`vcbmodel.laws.cam_follower`, a contact's force, energy and impact speed in
:mod:`vcbmodel.laws.contact` (both re-exported here).
"""
from ..cam_follower import (  # noqa: F401 -- re-exported: the breaker's laws are read from here too
    TWO_PI, polynomial_rise, pitch_radius, follower_point, roller_centre, output_point, angle_on_circle, Geometry,
    rest_geometry, CamRollerContact, CamRollerLaw, cam_roller_contact, cam_roller_loads, kinematic_follower_angle,
    pressure_angle_curve, follower_displacement)
from ..contact import contact_energy, contact_force, update_impact_speeds  # noqa: F401
from .forces import BreakerLaws, massless_pull, pin_weight_torque  # noqa: F401
from .latch import LatchPoint, latch_force, latch_torque  # noqa: F401
from .main_shaft import MainShaft, segment_stiffness, segment_torque, torsional_frequencies  # noqa: F401
from .poles import pole_gaps, push_rod_energy, push_rod_force  # noqa: F401
from .rest import InitialState  # noqa: F401
from .stops import (EndStop, HoldLatch, end_stop_damping, end_stop_force, hold_latch_engagement,  # noqa: F401
                    hold_latch_force, one_way_stop_energy)
