# Shared by tests/slurm/pack_*.test.sh (sourced after PACK_TEST=<name of the test> is set): a test folder $W, the study
# folder $DIR and the job name $JOB_NAME (with spaces, as users' folders have them), a cleanup trap that kills demsa
# and cancels the test's allocations, SLURM started (scripts/start-local-slurm.sh) when none runs and stopped at the
# end if this test started it, and $W/study.toml: 6 samples in pack mode, 2 at a time, with the fake LIGGGHTS of
# tests/integration/fake_liggghts.
: "${DEMSA_BINARY:?}" "${DEMSA_SOURCE_DIR:?}" "${PACK_TEST:?}"

W=$(mktemp -d "${TMPDIR:-/tmp}/demsa-$PACK_TEST-XXXXXX")
started_slurm=0
demsa_pid=
RUN_ID=${W##*-}
DIR="$W/${PACK_TEST//_/ } $RUN_ID"
JOB_NAME="demsa-${PACK_TEST}_$RUN_ID"
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

FAKE="$DEMSA_SOURCE_DIR/tests/integration/fake_liggghts"
cat > "$W/study.toml" <<TOML
[study]
name = "pack-check"
experiment = "pile"
seed = 3

[design]
method = "lhs"
samples = 6

[parameters]
mu_pp = { low = 0.2, high = 0.8 }
e_r = { low = 0.3, high = 0.7 }

[pile]
particles = 300

[run]
executor = "slurm"
liggghts = "$FAKE/liggghts"
mpirun = "$FAKE/mpirun"
ranks = 1
retries = 0

[run.slurm]
mode = "pack"
throttle = 2
time_limit = "00:05:00"
poll_interval = 0.5
TOML
export FAKE_LIGGGHTS_PLAN=""
