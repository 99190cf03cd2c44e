#!/usr/bin/env bash
# The one-way layering of ARCHITECTURE.md:
#   sobol/ and postprocess/ never include orchestrator/, nor each other;
#   inside orchestrator/, each folder includes only the folders below it:
#     util <- study <- experiments <- cases <- exec, util <- driver <- experiments, experiments <- analysis <- report,
#     and cli on top;
#   only orchestrator/driver/ includes LIGGGHTS (the one target that loads it).
set -euo pipefail
cd "${DEMSA_SOURCE_DIR:?}"
bad=$(grep -nE '#include[[:space:]]*[<"](orchestrator|postprocess)/' sobol/*.hpp sobol/*.cpp || true)
bad+=$(grep -nE '#include[[:space:]]*[<"](orchestrator|sobol)/' postprocess/*.hpp postprocess/*.cpp || true)

# folder -> the folders (inside orchestrator/ or beside it) it may include
declare -A allowed=(
  [util]="util"
  [study]="util study sobol postprocess"
  [driver]="util driver"
  [experiments]="util study driver experiments sobol postprocess"
  [cases]="util study experiments cases sobol"
  [exec]="util study experiments cases exec sobol postprocess"
  [analysis]="util study experiments analysis sobol"
  [report]="util study experiments analysis report sobol postprocess"
  [cli]="util study experiments cases driver exec analysis report cli sobol postprocess"
)
for folder in "${!allowed[@]}"; do
  [[ -d orchestrator/$folder ]] || { bad+=$'\n'"orchestrator/$folder: missing (ARCHITECTURE.md names it)"; continue; }
  while IFS= read -r hit; do
    [[ -n $hit ]] || continue
    target=$(sed -E 's/.*#include[[:space:]]*"(orchestrator\/)?([a-z_]+)\/.*/\2/' <<<"${hit#*:*:}")
    if [[ " ${allowed[$folder]} " != *" $target "* ]]; then bad+=$'\n'"$hit"; fi
  done < <(grep -rnE '#include[[:space:]]*"(orchestrator/[a-z_]+|sobol|postprocess)/' "orchestrator/$folder" || true)
done
# every folder of orchestrator/ is a layer of the table above
for dir in orchestrator/*/; do
  name=$(basename "$dir")
  [[ -n ${allowed[$name]+set} ]] || bad+=$'\n'"$dir: a folder that is not a layer of tests/style/layering.test.sh"
  grep -qE "^\| \`orchestrator/$name/\` \|" ARCHITECTURE.md || bad+=$'\n'"$dir: no line of its own in ARCHITECTURE.md"
done
liggghts=$(grep -rlnE '#include[[:space:]]*[<"](liggghts/|library\.h|lammps\.h)' orchestrator sobol postprocess |
  grep -v '^orchestrator/driver/' || true)
[[ -z $liggghts ]] || bad+=$'\n'"LIGGGHTS included outside orchestrator/driver/: $liggghts"

if [[ -n ${bad//$'\n'/} ]]; then
  echo "layering broken (ARCHITECTURE.md):"
  echo "$bad"
  exit 1
fi
echo "layering ok: sobol/ and postprocess/ stand alone; orchestrator/ folders include only the layers below them"
