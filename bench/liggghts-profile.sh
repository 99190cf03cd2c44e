#!/usr/bin/env bash
# Where a case's time goes (docs/explanation/benchmarks.md, "Where the time goes"): writes one case of a study with `demsa case`,
# runs it on one rank under `perf record -F 499 -g` with `modify_timing verbose` (LIGGGHTS's undocumented per-fix
# timer: input.cpp, reported in finish.cpp after every run), and prints
#   - the loop's sections (Pair, Neigh, Comm, Output, Modify, Other) and each fix, summed over every `run` of the
#     case, in % of the summed loop time (wall-clock timers: on a loaded machine they include waits);
#   - the symbols above 0.5 % of the samples (`perf report --no-children --sort symbol`).
# A case that runs longer than SECONDS (CPU-seconds; default: no limit) is stopped there by SIGINT (perf writes its
# data; the runs finished so far are summed): the profile of the case's start, which the output says.
#
# STUDY.toml may instead be a case folder (one that `demsa case` wrote, its params.liggghts edited, e.g. a shortened
# phase): it is copied to OUT_DIR as it is, and SAMPLE is not read.
#
# Usage: bench/liggghts-profile.sh DEMSA STUDY.toml SAMPLE LIGGGHTS OUT_DIR [SECONDS]
#   e.g. bench/liggghts-profile.sh build/orchestrator/demsa examples/quickstart.toml 1 \
#          $(scripts/build-liggghts.sh --print-prefix)/bin/liggghts /tmp/prof-pile 60
set -euo pipefail
(($# >= 5)) || { sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
demsa=$(realpath "$1")
study=$(realpath "$2")
sample=$3
exe=$(realpath "$4")
out=$5
limit=${6:-}
perf=${PERF:-perf}
rm -rf "$out"
if [[ -d $study ]]; then
  cp -r "$study" "$out"
  rm -f "$out"/log.liggghts "$out"/*.dump "$out"/perf.data* "$out"/cpu.txt
else
  "$demsa" case "$study" --sample "$sample" -o "$out" >/dev/null
fi
cd "$out"
# The timer is switched on before the first run (the command only sets a flag, valid before the box exists).
sed -i '1i modify_timing verbose' in.liggghts
# ulimit -t stops LIGGGHTS by SIGXCPU after SECONDS of CPU: perf then writes what it recorded.
(
  [[ -z $limit ]] || ulimit -t "$limit"
  /usr/bin/time -f "%U %S" -o cpu.txt "$perf" record -F 499 -g -q -o perf.data -- \
    "$exe" -in in.liggghts -log log.liggghts -screen screen.txt >/dev/null 2>&1
) || echo "liggghts-profile: stopped after ${limit:-?} CPU-seconds (or failed): the runs finished by then are summed" >&2
echo "load: $(cat /proc/loadavg)   CPU (user sys): $(cat cpu.txt 2>/dev/null | tail -1)"
python3 - log.liggghts <<'PY'
import re, sys
# `run N post no` prints no breakdown: the sections and fixes are in % of the loop time of the runs that print one.
loop = atoms = profiled = last = 0.0
runs = with_breakdown = 0
sections, fixes = {}, {}
for line in open(sys.argv[1], errors="replace"):
    m = re.match(r"Loop time of (\S+) on \d+ procs for (\d+) steps with (\d+) atoms", line)
    if m:
        last = float(m.group(1)); loop += last; atoms += int(m.group(2)) * int(m.group(3)); runs += 1
    m = re.match(r"(Pair|Neigh|Comm|Outpt|Modfy|Other) +time \(%\) = (\S+)", line)
    if m:
        if m.group(1) == "Pair":
            profiled += last; with_breakdown += 1
        sections[m.group(1)] = sections.get(m.group(1), 0.0) + float(m.group(2))
    m = re.match(r"Fix (\S+) (\S+) time \(%\) = (\S+)", line)
    if m:
        k = f"{m.group(1)} ({m.group(2)})"
        fixes[k] = fixes.get(k, 0.0) + float(m.group(3))
print(f"{runs} runs, {atoms:.3g} atom-steps, loop {loop:.1f} s (wall); {with_breakdown} runs with a breakdown, "
      f"{profiled:.1f} s of loop")
for k, v in sections.items():
    print(f"  {k:6s} {100 * v / max(profiled, 1e-300):5.1f} %")
for k, v in sorted(fixes.items(), key=lambda kv: -kv[1]):
    if v / max(profiled, 1e-300) >= 0.002:
        print(f"    fix {k:40s} {100 * v / profiled:5.1f} %")
PY
"$perf" report -i perf.data --no-children --sort symbol --stdio -q -g none --percent-limit 0.5 2>/dev/null |
  sed -E 's/^ +//; s/\(anonymous namespace\):://g' | cut -c1-150 | grep -v '^$' | head -40
# The samples in groups, by symbol (memset is counted with the contact history, its main caller in a pile: the
# mesh contact history's page clearing, then Verlet::force_clear).
"$perf" report -i perf.data --no-children --sort symbol --stdio -q -g none 2>/dev/null | python3 -c '
import re, sys
groups = [
    ("contacts: pair and wall kernels, contact models", r"PairStyles::Granular|Walls::Granular|surfacesIntersect|surfacesClose|ContactModel"),
    ("mesh wall: post_force_mesh, triangle/edge/corner resolution, mesh neighbour lists", r"FixWallGran::post_force_mesh|TriMesh::|FixNeighlistMesh|MultiNodeMesh|SurfaceMesh"),
    ("primitive walls", r"post_force_primitive|PrimitiveWall"),
    ("contact history bookkeeping", r"FixContactHistory|memset"),
    ("time integration, gravity, freeze", r"FixNVE|FixGravity|FixFreeze"),
    ("neighbour lists, binning", r"Neighbor::|NPair|NBin"),
    ("input, variables, output between runs", r"Variable::|Input::|strtod|strcmp|strlen|strncpy|strchr|printf|vfprintf|mpn_|str_to_mpn|hack_digit|round_and_return|isspace|malloc|_int_free|cfree|free|memmove|memcpy|Thermo|Output|Dump"),
    ("timers (modify_timing, CPU readings)", r"clock_gettime|Wtime|Timer::"),
]
tot = {g: 0.0 for g, _ in groups}; other = 0.0
for line in sys.stdin:
    m = re.match(r"\s*([\d.]+)%\s+\[[.k]\]\s+(.*)", line)
    if not m: continue
    v, sym = float(m.group(1)), m.group(2)
    for g, rx in groups:
        if re.search(rx, sym): tot[g] += v; break
    else: other += v
for g, _ in groups:
    if tot[g] >= 0.05: print(f"  {tot[g]:5.1f} %  {g}")
print(f"  {other:5.1f} %  other")
'
