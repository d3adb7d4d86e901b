"""Shaft friction identification from pendulum tests (paper section 2.2, Fig. 5).

Two laws, as in the paper:

- ``hybrid`` (case 1): Karnopp stick band + Stribeck + Coulomb + viscous; fitted
  mu_s, mu_k, stick velocity w0, Stribeck velocity ws, viscous Cv (reported also as zeta).
- ``stick-slip`` (case 2): Karnopp's stick-slip model only: static mu_s inside the stick
  band, kinetic mu_k outside it, no Stribeck slope and no viscous term. In the spec's law
  this is ``stribeck`` with ws = w0 (the Stribeck branch w0 < |w| < ws is empty).

The fit is staged: trust-region least squares from several starts derived from the
measured swing (the pendulum record's ``start_guesses``), then the paper's simplex
(Nelder-Mead) from the best point. The stated standard errors cover model-form error: a sandwich
covariance from the residual's own correlation (:mod:`.fit.covariance`), the white-noise ones kept
as ``stderr_naive``; when the residual stands above the record's own noise the result warns that
the law does not describe the record and that its errors are those of a wrong law, inflated by the
misfit.
The error measure is the paper's: max |error| as a percentage of the first peak amplitude
after release.
"""
from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from ..experiments import experiment_of
from ..experiments.pendulum import decay_split_guesses
from ..laws.friction import effective_static, zeta_from_viscous
from ..records.signals import first_peak_amplitude
from ..rig.spring_model import SpringModel
from .fit import Dataset, FitResult, SimulationPool, fit, make_parameters, staged_fit
from .release import release_parameter, release_setup, released_pairs, was_cut
from .thinning import usual_rate
from .diagnosis.judge import rival_form
from .diagnosis.options import DEFAULT_OPTIONS
from .held_out import HeldOut, held_out_validation
from .model_forms import MU_S_STARTS, ModelForms, fit_forms

if TYPE_CHECKING:
    from ..records.measurement import Measurement
    from ..rig.data import Rig

#: Simulations allowed to the optional simplex polish after the least-squares stage (it
#: refines the least-squares optimum the way the paper's simplex would).
SIMPLEX_BUDGET = 40
#: Integration step (s) of the first stage (the swinging part): twice the pendulum's default.
#: Against the event-driven reference a 6 s swing is within 0.14 mrad at 1e-3 s (noise 0.5
#: mrad): close enough to find the basin; the whole-record polish runs at the default step.
COARSE_STEP = 1e-3

MASSLESS = SpringModel()
log = logging.getLogger(__name__)

LAWS = {
    # the stick band w0 is not fitted: with passive sticking it barely changes the swing (a
    # stopped shaft stays stopped whatever the band), so it stays at the rig's value or the
    # documented default
    "hybrid": {"effects": ("coulomb_friction", "stribeck", "viscous_friction"),
               "vary": {"mu_k", "mu_s", "stribeck_velocity", "viscous"}},
    "stick-slip": {"effects": ("coulomb_friction", "stribeck"),
                   "vary": {"mu_k", "mu_s", "stick_velocity"}},
}


#: The residual may stand this far above the record's own noise before identify warns that the law
#: does not describe the record (a white residual of n samples at the noise is within a few percent).
WARN_RATIO = 1.5
#: Shares of the swing's decay put in Coulomb friction by the further starts spread along the
#: Coulomb-viscous valley (``experiments.pendulum.decay_split_guesses``): a fit from the record's
#: own regression stopped with viscous 0 at 7-9 times the noise on Tustin and LuGre records whose
#: better optimum (viscous about 0.55 N m s/rad) lies at 1-2.7 times it; three shares span the
#: valley between "mostly Coulomb" and "mostly viscous" without the all-viscous end's far start.
DECAY_SPLITS = (0.8, 0.6, 0.4)


def starts_at_release(meas: Measurement) -> None:
    """Refuse a record whose time does not start at the release (t = 0, within a sample interval):
    identify starts the model there, at the rig's initial angle, so a logger's clock offset (a record
    from t = 1.5 s) or a pre-trigger (from t < 0) would be fitted as a different swing (the fit ran,
    with a residual 100 times the noise)."""
    t0, step = float(meas.t[0]), float(np.median(np.diff(meas.t)))
    if abs(t0) > step:
        raise InputError(meas.path, "column 't'", f"starts at {t0:g} s: identify starts the model at the release, "
                         "t = 0 (the rig's initial angle); shift the time column so the release is at 0, or use "
                         "vcbmodel diagnose, which finds the release in the record")


@dataclass
class IdentifyResult:
    law: str
    fit: FitResult
    datasets: list
    first_peaks: list  # rad, per dataset
    forms: ModelForms | None = None  # the forms the records cannot tell apart (:mod:`.model_forms`)
    held_out: HeldOut | None = None  # fit on some records, predict the rest (:mod:`.held_out`)

    @property
    def values(self) -> dict[str, float]:
        v = dict(self.fit.values)
        v.setdefault("viscous", 0.0)
        v["mu_s"] = effective_static(v["mu_s"], v["mu_k"])  # what the law uses
        return v

    def max_error_percent(self) -> float:
        """max |error| / first peak amplitude after release, in %, worst dataset."""
        return float(max(100 * np.max(np.abs(r)) / a for r, a in zip(self.fit.residuals, self.first_peaks)))

    @property
    def residual_to_noise(self) -> float:
        """rms residual over the records' own high-frequency noise (not shaped by the fit)."""
        return float(self.fit.rms / self.fit.sigma) if self.fit.sigma > 0 else float("inf")

    @property
    def rival_form(self) -> dict | None:
        """A plausible model form the records prefer to the law by more than the diagnosis's
        ``rival_form_margin`` (BIC) that moves a fitted value beyond ``rival_form_errors`` of its stated
        errors (the diagnosis's rule, :func:`.diagnosis.judge.rival_form`), or None: the law's values then
        belong to a model the records reject, however white the residual."""
        if self.forms is None:
            return None
        return rival_form(self.datasets[0].rig, self.fit, self.forms, DEFAULT_OPTIONS)

    @property
    def warning(self) -> str | None:
        """Why the fitted values should not be trusted as they stand, or None."""
        r = self.residual_to_noise
        implausible = "; ".join(f.message for f in self.forms.findings) if self.forms is not None else ""
        parts = [f"implausible values: {implausible}"] if implausible else []
        rival = self.rival_form
        if rival:
            parts.append(rival["message"].replace("the final model", f"the {self.law} law")
                         + "; read the model forms' intervals")
        if self.held_out is not None and not self.held_out.consistent:
            c = self.held_out.consistency
            parts.append(f"the records disagree on the values (likelihood ratio {c['statistic']:.1f} for {c['dof']} "
                         f"degrees of freedom, p = {c['p_value']:.2g}): the {self.law} law lacks an effect that "
                         "differs between them, and the joint values are a compromise")
        if r > WARN_RATIO:
            parts.append(f"the residual is {r:.1f} times the records' own noise: the {self.law} law does not describe "
                         "these records to their noise (another friction behaviour, a rig value off, or a sensor "
                         "artefact); the values are those of the best fit of a wrong model, and their stated errors "
                         f"are inflated by the misfit ({self.fit.stderr_method}): read them as such. Try vcbmodel "
                         "diagnose")
        return ". ".join(parts) if parts else None

    def zeta(self) -> float:
        p, rig = self.datasets[0].rig.pendulum, self.datasets[0].rig
        return zeta_from_viscous(self.values["viscous"], p.inertia, p.mass, rig.gravity, p.com_distance)

    def to_json(self) -> dict:
        v = self.values
        return {"law": self.law, "mu_s": v["mu_s"], "mu_k": v["mu_k"], "stick_velocity": v["stick_velocity"],
                "stribeck_velocity": v["stribeck_velocity"], "viscous": v["viscous"], "zeta": self.zeta(),
                "rms": self.fit.rms, "max_error_percent": self.max_error_percent(),
                "stderr": {p.name: p.stderr for p in self.fit.parameters.values() if p.vary},
                "stderr_naive": {p.name: p.stderr_naive for p in self.fit.parameters.values() if p.vary},
                "stderr_method": self.fit.stderr_method,
                "correlations": {f"{a}~{b}": c for (a, b), c in self.fit.correlations.items()},
                "units": {"mu_s": "-", "mu_k": "-", "stick_velocity": "rad/s", "stribeck_velocity": "rad/s",
                          "viscous": "N m s/rad", "zeta": "-", "rms": "rad", "noise_estimate": "rad",
                          "max_error_percent": "%", "residual_to_noise": "-"},
                "at_bound": [p.name for p in self.fit.parameters.values() if p.at_bound()],
                "aic": self.fit.aic, "bic": self.fit.bic, "noise_estimate": self.fit.sigma,
                "residual_to_noise": self.residual_to_noise, "warning": self.warning,
                "simulated_with": self.fit.backend,
                "measurements": [d.measurement.path for d in self.datasets],
                "model_forms": self.forms.to_json() if self.forms is not None else None,
                "implausible": [f.to_json() for f in self.forms.findings] if self.forms is not None else [],
                "rival_form": self.rival_form,
                "held_out": self.held_out.to_json() if self.held_out is not None else None}

    def report(self) -> str:
        return (f"Friction identification, {self.law} law, {len(self.datasets)} measurement(s)\n"
                + (f"  WARNING: {self.warning}\n" if self.warning else "")
                + f"  max |error| {self.max_error_percent():.2f} % of the first peak amplitude; zeta {self.zeta():.4g}\n"
                + self.fit.report()
                + ("\n" + self.forms.report() if self.forms is not None else "")
                + ("\n" + self.held_out.report() if self.held_out is not None else ""))


def further_starts(rig: Rig, meas: Measurement, law: str, first: dict, splits: bool) -> list[dict]:
    """Starts beside a record's own first guess ``first``: mu_s as multiples of its mu_k (the hybrid
    law), and (``splits``) the swing's decay shared out between Coulomb and viscous friction."""
    scan = [{"mu_s": f * first.get("mu_k", 0.1)} for f in MU_S_STARTS] if law == "hybrid" else []
    if splits:
        scan += decay_split_guesses(rig, meas, DECAY_SPLITS)
    return scan


def identify(pairs: Sequence[tuple[Rig, Measurement]], law: str = "hybrid", verbose: bool = True, polish: bool = False,
             processes: int = 2, forms: bool = True, hold_out: bool = True) -> IdentifyResult:
    """Fit ``law`` to the (rig, measurement) pairs at once (shared friction parameters).

    Least squares from the record's own starting values (the swing's decay), first on the
    swinging part at a coarse step, then on the whole record; the Jacobian's simulations run
    in parallel on ``processes`` processes. ``polish``: a short simplex run afterwards, as in
    the paper (it rarely changes the least-squares optimum).

    Parameters
    ----------
    pairs : (rig, measurement) pairs of pendulum records (``t`` in s, angle in rad), e.g. from
        :func:`~vcbmodel.experiments.loading.load_pair`.
    law : a key of :data:`LAWS` (``hybrid``, ...): which friction parameters are fitted.
    verbose : report each fit's progress.
    polish : run the simplex afterwards.
    processes : processes for the Jacobian's simulations.
    forms : also fit the forms the records cannot tell apart and state every quantity over them
        (:mod:`.model_forms`).
    hold_out : with several records, fit on some and predict the rest, and fit each alone
        (:mod:`.held_out`).

    Returns
    -------
    IdentifyResult
        The fit; ``values`` in SI units: ``mu_s``, ``mu_k`` (-), ``stick_velocity``,
        ``stribeck_velocity`` (rad/s), ``viscous`` (N m s/rad); ``first_peaks`` in rad.
    """
    spec = LAWS[law]
    pairs = released_pairs(pairs)  # each record from its release, found
    pairs = [usual_rate(pair, "identify") for pair in pairs]
    # a record cut at a release found in it: its release refitted, as the diagnosis fits it
    datasets = [Dataset(rig, meas, setup=release_setup(meas) if was_cut(meas) else None) for rig, meas in pairs]
    rig0, meas0 = pairs[0]
    guesses = experiment_of(rig0.experiment).start_guesses(rig0, meas0)
    params = make_parameters(rig0, spec["effects"], initial=guesses[0], vary=spec["vary"])
    splits = "viscous" in spec["vary"] and params["viscous"].vary
    params.update({p.name: p for p in (release_parameter(i, d.setup) for i, d in enumerate(datasets) if d.setup)})
    if not any(p.vary for p in params.values()):
        raise InputError(rig0.path, "friction", f"gives every value of the {law} law: nothing to fit "
                         "(remove the values to identify from the rig's friction section)")
    effects = spec["effects"]
    if law == "stick-slip":  # ws follows w0: the Stribeck branch is empty
        params["stribeck_velocity"].vary = False
        params["stribeck_velocity"].tied_to = "stick_velocity"
    # further starts, tried only when the first does not reach the noise
    scan = further_starts(rig0, meas0, law, guesses[0], splits)
    with SimulationPool(processes, inline_single=True) as pool:
        # from the record's own starting values; the other starts only if that misses the noise
        result = staged_fit(datasets, effects, MASSLESS, params, verbose=verbose, label=f"{law} (least squares)",
                            pool=pool, coarse_step=COARSE_STEP)
        if result.rms > 1.1 * result.sigma:
            retry = staged_fit(datasets, effects, MASSLESS, params, starts=guesses[1:] + scan, verbose=verbose,
                               label=f"{law} (least squares, more starts)", pool=pool, coarse_step=COARSE_STEP)
            retry.nfev += result.nfev
            result = retry if retry.chi2 < result.chi2 else result
    if polish:
        polished = fit(datasets, effects, MASSLESS, result.parameters, method="nelder-mead", verbose=verbose,
                       label=f"{law} (simplex polish)", max_simulations=SIMPLEX_BUDGET)
        if polished.chi2 <= result.chi2:
            for name, p in polished.parameters.items():
                p.stderr, p.stderr_naive = result.parameters[name].stderr, result.parameters[name].stderr_naive
            polished.covariance = result.covariance
            polished.nfev += result.nfev
            result = polished
    out = IdentifyResult(law, result, datasets, [first_peak_amplitude(d.t, d.y) for d in datasets])
    if forms or (hold_out and len(datasets) > 1):
        _beside_the_fit(out, pairs, processes, forms, hold_out, splits)
    return out


def _beside_the_fit(out: IdentifyResult, pairs: Sequence, processes: int, forms: bool, hold_out: bool,
                    splits: bool) -> None:
    """Sets ``out.forms`` (the forms the records cannot tell apart, :mod:`.model_forms`) and, with
    several records, ``out.held_out`` (each fitted alone and tested for agreement, :mod:`.held_out`)."""
    result, datasets, law = out.fit, out.datasets, out.law
    with SimulationPool(processes, inline_single=True) as pool:
        def refit(effects, params, starts, label, on=datasets, **options):
            options.setdefault("sigma", result.sigma)
            return fit(on, effects, MASSLESS, params, pool=pool, starts=starts, verbose=False, label=label,
                       **options)
        if forms:
            out.forms = fit_forms(pairs[0][0], result, refit, None, label=law)
        if hold_out and len(datasets) > 1:
            own = []
            for rig, meas in pairs:
                g = experiment_of(rig.experiment).start_guesses(rig, meas)
                own.append(g + further_starts(rig, meas, law, g[0], splits))
            out.held_out = held_out_validation(datasets, result, refit, out.first_peaks, own)
