#!/bin/bash
# The Saltelli pipeline of Ishigami (design, evaluation, `demsa sensitivity --saltelli`) against OpenTURNS's
# in-memory pipeline, side by side (bench/saltelli_pipeline.py; docs/explanation/benchmarks.md, "Saltelli pipeline against
# OpenTURNS"). Needs python3-openturns (Debian) under /usr/bin/python3.
#
#   bench/saltelli-pipeline-vs-openturns.sh [N=16384] [RUNS=5] [BOOTSTRAP=200] [build dir=build] [--design-once]
set -euo pipefail
N=${1:-16384}
RUNS=${2:-5}
BOOTSTRAP=${3:-200}
BUILD=${4:-build}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
DEMSA=${DEMSA:-$ROOT/$BUILD/orchestrator/demsa}
[ -x "$DEMSA" ] || { echo "demsa not found at $DEMSA (build it, or set DEMSA)" >&2; exit 2; }
/usr/bin/python3 -c "import openturns" || { echo "OpenTURNS not found: apt-get install python3-openturns" >&2; exit 2; }
exec /usr/bin/python3 "$ROOT/bench/saltelli_pipeline.py" "$DEMSA" "$N" "$RUNS" "$BOOTSTRAP" "${@:5}"
