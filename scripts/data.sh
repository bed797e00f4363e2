#!/usr/bin/env bash
# Data step (idempotent): extracts the CGAL meshes the project uses into data/meshes/, builds the generated tiers in
# data/generated/, and verifies every file against data/manifest.csv (vertex/face counts and sha256).
#
#   scripts/data.sh                   default tier: CGAL meshes, cactus_cgal edit, armadillo_loop1 (104002 v)
#   scripts/data.sh --full            also armadillo_loop2 / _loop3 (416k / 1.66M v) for the scaling series
#   scripts/data.sh --write-manifest  rewrite data/manifest.csv from the files present (run with --full to record all)
#
# Environment: MESHTOOL (path to a built meshtool; default: build it in $DEFORMBENCH_BUILD_DIR, default build/),
# JOBS (build parallelism, default 2).
#
# Manifest columns: name,source,path,vertices,faces,sha256,tier. tier = default (always produced and checked),
# full (produced by --full; checked when present), bundled (committed in the repository: always checked). Paths
# are relative to the repository root. All meshes are .off: the writer prints each double as the shortest string
# that reads back exactly, so the generated files are deterministic and lossless.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
MANIFEST=data/manifest.csv
FULL=0
WRITE=0
for arg in "$@"; do
  case "$arg" in
    --full) FULL=1 ;;
    --write-manifest) WRITE=1 ;;
    -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
    *) echo "data.sh: unknown argument '$arg' (see --help)" >&2; exit 2 ;;
  esac
done

die() { echo "data.sh: ERROR: $*" >&2; exit 1; }
log() { echo "data.sh: $*"; }

CGAL_MESHES=(hand cylinder dino cactus camel ChineseDragon-10kv man diplodocus armadillo bunny00 refined_elephant)
DEFORM_DIR=examples/Surface_mesh_deformation/data

# Every file this step provides or checks: name|source|path|tier.
entries() {
  local m
  for m in "${CGAL_MESHES[@]}"; do
    echo "$m|cgal data.tar.gz:data/meshes/$m.off|data/meshes/$m.off|default"
  done
  echo "cactus_cgal|copy of data/meshes/cactus.off (stem for the CGAL cactus edit)|data/meshes/cactus_cgal.off|default"
  echo "cactus_cgal.sel|cgal examples.tar.gz:$DEFORM_DIR/cactus.sel|data/meshes/cactus_cgal.sel|default"
  echo "cactus_cgal.def|cgal examples.tar.gz:$DEFORM_DIR/cactus.def|data/meshes/cactus_cgal.def|default"
  echo "armadillo_loop1|meshtool subdivide armadillo.off 1 (OpenMesh Loop)|data/generated/armadillo_loop1.off|default"
  echo "armadillo_loop2|meshtool subdivide armadillo.off 2 (OpenMesh Loop)|data/generated/armadillo_loop2.off|full"
  echo "armadillo_loop3|meshtool subdivide armadillo.off 3 (OpenMesh Loop)|data/generated/armadillo_loop3.off|full"
  for m in plane cylinder bar cactus; do
    for ext in off sel def; do
      echo "bs08_$m.$ext|Botsch-Sorkine 2008 survey edit, bundled (data/README.md)|data/bs08/$m.$ext|bundled"
    done
  done
}

# ---------------------------------------------------------------- meshtool
if [[ -z "${MESHTOOL:-}" ]]; then
  BUILD_DIR=${DEFORMBENCH_BUILD_DIR:-$ROOT/build}
  if [[ ! -f "$BUILD_DIR/CMakeCache.txt" ]]; then
    cmake -S "$ROOT" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null || die "cmake configure failed"
  fi
  cmake --build "$BUILD_DIR" --target meshtool -j"${JOBS:-2}" >/dev/null || die "building meshtool failed"
  MESHTOOL=$BUILD_DIR/meshtool
fi
[[ -x "$MESHTOOL" ]] || die "meshtool not found at $MESHTOOL"

# ---------------------------------------------------------------- CGAL tarballs
CGAL_DOC=${CGAL_DOC:-/usr/share/doc/libcgal-dev}  # overridable to exercise the fallback
CACHE=data/cache
tarball() {  # prints the path of the named libcgal-demo tarball, fetching the package if dpkg dropped the docs
  local name=$1
  if [[ -f "$CGAL_DOC/$name" ]]; then echo "$CGAL_DOC/$name"; return; fi
  local extracted="$CACHE/libcgal-demo/usr/share/doc/libcgal-dev/$name"
  if [[ ! -f "$extracted" ]]; then
    mkdir -p "$CACHE"
    # Slim images exclude /usr/share/doc from installs: unpack the .deb ourselves.
    if ! ls "$CACHE"/libcgal-demo_*.deb >/dev/null 2>&1; then
      (cd "$CACHE" && apt-get download libcgal-demo >&2) ||
        die "$CGAL_DOC/$name is missing and 'apt-get download libcgal-demo' failed (install libcgal-demo, or run apt-get update)"
    fi
    dpkg-deb -x "$(ls "$CACHE"/libcgal-demo_*.deb | head -n1)" "$CACHE/libcgal-demo" ||
      die "cannot unpack $(ls "$CACHE"/libcgal-demo_*.deb | head -n1)"
  fi
  [[ -f "$extracted" ]] || die "$name is neither in $CGAL_DOC nor in the libcgal-demo package"
  echo "$extracted"
}

# extract TARBALL MEMBER DEST: one member to DEST via a temporary file (never a partial DEST).
extract() {
  local tb=$1 member=$2 dest=$3 tmp
  mkdir -p "$ROOT/$CACHE"
  tmp=$(mktemp -d "$ROOT/$CACHE/extract.XXXXXX")  # under data/cache/: git-ignored
  if ! tar -xzf "$tb" -C "$tmp" "$member"; then rm -rf "$tmp"; die "cannot extract $member from $tb"; fi
  mv "$tmp/$member" "$dest"
  rm -rf "$tmp"
}

mkdir -p data/meshes data/generated
for m in "${CGAL_MESHES[@]}"; do
  if [[ ! -f data/meshes/$m.off ]]; then
    log "extracting $m.off"
    tb=$(tarball data.tar.gz) || exit 1
    extract "$tb" "data/meshes/$m.off" "data/meshes/$m.off"
  fi
done
for ext in sel def; do
  if [[ ! -f data/meshes/cactus_cgal.$ext ]]; then
    log "extracting cactus.$ext (CGAL Surface_mesh_deformation example) as cactus_cgal.$ext"
    tb=$(tarball examples.tar.gz) || exit 1
    extract "$tb" "$DEFORM_DIR/cactus.$ext" "data/meshes/cactus_cgal.$ext"
  fi
done
# CGAL's .sel/.def are already in the Botsch-Sorkine format (0/1/2 per vertex of meshes/cactus.off, 620 lines);
# a copy of the mesh under the same stem makes data/meshes/cactus_cgal loadable as a BS08-style case.
[[ -f data/meshes/cactus_cgal.off ]] || cp data/meshes/cactus.off data/meshes/cactus_cgal.off

# ---------------------------------------------------------------- generated tiers
levels=(1)
[[ $FULL == 1 ]] && levels=(1 2 3)
for l in "${levels[@]}"; do
  out=data/generated/armadillo_loop$l.off
  if [[ ! -f $out ]]; then
    log "generating $out"
    "$MESHTOOL" subdivide data/meshes/armadillo.off "$out" "$l" >/dev/null || die "meshtool subdivide failed for $out"
  fi
done

# ---------------------------------------------------------------- verification
# measure PATH: prints "vertices faces sha256" (counts empty for .def; .sel counts its statuses).
measure() {
  local p=$1 v="" f="" sha info
  case "$p" in
    *.off|*.ply|*.obj)
      info=$("$MESHTOOL" info "$p" --validate) || die "meshtool info --validate failed on $p"
      v=$(sed -n 's/.* vertices=\([0-9]*\).*/\1/p' <<<"$info")
      f=$(sed -n 's/.* faces=\([0-9]*\).*/\1/p' <<<"$info") ;;
    *.sel) v=$(grep -v '^[[:space:]]*#' "$p" | grep -c '[^[:space:]]' || true) ;;
  esac
  sha=$(sha256sum "$p" | cut -d' ' -f1)
  echo "$v|$f|$sha"
}

if [[ $WRITE == 1 ]]; then
  mkdir -p "$ROOT/$CACHE"
  tmp=$(mktemp "$ROOT/$CACHE/manifest.XXXXXX")
  echo "name,source,path,vertices,faces,sha256,tier" >"$tmp"
  while IFS='|' read -r name source path tier; do
    if [[ -f $path ]]; then
      IFS='|' read -r v f sha <<<"$(measure "$path")"
      echo "$name,\"$source\",$path,$v,$f,$sha,$tier" >>"$tmp"
    elif [[ -f $MANIFEST ]] && old=$(grep -m1 "^$name," "$MANIFEST"); then
      log "keeping the recorded row for $path (not present)"
      echo "$old" >>"$tmp"
    else
      rm -f "$tmp"
      die "$path is not present and has no recorded row; run with --full"
    fi
  done < <(entries)
  mv "$tmp" "$MANIFEST"
  log "wrote $MANIFEST"
fi

[[ -f $MANIFEST ]] || die "$MANIFEST is missing (run scripts/data.sh --write-manifest)"
errors=0
checked=0
# Rows are read with python-free CSV handling: only the source column is quoted and it holds no '"'.
while IFS= read -r line; do
  [[ $line == name,* ]] && continue
  source=$(sed -n 's/^[^,]*,"\([^"]*\)".*/\1/p' <<<"$line")
  rest=$(sed 's/^\([^,]*\),"[^"]*",/\1,/' <<<"$line")
  IFS=',' read -r name path ev ef esha tier <<<"$rest"
  if [[ ! -f $path ]]; then
    case "$tier" in
      default|bundled) echo "data.sh: MISSING $path ($name, $source)" >&2; errors=$((errors + 1)) ;;
      full) [[ $FULL == 1 ]] && { echo "data.sh: MISSING $path ($name)" >&2; errors=$((errors + 1)); } ;;
    esac
    continue
  fi
  IFS='|' read -r v f sha <<<"$(measure "$path")"
  for what in vertices faces sha256; do
    case $what in vertices) e=$ev g=$v ;; faces) e=$ef g=$f ;; sha256) e=$esha g=$sha ;; esac
    if [[ "$e" != "$g" ]]; then
      echo "data.sh: MISMATCH $path: $what expected '$e' got '$g'" >&2
      errors=$((errors + 1))
    fi
  done
  checked=$((checked + 1))
done <"$MANIFEST"
[[ $errors == 0 ]] || die "$errors problem(s) against $MANIFEST (delete a stale file to rebuild it)"
log "ok: $checked files match $MANIFEST"
