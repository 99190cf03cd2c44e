#!/usr/bin/env bash
# The one-way layering of ARCHITECTURE.md: sobol/ and postprocess/ never include orchestrator/, nor each other.
set -euo pipefail
cd "${DEMSA_SOURCE_DIR:?}"
bad=$(grep -nE '#include[[:space:]]*[<"](orchestrator|postprocess)/' sobol/*.hpp sobol/*.cpp || true)
bad+=$(grep -nE '#include[[:space:]]*[<"](orchestrator|sobol)/' postprocess/*.hpp postprocess/*.cpp || true)
if [[ -n $bad ]]; then
  echo "layering broken (sobol/ and postprocess/ must not include orchestrator/ or each other):"
  echo "$bad"
  exit 1
fi
echo "layering ok: sobol/ and postprocess/ include neither orchestrator/ nor each other"
