#!/usr/bin/env bash
# A small real-LIGGGHTS study through a real local SLURM (scripts/start-local-slurm.sh), in a folder whose name has
# spaces: one running task is cancelled with scancel and one pending task is cancelled (it vanishes from squeue),
# demsa is killed (SIGKILL) while tasks are still queued, and a second `demsa run` resumes and adopts them. The
# results must equal those of the local executor on the same cases (same rank count: identical dumps). Then the
# study is started anew with `demsa run --submit-only`, and `demsa status` alone collects the cases.
# SLURM is stopped at the end, also when the test fails, if this test started it.
set -euo pipefail
: "${DEMSA_BINARY:?}" "${DEMSA_SOURCE_DIR:?}"

W=$(mktemp -d "${TMPDIR:-/tmp}/demsa-slurm-XXXXXX")
started_slurm=0
demsa_pid=
cleanup() {
  local rc=$?
  [ -n "$demsa_pid" ] && kill -KILL "$demsa_pid" 2>/dev/null || true
  # cancel this test's jobs (the study's job name) even when SLURM stays up
  squeue -h -o %A -n "$JOB_NAME" 2>/dev/null | sort -u | xargs -r scancel 2>/dev/null || true
  if [ "$started_slurm" = 1 ]; then "$DEMSA_SOURCE_DIR/scripts/stop-local-slurm.sh" || true; fi
  if [ "$rc" = 0 ] && [ -z "${DEMSA_KEEP_TEST_DIRS:-}" ]; then rm -rf "$W"; else echo "test folder kept: $W"; fi
  exit "$rc"
}
fail() { echo "FAIL: $*" >&2; exit 1; }
trap cleanup EXIT

# The job name is demsa-<study folder name>: unique per test run, so that this test only ever touches its own jobs
# when another run of it shares the SLURM.
RUN_ID=${W##*-}
SLURM_DIR="$W/slurm study's dir $RUN_ID"
LOCAL_DIR="$W/local study"
JOB_NAME="demsa-slurm_study's_dir_$RUN_ID"

# ---------------------------------------------------------------- a local SLURM
if sinfo -h -o %T >/dev/null 2>&1 && [ -n "$(sinfo -h -o %T 2>/dev/null)" ]; then
  echo "using the SLURM that is already running: $(sinfo -h -o '%P %D %T' | head -1)"
else
  [ "$(id -u)" = 0 ] || fail "no SLURM is running and starting one needs root (scripts/start-local-slurm.sh)"
  started_slurm=1
  "$DEMSA_SOURCE_DIR/scripts/start-local-slurm.sh"
fi

# ---------------------------------------------------------------- the study (4 tiny piles)
write_study() {  # file executor
  cat > "$1" <<EOF
[study]
name = "slurm-check"
experiment = "pile"
seed = 11

[design]
method = "lhs"
samples = 4

[parameters]
mu_pp = { low = 0.4, high = 0.8 }
e_r = { low = 0.3, high = 0.6 }

[pile]
particles = 150
settle_time = 0.05
directions = 36
levels = 4

[run]
executor = "$2"
ranks = 1
parallel = 2
retries = 0

[run.slurm]
time_limit = "00:10:00"
throttle = 1
poll_interval = 0.5
EOF
}
write_study "$W/slurm.toml" slurm
write_study "$W/local.toml" local

# ---------------------------------------------------------------- run through SLURM, cancel, kill, resume
t0=$(date +%s)
"$DEMSA_BINARY" run "$W/slurm.toml" --dir "$SLURM_DIR" --no-analyze > "$W/run1.out" 2>&1 &
demsa_pid=$!

wait_for() {  # seconds description command...
  local end=$(($(date +%s) + $1)) what=$2
  shift 2
  until "$@"; do
    [ "$(date +%s)" -lt "$end" ] || { cat "$W/run1.out" >&2; squeue -r -t all >&2 || true; fail "timed out waiting for: $what"; }
    kill -0 "$demsa_pid" 2>/dev/null || { cat "$W/run1.out" >&2; fail "demsa ended early while waiting for: $what"; }
    sleep 0.2
  done
}
tasks_in() { squeue -h -r -t "$1" -n "$JOB_NAME" -o '%F_%K' 2>/dev/null; }
has_running() { [ -n "$(tasks_in RUNNING)" ]; }
wait_for 120 "a running task" has_running
first_job=$(tasks_in RUNNING | head -1 | cut -d_ -f1)
running=$(tasks_in RUNNING | head -1)
pending=$(tasks_in PENDING | grep "^${first_job}_" | sort -t_ -k2 -n | tail -1)
[ -n "$pending" ] || fail "no pending task of job $first_job to cancel (throttle 1 should keep 3 pending)"
echo "cancelling running task $running and pending task $pending"
scancel "$running"
scancel "$pending"

# demsa requeues both and submits them again as a new array job; kill it once that one exists
resubmitted() { squeue -h -t all -n "$JOB_NAME" -o %F 2>/dev/null | sort -u | grep -qv "^${first_job}\$"; }
wait_for 60 "the cancelled cases to be submitted again" resubmitted
kill -KILL "$demsa_pid"
wait "$demsa_pid" 2>/dev/null || true
demsa_pid=
echo "demsa killed; still queued or running: $(squeue -h -r -n "$JOB_NAME" -o '%F_%K:%T' | tr '\n' ' ')"

"$DEMSA_BINARY" run "$W/slurm.toml" --dir "$SLURM_DIR" --no-analyze > "$W/run2.out" 2>&1 \
  || { cat "$W/run1.out" "$W/run2.out" >&2; fail "resumed demsa run failed"; }
cat "$W/run2.out"
echo "SLURM study: $(($(date +%s) - t0)) s"
grep -q "4 of 4 samples done" "$W/run2.out" || fail "resumed run did not finish all samples"

"$DEMSA_BINARY" status "$SLURM_DIR" --json > "$W/status.json"
python3 - "$W/status.json" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
assert s["done"] == 4 and s["failed"] == 0, s
# 4 first attempts + 2 requeued (cancelled running, vanished pending) runs
assert s["attempts"] >= 6, s
print("status:", {k: s[k] for k in ("done", "failed", "attempts")})
EOF
[ "$(ls "$SLURM_DIR/slurm/sentinels" | wc -l)" -ge 5 ] || fail "fewer sentinels than finished tasks"
grep -l "^signal TERM" "$SLURM_DIR/slurm/sentinels/"* >/dev/null || fail "no 'signal TERM' sentinel from the cancelled running task"

# ---------------------------------------------------------------- the same cases with the local executor
t0=$(date +%s)
"$DEMSA_BINARY" run "$W/local.toml" --dir "$LOCAL_DIR" --no-analyze > "$W/local.out" 2>&1 \
  || { cat "$W/local.out" >&2; fail "local run failed"; }
echo "local study: $(($(date +%s) - t0)) s"

for n in 000000 000001 000002 000003; do
  a="$SLURM_DIR/cases/$n"
  b="$LOCAL_DIR/cases/$n"
  cmp "$a/pile_final.dump" "$b/pile_final.dump" || fail "case $n: pile_final.dump differs between SLURM and local"
  python3 - "$a/result.json" "$b/result.json" <<'EOF' || fail "case $n: observables differ"
import json, sys
a, b = (json.load(open(f))["observables"] for f in sys.argv[1:3])
assert a == b, (a, b)
EOF
  [ -s "$a/run.out" ] || [ -e "$a/run.out" ] || fail "case $n: no run.out"
done
# ---------------------------------------------------------------- --submit-only, then `demsa status` collects
# The same study anew: demsa submits and returns at once; status (no demsa run in between) commits what has ended.
"$DEMSA_BINARY" run "$W/slurm.toml" --dir "$SLURM_DIR" --new --submit-only > "$W/submit.out" 2>&1 \
  || { cat "$W/submit.out" >&2; fail "demsa run --submit-only failed"; }
grep -q "4 case(s) submitted to SLURM now" "$W/submit.out" || { cat "$W/submit.out" >&2; fail "--submit-only did not submit 4"; }
end=$(($(date +%s) + 300))
until "$DEMSA_BINARY" status "$SLURM_DIR" --json > "$W/status2.json" \
  && python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); sys.exit(0 if s["done"] == 4 else 1)' "$W/status2.json"; do
  [ "$(date +%s)" -lt "$end" ] || { cat "$W/status2.json" >&2; fail "demsa status did not collect the submitted cases"; }
  sleep 2
done
for n in 000000 000001 000002 000003; do
  cmp "$SLURM_DIR/cases/$n/pile_final.dump" "$LOCAL_DIR/cases/$n/pile_final.dump" \
    || fail "case $n: pile_final.dump after --submit-only and status differs from the local executor's"
done
echo "--submit-only and demsa status: 4 cases collected without demsa run"

echo "PASS: 4 cases through SLURM (one cancelled while running, one while pending, demsa killed and resumed)" \
  "equal the local executor's"
