#!/usr/bin/env bash
# Growing a study through a real local SLURM (scripts/start-local-slurm.sh): a tiny pile study with replicates
# (2 design points x 2 packings) runs as SLURM array tasks; demsa is killed while tasks are queued and resumed;
# `demsa extend` adds 2 samples (run by `demsa run`) and `demsa refine` (an unreachable --target-ci, so it stops at --max-samples) 2
# more, both through SLURM. Every case must finish, the replicate of a point must hold another packing (its dump
# differs), and the analysis must report the angle's noise from the replicates.
# SLURM is stopped at the end, also when the test fails, if this test started it.
set -euo pipefail
: "${DEMSA_BINARY:?}" "${DEMSA_SOURCE_DIR:?}"

W=$(mktemp -d "${TMPDIR:-/tmp}/demsa-slurm-grow-XXXXXX")
started_slurm=0
demsa_pid=
RUN_ID=${W##*-}
DIR="$W/grow_$RUN_ID"
JOB_NAME="demsa-grow_$RUN_ID"
cleanup() {
  local rc=$?
  [ -n "$demsa_pid" ] && kill -KILL "$demsa_pid" 2>/dev/null || true
  squeue -h -o %A -n "$JOB_NAME" 2>/dev/null | sort -u | xargs -r scancel 2>/dev/null || true
  if [ "$started_slurm" = 1 ]; then "$DEMSA_SOURCE_DIR/scripts/stop-local-slurm.sh" || true; fi
  if [ "$rc" = 0 ] && [ -z "${DEMSA_KEEP_TEST_DIRS:-}" ]; then rm -rf "$W"; else echo "test folder kept: $W"; fi
  exit "$rc"
}
fail() { echo "FAIL: $*" >&2; exit 1; }
trap cleanup EXIT

if sinfo -h -o %T >/dev/null 2>&1 && [ -n "$(sinfo -h -o %T 2>/dev/null)" ]; then
  echo "using the SLURM that is already running: $(sinfo -h -o '%P %D %T' | head -1)"
else
  [ "$(id -u)" = 0 ] || fail "no SLURM is running and starting one needs root (scripts/start-local-slurm.sh)"
  started_slurm=1
  "$DEMSA_SOURCE_DIR/scripts/start-local-slurm.sh"
fi

cat > "$W/study.toml" <<EOF
[study]
name = "grow-check"
experiment = "pile"
seed = 17

[design]
method = "lhs"
samples = 4
replicates = { points = 2, repeats = 2 }

[parameters]
mu_pp = { low = 0.4, high = 0.8 }
e_r = { low = 0.3, high = 0.6 }

[analysis]
metamodels = ["rsm1"]
bootstrap = 5
base_samples = 64

[pile]
particles = 150
settle_time = 0.05
directions = 36
levels = 4

[run]
executor = "slurm"
ranks = 1
parallel = 2
retries = 0

[run.slurm]
time_limit = "00:10:00"
throttle = 1
poll_interval = 0.5
EOF

status_json() { "$DEMSA_BINARY" status "$DIR" --json > "$W/status.json"; }
check_done() {  # expected number of finished samples (the 2 replicate cases are counted apart)
  status_json
  python3 - "$W/status.json" "$1" <<'EOF' || { cat "$W/status.json" >&2; fail "status: not $1 samples and 2 replicates done"; }
import json, sys
s = json.load(open(sys.argv[1]))
assert s["done"] == int(sys.argv[2]) and s["samples"] == int(sys.argv[2]) and s["failed"] == 0, s
assert s["replicates"]["done"] == 2 and s["replicates"]["failed"] == 0, s
print("status:", {k: s[k] for k in ("done", "failed", "attempts", "replicates")})
EOF
}

# ---------------------------------------------------------------- run with replicates, kill while queued, resume
"$DEMSA_BINARY" run "$W/study.toml" --dir "$DIR" --no-analyze > "$W/run1.out" 2>&1 &
demsa_pid=$!
end=$(($(date +%s) + 120))
until [ -n "$(squeue -h -r -t PENDING -n "$JOB_NAME" 2>/dev/null)" ]; do
  [ "$(date +%s)" -lt "$end" ] || { cat "$W/run1.out" >&2; fail "timed out waiting for a pending task"; }
  kill -0 "$demsa_pid" 2>/dev/null || { cat "$W/run1.out" >&2; fail "demsa ended before any task was pending"; }
  sleep 0.2
done
kill -KILL "$demsa_pid"
wait "$demsa_pid" 2>/dev/null || true
demsa_pid=
echo "demsa killed; queued or running: $(squeue -h -r -n "$JOB_NAME" -o '%F_%K:%T' | tr '\n' ' ')"
"$DEMSA_BINARY" run "$W/study.toml" --dir "$DIR" > "$W/run2.out" 2>&1 \
  || { cat "$W/run1.out" "$W/run2.out" >&2; fail "resumed demsa run failed"; }
check_done 4  # and the 2 replicates
grep -qi "noise" "$W/run2.out" || { cat "$W/run2.out" >&2; fail "the analysis does not report the noise"; }
# The replicate of a point is another packing: its final dump differs from the point's own case.
replicate_dumps=$(ls "$DIR"/cases/*/pile_final.dump | wc -l)
[ "$replicate_dumps" = 6 ] || fail "$replicate_dumps final dumps, expected 6"
if [ "$(md5sum "$DIR"/cases/*/pile_final.dump | cut -d' ' -f1 | sort -u | wc -l)" != 6 ]; then
  fail "two cases have the same final dump: a replicate did not draw another packing"
fi

# ---------------------------------------------------------------- extend and refine through SLURM
"$DEMSA_BINARY" extend "$DIR" --samples 6 > "$W/extend.out" 2>&1 || { cat "$W/extend.out" >&2; fail "extend failed"; }
"$DEMSA_BINARY" run "$DIR/study.toml" --dir "$DIR" --no-analyze > "$W/run3.out" 2>&1 \
  || { cat "$W/extend.out" "$W/run3.out" >&2; fail "running the extended study failed"; }
check_done 6
# An unreachable target: refine spends its budget and says so with exit status 1 (the check failed).
rc=0
"$DEMSA_BINARY" refine "$DIR" --target-ci 1e-6 --batch 2 --max-samples 8 > "$W/refine.out" 2>&1 || rc=$?
cat "$W/refine.out"
[ "$rc" = 1 ] || fail "refine exited with $rc, expected 1 (budget spent, target not reached)"
grep -q "budget of 8 samples is spent" "$W/refine.out" || fail "refine did not say its budget was spent"
check_done 8
[ -n "$(ls "$DIR/slurm/sentinels" 2>/dev/null)" ] || fail "no SLURM sentinels: the cases did not run through SLURM"
echo "PASS: replicates, a kill and resume, extend and refine through SLURM: 8 samples and 2 replicates"
