"""Regenerate results/: every study in turn (about 1.5 hours on 2 cores; --quick: a smoke run)."""
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
STUDIES = ["friction_identification.py", "spring_models.py", "vcb_closing.py", "discrepancy_demo.py",
           "diagnosis_sweep.py", "diagnosis_realism.py", "design_sensitivity.py", "design_tolerance.py", "design_conclusion_map.py",
           "design_optimum.py", "benchmark.py"]

if __name__ == "__main__":
    extra = sys.argv[1:]
    for s in STUDIES:
        t0 = time.time()
        print(f"== {s}", flush=True)
        subprocess.run([sys.executable, str(HERE / s), *extra], check=True)
        print(f"== {s}: {time.time() - t0:.0f} s", flush=True)
