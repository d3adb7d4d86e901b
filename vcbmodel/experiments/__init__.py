"""One record per experiment kind (pendulum, cam drop, whole-breaker closing) that every
layer asks: its measured channel and unit, sensor, durations, rig sections, Exudyn builder,
channel assembly, figures of merit and fitting hints; the rig loader and the simulation
chain that use them; and the closing's evaluation.

May import: ``vcbmodel.builders``, ``vcbmodel.reference``, ``vcbmodel.model``,
``vcbmodel.records``, ``vcbmodel.rig``, ``vcbmodel.laws``, ``vcbmodel.errors``,
``vcbmodel.parameters``. Adding an experiment: one :class:`~vcbmodel.experiments.base.Experiment`
record registered with :func:`~vcbmodel.experiments.base.register`, plus its builder module.
"""
from .base import EXPERIMENTS, Experiment, experiment_of, register
from .cam_drop import CAM_DROP
from .pendulum import PENDULUM
from .vcb_closing import VCB_CLOSING

for _record in (PENDULUM, CAM_DROP, VCB_CLOSING):
    register(_record)

__all__ = ["EXPERIMENTS", "Experiment", "experiment_of", "register"]
