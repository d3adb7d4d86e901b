"""Output sample times of simulated measurements: the rates of the paper's sensors."""
import numpy as np

#: Potentiometer of the pendulum test (1 kHz) and high-speed camera of the cam drop
#: (12000 frames/s, paper section 3): the rates the example measurements use. The whole
#: breaker's follower displacement (Fig. 12) was filmed by the same camera.
SAMPLE_RATE = {"pendulum": 1000.0, "cam_drop": 12000.0, "vcb_closing": 12000.0}


def output_times(rig, t_end):
    """Sample times (s) from 0 to t_end at the experiment's sensor rate."""
    dt = 1.0 / SAMPLE_RATE[rig.experiment]
    n = int(np.floor(t_end / dt + 1e-9))
    return np.arange(n + 1) * dt
