"""Every threshold the diagnosis decides by, in one value (:class:`DiagnosisOptions`): passed
through the pipeline (``ctx.options``) and written into the report's JSON (``options``), so a
diagnosis says which thresholds produced it. Each default's reasoning is in its comment."""
from __future__ import annotations

from dataclasses import asdict, dataclass, fields, replace


@dataclass(frozen=True)
class DiagnosisOptions:
    """The diagnosis's thresholds (units in each comment; BIC in units of chi^2 of the whitened
    residual, variances in units of the noise variance)."""

    #: BIC improvement required to name an effect. Kass & Raftery (1995) call a BIC difference
    #: above 10 "very strong" evidence.
    bic_margin: float = 10.0
    #: An effect must also remove this share of the noise variance from the residual. The model's
    #: own numerical accuracy against the independent reference is about 0.4 % of a
    #: potentiometer's noise variance; with 6000 samples a difference that small is
    #: "significant" by BIC and an extra parameter can absorb part of it: five times more.
    min_variance_gain: float = 0.02
    #: A residual that fails the whiteness tests still counts as noise when its mean square
    #: exceeds the record's high-frequency noise variance by at most this share (its rms by 5 %);
    #: on a rounded record it is also the share of the noise variance an effect must remove
    #: (rounding is deterministic and a model a little off can follow some of it).
    structure_tolerance: float = 0.1
    #: Significance level of each whiteness test of the whitened residual (Ljung-Box, Bartlett's
    #: cumulative periodogram).
    whiteness_alpha: float = 0.01
    #: A residual may hold up to this factor times a level witness's noise (before its sampling
    #: spread): a stated sensor noise is rarely better than +-10 %, and the structure tolerance
    #: above is 10 % of the variance.
    level_factor: float = 1.15
    #: One-sided significance level of the variance-ratio test against a level witness.
    witness_alpha: float = 0.01
    #: A residual up to this factor times the record's high-frequency (third-difference) level is
    #: what correlated sensor noise alone can leave (an AR(1) noise of lag-1 correlation 0.65
    #: has a third-difference level of 1/2.0 of its own).
    high_frequency_factor: float = 2.0
    #: The noise model fitted to a residual that passes the noise tests tells it from a model
    #: error only while it stays within this factor of the record's high-frequency noise; above
    #: it, pairs of effects are tried too.
    separable_noise_ratio: float = 2.0
    #: Pairs are tried when the best single effect leaves more than this share of the residual
    #: variance in excess of the noise (two effects may be missing together).
    pair_share_left: float = 0.5
    #: A swing's period mismatch is reported when it exceeds this fraction (and 4 standard errors).
    period_tolerance: float = 0.002
    #: A model value fitted on a held-out record that differs from the diagnosed record's by more
    #: than this many combined stated errors has moved between records: an amplitude- or
    #: speed-dependent effect is missing (three: a 0.3 % chance for one value if both are right).
    moved_errors: float = 3.0
    #: The record is not explained when a plausible model form (:mod:`..model_forms`) beats the final
    #: model by more than this BIC (the forms' BIC, which counts a rounded record's runs of identical
    #: values once) and moves a value the final fit states beyond ``rival_form_errors``: the numbers
    #: the report gives belong to a model the record rejects. 10: the evidence margin of the forms.
    rival_form_margin: float = 10.0
    #: ... beyond this many of the value's stated errors (the half-width of its 95 % interval).
    rival_form_errors: float = 1.96
    #: Smallest clock error the time-base nuisance is kept for (relative): a crystal clock is
    #: good to about 1e-4.
    min_clock_error: float = 2e-4
    #: A pinned value is worth a caveat when its plausible error would move a fitted parameter by
    #: more than this many stated errors (the half-width of the stated 95 % interval).
    beyond_stated: float = 1.96
    #: Optimiser runs per fit (from the best ranked start, and the next when the first does not
    #: reach the noise).
    max_starts: int = 2
    #: Optimiser runs of the wider search of a free swing before a "not explained" verdict (in the
    #: measured case that needed it, the start that led to the noise ranked third).
    wider_starts: int = 3
    #: Shares of a free swing's decay put in Coulomb friction by the starts spread along the
    #: Coulomb-viscous valley (the same as identify.DECAY_SPLITS).
    valley_shares: tuple = (0.8, 0.6, 0.4)
    #: Time budget of one diagnosis (s of processor time per process); past 80 % of it no new fit
    #: starts; ``wall_factor`` times it in wall time stops it in any case.
    time_budget: float = 50.0
    wall_factor: float = 4.0
    #: Whether step 6 searches outside the registry when the verdict is "not explained". It changes
    #: no fit, name or verdict of the registered search (it is reported beside them), so a study
    #: that scores only those may switch it off; a user's diagnosis has it on.
    discovery: bool = True

    def with_(self, **changes) -> DiagnosisOptions:
        """A copy with ``changes`` (names of fields)."""
        unknown = set(changes) - {f.name for f in fields(self)}
        if unknown:
            raise ValueError(f"unknown diagnosis option(s): {', '.join(sorted(unknown))}")
        return replace(self, **changes)

    def to_json(self) -> dict:
        return {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(self).items()}


#: The defaults.
DEFAULT_OPTIONS = DiagnosisOptions()
