#!/usr/bin/env bash
# `demsa predict` against an independent numpy/scipy implementation (predict_numpy_check.py): 160 training points,
# 10,000 test points; rsm2, rsm3, rbf-cubic and rbf-tps fitted in Python from the same data, the GP rebuilt from its
# saved hyperparameters and training data (in long double): 1e-9 relative for every prediction (the GP without a
# nugget, whose correlation matrix has a condition number of 1e12 here, included: predict_numpy_check.py says how).
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
common=(--data "$work/data.csv" --inputs a,b,c --response y --bounds a=0:2,b=-1:1,c=1:100:log --bootstrap 0
        --base 256)
"$DEMSA_BINARY" sensitivity "${common[@]}" --metamodels rsm2,rsm3,rbf-cubic,rbf-tps,gp \
  --save-model "$work/models" > "$work/sensitivity.txt"
"$DEMSA_BINARY" sensitivity "${common[@]}" --metamodels gp --gp-nugget --save-model "$work/models-nugget" \
  > "$work/sensitivity-nugget.txt"
status=0
for model in rsm2 rsm3 rbf-cubic rbf-tps gp gp-nugget; do
  set=models
  std=()
  [[ $model == gp* ]] && std=(--std)
  [[ $model == gp-nugget ]] && { set=models-nugget; model=gp; }
  "$DEMSA_BINARY" predict "$work/$set/y.$model.json" --points "$work/points.csv" "${std[@]}" \
    --out "$work/$set/pred_$model.csv"
  "$python" "$checker" check "$work" "$model" "$set" || status=1
done
exit $status
