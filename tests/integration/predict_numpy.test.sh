#!/usr/bin/env bash
# `demsa predict` against an independent numpy/scipy implementation (predict_numpy_check.py): 160 training points,
# 10,000 test points; rsm2, rsm3, rbf-cubic and rbf-tps fitted in Python from the same data, the GP rebuilt from its
# saved hyperparameters and training data; 1e-9 relative.
set -euo pipefail
: "${DEMSA_BINARY:?}" "${DEMSA_SOURCE_DIR:?}"
python=${DEMSA_PYTHON:-/usr/bin/python3}
if ! "$python" -c 'import numpy, scipy.interpolate' 2>/dev/null; then
  echo "$python has no numpy/scipy: install python3-numpy python3-scipy (scripts/install-deps.sh)" >&2
  exit 1
fi
checker="$DEMSA_SOURCE_DIR/tests/integration/predict_numpy_check.py"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$python" "$checker" generate "$work"
"$DEMSA_BINARY" sensitivity --data "$work/data.csv" --inputs a,b,c --response y \
  --bounds a=0:2,b=-1:1,c=1:100:log --metamodels rsm2,rsm3,rbf-cubic,rbf-tps,gp --bootstrap 0 --base 256 \
  --save-model "$work/models" > "$work/sensitivity.txt"
status=0
for model in rsm2 rsm3 rbf-cubic rbf-tps gp; do
  std=()
  [[ $model == gp ]] && std=(--std)
  "$DEMSA_BINARY" predict "$work/models/y.$model.json" --points "$work/points.csv" "${std[@]}" \
    --out "$work/pred_$model.csv"
  "$python" "$checker" check "$work" "$model" || status=1
done
exit $status
