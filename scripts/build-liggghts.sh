#!/usr/bin/env bash
# Build LIGGGHTS 3.8.0 from Debian's source archive with the project's rolling model
# (liggghts/rolling_model_viscous.h) and compiled kernels for hertz / tangential history /
# cohesion off / rolling off, cdt, epsd, epsd2, epsd3 and viscous (liggghts/style_contact_model.whitelist), the
# mesh walls' contact history cleared per atom instead of per page, and the mesh wall's exact skip of particles out of
# reach of a triangle, compiled with the profile of demsa's own cases (liggghts/profile.tar.xz, GCC's
# -fprofile-use) and link-time optimisation (the same trajectories: docs/explanation/benchmarks.md).
#
#   scripts/build-liggghts.sh                build (once per source + patch hash), print the prefix
#   scripts/build-liggghts.sh --print-prefix print the prefix this checkout's build lives in; build nothing
#   scripts/build-liggghts.sh --jobs N       parallel compile jobs (default 2)
#   scripts/build-liggghts.sh --generic-viscous  the same without the compiled viscous kernel, in <prefix>-generic
#                                            (LIGGGHTS then runs the model through its generic path; for bench/)
#   scripts/build-liggghts.sh --instrument DIR   the same source and flags with -fprofile-generate, the executable
#                                            in DIR/bin (for scripts/write-liggghts-profile.sh, which writes the
#                                            profile)
#
# The result is a versioned prefix outside the repository:
#   ${XDG_CACHE_HOME:-$HOME/.cache}/demsa/liggghts-3.8.0-<key>/{bin/liggghts,lib/libliggghts.so,include/liggghts/}
# <key> = first 16 hex digits of sha256(source tarball hash, the patch files' and the profile's hashes, RECIPE).
# The library is libliggghts.so.3.8.0 with the soname of Debian's, libliggghts.so.3, so that demsa (linked against
# Debian's) can load it in its place for the in-process trial-step oedometer (LD_LIBRARY_PATH=<prefix>/lib). A prefix is
# complete once its `demsa-liggghts.txt` exists (written last); a finished prefix is never rebuilt.
# demsa finds it through `[run] liggghts`, $DEMSA_LIGGGHTS, or this cache (the newest complete prefix).
# ccache is used when installed (CCACHE_DIR defaults to <cache>/ccache), so a changed patch rebuilds cheaply.
# Needs: apt-get (source download), cmake, mpicxx (libopenmpi-dev): scripts/install-deps.sh --liggghts-build.
set -euo pipefail

RECIPE=6 # bump when the build commands below change the result
VERSION=3.8.0
TARBALL=liggghts_3.8.0+repack1.orig.tar.xz

repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cache=${XDG_CACHE_HOME:-$HOME/.cache}/demsa
jobs=2
print_only=0
generic=0
instrument=
while (($#)); do
  case $1 in
    --print-prefix) print_only=1 ;;
    --generic-viscous) generic=1 ;;
    --jobs) jobs=$2; shift ;;
    --instrument) instrument=${2:?--instrument needs a folder}; shift ;;
    -h | --help) sed -n '2,26p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "build-liggghts: error: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done

# The model header and the list of compiled kernels: the combinations demsa writes. Without the list Make.sh
# generates 119 combinations (a loop over 3780 in sh: many minutes), and each kernel costs compile time in lammps.cpp;
# any other combination still runs, through LIGGGHTS's generic path.
patches=("$repo/liggghts/rolling_model_viscous.h" "$repo/liggghts/style_contact_model.whitelist")
# The profile GCC optimises with (-fprofile-use): the counts of an instrumented build of this same source running
# demsa's cases of every experiment and rolling model (scripts/write-liggghts-profile.sh writes it). It changes which
# code is inlined and laid out hot, never the arithmetic (no -ffast-math, no -march): the trajectories stay Debian's.
profile=$repo/liggghts/profile.tar.xz
# The profile belongs to the builds that use it (not to --generic-viscous, whose kernels differ, nor --instrument).
keyed=("${patches[@]}")
((generic)) || [[ -n $instrument ]] || keyed+=("$profile")
for p in "${keyed[@]}"; do
  [[ -f $p ]] || { echo "build-liggghts: error: missing $p" >&2; exit 1; }
done

say() { echo "build-liggghts: $*" >&2; }

# 1. The upstream tarball, from Debian's source archive through a private deb-src list (the system's apt
#    configuration is not changed). Debian's patch tarball may be missing (404): apt-get then exits non-zero
#    after fetching the .orig tarball, which is all this build needs; success is judged by that file.
src_dl=$cache/src
mkdir -p "$src_dl"
if [[ ! -s $src_dl/$TARBALL ]]; then
  ((print_only == 0)) || { say "error: $TARBALL is not in $src_dl yet: run scripts/build-liggghts.sh"; exit 1; }
  say "fetching $TARBALL from Debian's source archive"
  apt_dir=$(mktemp -d)
  trap 'rm -rf "$apt_dir"' EXIT
  mkdir -p "$apt_dir/sources" "$apt_dir/lists/partial" "$apt_dir/archives/partial"
  cat >"$apt_dir/sources/debian-src.sources" <<'EOF'
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: bookworm
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
  apt_opts=(-o "Dir::Etc::SourceParts=$apt_dir/sources" -o Dir::Etc::SourceList=/dev/null
    -o "Dir::State::Lists=$apt_dir/lists" -o "Dir::Cache=$apt_dir" -o Debug::NoLocking=1)
  apt-get "${apt_opts[@]}" -qq update || { say "error: apt-get update of the deb-src list failed"; exit 1; }
  (cd "$src_dl" && apt-get "${apt_opts[@]}" -qq source --download-only liggghts) ||
    say "apt-get source exited non-zero (the Debian patch tarball is often missing); checking the upstream tarball"
  [[ -s $src_dl/$TARBALL ]] || { say "error: $TARBALL was not fetched into $src_dl"; exit 1; }
fi

key=$( {
  sha256sum "$src_dl/$TARBALL" | cut -d' ' -f1
  for p in "${keyed[@]}"; do sha256sum "$p" | cut -d' ' -f1; done
  echo "recipe $RECIPE"
} | sha256sum | cut -c1-16)
prefix=$cache/liggghts-$VERSION-$key
((generic == 0)) || prefix=$prefix-generic
[[ -z $instrument ]] || prefix=$(realpath -m "$instrument")

if ((print_only)); then
  echo "$prefix"
  exit 0
fi
if [[ -z $instrument && -f $prefix/demsa-liggghts.txt ]]; then
  say "already built: $prefix"
  echo "$prefix"
  exit 0
fi

command -v cmake >/dev/null || { say "error: cmake not found (scripts/install-deps.sh --liggghts-build)"; exit 1; }
command -v mpicxx >/dev/null || { say "error: mpicxx not found (scripts/install-deps.sh --liggghts-build)"; exit 1; }

# 2. Unpack into one fixed work tree (a fixed path lets ccache hit across keys), add the patch files.
work=$cache/work-$VERSION
rm -rf "$work"
mkdir -p "$work"
tar -xJf "$src_dl/$TARBALL" -C "$work"
src=$work/LIGGGHTS-PUBLIC-$VERSION/src
[[ -f $src/CMakeLists.txt ]] || { say "error: unexpected tarball layout (no $src/CMakeLists.txt)"; exit 1; }
cp "${patches[@]}" "$src/"
if ((generic)); then
  sed -i '/ROLLING_VISCOUS/d' "$src/style_contact_model.whitelist"
fi
# Fixes the upstream tree needs with GCC 12 and without VTK (Debian's own patches are not in its archive):
# utils.h casts an rvalue stream to an lvalue reference (an error since libstdc++ returns Ostream&& from the rvalue
# inserter, LWG 1203), and dump_mesh_vtk.* lack the LAMMPS_VTK guard of the other VTK dumps.
sed -i 's|return static_cast< std::ostringstream & >(( std::ostringstream() << std::dec << a ) ).str();|std::ostringstream s; s << std::dec << a; return s.str();|' "$src/utils.h"
grep -q 'std::ostringstream s; s << std::dec << a; return s.str();' "$src/utils.h" || { say "error: utils.h not patched"; exit 1; }
rm -f "$src/dump_mesh_vtk.h" "$src/dump_mesh_vtk.cpp"
# finish.cpp compares a pointer with 0 by `>` (an error in GCC 12): it means "not null".
sed -i 's|if (neighbor->lists\[m\]->numneigh > 0) {|if (neighbor->lists[m]->numneigh != NULL) {|' "$src/finish.cpp"
grep -q 'numneigh != NULL' "$src/finish.cpp" || { say "error: finish.cpp not patched"; exit 1; }
# The mesh walls' contact history clears its keep flags every step by zeroing every page of their pool
# (MyPage::reset(true): pgsize bools per page whatever the atoms use); only the flags of each atom's mesh neighbours
# are ever read (fix_contact_history_mesh_I.h), so clearing those is the same state at a fraction of the cost.
sed -i -e '/^void FixContactHistoryMesh::markAllContacts()/,/^}/{' \
  -e 's|^    keeppage_\[0\]->reset(true);|    keeppage_[0]->reset();|' \
  -e '/mesh contact history overflow, boost neigh_modify one");/a\      memset(keepflag_[i], 0, nneighs*sizeof(bool));' \
  -e '}' "$src/fix_contact_history_mesh.cpp"
grep -q 'memset(keepflag_\[i\], 0, nneighs\*sizeof(bool));' "$src/fix_contact_history_mesh.cpp" &&
  ! grep -q 'keeppage_\[0\]->reset(true);' "$src/fix_contact_history_mesh.cpp" ||
  { say "error: fix_contact_history_mesh.cpp not patched"; exit 1; }
# The mesh wall's exact shortcut (RECIPE 5). FixWallGran::post_force_mesh resolves every particle of each triangle's
# mesh neighbour list (TriMesh::resolveTriSphereContactBary: barycentric coordinates, then the face, an edge or a
# corner) and does nothing with it when the distance found exceeds the particle's radius (plus contactDistanceFactor's
# share): no contact, no history, no force. Every point that resolution can return lies in the triangle's plane and
# within SMALL_TRIMESH (edge ends) or the mesh precision (the face test's tolerance) of the triangle. So a sphere
# whose centre is farther than reach + margin from the plane, or whose centre lies outside one edge by dk > margin
# (in-plane outward edge normal) with dn² + (dk − margin)² > (reach + margin)², cannot be found in contact, and
# skipping it changes no state. The margin, 1e-10 + precision + 1e-9·reach + 1e-12·(|x|+|node0|), is orders of
# magnitude above the rounding of both computations; the skip applies to spheres only (not atom->shapetype_flag).
cat >"$work/demsa-mesh-apart.cpp" <<'EOF'

// demsa (scripts/build-liggghts.sh, RECIPE 5): an exact rejection before TriMesh::resolveTriSphereContactBary.
// True only if the sphere centre p is farther than reach from every point that resolution can return.
namespace {
struct DemsaTriMeshAccess : public LAMMPS_NS::TriMesh
{
    // protected members of a TriMesh, read through pointers to members of this class (no object of it is made)
    static inline double **nodeOf(LAMMPS_NS::TriMesh *m, int i)
    { return (m->*(&DemsaTriMeshAccess::node_))(i); }
    static inline double *surfaceNormOf(LAMMPS_NS::TriMesh *m, int i)
    { return (m->*static_cast<double *(LAMMPS_NS::SurfaceMeshBase::*)(int)>(&DemsaTriMeshAccess::surfaceNorm))(i); }
    static inline double **edgeNormOf(LAMMPS_NS::TriMesh *m, int i)
    { return (m->*(&DemsaTriMeshAccess::edgeNorm))(i); }
    static inline double precisionOf(LAMMPS_NS::TriMesh *m)
    { return (m->*(&DemsaTriMeshAccess::precision))(); }
};

inline bool demsaSphereApartFromTri(LAMMPS_NS::TriMesh *mesh, int iTri, const double *p, double reach)
{
    double **node = DemsaTriMeshAccess::nodeOf(mesh, iTri);
    const double *sn = DemsaTriMeshAccess::surfaceNormOf(mesh, iTri);
    const double v[3] = { p[0] - node[0][0], p[1] - node[0][1], p[2] - node[0][2] };
    const double margin = 1e-10 + DemsaTriMeshAccess::precisionOf(mesh) + 1e-9*reach
        + 1e-12*(fabs(p[0]) + fabs(p[1]) + fabs(p[2]) + fabs(node[0][0]) + fabs(node[0][1]) + fabs(node[0][2]));
    const double far = reach + margin;
    const double far2 = far*far;
    const double dn = sn[0]*v[0] + sn[1]*v[1] + sn[2]*v[2];
    const double dn2 = dn*dn;
    if (dn2 > far2) return true;
    double **en = DemsaTriMeshAccess::edgeNormOf(mesh, iTri);
    for (int k = 0; k < 3; k++)
    {
        const double dk = (p[0] - node[k][0])*en[k][0] + (p[1] - node[k][1])*en[k][1] + (p[2] - node[k][2])*en[k][2]
            - margin;
        if (dk > 0. && dn2 + dk*dk > far2) return true;
    }
    return false;
}
}
EOF
sed -i "/^const double SMALL = 1e-12;\$/r $work/demsa-mesh-apart.cpp" "$src/fix_wall_gran.cpp"
sed -i 's|^\( *\)\(deltan = mesh->resolveTriSphereContactBary(iPart, iTri, sidata.radi, x_\[iPart\], delta, bary, barysign, atom->shapetype_flag ? false : true);\)$|\1if (!atom->shapetype_flag \&\& demsaSphereApartFromTri(mesh, iTri, x_[iPart], sidata.radi + ((radius \&\& contactDistanceMultiplier > 0.) ? contactDistanceMultiplier*radius[iPart] : 0.))) continue;\n\1\2|' \
  "$src/fix_wall_gran.cpp"
[[ $(grep -c 'inline bool demsaSphereApartFromTri' "$src/fix_wall_gran.cpp") == 1 &&
  $(grep -c 'demsaSphereApartFromTri(mesh, iTri, x_\[iPart\]' "$src/fix_wall_gran.cpp") == 2 ]] ||
  { say "error: fix_wall_gran.cpp not patched"; exit 1; }
# The mesh contact history's per-step loops over every atom (RECIPE 5), the same writes at less cost:
# markAllContacts calls memset for the keep flags of each atom even when it has no mesh neighbours (a call for
# nothing, for most atoms of a pile); cleanUpContacts reloads the atom's four page pointers and dnum_ after every
# flag it stores (a bool store may alias them) and decrements npartner_ in memory; it now reads them once per atom
# and stores the decremented count once. The values written, and where, are the same.
sed -i 's|^      memset(keepflag_\[i\], 0, nneighs\*sizeof(bool));$|      if (nneighs > 0) memset(keepflag_[i], 0, nneighs*sizeof(bool));|' \
  "$src/fix_contact_history_mesh.cpp"
cat >"$work/demsa-clean-up-contacts.cpp" <<'EOF'
void FixContactHistoryMesh::cleanUpContacts(int ifrom, int ito)
{
    // demsa (scripts/build-liggghts.sh, RECIPE 5): the same stores as upstream's loop, the pointers read once
    const int dnum = dnum_;
    for(int i = ifrom; i < ito; i++)
    {
        const int nneighs = fix_nneighs_->get_vector_atom_int(i);
        if (nneighs <= 0) continue;
        const bool *const keep = keepflag_[i];
        int *const partner = partner_[i];
        bool *const intersect = intersectflag_[i];
        double *const history = contacthistory_[i];
        int npartner = npartner_[i];
        for(int j = 0; j < nneighs; j++)
        {
            // delete values
            if(!keep[j])
            {
                if(partner[j] > -1)
                    npartner--;
                partner[j] = -1;
                intersect[j] = false;
                vectorZeroizeN(&(history[j*dnum]),dnum);
            }
        }
        npartner_[i] = npartner;
    }
}
EOF
sed -i -e '/^void FixContactHistoryMesh::cleanUpContacts(int ifrom, int ito)$/,/^}$/{/^}$/r '"$work/demsa-clean-up-contacts.cpp" \
  -e 'd}' "$src/fix_contact_history_mesh.cpp"
grep -q '^      if (nneighs > 0) memset(keepflag_\[i\], 0, nneighs\*sizeof(bool));$' "$src/fix_contact_history_mesh.cpp" &&
  [[ $(grep -c '^void FixContactHistoryMesh::cleanUpContacts(int ifrom, int ito)$' "$src/fix_contact_history_mesh.cpp") == 1 ]] &&
  grep -q 'the same stores as upstream' "$src/fix_contact_history_mesh.cpp" &&
  ! grep -q '^                    npartner_\[i\]--;$' "$src/fix_contact_history_mesh.cpp" ||
  { say "error: fix_contact_history_mesh.cpp (RECIPE 5) not patched"; exit 1; }
# Debian's soname (the upstream CMakeLists gives the library none of its own).
echo 'SET_TARGET_PROPERTIES(liggghts_shared PROPERTIES VERSION 3.8.0 SOVERSION 3)' >>"$src/CMakeLists.txt"
say "source in $src, patched with: ${patches[*]##*/}"

# 3. Configure and build the executable and the shared library (the OBJECT library is compiled once).
launcher=()
if command -v ccache >/dev/null; then
  export CCACHE_DIR=${CCACHE_DIR:-$cache/ccache} CCACHE_BASEDIR=$work CCACHE_NOHASHDIR=1
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  say "using ccache ($CCACHE_DIR)"
fi
# Upstream's flags (src/CMakeLists.txt sets them only when none are given), then the profile's.
flags="-O2 -funroll-loops -fstrict-aliasing -Wall -Wno-uninitialized -std=c++11 -Wno-literal-suffix -fPIC"
build=$work/build
targets=(liggghts_bin liggghts_shared)
profiled=0
if [[ -n $instrument ]]; then
  # One counter update per event (single-threaded runs); the counts land next to each object, or under $GCOV_PREFIX
  # with $GCOV_PREFIX_STRIP leading folders of that path stripped (scripts/write-liggghts-profile.sh).
  flags+=" -fprofile-generate -fprofile-update=single"
  build=$work/build-instrumented
  targets=(liggghts_bin)
elif ((generic == 0)); then
  # -fprofile-partial-training: code the training never ran is optimised as without a profile, not for size (a
  # study may use a combination the training did not). -flto: the calls between LIGGGHTS's files (the atom arrays,
  # the neighbour lists, the contact history) are inlined like those within one.
  # -Wno-error=coverage-mismatch: GCC checksums each function's source path with its lines, and the profile was
  # counted in one work tree ($HOME/.cache/demsa/work-3.8.0 of the machine that wrote it). Built in another (another
  # $HOME or $XDG_CACHE_HOME), every function's "source locations ... have changed": a warning only, and GCC uses
  # the counts as they are (the same objects as built in the profile's tree). A profile of another source is caught
  # after the build, below.
  flags+=" -fprofile-use -fprofile-partial-training -fprofile-correction -Wno-missing-profile"
  flags+=" -Wno-error=coverage-mismatch -flto=$jobs -fno-fat-lto-objects"
  profiled=1
fi
start=$(date +%s)
CC=mpicc CXX=mpicxx cmake -S "$src" -B "$build" -DCMAKE_BUILD_TYPE= "${launcher[@]}" -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_DISABLE_FIND_PACKAGE_VTK=ON -Wno-dev >"$work/configure.log" 2>&1 ||
  { say "error: cmake configure failed, see $work/configure.log"; tail -20 "$work/configure.log" >&2; exit 1; }
if ((profiled)); then
  # The counts of each object, CMakeFiles/liggghts_obj.dir/FILE.cpp.gcda, where GCC looks for them: beside it.
  tar -xJf "$profile" -C "$build" || { say "error: cannot unpack $profile"; exit 1; }
  counted=$(find "$build/CMakeFiles/liggghts_obj.dir" -name '*.gcda' | wc -l)
  ((counted > 100)) ||
    { say "error: $profile holds $counted profiles of liggghts_obj (scripts/write-liggghts-profile.sh)"; exit 1; }
  say "optimising with the profile of $counted files ($profile)"
fi
say "building with $jobs job(s) (nice 10); log: $work/build.log"
# -k: every file that fails is reported in one pass.
nice -n 10 cmake --build "$build" --target "${targets[@]}" -j "$jobs" -- -k >"$work/build.log" 2>&1 || {
  say "error: build failed, see $work/build.log"
  grep -m 20 -E ': error:' "$work/build.log" >&2
  exit 1
}
# A profile of another source (a changed patch, or a changed edit of the source above) no longer matches the control
# flow of its functions: GCC warns and drops their counts. Such a build is not kept. A new RECIPE alone leaves the
# source, and so the profile, as it was.
if ((profiled)) && grep -q 'does not match its profile data' "$work/build.log"; then
  grep -m 5 'does not match its profile data' "$work/build.log" >&2
  say "error: $profile was written for another source: run scripts/write-liggghts-profile.sh to write it again"
  exit 1
fi
grep -q 'ROLLING_VISCOUS' "$src/style_contact_model.h" || ((generic)) ||
  { say "error: the viscous kernel is missing from $src/style_contact_model.h"; exit 1; }
if [[ -n $instrument ]]; then
  mkdir -p "$prefix/bin"
  cp "$build/liggghts" "$prefix/bin/liggghts"
  echo "$build" >"$prefix/objects-dir.txt"
  say "instrumented build in $prefix (its counts: $build/CMakeFiles/liggghts_obj.dir/*.gcda)"
  echo "$prefix"
  exit 0
fi

# 4. Install into the versioned prefix atomically (a temporary sibling, renamed at the end).
tmp=$prefix.tmp.$$
rm -rf "$tmp"
mkdir -p "$tmp/bin" "$tmp/lib" "$tmp/include/liggghts"
cp "$build/liggghts" "$tmp/bin/liggghts"
cp -P "$build"/libliggghts.so* "$tmp/lib/"
[[ -e $tmp/lib/libliggghts.so.3 ]] || { say "error: no libliggghts.so.3 in $build"; exit 1; }
cp "$src"/*.h "$tmp/include/liggghts/"
"$tmp/bin/liggghts" -h </dev/null 2>/dev/null | sed -n '/Rolling models for pair gran/,/^\* /p' >"$tmp/rolling-models.txt" || true
grep -qw viscous "$tmp/rolling-models.txt" || { say "error: the built binary does not list the viscous rolling model"; exit 1; }
{
  echo "LIGGGHTS $VERSION from Debian's $TARBALL"
  echo "key $key"
  echo "patches ${patches[*]##*/}"
  echo "built $(date -u +%Y-%m-%dT%H:%M:%SZ) in $(($(date +%s) - start)) s with -j$jobs"
} >"$tmp/demsa-liggghts.txt"
rm -rf "$prefix"
mv "$tmp" "$prefix"
say "done in $(($(date +%s) - start)) s: $prefix"
echo "$prefix"
