"""The whole breaker's closing (paper section 4, Fig. 11-12): latch release to contacts closed.

The rig's ``cam``, ``closing_spring`` and ``breaker`` sections are read by
:func:`vcbmodel.rig.sections.read_closing` (the contact law and latch point included).
"""
from __future__ import annotations


from typing import TYPE_CHECKING

import numpy as np

from .. import parameters as P
from ..errors import InputError
from ..builders.breaker import build_vcb_closing
from ..compiled import OdeModel
from ..reference.solve import reference_closing
from ..compiled.equations import closing_equations, closing_prestep, prepare_closing
from ..rig.sections import read_closing
from .base import Experiment
from .summaries import closing_record_channels, closing_report
from .cam_drop import spring_signature
from .closing_evaluation import closing_channels, figures_of_merit

if TYPE_CHECKING:
    from ..builders.ancf import AncfOptions
    from ..builders.core import ExudynModel
    from ..laws.friction import FrictionLaw
    from ..laws.springs import LumpedChain
    from ..model.effects import ModelSpec
    from ..rig.data import Rig


def build(rig: Rig, spec: ModelSpec, law: FrictionLaw, chain: LumpedChain | None, user_function: str,
          ancf_elements: AncfOptions | int | None) -> ExudynModel:
    return build_vcb_closing(rig, spec, law, chain, user_function, ancf_elements)


def reference(rig: Rig, spec: ModelSpec, law: FrictionLaw, chain: LumpedChain | None, t_end: float,
              method: str = "DOP853", step: float | None = None) -> tuple[dict[str, np.ndarray], dict]:
    """The reference solve of a closing (:func:`vcbmodel.reference.solve.reference_closing`) where it
    covers the rig: an InputError naming what it does not cover (an elastic main shaft; an operating
    cycle's parts: a making current, a trip latch, an opening dashpot, a run that trips, whose own
    independent solve is :mod:`vcbmodel.reference.breaker_opening`; the contact damping and the holding
    latch need ``method='rk4'``), never a solve of another model. Its fixed step defaults to the
    experiment's."""
    b = rig.breaker
    uncovered = [f"breaker.{k} (the reference closing solve knows the closing only: use backend='exudyn' or 'compiled'; "
                 "the opening's independent check: vcbmodel.reference.breaker_opening)"
                 for k in ("making_current", "trip_latch", "opening_dashpot", "commands") if getattr(b, k) is not None]
    if b.main_shaft is not None:
        uncovered.append("breaker.main_shaft (the reference solve has a rigid main shaft only: leave the section out "
                         "for a rigid shaft, or use backend='exudyn' or 'compiled')")
    if method != "rk4" and spec.restitution < 1.0:
        uncovered.append("breaker.contact.restitution (the contacts' damping needs method='rk4')")
    if method != "rk4" and b.hold_latch is not None:
        uncovered.append("breaker.hold_latch (its engagement needs method='rk4')")
    if uncovered:
        raise InputError(rig.path, uncovered[0].split(" ")[0], "backend='reference' does not cover "
                         + "; nor ".join(uncovered))
    return reference_closing(rig, spec, law, chain, t_end, method, step if step is not None else default_step(rig))


def default_step(rig: Rig) -> float:
    return P.BREAKER_STEP


#: Integration step of a closing's fits (s): at 2e-5 s (1.7e-5 s on the 12 kHz camera's grid) the
#: follower stays within 6 um (max) of a 2.5e-6 s solve (the studies' 1e-5 s: 2.5 um), an eighth of
#: the camera's noise, at 0.75 of the cost (reference breaker, measured).
CLOSING_FIT_STEP = 2e-5
#: Integration step of the grid scans that rank a closing fit's starting points (s). The breaker's
#: 1e-5 s is sized for studies; at 4e-5 s (2.8e-5 s on the 12 kHz camera's grid) the follower stays
#: within 12 um (max) of a 2.5e-6 s solve, a quarter of the camera's noise, at a third of the cost
#: (reference breaker, measured). A scan only ranks starting points: the fit runs at the full step.
CLOSING_SCAN_STEP = 4e-5


def fit_step(rig: Rig, spring_kind: str) -> float | None:
    """Step (s) of a closing's fits: CLOSING_FIT_STEP for lumped and massless springs, the
    experiment's own for the ANCF continuum (None)."""
    return None if spring_kind == "ancf" else CLOSING_FIT_STEP


VCB_CLOSING = Experiment(
    name="vcb_closing", description="whole-breaker closing: cam, roller follower, push rods, poles (paper section 4)",
    measured_channel="follower_displacement", unit="m", sections=("cam", "closing_spring", "breaker"),
    read_sections=read_closing, provides=("journal", "closing_spring", "breaker"),
    # model-form uncertainty: a drive's dissipation at speed is shared between the shaft's viscous
    # friction and the closing springs' internal damping; a record at the noise may hold either
    form_alternatives=("viscous_friction", "spring_damping"),
    # the cam drop's camera (12 kHz) filming the follower: about 0.1 mm resolved over a 100 mm field
    sample_rate=12000.0, noise_sigma=5e-5, default_duration=P.BREAKER_T_END, max_duration=1.0,
    # the follower moves a few centimetres at most: a value above 0.5 is millimetres
    min_duration=2e-3, max_magnitude=0.5, unit_hint=": is it in millimetres? follower_displacement must be in m",
    # a vacuum interrupter's contact gap is 6-20 mm and the drive travels as far or more: a closing
    # whose follower spans less than 1 mm is metres under a stated unit of mm (or no closing at all)
    min_span=1e-3, small_hint=": metres under a stated unit of mm? State the unit the values are in",
    channel_hint=("the drive's travel (an analyser's travel transducer on the operating rod or main shaft): "
                  "name that column 'follower_displacement', not a pole's travel (a pole stops at its touch "
                  "while the drive goes on through the wipe: a record of the poles alone cannot be fitted); "
                  "each pole's pole_N_travel and pole_N_contact are read beside it"),
    build=build, channels=closing_channels, step=default_step, figures_of_merit=figures_of_merit,
    signature=spring_signature,
    # a breaker analyser's timing and travel channels (vcbmodel.records.analyser), fitted when present
    extra_channels=(r"pole_\d+_contact", r"pole_\d+_travel"),
    figure_units=(("closing_time_s", "s"), ("closing_speed_m_s", "m/s"), ("zone_speed_min_m_s", "m/s"),
                  ("zone_speed_max_m_s", "m/s"), ("pole_spread_s", "s"), ("bounce_count", "-"),
                  ("bounce_duration_s", "s"), ("wipe_m", "m"), ("overtravel_m", "m"), ("rebound_m", "m"),
                  ("travel_settled_s", "s"), ("peak_cam_roller_force_N", "N"), ("kinetic_at_touch_J", "J"),
                  ("kinetic_margin_J", "J")),
    missing_means=(("closing_time_s", "not_closed"),), summary=closing_report,
    record_channels=closing_record_channels, fit_step=fit_step, scan_step=CLOSING_SCAN_STEP,
    # "auto": the cam's friction law compiled with the ANCF spring, the Python function otherwise (builders.breaker)
    fit_user_function="auto", release_from_model=True,
    ode_model=OdeModel("vcb_closing", prepare_closing, closing_equations, closing_prestep), reference=reference,
    sensor="camera")
