"""Regenerate results/: every study (--quick: a smoke run; --out DIR: write there; --log FILE: where
the studies' own output goes, default a file in the temporary folder, named at the end).

The studies are independent processes (none reads another's output), run two at a time so the
2 cores stay busy: two lanes take the next study from one queue, longest first (the realism study,
itself two diagnoses at a time, then the others by their measured time), so neither lane idles while
the other has a queue. The benchmark runs last and alone: its wall times are the speed evidence. Times a study
reports of its own work (a fit's, a diagnosis's seconds) are wall times beside the other lane.

The console gets one line per study: its status, wall and processor time and the files it wrote
(those changed in the output folder while it ran; a file changed while two studies ran goes to the
one whose name it carries, else to the shorter run). A failed study's last lines follow its line.
The wall and processor time of each study go to ``run_all_timing.json`` in the output folder."""
import json
import os
import platform
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
#: The studies two lanes take in turn from one queue, longest first (wall seconds on 2 cores,
#: results/run_all_timing.json); then the studies in ALONE, one at a time.
QUEUE = ["diagnosis_realism.py", "design_tolerance.py", "discovery_demo.py", "spring_models.py",
         "friction_identification.py", "vcb_closing.py", "design_sensitivity.py", "diagnosis_sweep.py",
         "design_optimum.py", "vcb_cycle.py", "discrepancy_demo.py", "design_conclusion_map.py", "spring_reading.py"]
LANES = 2
ALONE = ["benchmark.py"]
STUDIES = QUEUE + ALONE


def output_folder(args):
    """The folder the studies write to: ``--out DIR`` or results/."""
    for i, a in enumerate(args):
        if a == "--out" and i + 1 < len(args):
            return Path(args[i + 1])
        if a.startswith("--out="):
            return Path(a.split("=", 1)[1])
    return HERE.parent / "results"


def split_log(args):
    """(the studies' arguments, the log file): ``--log FILE`` is run_all's own."""
    rest, log = [], None
    it = iter(args)
    for a in it:
        if a == "--log":
            log = Path(next(it, "") or sys.exit("run_all: --log needs a file name"))
        elif a.startswith("--log="):
            log = Path(a.split("=", 1)[1])
        else:
            rest.append(a)
    return rest, log or Path(tempfile.gettempdir()) / f"vcbmodel-run_all-{time.strftime('%Y%m%d-%H%M%S')}.log"


def snapshot(folder):
    """{path relative to ``folder``: modification time (ns)} of every file under it."""
    if not folder.is_dir():
        return {}
    return {str(p.relative_to(folder)): p.stat().st_mtime_ns for p in folder.rglob("*") if p.is_file()}


class Runner:
    """Runs studies as child processes, their output into the log; keeps each one's wall and processor
    seconds (its own and its children's: simulation and record workers), when it ran and what changed
    in the output folder meanwhile; after a failure no new study starts (the one running in the other
    lane finishes)."""

    def __init__(self, extra, out, log):
        self.extra, self.out, self.log = extra, out, log
        self.wall, self.cpu, self.failed, self.span, self.changed, self.status = {}, {}, [], {}, {}, {}
        self.lock = threading.Lock()
        self.running, self.pending, self.tails = {}, [], {}

    def run(self, script):
        with self.lock:
            if self.failed:
                return
            before, t0 = snapshot(self.out), time.time()
            capture = tempfile.TemporaryFile(mode="w+")
            p = subprocess.Popen([sys.executable, str(HERE / script), *self.extra], stdout=capture,
                                 stderr=subprocess.STDOUT)
            self.running[script] = t0  # once it runs: a study that could not start holds no line back
        _, status, usage = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
        with self.lock:
            after = snapshot(self.out)
            self.span[script] = (t0, time.time())
            self.changed[script] = {f for f, m in after.items() if before.get(f) != m}
            self.wall[script] = round(time.time() - t0, 1)
            self.cpu[script] = round(usage.ru_utime + usage.ru_stime, 1)
            capture.seek(0)
            text = capture.read()
            capture.close()
            with open(self.log, "a") as f:
                f.write(f"== {script} (exit status {p.returncode}, {self.wall[script]:.0f} s)\n{text}\n")
            self.status[script] = "ok" if p.returncode == 0 else f"FAILED (exit status {p.returncode})"
            if p.returncode != 0:
                self.failed.append(f"{script} (exit status {p.returncode})")
                self.tails[script] = "\n".join("   | " + line for line in text.rstrip().splitlines()[-20:])
            del self.running[script]
            self.pending.append(script)
            self.flush()

    def flush(self):
        """Print the line of each finished study that no running study overlaps (one that started
        before it ended may still change files it would claim), in the order they finished."""
        for script in list(self.pending):
            if any(t0 < self.span[script][1] for t0 in self.running.values()):
                continue
            self.pending.remove(script)
            print(self.line(script), flush=True)
            if script in self.tails:
                print(self.tails[script], flush=True)

    def files(self, script):
        """The files ``script`` wrote: changed while it ran, less those another study running beside it
        has a better claim to (:func:`owner`)."""
        return sorted(f for f in self.changed.get(script, ()) if owner(f, script, self.span, self.changed) == script)

    def line(self, script):
        files = self.files(script)
        return (f"{script:<28}{self.status[script]:<6}{self.wall[script]:>6.0f} s ({self.cpu[script]:.0f} s processor)  "
                + (", ".join(files) if files else "no files"))

    def lane(self, scripts):
        for s in scripts:
            self.run(s)

    def take(self, queue, lock):
        """Run studies from the shared ``queue`` until it is empty."""
        while True:
            with lock:
                if not queue:
                    return
                script = queue.pop(0)
            self.run(script)


def owner(path, script, spans, changed):
    """Which study wrote ``path`` of those that changed it: one whose name the file carries
    (``vcb_closing_detail.png``: vcb_closing.py), else the one that ran for the shortest time (the
    long realism study runs beside every other)."""
    claims = [s for s in changed if path in changed[s]]
    named = [s for s in claims if Path(path).name.startswith(Path(s).stem)]
    pool = named or claims
    return min(pool, key=lambda s: spans[s][1] - spans[s][0]) if script in pool else None


def main():
    extra, log = split_log(sys.argv[1:])
    out = output_folder(extra)
    runner = Runner(extra, out, log)
    start = time.time()
    print(f"run_all: {len(STUDIES)} studies into {out}; their output goes to {log}", flush=True)
    queue, lock = list(QUEUE), threading.Lock()
    threads = [threading.Thread(target=runner.take, args=(queue, lock)) for _ in range(LANES)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    runner.lane(ALONE)
    if runner.failed:
        sys.exit(f"run_all: failed: {', '.join(runner.failed)} (the full output: {log})")
    timing = {"quick": "--quick" in extra, "python": platform.python_version(), "cores": os.cpu_count(),
              "lanes": LANES, "queue": QUEUE, "alone": ALONE,
              "studies_s": {s: runner.wall[s] for s in STUDIES},
              "studies_processor_s": {s: runner.cpu[s] for s in STUDIES},
              "total_min": round((time.time() - start) / 60, 2)}
    out.mkdir(parents=True, exist_ok=True)
    (out / "run_all_timing.json").write_text(json.dumps(timing, indent=1) + "\n")
    print(f"run_all: all studies in {timing['total_min']:.1f} min; timing in {out / 'run_all_timing.json'}; "
          f"their output in {log}", flush=True)


if __name__ == "__main__":
    main()
