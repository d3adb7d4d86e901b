# The 16-core scale-out run (studies/benchmark.py --scaling-only) on a bare node without network, from the
# repository's root: Exudyn's libGL (the Debian packages docs/cli.md lists, in .gl/) and the Python packages
# the node lacks (wheels for its Python, in .whl/) travel with the checkout. Usage:
#   LIMIT=470 bash studies/device/scaling.sh OUTDIR [--quick] [PYTHON]      (LIMIT: seconds for the benchmark)
# results/scale_out_16_cores/ holds one such run (OUTDIR's files). The machine's own ceiling was measured on
# the same node, after the same unpacking and install, with
#   python3 studies/device/cpu_probe.py OUTDIR/cpu_probe.json               (an arithmetic loop, 1-16 processes)
#   python3 studies/device/fork_probe.py OUTDIR/fork_probe.json 30          (a closing in this, forked, fresh processes)
set -o pipefail
OUTD=$1; QUICK=$2; PY=${3:-python3}
mkdir -p /tmp/gl "$OUTD"
for f in .gl/*.deb; do dpkg -x "$f" /tmp/gl; done
export LD_LIBRARY_PATH=/tmp/gl/usr/lib/x86_64-linux-gnu:/tmp/gl/lib/x86_64-linux-gnu${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
$PY -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl || exit 3
export PYTHONPATH=/tmp/site${PYTHONPATH:+:$PYTHONPATH} PATH=/tmp/site/bin:$PATH MPLBACKEND=Agg PYTHONUNBUFFERED=1
{ nproc; $PY --version; which gcc cc; $PY -c "import os; print('affinity', len(os.sched_getaffinity(0)), 'cpu_count', os.cpu_count())"
  $PY -c "import exudyn, cffi, distributed, numpy, pandas, vcbmodel; print('exudyn', exudyn.__version__, 'distributed', distributed.__version__, 'numpy', numpy.__version__, 'pandas', pandas.__version__)"; } 2>&1 | tee "$OUTD/env.txt" || exit 4
timeout ${LIMIT:-480} $PY studies/benchmark.py --scaling-only $QUICK --out "$OUTD" > "$OUTD/log.txt" 2>&1
echo "rc=$?"; tail -5 "$OUTD/log.txt"; cat "$OUTD/scale_out.md"
