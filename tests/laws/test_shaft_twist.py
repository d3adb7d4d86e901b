"""The main shaft's twist between the pole levers (vcbmodel.laws.mechanics.main_shaft_twist)."""
import math

import pytest

from vcbmodel.laws.mechanics import main_shaft_twist, shaft_torsional_stiffness


def test_torsional_stiffness_of_a_round_shaft():
    # G J of a 40 mm solid steel shaft: 79.3e9 * pi * 0.04^4 / 32
    assert shaft_torsional_stiffness(0.04, 79.3e9) == pytest.approx(19930.0, rel=1e-3)
    # a tube of the same outer diameter is softer by (1 - (d_i/d)^4)
    assert shaft_torsional_stiffness(0.04, 79.3e9, 0.02) == pytest.approx(19930.0 * (1 - 1 / 16), rel=1e-3)


def test_twist_adds_the_torques_beyond_each_segment():
    gj = shaft_torsional_stiffness(0.04, 79.3e9)
    twists = main_shaft_twist([50.0, 50.0, 50.0], 0.21, 0.04, 79.3e9)
    assert twists[0] == 0.0
    assert twists[1] == pytest.approx(100.0 * 0.21 / gj)  # first segment carries poles 2 and 3
    assert twists[2] == pytest.approx(150.0 * 0.21 / gj)  # plus the second segment carrying pole 3
    # a single lever twists nothing; twice the diameter: 16x stiffer
    assert main_shaft_twist([80.0], 0.21, 0.04, 79.3e9) == [0.0]
    assert main_shaft_twist([50.0] * 3, 0.21, 0.08, 79.3e9)[2] == pytest.approx(twists[2] / 16)
    assert math.isclose(main_shaft_twist([0.0, 0.0, 60.0], 0.21, 0.04, 79.3e9)[2], 2 * 60.0 * 0.21 / gj)
