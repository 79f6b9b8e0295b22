#!/usr/bin/env bash
# Fetches the third-party scenes that configs/scenes/*.json name through ${GIBENCH_SCENES}, then
# checks every file against experiments/scenes.sha256.
#
#   experiments/fetch_scenes.sh [FOLDER]
#
# FOLDER defaults to ../shared/scenes next to the repository, where gibench looks when
# GIBENCH_SCENES is not set; for any other folder the script prints the export line to use.
# The scenes are copied from ../shared/scenes when that folder exists, else downloaded from their
# public sources (McGuire's Computer Graphics Archive, Bitterli's rendering resources). Run by
# hand only: nothing in the build or the tests calls it.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
shared="$(cd "$repo/.." && pwd)/shared/scenes"
sums="$repo/experiments/scenes.sha256"
target="${1:-$shared}"
mkdir -p "$target"
target="$(cd "$target" && pwd)"

scenes=(cornell-box sponza-dabrovic living-room)
declare -A url=(
  [cornell-box]="https://casual-effects.com/g3d/data10/common/model/CornellBox/CornellBox.zip"
  [sponza-dabrovic]="https://casual-effects.com/g3d/data10/research/model/dabrovic_sponza/sponza.zip"
  [living-room]="https://benedikt-bitterli.me/resources/mitsuba/living-room.zip"
)

die() { echo "fetch_scenes: $*" >&2; exit 1; }

if command -v sha256sum >/dev/null; then
  hash_of() { sha256sum "$1" | cut -d' ' -f1; }
elif command -v shasum >/dev/null; then
  hash_of() { shasum -a 256 "$1" | cut -d' ' -f1; }
else
  die "need sha256sum or shasum"
fi

download() {  # URL FILE
  if command -v curl >/dev/null; then
    curl -fL --retry 3 --progress-bar -o "$2" "$1"
  elif command -v wget >/dev/null; then
    wget -O "$2" "$1"
  else
    die "need curl or wget to download $1"
  fi
}

unpack() {  # ZIP FOLDER
  if command -v unzip >/dev/null; then
    unzip -q -o "$1" -d "$2"
  elif command -v python3 >/dev/null; then
    python3 -m zipfile -e "$1" "$2"
  else
    die "need unzip or python3 to unpack $1"
  fi
}

# Unpacks the archive of scene $1 into $target/$1; an archive whose only entry is a folder is
# unpacked from inside that folder.
fetch() {
  local scene="$1"
  mkdir -p "$work/$scene"
  echo "downloading $scene from ${url[$scene]}"
  download "${url[$scene]}" "$work/$scene.zip"
  unpack "$work/$scene.zip" "$work/$scene"
  local root="$work/$scene"
  local entries=("$root"/*)
  if [ ${#entries[@]} -eq 1 ] && [ -d "${entries[0]}" ]; then root="${entries[0]}"; fi
  mkdir -p "$target/$scene"
  cp -Rf "$root"/. "$target/$scene"/
}

if [ "$target" = "$shared" ]; then
  [ -d "$shared" ] || die "no folder $shared"
  echo "checking the scenes in $target"
elif [ -d "$shared" ]; then
  for scene in "${scenes[@]}"; do
    echo "copying $scene from $shared"
    cp -Rf "$shared/$scene" "$target/"
    chmod -R u+w "$target/$scene"  # the shared copies are read-only; keep reruns possible
  done
else
  work="$(mktemp -d)"
  trap 'rm -rf "$work"' EXIT
  for scene in "${scenes[@]}"; do fetch "$scene"; done
fi

# Check every listed file, reporting each problem rather than stopping at the first.
problems=0
while read -r expected path; do
  [ -n "$expected" ] || continue
  file="$target/${path#./}"
  if [ ! -f "$file" ]; then
    echo "MISSING  ${path#./}"
    problems=$((problems + 1))
  elif [ "$(hash_of "$file")" != "$expected" ]; then
    echo "DIFFERS  ${path#./}: SHA-256 $(hash_of "$file"), expected $expected"
    problems=$((problems + 1))
  fi
done < "$sums"

if [ "$problems" -ne 0 ]; then
  cat >&2 <<MESSAGE
fetch_scenes: $problems file(s) do not match experiments/scenes.sha256.
The reference copies (../shared/scenes) carry small documented changes, so a fresh download
differs from them in places: the Cornell box OBJ has its tall block's bottom face, mtllib path and
line endings fixed; the living room's 65 meshes are merged into living-room.obj with diffuse
approximations in living-room.mtl (a conversion this script does not perform); and each folder
has a notes.json written for gibench. Copy the scenes from a machine that has ../shared/scenes
to reproduce the reference exactly; results from differing files are not comparable with it.
MESSAGE
  exit 1
fi

echo "all $(grep -c . "$sums") files match"
if [ "$target" != "$shared" ]; then
  echo "export GIBENCH_SCENES=$target"
fi
