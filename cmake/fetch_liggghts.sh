#!/usr/bin/env bash
# Obtain, verify, unpack and patch the LIGGGHTS 3.8.0 source (Debian source package).
#   fetch_liggghts.sh DEST DOWNLOADS
# DEST      unpacked, patched tree (DEST/src holds the sources)
# DOWNLOADS where the orig tarball is kept between builds
# Idempotent: does nothing when DEST/.wirenet-stamp matches the pinned tarball and patches.
# WIRENET_LIGGGHTS_TARBALL may name a local copy of the tarball (offline builds).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
dest=$1
downloads=$2
# shellcheck source=liggghts.env
. "$here/liggghts.env"

die() { echo "fetch_liggghts: error: $*" >&2; exit 1; }

# What the unpacked tree depends on: the tarball, the patches and the recipe version below (bump
# it when the unpack steps change). Not this whole script: how the tarball is obtained does not
# change the tree, and re-extracting means a full 7-minute rebuild.
TREE_RECIPE=2
stamp_text() {
  { echo "$LIGGGHTS_SHA256 recipe $TREE_RECIPE"; cat "$here"/patches/*.patch; } | sha256sum | cut -d' ' -f1
}

sha_ok() { [ -f "$1" ] && [ "$(sha256sum "$1" | cut -d' ' -f1)" = "$LIGGGHTS_SHA256" ]; }

# URL of the orig tarball as apt knows it from the machine's deb-src entries (./wirenet setup
# derives one from the deb entries when there is none). No archive host is written here: a
# mirror configured in apt is used as it is.
tarball_url() {
  command -v apt-get >/dev/null 2>&1 || die "apt-get not found: set WIRENET_LIGGGHTS_TARBALL to a local $LIGGGHTS_TARBALL"
  local url
  url=$(apt-get source --print-uris "$LIGGGHTS_PACKAGE" 2>/dev/null |
        awk -v t="$LIGGGHTS_TARBALL" '$2 == t { gsub("\047", "", $1); print $1 }' | head -n1)
  [ -n "$url" ] || die "apt knows no source of $LIGGGHTS_PACKAGE ($LIGGGHTS_TARBALL): add a deb-src entry (./wirenet setup does it as root) and run apt-get update, or set WIRENET_LIGGGHTS_TARBALL to a local copy"
  echo "$url"
}

download() {
  local url=$1 out=$2
  if command -v curl >/dev/null 2>&1; then curl -sSfL --retry 3 -o "$out" "$url"
  elif command -v wget >/dev/null 2>&1; then wget -q -O "$out" "$url"
  else /usr/bin/python3 -c 'import sys, urllib.request; urllib.request.urlretrieve(sys.argv[1], sys.argv[2])' "$url" "$out"
  fi
}

obtain_tarball() {
  local tb="$downloads/$LIGGGHTS_TARBALL"
  if [ -n "${WIRENET_LIGGGHTS_TARBALL:-}" ]; then
    sha_ok "$WIRENET_LIGGGHTS_TARBALL" || die "WIRENET_LIGGGHTS_TARBALL=$WIRENET_LIGGGHTS_TARBALL does not have the pinned sha256 $LIGGGHTS_SHA256"
    echo "$WIRENET_LIGGGHTS_TARBALL"; return
  fi
  if ! sha_ok "$tb"; then
    mkdir -p "$downloads"
    local url; url=$(tarball_url) || exit 1
    echo "fetch_liggghts: downloading $url" >&2
    download "$url" "$tb.part" || { rm -f "$tb.part"; die "could not download $url (is Debian's archive reachable?)"; }
    sha_ok "$tb.part" || { rm -f "$tb.part"; die "$LIGGGHTS_TARBALL: sha256 mismatch (expected $LIGGGHTS_SHA256)"; }
    mv "$tb.part" "$tb"
  fi
  echo "$tb"
}

want=$(stamp_text)
if [ -f "$dest/.wirenet-stamp" ] && [ "$(cat "$dest/.wirenet-stamp")" = "$want" ]; then
  exit 0
fi

tb=$(obtain_tarball)
work=$(mktemp -d "${dest%/}.tmp.XXXXXX")
trap 'rm -rf "$work"' EXIT
tar -xJf "$tb" -C "$work"
src="$work/$LIGGGHTS_TOPDIR"
[ -d "$src/src" ] || die "$LIGGGHTS_TARBALL does not contain $LIGGGHTS_TOPDIR/src"

for p in "$here"/patches/*.patch; do
  patch -s -p1 -d "$src" < "$p" || die "patch $(basename "$p") does not apply"
done

# Styles whose dependencies are absent: dump mesh/vtk includes VTK headers unconditionally.
if ! ls /usr/include/vtk* >/dev/null 2>&1; then
  rm -f "$src/src/dump_mesh_vtk.cpp" "$src/src/dump_mesh_vtk.h"
fi

# Contact-model tables are generated once; the project adds no contact model.
(cd "$src/src" && sh Make.sh models >/dev/null)

rm -rf "$dest"
mkdir -p "$(dirname "$dest")"
mv "$src" "$dest"
echo "$want" > "$dest/.wirenet-stamp"
echo "fetch_liggghts: LIGGGHTS source ready in $dest" >&2
