#!/usr/bin/env bash
# scripts/docs-pictures.sh: redraws the pictures of docs/images/ that come from a source in the tree:
# pipeline.png from pipeline.dot (graphviz `dot`; Debian: apt-get install graphviz). The pictures demsa draws
# itself are copied from its own output; each page that shows one names the command that made it.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v dot >/dev/null || { echo "docs-pictures.sh: graphviz's dot is not installed" >&2; exit 2; }
dot -Tpng -Gdpi=96 docs/images/pipeline.dot -o docs/images/pipeline.png
echo "docs/images/pipeline.png"
