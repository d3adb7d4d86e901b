"""Discovery of what no registry has: the missing torque estimated from the record and the fitted
model (:mod:`.force`), a library of candidate terms (:mod:`.library`), sparse selection
(:mod:`.regression`, scikit-learn), the model refitted with the discovered torque (:mod:`.refit`)
and the evidence it must earn (:mod:`.judge`); :func:`discover` runs them in order
(:mod:`.discover`)."""
from .discover import DiscoveredTerm, Discovery, covers, discover, discover_among, discovery_step, excess, record_dataset

__all__ = ["DiscoveredTerm", "Discovery", "covers", "discover", "discover_among", "discovery_step", "excess", "record_dataset"]
