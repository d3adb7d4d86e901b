"""What a sensor or logger does to a record that no fit may take as motion: an angle encoder that
wraps at a full turn (read as meant: unwrapped), and a channel that holds one value exactly while the
samples around it move (a sensor clipped at the end of its range, a dropout the logger fills with the
last value or with zeros: refused, naming the column and when), and a travel a transducer counts the
other way. Units follow the channel (rad, m)."""
from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from .signals import noise_estimate, quantisation_step

#: A step between two samples that is a full turn (2 pi rad) give or take this share of a turn is a wrap of
#: the encoder's count, when the steps beside it (less any turn they wrap) are as small: no shaft of these
#: tests turns by a twentieth of a turn between two samples, let alone a whole one.
WRAP_TOLERANCE = 0.05


def unwrap_turns(y: np.ndarray) -> tuple[np.ndarray, int]:
    """(``y`` with every full-turn wrap undone, how many wraps): an angle (rad) from an encoder that counts
    0..2 pi or -pi..pi jumps by about 2 pi where the shaft passes the count's end; each such jump, between
    small steps, is taken back by adding the turn to every later sample. The first sample is kept as read.
    A record whose values span more than a turn is no encoder's count and is left as it is."""
    y = np.asarray(y, float)
    turn = 2 * math.pi
    if y.size < 2 or not np.all(np.isfinite(y)) or float(np.ptp(y)) > (1 + WRAP_TOLERANCE) * turn:
        return y, 0  # an encoder's count stays within one turn
    d = np.diff(y)
    rest = d - turn * np.round(d / turn)  # each step less the whole turn it may have wrapped
    wraps = (np.abs(np.round(d / turn)) == 1) & (np.abs(rest) < WRAP_TOLERANCE * turn)
    if not wraps.any():
        return y, 0
    small = np.abs(rest) < WRAP_TOLERANCE * turn
    wraps &= np.concatenate([[True], small[:-1]]) & np.concatenate([small[1:], [True]])
    if not wraps.any():
        return y, 0
    shift = np.concatenate([[0.0], np.cumsum(np.where(wraps, d - rest, 0.0))])
    return y - shift, int(wraps.sum())


#: A run of identical samples at least this long is looked at (a few equal samples happen on any quantised
#: sensor, and are too few to fit a wrong diagnosis on).
MIN_RUN = 5
#: A run is held (not measured) when the samples on both sides, continued across it by a parabola, leave
#: its value by more than this many noise levels and this many quantisation steps: a smooth motion rounded
#: to a sensor's steps stays within a step or so of it.
HELD_NOISE = 8.0
HELD_STEPS = 4.0
#: ... and by more than this share of the channel's span: a departure smaller than that moves no fit
#: (a 20 ms hold of a 1 kHz pendulum swing), and a quiet record whose rounding is not recognised as a
#: grid (its noise estimate near 0) would otherwise count any departure.
HELD_SPAN = 0.01
#: The longest runs looked at (a quantised record that moves slowly has thousands of short runs).
MOST_RUNS = 2000


def runs_of_equal(y: np.ndarray, least: int = MIN_RUN) -> list[tuple[int, int]]:
    """(first, last) sample index of each run of at least ``least`` identical consecutive values."""
    equal = np.concatenate([[0], (np.diff(y) == 0).astype(int), [0]])  # equal[j + 1]: y[j] == y[j + 1]
    edges = np.diff(equal)
    starts, ends = np.nonzero(edges == 1)[0], np.nonzero(edges == -1)[0]  # samples starts..ends are equal
    return [(int(s), int(e)) for s, e in zip(starts, ends) if e - s + 1 >= least]


#: Runs at either end of the record shorter than this are not looked at: a few equal samples where a
#: quantised record starts or ends are its rest, and too short to fit a wrong diagnosis on.
EDGE_RUN = 10


def held_excess(y: np.ndarray, first: int, last: int) -> float:
    """How far (same unit as ``y``) the motion around the run ``y[first..last]``, carried across it by a
    parabola through the samples beside it, leaves the run's value, less :data:`FIT_MARGIN` times the
    parabola's own misfit there (a motion the parabola does not follow, such as a rest before a quick
    rise, says nothing). With samples on both sides: the parabola through both. At either end of the
    record (the rest before a release, a shaft stopped at the end) only a run of at least
    :data:`EDGE_RUN` samples at the record's largest or smallest value counts, and only a departure
    beyond that value: a motion that arrives at (or leaves) the run heading past it, as at a sensor's
    range end, and no further than the motion beside the run goes; a motion that comes to rest (or
    starts from it) turns back inside and gives 0."""
    n = last - first + 1
    k = max(5, n // 2)
    if first >= k and last + k < y.size:
        return _departure(y, np.concatenate([np.arange(first - k, first), np.arange(last + 1, last + 1 + k)]),
                          np.arange(first, last + 1), 0)
    outward = 1 if y[first] == y.max() else -1 if y[first] == y.min() else 0
    k = min(max(10, n // 2), 50)
    left, right = first >= k, last + k < y.size
    if outward == 0 or n < EDGE_RUN or not (left or right):
        return 0.0
    if right:  # at the start: the motion leaving the run, carried back into it
        beside, inside = np.arange(last + 1, last + 1 + k), np.arange(last - min(n, k) + 1, last + 1)
    else:
        beside, inside = np.arange(first - k, first), np.arange(first, first + min(n, k))
    # no further than the motion beside it goes: a parabola through a quantised flicker overshoots
    return min(_departure(y, beside, inside, outward), float(np.ptp(y[beside])))


#: A departure counts only beyond this many times the parabola's rms misfit on the samples it was fitted to.
FIT_MARGIN = 6.0


def _departure(y: np.ndarray, fitted: np.ndarray, inside: np.ndarray, outward: int) -> float:
    """The largest departure from ``y[inside[0]]`` of a parabola fitted to ``y[fitted]`` at the samples
    ``inside`` (either way for ``outward`` 0, else only beyond it in the direction ``outward``, +1 up),
    less :data:`FIT_MARGIN` times the parabola's rms misfit on ``fitted``; at least 0."""
    lo, hi = min(fitted[0], inside[0]), max(fitted[-1], inside[-1])
    centre, scale = 0.5 * (lo + hi), float(hi - lo + 1)
    x = (fitted - centre) / scale
    coef = np.polyfit(x, y[fitted], 2)
    misfit = float(np.sqrt(np.mean((np.polyval(coef, x) - y[fitted]) ** 2)))
    gap = np.polyval(coef, (inside - centre) / scale) - y[inside[0]]
    far = float(np.max(np.abs(gap)) if outward == 0 else np.max(outward * gap))
    return max(0.0, far - FIT_MARGIN * misfit)


def check_held_values(t: np.ndarray, y: np.ndarray, path: str, column: str) -> None:
    """Refuse a channel that holds one value exactly over a run of samples where the samples around it say
    it moved (:func:`held_excess` beyond :data:`HELD_NOISE` noise levels, :data:`HELD_STEPS`
    quantisation steps and :data:`HELD_SPAN` of the channel's span): clipped at the sensor's range when
    the value is the record's largest or smallest, else a dropout filled by the logger. Fitted as motion,
    it would be a wrong diagnosis."""
    y = np.asarray(y, float)
    runs = sorted(runs_of_equal(y), key=lambda r: r[0] - r[1])[:MOST_RUNS]
    if not runs:
        return
    sigma = noise_estimate(y)
    level = max(HELD_NOISE * (sigma if math.isfinite(sigma) else 0.0), HELD_STEPS * quantisation_step(y),
                HELD_SPAN * float(np.ptp(y)))
    held = sorted(r for r in runs if held_excess(y, *r) > level)
    if not held:
        return
    first, last = held[0]
    value = y[first]
    at = f"t = {t[first]:.6g} to {t[last]:.6g} s"
    more = f" (and {len(held) - 1} more such run{'s' if len(held) > 2 else ''})" if len(held) > 1 else ""
    if value == 0:
        why = "a dropout the logger filled with zeros (or a sensor clipped at zero)? Cut the record before it"
    elif value in (y.max(), y.min()):
        why = (f"the record's {'largest' if value == y.max() else 'smallest'} value: a sensor or digitiser "
               "clipped at the end of its range? Re-record with a wider range")
    else:
        why = "a dropout the logger filled with its last value? Cut the record before it"
    raise InputError(path, f"column {column!r}", f"holds {value:.6g} exactly over {last - first + 1} samples, "
                     f"{at}{more}, where the samples around it move on: {why} (a held value fitted as motion "
                     "would give a wrong diagnosis)")


def runs_backwards(y: np.ndarray) -> bool:
    """Whether a travel that runs forward from rest (m: a follower's or a pole's towards closing) goes
    mostly backwards instead: more than half its span below zero, as a transducer counting the other way
    gives it (a sensor's zero offset moves it by a small share of the span only)."""
    y = np.asarray(y, float)
    return y.size > 0 and float(-np.min(y)) > 0.5 * float(np.ptp(y)) > 0.0
