#!/usr/bin/env bash
# Pack mode ([run.slurm] mode = "pack") through a real local SLURM (scripts/start-local-slurm.sh), with the fake
# LIGGGHTS of tests/integration/fake_liggghts (every start of a case appends its sample to starts.log):
#   1. a study of 6 cases runs to its end in one allocation, 2 cases at a time, each case started once;
#   2. the same study anew: demsa is killed (SIGKILL) while the allocation runs, the allocation runs on, and a second
#      `demsa run` adopts its cases: every case is started exactly once and nothing is submitted again.
# SLURM is stopped at the end, also when the test fails, if this test started it.
set -euo pipefail
: "${DEMSA_BINARY:?}" "${DEMSA_SOURCE_DIR:?}"

PACK_TEST=pack_study
# shellcheck source=tests/slurm/pack_lib.sh
source "$DEMSA_SOURCE_DIR/tests/slurm/pack_lib.sh"

jobs_of_study() { squeue -h -t all -n "$JOB_NAME" -o %F 2>/dev/null | sort -u; }
# every sample in starts.log exactly once
check_started_once() {  # state-dir
  local log=$1/starts.log
  [ "$(wc -l < "$log")" = 6 ] || fail "$(wc -l < "$log") starts instead of 6: $(tr '\n' ' ' < "$log")"
  [ "$(sort -n "$log" | tr '\n' ' ')" = "0 1 2 3 4 5 " ] || fail "starts: $(sort -n "$log" | tr '\n' ' ')"
}
check_status() {  # expected attempts
  "$DEMSA_BINARY" status "$DIR" --json > "$W/status.json"
  python3 - "$W/status.json" "$1" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
assert s["done"] == 6 and s["failed"] == 0 and s["attempts"] == int(sys.argv[2]), s
print("status:", {k: s[k] for k in ("done", "failed", "attempts")})
PY
}

# ---------------------------------------------------------------- 1. to the end, in one allocation
t0=$(date +%s.%N)
export FAKE_LIGGGHTS_STATE="$W/state1" FAKE_LIGGGHTS_SECONDS=1
mkdir -p "$FAKE_LIGGGHTS_STATE"
"$DEMSA_BINARY" run "$W/study.toml" --dir "$DIR" --no-analyze > "$W/run1.out" 2>&1 \
  || { cat "$W/run1.out" >&2; fail "demsa run in pack mode failed"; }
grep -q "6 of 6 samples done" "$W/run1.out" || { cat "$W/run1.out" >&2; fail "not every sample done"; }
grep -q "as pack allocation" "$W/run1.out" || { cat "$W/run1.out" >&2; fail "no pack allocation in the log"; }
check_started_once "$FAKE_LIGGGHTS_STATE"
check_status 6
[ "$(jobs_of_study | wc -l)" = 1 ] || fail "jobs submitted: $(jobs_of_study | tr '\n' ' ') (want one allocation)"
job=$(jobs_of_study)
[ "$(grep -l '^exit 0 ' "$DIR"/slurm/sentinels/"${job}"_? | wc -l)" = 6 ] || fail "not 6 sentinels 'exit 0' of job $job"
ls "$DIR"/slurm/pack-*.sh > /dev/null || fail "no pack driver script kept"
echo "1. 6 cases in allocation $job: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s"

# ---------------------------------------------------------------- 2. SIGKILL of demsa, then resume
t0=$(date +%s.%N)
export FAKE_LIGGGHTS_STATE="$W/state2" FAKE_LIGGGHTS_SECONDS=3
mkdir -p "$FAKE_LIGGGHTS_STATE"
"$DEMSA_BINARY" run "$W/study.toml" --dir "$DIR" --new --no-analyze > "$W/run2.out" 2>&1 &
demsa_pid=$!
end=$(($(date +%s) + 60))
until [ -s "$FAKE_LIGGGHTS_STATE/starts.log" ]; do
  [ "$(date +%s)" -lt "$end" ] || { cat "$W/run2.out" >&2; fail "no case started"; }
  kill -0 "$demsa_pid" 2>/dev/null || { cat "$W/run2.out" >&2; fail "demsa ended before a case started"; }
  sleep 0.1
done
kill -KILL "$demsa_pid"
wait "$demsa_pid" 2>/dev/null || true
demsa_pid=
killed_job=$(squeue -h -n "$JOB_NAME" -t RUNNING -o %A)
[ -n "$killed_job" ] || fail "the allocation is not running after demsa was killed"
echo "demsa killed; allocation $killed_job runs on, started so far: $(tr '\n' ' ' < "$FAKE_LIGGGHTS_STATE/starts.log")"

"$DEMSA_BINARY" run "$W/study.toml" --dir "$DIR" --no-analyze > "$W/run3.out" 2>&1 \
  || { cat "$W/run2.out" "$W/run3.out" >&2; fail "resumed demsa run failed"; }
grep -q "6 of 6 samples done" "$W/run3.out" || { cat "$W/run3.out" >&2; fail "resume did not finish"; }
if grep -q "submitted .* case(s)" "$W/run3.out"; then cat "$W/run3.out" >&2; fail "the resume submitted again"; fi
check_started_once "$FAKE_LIGGGHTS_STATE"
check_status 6
[ "$(jobs_of_study | wc -l)" = 2 ] || fail "jobs: $(jobs_of_study | tr '\n' ' ') (want the first run's and one more)"
[ "$(grep -l '^exit 0 ' "$DIR"/slurm/sentinels/"${killed_job}"_? | wc -l)" = 6 ] || fail "sentinels of $killed_job"
echo "2. killed and resumed, each case once: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s"
echo "PASS: pack mode on a real SLURM"
