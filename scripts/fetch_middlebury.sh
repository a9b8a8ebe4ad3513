#!/usr/bin/env bash
# Downloads a Middlebury ring set into DATA_DIR and checks its camera file's SHA-256.
# Usage: fetch_middlebury.sh <dinoRing|templeRing|dinoSparseRing|templeSparseRing> <DATA_DIR>
set -euo pipefail
name=$1; dir=$2
declare -A SHA=(
  [dinoRing]=a1ff4466587abe2bad6e7999e99e052994c7515ddcbe8ab0326732c3b04474a0
  [templeRing]=ad81a6208dd931997ea885859b711608614f11a6aa54c432b621cf3007fb09f6
  [dinoSparseRing]=ab951cc4bb0eb11b0af508d4344f84748bee22b02fd3c578bdad87b20ae75002
  [templeSparseRing]=172e2b8957f214aee409add74f09cb4794d5697a2721598d61279bb0afc25388
)
declare -A PAR=([dinoRing]=dinoR [templeRing]=templeR [dinoSparseRing]=dinoSR [templeSparseRing]=templeSR)
[ -n "${SHA[$name]:-}" ] || { echo "fetch: unknown Middlebury set '$name'" >&2; exit 2; }
par="$dir/$name/${PAR[$name]}_par.txt"
if [ ! -f "$par" ]; then
  mkdir -p "$dir"
  url="https://vision.middlebury.edu/mview/data/data/$name.zip"
  tmp=$(mktemp -d)
  echo "fetch: downloading $url" >&2
  if ! curl -fsSL -o "$tmp/$name.zip" "$url"; then
    echo "fetch: cannot download $url (no network?); put the set in $dir/$name or pass DATA_DIR=..." >&2
    rm -rf "$tmp"; exit 1
  fi
  (cd "$tmp" && unzip -q "$name.zip")
  rm -f "$tmp/$name.zip"
  src=$(dirname "$(find "$tmp" -name "${PAR[$name]}_par.txt" | head -1)")
  mkdir -p "$dir/$name"
  cp -r "$src"/. "$dir/$name/"
  rm -rf "$tmp"
fi
got=$(sha256sum "$par" | cut -d' ' -f1)
if [ "$got" != "${SHA[$name]}" ]; then
  echo "fetch: $par has SHA-256 $got, expected ${SHA[$name]}; the download is not the official set" >&2
  exit 1
fi
touch "$dir/$name/.present" 2>/dev/null || true
