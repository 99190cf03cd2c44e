#!/usr/bin/env bash
# Pack mode ([run.slurm] mode = "pack") through a real local SLURM (scripts/start-local-slurm.sh), with the fake
# LIGGGHTS of tests/integration/fake_liggghts: SIGTERM to `demsa run --cancel-on-interrupt` while the allocation runs
# cancels the allocation (squeue shows nothing of it afterwards), the running cases write "signal TERM" sentinels,
# and every case is left to run again (requeued, none failed).
# SLURM is stopped at the end, also when the test fails, if this test started it.
set -euo pipefail
: "${DEMSA_BINARY:?}" "${DEMSA_SOURCE_DIR:?}"

PACK_TEST=pack_cancel
# shellcheck source=tests/slurm/pack_lib.sh
source "$DEMSA_SOURCE_DIR/tests/slurm/pack_lib.sh"

t0=$(date +%s.%N)
export FAKE_LIGGGHTS_STATE="$W/state" FAKE_LIGGGHTS_SECONDS=60
mkdir -p "$FAKE_LIGGGHTS_STATE"
"$DEMSA_BINARY" run "$W/study.toml" --dir "$DIR" --no-analyze --cancel-on-interrupt > "$W/run.out" 2>&1 &
demsa_pid=$!
end=$(($(date +%s) + 60))
until [ "$(wc -l < "$FAKE_LIGGGHTS_STATE/starts.log" 2>/dev/null || echo 0)" -ge 2 ]; do
  [ "$(date +%s)" -lt "$end" ] || { cat "$W/run.out" >&2; fail "no two cases started"; }
  kill -0 "$demsa_pid" 2>/dev/null || { cat "$W/run.out" >&2; fail "demsa ended before the cases started"; }
  sleep 0.1
done
job=$(squeue -h -n "$JOB_NAME" -t RUNNING -o %A)
[ -n "$job" ] || fail "no running allocation"
kill -TERM "$demsa_pid"
rc=0
wait "$demsa_pid" || rc=$?
demsa_pid=
[ "$rc" = 143 ] || { cat "$W/run.out" >&2; fail "demsa ended with status $rc after SIGTERM (want 143)"; }
left=$(squeue -h -n "$JOB_NAME" -o '%A %T')
[ -z "$left" ] || fail "still in squeue after the cancellation: $left"
state=$(squeue -h -t all -j "$job" -o %T)
[ "$state" = CANCELLED ] || fail "allocation $job is $state, not CANCELLED"
[ "$(grep -l '^signal TERM' "$DIR"/slurm/sentinels/"${job}"_? | wc -l)" = 2 ] \
  || fail "want 2 'signal TERM' sentinels: $(head -qn1 "$DIR"/slurm/sentinels/"${job}"_* 2>/dev/null | tr '\n' ';')"
"$DEMSA_BINARY" status "$DIR" --json > "$W/status.json"
python3 - "$W/status.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
assert s["done"] == 0 and s["failed"] == 0 and s["running"] == 0, s
print("status:", {k: s[k] for k in ("done", "failed", "running", "pending", "attempts")})
PY
echo "SIGTERM cancelled allocation $job: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s"
echo "PASS: SIGTERM cancels the pack allocation"
