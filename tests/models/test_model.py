"""The model layer: one spring-model value, the one rule for model values, the result type."""
from dataclasses import replace

import numpy as np
import pytest

from vcbmodel.errors import InputError
from vcbmodel.experiments.simulation import model_spec, simulate
from vcbmodel.model.choice import choose, consistent_effects
from vcbmodel.model.values import model_values
from vcbmodel.rig.spring_model import SpringModel


@pytest.mark.parametrize("text,kind,n,convention", [
    ("massless", "massless", 0, "exact"), ("lumped-3", "lumped", 3, "exact"), ("lumped-12:paper", "lumped", 12, "paper"),
    ("lumped-2:uniform", "lumped", 2, "uniform"), ("ancf", "ancf", 0, "exact")])
def test_spring_model_parses_in_one_place(text, kind, n, convention):
    m = SpringModel.parse(text)
    assert (m.kind, m.masses, m.convention) == (kind, n, convention)
    assert SpringModel.parse(m.name, m.convention) == m  # round trip
    assert SpringModel.parse("lumped-2", "paper").convention == "paper"  # a default convention applies
    assert SpringModel.parse("lumped-2:exact", "paper").convention == "exact"  # the named one wins


@pytest.mark.parametrize("text", ["lumped-0", "lumped-100", "lumped-2:fancy", "massless:paper", "beam", "", 3])
def test_bad_spring_models_are_refused(text):
    with pytest.raises(ValueError):
        SpringModel.parse(text)


def test_spring_mass_follows_the_spring_model():
    assert consistent_effects(("coulomb_friction",), SpringModel.parse("lumped-2")) == ("coulomb_friction", "spring_mass")
    assert consistent_effects(("spring_mass", "stribeck"), SpringModel()) == ("stribeck",)


def test_the_model_choice_is_made_by_one_rule(cam_rig):
    """The rig's lumped-2 cam drop: a named spring model decides spring_mass (keeping the rig's
    convention unless it names one); effects named alone decide whether the spring has mass; a
    spring's mass listed on a massless spring is refused, never given a default mass model."""
    assert choose(cam_rig) is cam_rig.model
    named = choose(cam_rig, ("coulomb_friction",), "lumped-3")
    assert named.effects == ("coulomb_friction", "spring_mass") and named.spring_model == SpringModel("lumped", 3, "exact")
    assert choose(cam_rig, spring_model="massless").spring_model.is_massless
    assert "spring_mass" not in choose(cam_rig, spring_model="massless").effects
    alone = choose(cam_rig, ("stribeck", "coulomb_friction"))
    assert alone.effects == ("stribeck", "coulomb_friction") and alone.spring_model == SpringModel("massless", 0, "exact")
    assert choose(cam_rig, ("coulomb_friction", "spring_mass")).spring_model == cam_rig.model.spring_model
    massless = choose(cam_rig, ("coulomb_friction",))
    rig = replace(cam_rig, model=massless)
    with pytest.raises(ValueError, match="spring_mass.*massless"):
        choose(rig, ("coulomb_friction", "spring_mass"))
    with pytest.raises(ValueError, match="spring_mass.*massless"):
        simulate(rig, ("coulomb_friction", "spring_mass"), t_end=0.001)


def test_values_given_over_rig_and_missing_values_refused(cam_rig, tmp_path):
    # the rig gives mu_k = 0.13; a given value wins; a value nobody gives is refused, naming the rig field
    assert model_values(cam_rig, ("coulomb_friction",))["mu_k"] == 0.13
    assert model_values(cam_rig, ("coulomb_friction",), {"mu_k": 0.2})["mu_k"] == 0.2
    with pytest.raises(InputError, match="friction.viscous"):
        model_values(cam_rig, ("viscous_friction",))
    assert model_values(cam_rig, ("viscous_friction",), for_fit=True)["viscous"] > 0  # fits start from a guess
    with pytest.raises(InputError, match="friction.viscous"):
        simulate(cam_rig, ("viscous_friction",), t_end=0.001)


def test_result_carries_units_model_and_a_dataframe(cam_rig):
    r = simulate(cam_rig, ("coulomb_friction",), spring_model="lumped-2:paper", t_end=0.002)
    assert r.measured is r.channels["cam_angle"] and r.units["cam_angle"] == "rad"
    assert r.units["shaft_velocity"] == "rad/s" and r.units["friction_torque"] == "N m"
    assert r.units["spring_mass_1_x"] == "m" and r.units["spring_velocity_2_y"] == "m/s"
    assert r.effects == ("coulomb_friction", "spring_mass") and r.spring_model == SpringModel("lumped", 2, "paper")
    frame = r.to_dataframe()
    assert frame.index.name == "t [s]" and "cam_angle [rad]" in frame.columns
    np.testing.assert_array_equal(frame["cam_angle [rad]"].to_numpy(), r.measured)
    assert model_spec(cam_rig).spring_model == SpringModel.parse("lumped-2")  # the rig's own model


def test_the_model_is_the_same_in_any_registry_order(cam_rig, monkeypatch):
    """Effects declare the fields they set and read: Stribeck friction's static coefficient falls
    to the kinetic one, so it is assembled after Coulomb friction whatever the registry's order."""
    from vcbmodel.model import effects as E
    cases = [(("coulomb_friction", "stribeck"), {"mu_k": 0.12, "mu_s": 0.2, "stribeck_velocity": 0.05}),
             (("stribeck",), {"mu_s": 0.2, "stribeck_velocity": 0.05}), (("coulomb_friction",), {"mu_k": 0.12}), ((), {}),
             (("coulomb_friction", "viscous_friction", "spring_mass", "spring_damping"),
              {"mu_k": 0.12, "viscous": 0.3, "damping_ratio": 0.02})]
    expected = [model_spec(cam_rig, effects, values) for effects, values in cases]
    assert expected[0].mu_s == 0.2 and expected[2].mu_s == 0.12 and expected[1].mu_k == 0.0
    registry = dict(E.EFFECTS)
    for seed in range(6):
        names = list(registry)
        np.random.default_rng(seed).shuffle(names)
        monkeypatch.setattr(E, "EFFECTS", {n: registry[n] for n in names})
        order = [e.name for e in E.assembly_order(E.EFFECTS)]
        assert order.index("coulomb_friction") < order.index("stribeck")
        assert [model_spec(cam_rig, effects, values) for effects, values in cases] == expected


def test_an_effect_that_breaks_the_assembly_contract_is_refused():
    from vcbmodel.model import effects as E

    class Twice(E.Effect):
        name, sets = "twice", ("mu_k",)

    class Reader(E.Effect):
        name, sets, reads = "reader", ("drag",), ("nowhere",)

    class A(E.Effect):
        name, sets, reads = "a", ("x",), ("y",)

    class B(E.Effect):
        name, sets, reads = "b", ("y",), ("x",)
    with pytest.raises(ValueError, match="'mu_k' is set by two effects"):
        E.assembly_order(dict(E.EFFECTS, twice=Twice()))
    with pytest.raises(ValueError, match="reads model field 'nowhere'"):
        E.assembly_order({"reader": Reader()})
    with pytest.raises(ValueError, match="circle"):
        E.assembly_order({"a": A(), "b": B()})


def test_an_effect_sets_only_the_fields_it_declares(cam_rig, monkeypatch):
    from vcbmodel.model import effects as E

    class Sneaky(E.Effect):
        name, sets = "sneaky", ("drag",)

        def on(self, values, model):
            return {"drag": 0.0, "viscous": 1.0}  # viscous is viscous friction's

        def off(self, model):
            return self.on({}, model)
    monkeypatch.setattr(E, "EFFECTS", {n: e for n, e in E.EFFECTS.items() if n != "aerodynamic_drag"} | {"sneaky": Sneaky()})
    with pytest.raises(ValueError, match="'sneaky' set \\['drag', 'viscous'\\], not the fields it declares \\['drag'\\]"):
        model_spec(cam_rig, ("coulomb_friction",), {"mu_k": 0.1})
