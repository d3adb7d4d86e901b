"""The whole breaker's closing (paper section 4, Fig. 11-12): latch release to contacts closed.

The rig's ``breaker`` section is read by :func:`vcbmodel.rig.sections.read_closing`; the fields
added with the review of the whole breaker (issue 10) are read here until the section reader
takes them over (:func:`read_closing_sections`):

- ``breaker.contact.cam_roller_law``: ``"hertz_point"`` (default: ``cam_roller_stiffness``
  K delta^``exponent``) or ``"line"`` (a cylindrical roller's line contact, Palmgren's
  K_L delta^(10/9) with K_L from ``roller_width``; :mod:`vcbmodel.laws.contact`);
- ``breaker.contact.roller_width`` (m): the roller's effective contact length; required by
  ``"line"``;
- ``breaker.contact.cam_roller_damping``: ``"lankarani_nikravesh"`` (default: impact-speed
  based, with ``restitution`` and ``min_impact_speed``) or ``"hunt_crossley"`` (fixed factor);
- ``breaker.contact.cam_roller_damping_factor`` (s/m): Hunt-Crossley alpha; required by
  ``"hunt_crossley"``; it acts when the ``contact_damping`` effect is on;
- ``breaker.latch.arm`` (m, default ``cam.arm_length``) and ``breaker.latch.angle`` (rad,
  default 0): the latch point on the cam, at ``arm`` from A and ``angle`` from A->B; the latch
  force acts there, perpendicular to A->point (default: at the spring pin B).
"""
from __future__ import annotations

from dataclasses import dataclass, fields

from .. import parameters as P
from ..builders.breaker import build_vcb_closing
from ..laws.breaker import CamRollerLaw, LatchPoint
from ..laws.contact import CAM_ROLLER_LAWS, DAMPING_LAWS
from ..rig.data import Breaker
from ..rig.sections import read_closing
from .base import Experiment
from .cam_drop import spring_signature
from .closing_evaluation import closing_channels, figures_of_merit

#: Fields of ``breaker.contact`` and ``breaker.latch`` read here (module docstring).
CONTACT_FIELDS = ("cam_roller_law", "roller_width", "cam_roller_damping", "cam_roller_damping_factor")
LATCH_FIELDS = ("arm", "angle")


@dataclass(frozen=True)
class ClosingBreaker(Breaker):
    """The rig's breaker with the cam-roller contact's law and the latch point."""

    cam_roller: CamRollerLaw = CamRollerLaw()
    latch_point: LatchPoint = LatchPoint()


def _split(data, section, names):
    """(copy of ``data`` without ``breaker.<section>.<names>``, the removed fields)."""
    breaker = data.get("breaker")
    if not isinstance(breaker, dict) or not isinstance(breaker.get(section), dict):
        return data, {}
    part = dict(breaker[section])
    taken = {k: part.pop(k) for k in names if k in part}
    return {**data, "breaker": {**breaker, section: part}}, taken


def _choice(rd, obj, key, prefix, options, default):
    v = obj.get(key, default)
    if v not in options:
        rd.fail(prefix + key, f"must be one of {', '.join(options)}")
    return v


def read_closing_sections(rd, data):
    """``cam``, ``closing_spring`` and ``breaker`` of a ``vcb_closing`` rig, with the contact
    and latch fields of the module docstring."""
    data, contact = _split(data, "contact", CONTACT_FIELDS)
    data, latch = _split(data, "latch", LATCH_FIELDS)
    sections = read_closing(rd, data)
    p = "breaker.contact."
    law = _choice(rd, contact, "cam_roller_law", p, CAM_ROLLER_LAWS, "hertz_point")
    damping = _choice(rd, contact, "cam_roller_damping", p, DAMPING_LAWS, "lankarani_nikravesh")
    width = rd.number(contact, "roller_width", p, positive=True) if "roller_width" in contact or law == "line" else None
    factor = (rd.number(contact, "cam_roller_damping_factor", p, nonnegative=True)
              if "cam_roller_damping_factor" in contact or damping == "hunt_crossley" else 0.0)
    p = "breaker.latch."
    arm = rd.number(latch, "arm", p, positive=True) if "arm" in latch else None
    angle = rd.number(latch, "angle", p, default=0.0)
    b = sections["breaker"]
    sections["breaker"] = ClosingBreaker(**{f.name: getattr(b, f.name) for f in fields(Breaker)},
                                         cam_roller=CamRollerLaw(law, width, damping, factor),
                                         latch_point=LatchPoint(arm, angle))
    return sections


def build(rig, spec, law, chain, user_function, ancf_elements):
    return build_vcb_closing(rig, spec, law, chain, user_function, ancf_elements)


def default_step(rig):
    return P.BREAKER_STEP


VCB_CLOSING = Experiment(
    name="vcb_closing", description="whole-breaker closing: cam, roller follower, push rods, poles (paper section 4)",
    measured_channel="follower_displacement", unit="m", sections=("cam", "closing_spring", "breaker"),
    read_sections=read_closing_sections,
    # the cam drop's camera (12 kHz) filming the follower: about 0.1 mm resolved over a 100 mm field
    sample_rate=12000.0, noise_sigma=5e-5, default_duration=P.BREAKER_T_END, max_duration=1.0,
    build=build, channels=closing_channels, step=default_step, figures_of_merit=figures_of_merit,
    has_closing_spring=True, signature=spring_signature,
    # a breaker analyser's timing and travel channels (vcbmodel.records.analyser), fitted when present
    extra_channels=(r"pole_\d+_contact", r"pole_\d+_travel"))
