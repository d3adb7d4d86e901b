"""Adding an experiment kind is one record plus its builder: shown with a small dummy
experiment (a mass on a spring, released from a displacement) that every layer handles by
asking the record: rig loading, simulation, units, figures of merit, synthetic records,
measurement loading and the command line."""
import json
import math

import numpy as np
import pytest

from vcbmodel.analysis.synthetic import synthetic_measurement
from vcbmodel.app.cli import main
from vcbmodel.builders.core import ExudynModel, exudyn_modules
from vcbmodel.errors import InputError
from vcbmodel.experiments import EXPERIMENTS, Experiment
from vcbmodel.experiments.loading import load_record, load_rig
from vcbmodel.experiments.simulation import simulate
from vcbmodel.records.measurement import write_measurement
from vcbmodel.rig.data import Pendulum


# --- the builder module of the new experiment (here inline) --------------------------------
def read_oscillator(rd, data):
    s = rd.section(data, "oscillator", known=("mass", "stiffness", "initial_position"))
    # reuse a dataclass with the fields we need: mass, inertia (stiffness here), initial angle
    return {"oscillator": Pendulum(mass=rd.number(s, "mass", "oscillator.", positive=True),
                                   inertia=rd.number(s, "stiffness", "oscillator.", positive=True),
                                   com_distance=1.0, initial_angle=rd.number(s, "initial_position", "oscillator."))}


def build_oscillator(rig, spec, law, chain, user_function, ancf_elements):
    exu, it = exudyn_modules()
    o = rig.sections["oscillator"]
    model = ExudynModel()
    mbs = model.mbs
    node = mbs.AddNode(it.Node1D(referenceCoordinates=[0.0], initialCoordinates=[o.initial_angle], initialVelocities=[0.0]))
    mbs.AddObject(it.ObjectMass1D(nodeNumber=node, mass=o.mass))
    ground = mbs.AddNode(it.NodePointGround())
    markers = [mbs.AddMarker(it.MarkerNodeCoordinate(nodeNumber=n, coordinate=0)) for n in (ground, node)]
    mbs.AddObject(it.ObjectConnectorCoordinateSpringDamper(markerNumbers=markers, stiffness=o.inertia, damping=0.0))
    model.add_sensor("angle", node, "Coordinates")  # the experiments' common sensor names
    model.add_sensor("velocity", node, "Coordinates_t")
    return model


OSCILLATOR = Experiment(
    name="oscillator", description="mass on a spring", measured_channel="oscillator_position", unit="m",
    sections=("oscillator",), read_sections=read_oscillator, sample_rate=1000.0, noise_sigma=1e-4,
    default_duration=0.5, max_duration=10.0, build=build_oscillator,
    channels=lambda data, rig, spec, info: {"oscillator_position": data["angle"][:, 1],
                                            "oscillator_velocity": data["velocity"][:, 1]},
    step=lambda rig: 1e-4,
    figures_of_merit=lambda result, rig: {"peak_speed_m_s": float(np.max(np.abs(result.channels["oscillator_velocity"])))})


@pytest.fixture
def oscillator(monkeypatch, tmp_path):
    monkeypatch.setitem(EXPERIMENTS, "oscillator", OSCILLATOR)
    rig = {"format": "vcb-rig/1", "name": "dummy oscillator", "experiment": "oscillator", "shaft": {"radius": 0.01},
           "oscillator": {"mass": 2.0, "stiffness": 800.0, "initial_position": 0.01},
           "model": {"effects": [], "spring_model": "massless"}}
    path = tmp_path / "osc.rig.json"
    path.write_text(json.dumps(rig))
    return path


def test_a_new_experiment_runs_through_every_layer(oscillator, tmp_path, capsys):
    rig = load_rig(oscillator)
    assert rig.experiment == "oscillator" and rig.sections["oscillator"].mass == 2.0
    r = simulate(rig)
    omega = math.sqrt(800.0 / 2.0)
    assert r.units["oscillator_position"] == "m"
    np.testing.assert_allclose(r.measured, 0.01 * np.cos(omega * r.t), atol=1e-8)  # analytic solution
    assert OSCILLATOR.figures_of_merit(r, rig)["peak_speed_m_s"] == pytest.approx(0.01 * omega, rel=1e-4)
    meas = synthetic_measurement(rig, (), {}, seed=1, path=tmp_path / "osc.csv")
    assert meas.t[1] == pytest.approx(1e-3) and np.std(meas.channels["oscillator_position"] - r.resample(meas.t).measured) < 2e-4
    write_measurement(meas, meas.path)
    assert load_record(meas.path, rig).channels["oscillator_position"].size == meas.t.size
    assert main(["simulate", str(oscillator), "-o", str(tmp_path / "sim.csv")]) == 0
    assert "t,oscillator_position" in (tmp_path / "sim.csv").read_text()
    assert main(["check", str(oscillator)]) == 0


def test_a_new_experiment_gets_the_front_door_checks(oscillator, tmp_path, capsys):
    data = json.loads(oscillator.read_text())
    data["oscillator"]["masss"] = 1.0
    bad = tmp_path / "bad.rig.json"
    bad.write_text(json.dumps(data))
    with pytest.raises(InputError, match="oscillator.masss.*did you mean 'mass'"):
        load_rig(bad)
    data["oscillator"].pop("masss")
    # which effects apply is asked of the record (what it provides), not of a list in the effects' module
    assert OSCILLATOR.provides == ()
    for effect in ("spring_mass", "viscous_friction", "aerodynamic_drag"):
        data["model"]["effects"] = [effect]
        bad.write_text(json.dumps(data))
        with pytest.raises(InputError, match=f"model.effects.*{effect}' does not apply to an? oscillator test"):
            load_rig(bad)
    assert main(["simulate", str(oscillator), "--effects", "coulomb_friction", "-o", str(tmp_path / "sim.csv")]) == 2
    assert "--effects: effects: effect 'coulomb_friction' does not apply" in capsys.readouterr().err


def test_every_registered_experiment_is_complete():
    for record in EXPERIMENTS.values():
        assert record.sample_rate > 0 and record.noise_sigma > 0 and 0 < record.default_duration < record.max_duration
        assert record.unit in ("rad", "m") and record.sections
