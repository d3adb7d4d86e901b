"""The record's time base as a nuisance: a clock a fraction of a percent off (a camera's frame
rate, a data logger's clock) stretches the whole record in time. It is estimated like the sensor's
offset and gain, as the alignment parameter ``time_scale_0`` (seconds that passed per second of
the record's stamps, :func:`vcbmodel.analysis.fit.dataset.time_scale_name`), within
+-:data:`~vcbmodel.analysis.fit.dataset.TIME_SCALE_SPAN`.

How a clock error is told from an error of the rig (its inertia): a clock error scales the time of
everything the record holds by the same factor (every channel, the sensor's own lines); an error
of the shaft's inertia scales only the dynamics it governs (a pendulum's period by the square
root, a cam drop's duration likewise while the drive is the spring on the rigid shaft), not a
spring's own surge, not a mains line. So:

- a mains line (:mod:`.artefacts.lines`) reads the clock directly (f / f_grid - 1, within the
  grid's 0.1 %): then the clock is known and an inertia error is what is left;
- otherwise, where the rig's inertia is fitted too (a free swing with a period mismatch, or an
  ``uncertain`` inertia), the two change the record alike: reported as not separable;
- where the inertia is held at the rig's value, a fitted clock error may still be an inertia error
  of twice the size (period ~ sqrt(inertia)): the report says so.
"""
from __future__ import annotations

from ..fit.dataset import TIME_SCALE_SPAN, time_scale_name
from ..fit.parameters import Parameter

#: The smallest clock error the time-base nuisance is kept for is the options' ``min_clock_error``
#: (:class:`.options.DiagnosisOptions`): a crystal clock is good to about 1e-4, so a fitted scale
#: closer to 1 is the refit finding better values of the physics, not a clock (the air-drag demo's
#: refit gave 3e-5 and would have passed it for one).
#: A mains grid holds its frequency to about this fraction (continental grids: +-0.2 Hz at worst,
#: usually within 0.05 Hz of 50 Hz): the uncertainty of a clock read off a mains line.
GRID_TOLERANCE = 0.001


def time_scale_parameter(prior_sd: float | None = None, value: float = 1.0, fixed: bool = False) -> Parameter:
    """The time-scale nuisance of dataset 0: bounded to 1 +- TIME_SCALE_SPAN, with a Gaussian
    prior around ``value`` when ``prior_sd`` (relative) is given."""
    name = time_scale_name(0)
    lo, hi = 1.0 - TIME_SCALE_SPAN, 1.0 + TIME_SCALE_SPAN
    value = min(max(value, lo), hi)
    return Parameter(name, value, lo, hi, vary=not fixed, unit="-", kind="time_scale", dataset=0,
                     prior=(value, prior_sd) if prior_sd else None)


def clock_from_lines(lines: list | None) -> tuple[float, float] | None:
    """(time scale, its relative sd) read off the strongest mains line among ``lines``
    (:class:`.artefacts.lines.Line`), or None."""
    mains = [line for line in lines or () if line.clock_offset is not None]
    if not mains:
        return None
    best = max(mains, key=lambda line: line.power_ratio)
    return 1.0 + best.clock_offset, GRID_TOLERANCE


def time_base_report(value: float, stderr: float | None, source: str, inertia_fitted: bool) -> dict:
    """The time base for the report's ``nuisance``: the time scale, the clock's error in percent
    (positive: more time passed than the record's stamps say) and whether it is told apart from
    an error of the rig's inertia, with why."""
    if source == "mains line":
        how = ("read off the mains line's frequency: a clock error shifts the grid's line, an inertia error "
               "does not; separable")
        separable = True
    elif inertia_fitted:
        how = ("the rig's inertia is fitted too, and a clock error and an inertia error change the swing alike: "
               "not separable from this record (a mains line, a second channel on another clock or a "
               "pre-trigger of known length would separate them)")
        separable = False
    else:
        how = (f"fitted with the rig's inertia held at its value: a clock {100 * (value - 1):+.2f} % off, or the "
               f"rig's inertia about {200 * (value - 1):+.1f} % off where the shaft's inertia sets the record's pace "
               "(not separable without a line of known frequency)")
        separable = False
    return {"time_scale": value, "stderr": stderr, "clock_error_percent": 100 * (value - 1.0), "source": source,
            "separable_from_inertia": separable, "how_told_apart": how}
